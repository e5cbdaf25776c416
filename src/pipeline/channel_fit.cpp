#include "src/pipeline/channel_fit.hpp"

#include "kernels/diagnose/diagnose.hpp"
#include "kernels/model/effective_taus.hpp"
#include "kernels/model/fit.hpp"
#include "kernels/model/psd_fit.hpp"
#include "kernels/model/units.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <map>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string_view>

namespace allanlot::pipeline {
namespace {

using kernels::units::Term;

// Indices of the rows of `r` nearest to a log:16 grid of its own tau range: the fit's
// information is in the shape of the curve over decades, not in the number of points, and
// the covariance model costs O(P^2) memory and time.
std::vector<std::size_t> fit_rows(const kernels::StatResult& r) {
  constexpr double kPerDecade = 16.0;
  std::vector<std::size_t> rows;
  if (r.size() <= 200) {
    for (std::size_t i = 0; i < r.size(); ++i)
      rows.push_back(i);
    return rows;
  }
  const double lo = std::log10(static_cast<double>(r.m.front()));
  const double hi = std::log10(static_cast<double>(r.m.back()));
  for (double e = lo; e <= hi + 1e-12; e += 1.0 / kPerDecade) {
    const double target = std::pow(10.0, e);
    const auto it = std::lower_bound(r.m.begin(), r.m.end(), static_cast<std::int64_t>(target));
    std::size_t i = static_cast<std::size_t>(it - r.m.begin());
    if (i == r.size()) i = r.size() - 1;
    if (i > 0 && std::abs(static_cast<double>(r.m[i - 1]) - target) <
                     std::abs(static_cast<double>(r.m[i]) - target))
      --i;
    if (rows.empty() || rows.back() != i) rows.push_back(i);
  }
  return rows;
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The filter the fit leaves its taus to, and where that leaves the fit.
struct FilterUsed {
  // "auto" (found on the curve), "auto-unused" (found, all taus kept: see fit_channel),
  // "option" (--lowpass), "none"
  std::string source = "none";
  kernels::Lowpass filter;
  double delta_ic = kNaN;  // the auto test's criterion; NaN when not tested
  std::int64_t first_m = 1;
  double first_tau_s = kNaN;
  std::size_t taus = 0;
};

// --lowpass auto: diagnose's lowpass test on the curve when the all-taus fit is not ok (an ok
// fit explains every tau within its noise, so no filter biases it beyond what the fit allows;
// the test's 84 trial fits and 27 refining ones, about 0.3 s a channel, are spared). n_eff is
// the all-taus fit's when it converged (no second covariance model); the filter's deficit can
// keep it from converging, and then find_lowpass computes its own. A filter given by the option is
// taken as it is. The first m is where the filter biases white FM's Allan variance by less than
// half a sigma (kernels::lowpass_first_m), so no tau the fit uses is biased by more.
FilterUsed filter_of(const LowpassChoice& choice, const kernels::StatResult& sub,
                     const kernels::FitResult& all, const Eigen::MatrixXd& all_covariance,
                     double rate_hz, std::int64_t n_samples) {
  FilterUsed u;
  u.taus = sub.size();
  u.first_tau_s = sub.tau_s.empty() ? kNaN : sub.tau_s.front();
  if (choice.mode == LowpassChoice::Mode::Given) {
    kernels::validate_lowpass(choice.filter, rate_hz);  // a cutoff at or above this Nyquist
    u.source = "option";
    u.filter = choice.filter;
  } else if (choice.mode == LowpassChoice::Mode::Auto && !sub.m.empty() &&
             all.status != kernels::FitStatus::Ok) {
    const double n_eff =
        kernels::has_terms(all.status) ? kernels::effective_taus_of(all_covariance) : 0.0;
    const kernels::LowpassFinding found = kernels::find_lowpass(sub, rate_hz, n_samples, n_eff);
    u.delta_ic = found.delta_ic;
    if (found.filter.active()) {
      u.source = "auto";
      u.filter = found.filter;
    }
  }
  u.first_m = kernels::lowpass_first_m(u.filter, rate_hz, n_samples);
  return u;
}

void set_filter_fields(io::FitRecord& rec, const FilterUsed& u, const kernels::FitResult& all) {
  rec.lowpass = u.source;
  rec.lowpass_cutoff_hz = u.filter.cutoff_hz > 0 ? u.filter.cutoff_hz : kNaN;
  rec.lowpass_taps = u.filter.taps > 0 ? u.filter.taps : kNaN;
  rec.lowpass_delta_ic = u.delta_ic;
  rec.first_tau_fitted = u.first_tau_s;
  rec.taus_fitted = static_cast<std::int64_t>(u.taus);
  rec.chi2_dof_all_taus = all.chi2_dof;  // what --lowpass none writes as chi2_dof
}

// The read-outs (IEEE Std 952 annex C) read the measured curve over all its taus, as a
// datasheet reads it, whatever taus the fit leaves out; whether each is valid (its term
// detected) and its `model` come from the fit reported, `used` with squared coefficients theta,
// on the same taus (FitResult: N at 1 s, the minimum over 2 ln2 / pi, the lowest +1/2 line at
// 3 s).
kernels::FitResult readouts_under(const kernels::FitResult& all, const kernels::FitResult& used,
                                  const std::array<double, kernels::kNumTerms>& theta,
                                  std::span<const double> taus) {
  kernels::FitResult out = all;
  double min_avar = std::numeric_limits<double>::infinity(), min_k = min_avar;
  for (const double tau : taus) {
    min_avar = std::min(min_avar, kernels::eq3_avar(theta, tau));
    min_k = std::min(min_k, kernels::eq3_avar(theta, tau) / tau);
  }
  const double floor = kernels::eq3_regressors(1.0)[static_cast<std::size_t>(Term::B)];
  out.n_1s.model = std::sqrt(kernels::eq3_avar(theta, 1.0));
  out.bias_instability.model = std::sqrt(min_avar / floor);
  out.k_3s.model = std::sqrt(3.0 * min_k);
  out.n_1s.valid = out.n_1s.value > 0.0 && used[Term::N].detected;  // 1 s on the curve
  out.bias_instability.valid = used[Term::B].detected;
  out.k_3s.valid = used[Term::K].detected;
  return out;
}

io::ReadoutRecord readout_record(const std::string& name, Term t, const kernels::Readout& r,
                                 const std::string& units) {
  namespace u = kernels::units;
  io::ReadoutRecord rec;
  rec.name = name;
  rec.valid = r.valid;
  rec.value = r.value;
  rec.sigma = r.sigma;
  rec.tau_s = r.tau_s;
  rec.model = r.model;
  const u::Datasheet ds = u::to_datasheet(t, r.value, units);
  rec.value_datasheet = ds.primary.value;
  rec.unit_datasheet = ds.primary.unit;
  rec.sigma_datasheet = u::to_datasheet(t, r.sigma, units).primary.value;
  if (ds.secondary && t == Term::N) {  // ARW or VRW, as datasheets quote N
    rec.value_datasheet_alt = ds.secondary->value;
    rec.sigma_datasheet_alt = u::to_datasheet(t, r.sigma, units).secondary->value;
    rec.unit_datasheet_alt = ds.secondary->unit;
  }
  return rec;
}

// The fields every fit record opens with, alike for the eq. (3) fit to the Allan variance
// (kernels::FitResult) and the fit to the PSD (kernels::PsdFitResult).
template <class Fit>
io::FitRecord fit_record(std::string_view method, const Fit& f) {
  io::FitRecord rec;
  rec.method = std::string(method);
  rec.status = f.status;
  rec.rank = f.rank;
  rec.chi2_dof = f.chi2_dof;
  return rec;
}

}  // namespace

io::TermRecord term_record(kernels::units::Term t, const kernels::TermFit& f,
                           const std::string& units) {
  namespace u = kernels::units;
  io::TermRecord rec;
  rec.term = std::string(u::term_name(t));
  rec.value = f.value;
  rec.sigma = f.sigma;
  rec.upper = f.upper;
  rec.detected = f.detected;
  rec.unit = u::channel_unit(t, units);
  // The conversions are pure scale factors, so sigma and the bound convert like the value.
  const u::Datasheet ds = u::to_datasheet(t, f.value, units);
  rec.value_datasheet = ds.primary.value;
  rec.unit_datasheet = ds.primary.unit;
  rec.sigma_datasheet = u::to_datasheet(t, f.sigma, units).primary.value;
  rec.upper_datasheet = u::to_datasheet(t, f.upper, units).primary.value;
  if (ds.secondary) {
    rec.value_datasheet_alt = ds.secondary->value;
    rec.unit_datasheet_alt = ds.secondary->unit;
  }
  return rec;
}

io::FitRecord fit_channel(const kernels::StatResult& oadev, double tau0_s, std::int64_t n_samples,
                          const std::string& units, const LowpassChoice& lowpass,
                          std::array<kernels::TermFit, kernels::kNumTerms>* terms_out,
                          int threads) {
  // One fit object per thread and curve shape: each caches the covariance model of a shape,
  // which every channel of the same length and grid shares (about 0.2 s to build, 0.5 ms per
  // fit after); the fit from a filter's first tau on has a shape of its own.
  thread_local kernels::Eq3Fit fitter_all, fitter_cut;
  fitter_all.set_threads(threads);
  fitter_cut.set_threads(threads);
  const kernels::StatResult sub = kernels::fit_subset(oadev, fit_rows(oadev));
  const kernels::FitResult all = fitter_all.fit(sub, tau0_s, n_samples);
  const double rate_hz = 1.0 / tau0_s;
  FilterUsed used = filter_of(lowpass, sub, all, fitter_all.covariance(), rate_hz, n_samples);
  kernels::FitResult f = all;
  if (!sub.m.empty() && used.first_m > sub.m.front()) {
    const kernels::StatResult cut = kernels::fit_subset(sub, used.first_m);
    f = fitter_cut.fit(cut, tau0_s, n_samples);
    used.first_tau_s = cut.tau_s.empty() ? kNaN : cut.tau_s.front();
    used.taus = cut.size();
    // A filter found on the curve must explain its misfit: when the fit from the filter's first
    // tau is no better per degree of freedom than the fit over every tau, the misfit lies
    // elsewhere (the real accelerometers' vibration lines, docs/fit-and-psd.md), and leaving
    // out the short taus would only lose the white noise they measure best.
    if (used.source == "auto" && kernels::has_terms(all.status) && !(f.chi2_dof < all.chi2_dof)) {
      used.source = "auto-unused";
      used.first_tau_s = sub.tau_s.front();
      used.taus = sub.size();
      f = all;
    }
  }

  io::FitRecord rec = fit_record(kernels::kFitMethod, f);
  rec.tau = oadev.tau_s;
  set_filter_fields(rec, used, all);
  if (!kernels::has_terms(f.status)) return rec;
  if (terms_out) *terms_out = f.terms;
  std::array<double, kernels::kNumTerms> theta{};
  for (const Term t : kernels::units::all_terms()) {
    const auto& tf = f[t];
    theta[static_cast<std::size_t>(t)] = tf.theta;
    rec.terms.push_back(term_record(t, tf, units));
  }
  for (const double tau : oadev.tau_s)
    rec.adev_model.push_back(std::sqrt(kernels::eq3_avar(theta, tau)));
  // Without taus left out the fit is the all-taus fit, read-outs and all (bit for bit).
  const kernels::FitResult ro =
      used.taus < sub.size() ? readouts_under(all, f, theta, sub.tau_s) : f;
  rec.readouts.push_back(readout_record("N_1s", Term::N, ro.n_1s, units));
  rec.readouts.push_back(readout_record("bias_instability", Term::B, ro.bias_instability, units));
  rec.readouts.push_back(readout_record("K_3s", Term::K, ro.k_3s, units));
  return rec;
}

LowpassChoice parse_lowpass_choice(const std::string& text) {
  LowpassChoice c;
  if (text == "auto") return c;
  c.mode = LowpassChoice::Mode::None;
  if (text == "none") return c;
  const auto eq = text.find('=');
  const std::string key = text.substr(0, eq);
  double value = 0.0;
  std::size_t used = 0;
  try {
    if (eq != std::string::npos) value = std::stod(text.substr(eq + 1), &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (eq == std::string::npos || used == 0 || eq + 1 + used != text.size() ||
      (key != "cutoff_hz" && key != "taps"))
    throw std::invalid_argument("expected auto, none, cutoff_hz=X or taps=X, got '" + text + "'");
  c.mode = LowpassChoice::Mode::Given;
  (key == "taps" ? c.filter.taps : c.filter.cutoff_hz) = value;
  // The range checks of the model file's lowpass (kernels/simulate/lowpass.hpp); the cutoff
  // against each channel's Nyquist frequency when it is fitted.
  kernels::validate_lowpass(c.filter, std::numeric_limits<double>::infinity());
  return c;
}

io::FitRecord psd_fit_channel(const kernels::PsdResult& psd, const std::string& units,
                              const std::array<kernels::TermFit, kernels::kNumTerms>* allan_terms,
                              int threads) {
  // One cache per thread, as the Eq3Fit plan above: the regressors depend only on the segment
  // length and the rate, which the channels of a lot share.
  thread_local kernels::WelchTermCache welch_terms;
  kernels::PsdFitOptions options;
  options.threads = threads;
  const kernels::PsdFitResult f = kernels::psd_fit(psd, options, &welch_terms);
  io::FitRecord rec = fit_record(kernels::kPsdFitMethod, f);
  rec.f = f.f_hz;
  rec.psd_model = f.psd_model;
  if (!kernels::has_terms(f.status)) return rec;
  for (const Term t : kernels::units::all_terms())
    rec.terms.push_back(term_record(t, f[t], units));
  if (allan_terms) {
    const kernels::FitAgreement g = kernels::compare_fits(*allan_terms, f.terms);
    rec.z_vs_fit.assign(g.z.begin(), g.z.end());
    rec.max_abs_z = g.max_abs_z;
    rec.worst_term = g.worst_term >= 0
                         ? std::string(kernels::units::term_name(static_cast<Term>(g.worst_term)))
                         : "";
    rec.agree = g.agree ? 1 : 0;
  }
  return rec;
}

namespace {

// Columns are aligned by UTF-8 code points, not bytes ("±" is two bytes, one column).
std::size_t display_width(const std::string& s) {
  std::size_t w = 0;
  for (const unsigned char ch : s)
    w += (ch & 0xC0) != 0x80;
  return w;
}

// A read-out cell: value ± sigma in its datasheet form (ARW/VRW for N when there is one), the
// tau it was read at for B and K, '*' when the fit does not detect the term; '-' when the
// curve does not reach the read-out's tau.
// The term a read-out reads (IEEE Std 952 annex C): N at 1 s, B at the minimum, K at 3 s.
kernels::Term readout_term(std::string_view name) {
  if (name == "bias_instability") return kernels::Term::B;
  return name == "K_3s" ? kernels::Term::K : kernels::Term::N;
}

std::string format_readout(const io::ReadoutRecord& x, const std::string& units, bool si,
                           bool* undetected) {
  const bool alt = !si && !x.unit_datasheet_alt.empty();
  const kernels::Term t = readout_term(x.name);
  const double v = si    ? kernels::units::to_si(t, x.value, units).value
                   : alt ? x.value_datasheet_alt
                         : x.value_datasheet;
  const double sd = si    ? kernels::units::to_si(t, x.sigma, units).value
                    : alt ? x.sigma_datasheet_alt
                          : x.sigma_datasheet;
  if (!(x.tau_s > 0.0) || !std::isfinite(v)) return "-";
  char buf[96];
  if (x.name == "N_1s")
    std::snprintf(buf, sizeof buf, "%.3g ± %.2g", v, sd);
  else
    std::snprintf(buf, sizeof buf, "%.3g ± %.2g @ %.3g s", v, sd, x.tau_s);
  std::string cell = buf;
  if (!x.valid) {
    cell += " *";
    *undetected = true;
  }
  return cell;
}

// The sensor's filter and the taus the fit used (docs/fit-and-psd.md "The sensor's filter"):
// "auto 29.2 Hz" or "option 1.5 taps" or "none", and the first tau with the chi2/dof of the
// fit over every tau when the filter left taus out.
void add_filter_rows(const std::vector<const io::ChannelResult*>& chans,
                     std::vector<std::vector<std::string>>& rows) {
  std::vector<std::string> filter = {"lowpass", ""}, from = {"fitted from", "s"};
  bool cut = false;
  for (const auto* ch : chans) {
    const io::FitRecord& f = *ch->fit;
    char buf[96];
    if (std::isfinite(f.lowpass_cutoff_hz))
      std::snprintf(buf, sizeof buf, "%s %.3g Hz", f.lowpass.c_str(), f.lowpass_cutoff_hz);
    else if (std::isfinite(f.lowpass_taps))
      std::snprintf(buf, sizeof buf, "%s %.3g taps", f.lowpass.c_str(), f.lowpass_taps);
    else
      std::snprintf(buf, sizeof buf, "%s", f.lowpass.empty() ? "-" : f.lowpass.c_str());
    filter.emplace_back(buf);
    const bool left_out = !f.tau.empty() && f.first_tau_fitted > f.tau.front();
    cut = cut || left_out;
    if (left_out)
      std::snprintf(buf, sizeof buf, "%.3g (all: chi2/dof %.3g)", f.first_tau_fitted,
                    f.chi2_dof_all_taus);
    else
      std::snprintf(buf, sizeof buf, "%.3g", f.first_tau_fitted);
    from.emplace_back(buf);
  }
  rows.push_back(filter);
  if (cut) rows.push_back(from);
}

// The read-out rows under a group's coefficients (IEEE Std 952 annex C).
void add_readout_rows(const std::vector<const io::ChannelResult*>& chans,
                      std::vector<std::vector<std::string>>& rows, bool si, bool* undetected) {
  static constexpr std::pair<const char*, const char*> kRows[] = {
      {"N_1s", "N at 1 s"}, {"bias_instability", "B: min/0.664"}, {"K_3s", "K at 3 s"}};
  const auto& first = chans.front()->fit->readouts;
  for (const auto& kv : kRows) {
    // Plain variables, not a structured binding: clang 14 (the TSan build) cannot capture one.
    const std::string_view name = kv.first, label = kv.second;
    const auto it = std::find_if(first.begin(), first.end(),
                                 [&](const io::ReadoutRecord& x) { return x.name == name; });
    if (it == first.end()) continue;
    const std::string unit =
        si ? kernels::units::to_si(readout_term(name), 1.0, chans.front()->units).unit
        : it->unit_datasheet_alt.empty() ? it->unit_datasheet
                                         : it->unit_datasheet_alt;
    std::vector<std::string> row = {std::string(label), unit};
    for (const auto* ch : chans) {
      const auto& xs = ch->fit->readouts;
      const auto x = std::find_if(xs.begin(), xs.end(),
                                  [&](const io::ReadoutRecord& r) { return r.name == name; });
      row.push_back(x == xs.end() ? "-" : format_readout(*x, ch->units, si, undetected));
    }
    rows.push_back(row);
  }
}

// A modelled poor fit in the "fit" row: the model's verdict beside eq. (3)'s chi2/dof.
std::string model_cell(const io::FitRecord& f) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "model %s (gap %.3g, p95 %.3g; eq. (3) chi2/dof %.3g)",
                f.model_within_noise == 1 ? "within noise" : "NOT within noise", f.model_gap,
                f.model_gap_p95, f.chi2_dof);
  return buf;
}

// A term's cell in its datasheet form, or in SI (kernels::units::to_si) with `si`.
std::string format_term(const io::TermRecord& t, const std::string& units, bool si) {
  const auto term = kernels::parse_term(t.term).value_or(kernels::Term::N);
  const auto in = [&](double datasheet, double stored) {
    return si ? kernels::units::to_si(term, stored, units).value : datasheet;
  };
  char buf[64];
  if (t.detected)
    std::snprintf(buf, sizeof buf, "%.3g ± %.2g", in(t.value_datasheet, t.value),
                  in(t.sigma_datasheet, t.sigma));
  else
    std::snprintf(buf, sizeof buf, "< %.2g", in(t.upper_datasheet, t.upper));
  return buf;
}

std::string term_unit(const io::TermRecord& t, const std::string& units, bool si) {
  if (!si) return t.unit_datasheet;
  return kernels::units::to_si(kernels::parse_term(t.term).value_or(kernels::Term::N), 1.0, units)
      .unit;
}

}  // namespace

std::string aligned_rows(const std::vector<std::vector<std::string>>& rows) {
  std::vector<std::size_t> width;
  for (const auto& row : rows) {
    width.resize(std::max(width.size(), row.size()), 0);
    for (std::size_t c = 0; c < row.size(); ++c)
      width[c] = std::max(width[c], display_width(row[c]));
  }
  std::ostringstream out;
  for (const auto& row : rows) {
    out << "  ";
    for (std::size_t c = 0; c < row.size(); ++c)
      out << row[c] << std::string(width[c] - display_width(row[c]) + 2, ' ');
    out << "\n";
  }
  return out.str();
}

std::string fit_table(const io::RecordingResult& r, bool si) {
  // Channels with a fit, grouped by their datasheet units (gyros, accelerometers, ...) as in
  // the paper's Table.
  std::map<std::string, std::vector<const io::ChannelResult*>> groups;
  for (const auto& ch : r.channels) {
    if (!ch.fit || ch.fit->terms.empty()) continue;
    std::string key;
    for (const auto& t : ch.fit->terms)
      key += t.unit_datasheet + "|";
    groups[key].push_back(&ch);
  }
  if (groups.empty()) return "";
  std::ostringstream out;
  out << r.device_id << ": noise coefficients of eq. (3), value ± 1 sigma ('<': not detected, "
      << "95 % upper bound)" << (si ? ", in SI units" : "") << "\n";
  bool poor = false, undetected = false;
  // A data type nobody gave is said where the numbers are read (docs/formats.md).
  std::string defaulted;
  for (const auto& ch : r.channels)
    if (ch.data_type.ends_with("(default)")) {
      if (!defaulted.empty()) defaulted += ", ";
      defaulted += ch.path.substr(ch.path.find_last_of('/') + 1);
    }
  if (!defaulted.empty())
    out << "  data type rate (default) for " << defaulted
        << ": the input does not say; --data-type sets it\n";
  for (const auto& [family, chans] : groups) {
    std::vector<std::string> header = {"term", "unit"};
    for (const auto* ch : chans)
      header.push_back(ch->path.substr(ch->path.find_last_of('/') + 1));
    std::vector<std::vector<std::string>> rows = {header};
    for (std::size_t t = 0; t < chans.front()->fit->terms.size(); ++t) {
      std::vector<std::string> row = {
          chans.front()->fit->terms[t].term,
          term_unit(chans.front()->fit->terms[t], chans.front()->units, si)};
      for (const auto* ch : chans)
        row.push_back(format_term(ch->fit->terms[t], ch->units, si));
      rows.push_back(row);
    }
    std::vector<std::string> status = {"fit", ""};
    for (const auto* ch : chans) {
      const io::FitRecord& f = *ch->fit;
      status.push_back(f.model.empty() ? io::fit_status_text(f) : model_cell(f));
      poor = poor || (f.status == kernels::FitStatus::PoorFit && f.model_within_noise != 1);
    }
    rows.push_back(status);
    add_filter_rows(chans, rows);
    add_readout_rows(chans, rows, si, &undetected);
    out << aligned_rows(rows);
    for (const auto* ch : chans)
      if (!ch->fit->model.empty())
        out << "  " << ch->path.substr(ch->path.find_last_of('/') + 1) << ": terms of the model "
            << ch->fit->model << "\n";
  }
  if (undetected)
    out << "  read-outs (IEEE 952 annex C) marked * read a branch the fit does not detect: the "
           "curve may not have it\n";
  if (poor)
    out << "  poor fit: the five terms (and a model of eq. (3) plus effects, where one was made) "
           "do not explain the measured curve within its noise; "
           "`allanlot diagnose "
        << r.source_file << " --model MODEL.json` names what they miss\n";
  return out.str();
}

}  // namespace allanlot::pipeline
