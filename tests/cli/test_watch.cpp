// `allanlot watch` and its sequential rule. Over 40 simulated units near a B limit, judged at
// looks with the alpha-spending quantiles (kernels/plan/sequential.hpp) and the fit watch
// makes (workflow::look_fit),
// wrong decisions stay within the stated rate (with its binomial margin) and the mean
// recording time is at least 30 % shorter than the fixed length `plan --spec` gives for the
// same limit. The command itself: a unit far inside the limit passes, one far outside fails,
// both on a recording replayed faster than real time, and a CSV being appended is followed.
#include "kernels/plan/length.hpp"
#include "kernels/plan/record_fit.hpp"
#include "kernels/plan/sequential.hpp"
#include "src/cli/plan.hpp"
#include "src/lot/model.hpp"
#include "src/lot/spec.hpp"
#include "src/workflow/watch.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

namespace allanlot {
namespace {

namespace fs = std::filesystem;

constexpr const char* kModel = R"({
  "units": "deg/s",
  "sample_rate_hz": 1,
  "terms": {"N": 0.001, "B": 0.001, "K": 0.0001}
})";
constexpr double kLimit = 0.001;  // deg/s: the model's B sits on it
constexpr const char* kSpec =
    R"({"confidence": 0.95, "channels": {"gyro_*": {"B": {"max": 0.001, "unit": "deg/s"}}}})";

fs::path tmp_dir() {
  const fs::path dir = fs::path(ALLANLOT_TEST_TMP) / "watch";
  fs::create_directories(dir);
  return dir;
}

std::string write(const std::string& name, const std::string& text) {
  const fs::path p = tmp_dir() / name;
  std::ofstream(p) << text;
  return p.string();
}

double fixed_length_s() {
  cli::PlanOptions opt;
  opt.model_path = write("model.json", kModel);
  opt.spec_path = write("spec.json", kSpec);
  opt.json = true;
  opt.threads = 1;
  std::ostringstream out, err;
  EXPECT_EQ(cli::run_plan(opt, out, err), 0) << err.str();
  return nlohmann::json::parse(out.str()).at("duration_s").get<double>();
}

TEST(WatchRule, FewWrongDecisionsAndShorterThanThePlan) {
  const double fixed = fixed_length_s();
  const kernels::ChannelSpec model = model::to_spec(model::parse_model(kModel, "model"), 0);
  constexpr int kUnits = 40, kLooks = 8;
  const auto n_fix = static_cast<std::size_t>(std::llround(fixed * model.rate_hz));
  kernels::SimulationPlan sim(n_fix);
  // Units from 40 % below to 40 % above the limit, none on it: near it, on both sides.
  std::vector<double> truth(kUnits);
  std::vector<std::vector<double>> y(kUnits, std::vector<double>(n_fix));
  for (int u = 0; u < kUnits; ++u) {
    kernels::ChannelSpec spec = model;
    spec.terms.B = truth[u] = kLimit * (1.0 - 0.4 + 0.8 * (u + 0.5) / kUnits);
    sim.run(spec, 11, static_cast<std::uint64_t>(u), y[u], 1);
  }
  // Look by look, every unit still recording (so that the units' fits of one look share
  // their curve shape's covariance model), with the quantile watch uses at that look.
  std::vector<double> stop(kUnits, fixed);
  std::vector<bool> open(kUnits, true);
  int wrong = 0, decided = 0;
  for (int j = 1; j <= kLooks; ++j) {
    const double t = fixed * j / kLooks;
    const double k = kernels::look_quantile(0.05, fixed * (j - 1) / kLooks, t, fixed);
    const auto n = static_cast<std::size_t>(std::llround(t * model.rate_hz));
    for (int u = 0; u < kUnits; ++u) {
      if (!open[u]) continue;
      const workflow::LookFit f =
          workflow::look_fit(std::span<const double>(y[u].data(), n), model.rate_hz, "deg/s", 1);
      if (f.status != kernels::FitStatus::Ok) continue;
      const auto& b = f.terms[static_cast<std::size_t>(kernels::Term::B)];
      const spec::Estimate e{b.value, b.sigma, std::nan(""), b.detected};
      const spec::Outcome o = spec::decide(e, std::nullopt, kLimit, k);
      if (o == spec::Outcome::Undecided) continue;
      ++decided;
      wrong += (o == spec::Outcome::Pass) != (truth[u] <= kLimit);
      stop[u] = t;
      open[u] = false;
    }
  }
  double mean = 0.0;
  std::string undecided;
  for (int u = 0; u < kUnits; ++u) {
    mean += stop[u] / kUnits;
    if (open[u]) undecided += " " + std::to_string(truth[u] / kLimit - 1.0);
  }
  std::cout << "fixed length " << fixed << " s; " << decided << " of " << kUnits << " decided, "
            << wrong << " wrong; mean recording " << mean << " s (" << mean / fixed
            << " of the fixed); undecided at B / limit - 1 =" << undecided << "\n";
  // Binomial(40, 0.05): P(X <= 5) = 0.986; more than 5 wrong would contradict the rate.
  EXPECT_LE(wrong, 5);
  EXPECT_LE(mean, 0.7 * fixed);
}

TEST(WatchRule, QuantilesSpendTheRateOverTheLooks) {
  // Eight equal looks at 5 %: each spends 0.625 %, z = 2.4977.
  EXPECT_NEAR(kernels::look_quantile(0.05, 0, 1, 8), 2.4977, 1e-3);
  EXPECT_NEAR(kernels::look_quantile(0.05, 7, 8, 8), 2.4977, 1e-3);
  EXPECT_TRUE(std::isinf(kernels::look_quantile(0.05, 8, 9, 8)));
  EXPECT_NEAR(kernels::normal_quantile(0.975), 1.959964, 1e-5);
}

int run_cli(const std::string& args, std::string* output) {
  const std::string log = (tmp_dir() / "cli.log").string();
  const int rc =
      std::system((std::string(ALLANLOT_BINARY) + " " + args + " > " + log + " 2>&1").c_str());
  std::ifstream in(log);
  std::stringstream ss;
  ss << in.rdbuf();
  *output = ss.str();
  return WEXITSTATUS(rc);
}

std::string simulated_unit(const std::string& name, double b, double seconds) {
  const std::string model = write(name + ".json", R"({"units": "deg/s", "sample_rate_hz": 1,
    "terms": {"N": 0.001, "B": )" + std::to_string(b) +
                                                      R"(, "K": 0.0001}})");
  const std::string h5 = (tmp_dir() / (name + ".h5")).string();
  std::string log;
  EXPECT_EQ(run_cli("simulate -q --model " + model + " --duration " + std::to_string(seconds) +
                        " -o " + h5,
                    &log),
            0)
      << log;
  return h5;
}

TEST(WatchCommand, ReplayPassesAUnitFarInsideAndFailsOneFarOutside) {
  const std::string spec = write("spec.json", kSpec);
  std::string log;
  const std::string good = simulated_unit("good", 0.0004, 20000);
  EXPECT_EQ(run_cli("watch " + good + " --spec " + spec +
                        " --replay --interval 2500 --max-duration 20000 --threads 1",
                    &log),
            0)
      << log;
  EXPECT_NE(log.find("unit passes"), std::string::npos) << log;
  const std::string bad = simulated_unit("bad", 0.0025, 20000);
  EXPECT_EQ(run_cli("watch " + bad + " --spec " + spec +
                        " --replay --interval 2500 --max-duration 20000 --threads 1",
                    &log),
            1)
      << log;
  EXPECT_NE(log.find("B fail"), std::string::npos) << log;
}

TEST(WatchCommand, FollowsAGrowingCsv) {
  const std::string spec = write("spec.json", kSpec);
  const auto model = model::to_spec(model::parse_model(kModel, "m"), 0);
  kernels::ChannelSpec s = model;
  s.terms.B = 0.0004;
  std::vector<double> y(12000);
  kernels::simulate_channel(s, 3, 0, y, 1);
  const fs::path csv = tmp_dir() / "growing.csv";
  std::ofstream(csv) << "gyro_x\n";
  // A writer appending 3000 samples (50 min of data) every 50 ms, the last line of each batch
  // left partial until the next.
  std::thread writer([&] {
    std::ofstream out(csv, std::ios::app);
    for (std::size_t i = 0; i < y.size(); ++i) {
      out << y[i] << "\n";
      if ((i + 1) % 3000 == 0) {
        out.flush();
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
    }
  });
  std::string log;
  const int rc = run_cli("watch " + csv.string() + " --spec " + spec +
                             " --sample-rate 1 --units deg/s --interval 3000 --max-duration 12000 "
                             "--poll 0.02 --idle-timeout 20 --threads 1",
                         &log);
  writer.join();
  EXPECT_EQ(rc, 0) << log;
  EXPECT_NE(log.find("look 1 at 3000 s"), std::string::npos) << log;
}

}  // namespace
}  // namespace allanlot
