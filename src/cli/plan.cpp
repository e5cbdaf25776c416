#include "src/cli/plan.hpp"

#include "src/lot/spec.hpp"
#include "src/workflow/status.hpp"

#include <CLI/CLI.hpp>

#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

namespace allanlot::cli {
namespace {

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

void print_text(const workflow::Plan& p, const PlanOptions& opt, std::ostream& out) {
  const auto& es = p.lengths;
  const auto& bind = es[p.binding];
  const double confidence = p.confidence;
  out << "confidence " << confidence << "\n";
  for (const workflow::PlannedLength& e : es) {
    out << "  " << std::left << std::setw(24) << e.key << std::setw(24) << e.label << std::right
        << (e.plan.reached ? "" : "> ") << duration_text(e.plan.duration_s) << "  (sigma "
        << workflow::percent_text(e.plan.relative_sigma) << " of the value; decided by tau "
        << e.plan.tau_lo_s << " .. " << e.plan.tau_hi_s << " s)\n";
  }
  out << "record " << duration_text(bind.plan.duration_s) << " (" << bind.plan.duration_s
      << " s), bound by " << bind.key << "\n";
  if (opt.verify <= 0) return;
  out << "verify: " << opt.verify << " simulated recordings of " << bind.plan.duration_s << " s\n";
  for (const workflow::PlannedLength& e : es)
    out << "  " << std::left << std::setw(24) << e.key << std::right
        << workflow::percent_text(e.share)
        << (e.max || e.min ? " decided pass\n" : " within target\n");
}

}  // namespace

int run_plan(const PlanOptions& opt, std::ostream& out, std::ostream& err) {
  workflow::Plan p;
  try {
    p = workflow::plan_recording(opt);
  } catch (const std::exception&) {
    return workflow::print_usage_error(std::current_exception(), err);
  }
  if (opt.json)
    out << workflow::plan_json(p).dump(2) << "\n";
  else
    print_text(p, opt, out);
  for (const workflow::PlannedLength& e : p.lengths)
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
