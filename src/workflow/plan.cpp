#include "src/cli/plan.hpp"

#include "kernels/common/parallel.hpp"
#include "kernels/model/units.hpp"
#include "kernels/plan/length.hpp"
#include "kernels/plan/record_fit.hpp"
#include "kernels/plan/sequential.hpp"
#include "src/lot/model.hpp"
#include "src/lot/spec.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <iomanip>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace allanlot::cli {
namespace {

using kernels::Term;
namespace units = kernels::units;

// One length to plan: a term of a channel to measure, or one of its limits to decide.
struct Entry {
  std::string key;    // "gyro_x:B", "gyro_x:B<=max"
  std::string label;  // what the table says of it
  kernels::ChannelSpec spec;
  kernels::LengthTarget target;
  double value = 0;                // the coefficient simulated, channel units
  std::optional<double> min, max;  // with --spec: the limits, channel units
  double k = 0;                    // with --spec: the spec's interval quantile
  kernels::LengthPlan plan;
  double share = std::numeric_limits<double>::quiet_NaN();  // --verify
};

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
    throw CLI::ValidationError("--target", "expected TERM=PRECISION with TERM one of R, K, B, N, "
                                           "Q and 0 < PRECISION < 1 (e.g. B=10%), got '" +
                                               text + "'");
  return {*term, x};
}

std::string percent(double x) {
  std::ostringstream s;
  s << std::setprecision(3) << 100.0 * x << "%";
  return s.str();
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
      e.label = std::string(kernels::term_name(term)) + " ±" + percent(rel);
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

std::string duration_text(double s) {
  std::ostringstream o;
  o << std::setprecision(3);
  if (s >= 7200.0)
    o << s / 3600.0 << " h";
  else if (s >= 120.0)
    o << s / 60.0 << " min";
  else
    o << s << " s";
  return o.str();
}

void print_text(const std::vector<Entry>& es, const Entry& bind, const PlanOptions& opt,
                double confidence, std::ostream& out) {
  out << "confidence " << confidence << "\n";
  for (const Entry& e : es) {
    out << "  " << std::left << std::setw(24) << e.key << std::setw(24) << e.label << std::right
        << (e.plan.reached ? "" : "> ") << duration_text(e.plan.duration_s) << "  (sigma "
        << percent(e.plan.relative_sigma) << " of the value; decided by tau " << e.plan.tau_lo_s
        << " .. " << e.plan.tau_hi_s << " s)\n";
  }
  out << "record " << duration_text(bind.plan.duration_s) << " (" << bind.plan.duration_s
      << " s), bound by " << bind.key << "\n";
  if (opt.verify <= 0) return;
  out << "verify: " << opt.verify << " simulated recordings of " << bind.plan.duration_s << " s\n";
  for (const Entry& e : es)
    out << "  " << std::left << std::setw(24) << e.key << std::right << percent(e.share)
        << (e.max || e.min ? " decided pass\n" : " within target\n");
}

void print_json(const std::vector<Entry>& es, const Entry& bind, double confidence,
                std::ostream& out) {
  nlohmann::ordered_json j;
  j["duration_s"] = bind.plan.duration_s;
  j["binding"] = bind.key;
  j["confidence"] = confidence;
  auto& per = j["per_target"] = nlohmann::ordered_json::object();
  for (const Entry& e : es) {
    auto& t = per[e.key];
    t["duration_s"] = e.plan.duration_s;
    t["reached"] = e.plan.reached;
    t["relative"] = e.target.relative;
    t["relative_sigma"] = e.plan.relative_sigma;
    t["tau_s"] = {e.plan.tau_lo_s, e.plan.tau_hi_s};
    if (!std::isnan(e.share)) t["verified_share"] = e.share;
  }
  out << j.dump(2) << "\n";
}

}  // namespace

int run_plan(const PlanOptions& opt, std::ostream& out, std::ostream& err) {
  std::vector<Entry> entries;
  double confidence = opt.confidence;
  model::UnitModel m;
  try {
    m = opt.model_path.empty() ? model::default_demo_model()
                               : model::load_model(opt.model_path, opt.channel);
    if (!opt.spec_path.empty()) {
      const spec::Spec s = spec::load_spec(opt.spec_path);
      confidence = opt.confidence_given ? opt.confidence : s.confidence;
      spec::Spec used = s;
      used.confidence = confidence;
      used.k = spec::two_sided_normal_quantile(confidence);
      entries = spec_entries(m, used, opt.margin);
    } else {
      entries = target_entries(m, opt);
    }
  } catch (const spec::Error& e) {
    for (const std::string& msg : e.messages())
      err << "allanlot: error: " << msg << "\n";
    return kExitUsage;
  } catch (const std::exception& e) {
    err << "allanlot: error: " << e.what() << "\n";
    return kExitUsage;
  }
  if (entries.empty()) {
    err << "allanlot: error: nothing to plan: no channel of the model has a targeted term"
        << (opt.spec_path.empty() ? "" : " or a limit of the spec") << "\n";
    return kExitUsage;
  }
  const int threads = kernels::resolve_threads(opt.threads);
  kernels::Eq3Fit fitter;
  fitter.set_threads(threads);
  const Entry* bind = nullptr;
  try {
    for (Entry& e : entries) {
      const auto max_n =
          static_cast<std::int64_t>(std::llround(opt.max_duration_s * e.spec.rate_hz));
      e.plan = kernels::plan_length(e.spec, e.target, max_n, fitter);
      if (!bind || e.plan.duration_s > bind->plan.duration_s) bind = &e;
    }
    if (opt.verify > 0) verify(entries, bind->plan.n_samples, opt, threads);
  } catch (const std::exception& e) {
    err << "allanlot: error: " << e.what() << "\n";
    return kExitUsage;
  }
  if (opt.json)
    print_json(entries, *bind, confidence, out);
  else
    print_text(entries, *bind, opt, confidence, out);
  for (const Entry& e : entries)
    if (!e.plan.reached) {
      err << "allanlot: " << e.key << ": not reached within --max-duration " << opt.max_duration_s
          << " s\n";
      return kExitSomeFailed;
    }
  return kExitOk;
}

Command add_plan_command(CLI::App& app) {
  auto opt = std::make_shared<PlanOptions>();
  auto* sub = app.add_subcommand("plan", "How long to record: the length that measures the "
                                         "targets (or decides the spec) at a confidence");
  sub->add_option("--model", opt->model_path, "Model file (JSON, see docs/formats.md)");
  sub->add_option("--channel", opt->channel, "Dataset name of a single-channel model")
      ->capture_default_str();
  sub->add_option("--target", opt->targets, "TERM=PRECISION,... e.g. B=10%,N=2%")->delimiter(',');
  sub->add_option("--spec", opt->spec_path, "Spec file: the length that decides its limits");
  sub->add_option("--margin", opt->margin,
                  "With --spec: the unit's distance inside each limit (fraction)")
      ->check(CLI::Range(1e-6, 0.999))
      ->capture_default_str();
  sub->add_option("--confidence", opt->confidence, "Confidence of the intervals")
      ->check(CLI::Range(1e-6, 1.0 - 1e-9))
      ->capture_default_str();
  sub->add_option("--verify", opt->verify, "Simulate R recordings of the length and fit them")
      ->check(CLI::Range(1, 100000));
  sub->add_option("--seed", opt->seed, "Random seed of --verify")->check(seed_number());
  sub->add_option("--max-duration", opt->max_duration_s, "Longest record searched, seconds")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  sub->add_flag("--json", opt->json, "Print JSON {\"duration_s\": ..., \"per_target\": {...}}");
  sub->add_option("--threads", opt->threads, "Threads (default: OMP_NUM_THREADS, else all cores)")
      ->check(CLI::Range(0, kMaxThreads));
  return {sub, [opt, sub](const std::string&) {
            opt->confidence_given = sub->count("--confidence") > 0;
            if (opt->targets.empty() == opt->spec_path.empty())
              throw CLI::ValidationError("plan", "give either --target or --spec");
            return run_plan(*opt, std::cout, std::cerr);
          }};
}

}  // namespace allanlot::cli
