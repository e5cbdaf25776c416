#include "src/workflow/plan.hpp"

#include "kernels/common/parallel.hpp"
#include "kernels/model/units.hpp"
#include "kernels/plan/length.hpp"
#include "kernels/plan/record_fit.hpp"
#include "kernels/plan/sequential.hpp"
#include "src/lot/model.hpp"
#include "src/lot/spec.hpp"
#include "src/workflow/status.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>

namespace allanlot::workflow {
namespace {

using kernels::Term;
namespace units = kernels::units;

using Entry = PlannedLength;

// "B=10%" or "B=0.1": a term and a relative precision in (0, 1).
std::pair<Term, double> parse_target(const std::string& text) {
  const auto eq = text.find('=');
  const auto term = kernels::parse_term(text.substr(0, eq));
  std::string v = eq == std::string::npos ? "" : text.substr(eq + 1);
  const bool percent = !v.empty() && v.back() == '%';
  if (percent) v.pop_back();
  char* end = nullptr;
  double x = std::strtod(v.c_str(), &end);
  if (percent) x /= 100.0;
  if (!term || v.empty() || *end != '\0' || !(x > 0.0 && x < 1.0))
    throw UsageError("--target: expected TERM=PRECISION with TERM one of R, K, B, N, Q and 0 < "
                     "PRECISION < 1 (e.g. B=10%), got '" +
                     text + "'");
  return {*term, x};
}

std::vector<Entry> target_entries(const model::UnitModel& m, const PlanOptions& opt) {
  std::vector<Entry> out;
  const double k = kernels::normal_quantile(0.5 + 0.5 * opt.confidence);
  for (std::size_t c = 0; c < m.channels.size(); ++c)
    for (const std::string& text : opt.targets) {
      const auto [term, rel] = parse_target(text);
      Entry e;
      e.spec = model::to_spec(m, c);
      e.value = kernels::coefficient(e.spec.terms, term);
      if (!(e.value > 0.0)) continue;  // a channel without the term has nothing to measure
      e.key = m.channels[c].name + ":" + std::string(kernels::term_name(term));
      e.label = std::string(kernels::term_name(term)) + " ±" + percent_text(rel);
      e.target = {term, rel, k};
      out.push_back(std::move(e));
    }
  return out;
}

// Each limit of each channel the spec covers: the unit placed `margin` inside it.
std::vector<Entry> spec_entries(const model::UnitModel& m, const spec::Spec& s, double margin) {
  std::vector<Entry> out;
  for (std::size_t c = 0; c < m.channels.size(); ++c) {
    const spec::Rule* rule = spec::find_rule(s, m.channels[c].name);
    if (!rule) continue;
    for (const spec::TermLimit& l : rule->limits)
      for (const bool is_max : {true, false}) {
        const std::optional<double>& lim = is_max ? l.max : l.min;
        if (!lim || !(*lim > 0.0)) continue;  // a min of 0 is always met
        const std::string& units = m.channels[c].units;
        const double limit =
            spec::convert(l.term, *lim, l.unit, units::channel_unit(l.term, units), units);
        Entry e;
        e.spec = model::to_spec(m, c);
        e.target = kernels::limit_target(l.term, limit, is_max, margin, s.confidence, &e.value);
        kernels::coefficient(e.spec.terms, l.term) = e.value;
        (is_max ? e.max : e.min) = limit;
        e.k = s.k;
        const std::string t(kernels::term_name(l.term));
        e.key = m.channels[c].name + ":" + t + (is_max ? "<=max" : ">=min");
        std::ostringstream label;
        label << t << (is_max ? " <= " : " >= ") << *lim << " " << l.unit;
        e.label = label.str();
        out.push_back(std::move(e));
      }
  }
  return out;
}

// The share of `replicas` simulated recordings of n samples that meet each entry's target: the
// coefficient within the relative precision, or the limit decided pass.
void verify(std::vector<Entry>& entries, std::int64_t n, const PlanOptions& opt, int threads) {
  for (Entry& e : entries) {
    const auto fits = kernels::simulated_fits(e.spec, n, opt.verify, opt.seed, threads);
    int good = 0;
    for (const kernels::FitResult& f : fits) {
      if (!kernels::has_terms(f.status)) continue;
      const kernels::TermFit& t = f[e.target.term];
      if (e.max || e.min) {
        const spec::Estimate est{t.value, t.sigma, t.upper, t.detected};
        good += spec::decide(est, e.min, e.max, e.k) == spec::Outcome::Pass;
      } else {
        good += std::abs(t.value - e.value) <= e.target.relative * e.value;
      }
    }
    e.share = static_cast<double>(good) / opt.verify;
  }
}

}  // namespace

std::string percent_text(double x) {
  std::ostringstream s;
  s << std::setprecision(3) << 100.0 * x << "%";
  return s.str();
}

Plan plan_recording(const PlanOptions& opt) {
  Plan out;
  out.confidence = opt.confidence;
  const model::UnitModel m = opt.model_path.empty()
                                 ? model::default_demo_model()
                                 : model::load_model(opt.model_path, opt.channel);
  if (!opt.spec_path.empty()) {
    const spec::Spec s = spec::load_spec(opt.spec_path);
    out.confidence = opt.confidence_given ? opt.confidence : s.confidence;
    spec::Spec used = s;
    used.confidence = out.confidence;
    used.k = spec::two_sided_normal_quantile(out.confidence);
    out.lengths = spec_entries(m, used, opt.margin);
  } else {
    out.lengths = target_entries(m, opt);
  }
  if (out.lengths.empty())
    throw UsageError(std::string("nothing to plan: no channel of the model has a targeted term") +
                     (opt.spec_path.empty() ? "" : " or a limit of the spec"));
  const int threads = kernels::resolve_threads(opt.threads);
  kernels::Eq3Fit fitter;
  fitter.set_threads(threads);
  for (std::size_t i = 0; i < out.lengths.size(); ++i) {
    Entry& e = out.lengths[i];
    const auto max_n = static_cast<std::int64_t>(std::llround(opt.max_duration_s * e.spec.rate_hz));
    e.plan = kernels::plan_length(e.spec, e.target, max_n, fitter);
    if (i == 0 || e.plan.duration_s > out.lengths[out.binding].plan.duration_s) out.binding = i;
  }
  if (opt.verify > 0) verify(out.lengths, out.lengths[out.binding].plan.n_samples, opt, threads);
  return out;
}

nlohmann::ordered_json plan_json(const Plan& plan) {
  const Entry& bind = plan.lengths.at(plan.binding);
  nlohmann::ordered_json j;
  j["duration_s"] = bind.plan.duration_s;
  j["binding"] = bind.key;
  j["confidence"] = plan.confidence;
  auto& per = j["per_target"] = nlohmann::ordered_json::object();
  for (const Entry& e : plan.lengths) {
    auto& t = per[e.key];
    t["duration_s"] = e.plan.duration_s;
    t["reached"] = e.plan.reached;
    t["relative"] = e.target.relative;
    t["relative_sigma"] = e.plan.relative_sigma;
    t["tau_s"] = {e.plan.tau_lo_s, e.plan.tau_hi_s};
    if (!std::isnan(e.share)) t["verified_share"] = e.share;
  }
  return j;
}

}  // namespace allanlot::workflow
