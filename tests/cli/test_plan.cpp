// `allanlot plan`: the planned length is neither short nor padded. For a model with white,
// flicker and random-walk terms, --target B=10% at 95 % gives a length at which at least 85 % of
// independently simulated recordings fit B within 10 % of the truth, while at a third of that
// length fewer than 85 % do; --verify prints the same share; --json has its keys; bad targets
// are usage errors.
#include "kernels/plan/length.hpp"
#include "kernels/plan/record_fit.hpp"
#include "src/cli/plan.hpp"
#include "src/lot/model.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace allanlot {
namespace {

// 1 Hz keeps the records short (tens of thousands of samples); white noise to about 2 s, the
// flicker floor from there to about 100 s, random walk beyond.
constexpr const char* kModel = R"({
  "units": "deg/s",
  "sample_rate_hz": 1,
  "terms": {"N": 0.001, "B": 0.001, "K": 0.0001}
})";

std::string model_file() {
  const std::filesystem::path dir = ALLANLOT_TEST_TMP;
  std::filesystem::create_directories(dir);
  const auto path = dir / "plan_model.json";
  std::ofstream(path) << kModel;
  return path.string();
}

// The share of `replicas` simulated records of n samples whose fitted B is within 10 %.
double share_within(const kernels::ChannelSpec& spec, std::int64_t n, int replicas) {
  int good = 0;
  for (const auto& f : kernels::simulated_fits(spec, n, replicas, 7, 1))
    good += kernels::has_terms(f.status) &&
            std::abs(f[kernels::Term::B].value - spec.terms.B) <= 0.1 * spec.terms.B;
  return static_cast<double>(good) / replicas;
}

TEST(Plan, LengthIsNeitherShortNorPadded) {
  cli::PlanOptions opt;
  opt.model_path = model_file();
  opt.targets = {"B=10%"};
  opt.json = true;
  opt.threads = 1;
  std::ostringstream out, err;
  ASSERT_EQ(cli::run_plan(opt, out, err), 0) << err.str();
  const auto j = nlohmann::json::parse(out.str());
  const double duration = j.at("duration_s").get<double>();
  ASSERT_TRUE(j.at("per_target").contains("gyro_x:B"));
  const auto spec = model::to_spec(model::load_model(opt.model_path), 0);
  const auto n = static_cast<std::int64_t>(std::llround(duration * spec.rate_hz));
  constexpr int kReplicas = 200;
  const double at_plan = share_within(spec, n, kReplicas);
  const double at_third = share_within(spec, n / 3, kReplicas);
  std::cout << "plan: " << duration << " s; B within 10 %: " << at_plan << " at the plan, "
            << at_third << " at a third\n";
  EXPECT_GE(at_plan, 0.85);
  EXPECT_LT(at_third, 0.85);
}

TEST(Plan, VerifyPrintsTheShare) {
  cli::PlanOptions opt;
  opt.model_path = model_file();
  opt.targets = {"B=10%"};
  opt.verify = 20;
  opt.threads = 1;
  std::ostringstream out, err;
  ASSERT_EQ(cli::run_plan(opt, out, err), 0) << err.str();
  EXPECT_NE(out.str().find("verify: 20 simulated recordings"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("within target"), std::string::npos) << out.str();
}

TEST(Plan, PredictedSigmaFallsWithLength) {
  const auto spec = model::to_spec(model::parse_model(kModel, "model"), 0);
  kernels::Eq3Fit fitter;
  const double s1 = kernels::predicted_fit(spec, 4000, fitter)[kernels::Term::B].sigma;
  const double s2 = kernels::predicted_fit(spec, 16000, fitter)[kernels::Term::B].sigma;
  EXPECT_LT(s2, 0.75 * s1);
}

TEST(Plan, BadTargetIsAUsageError) {
  cli::PlanOptions opt;
  opt.model_path = model_file();
  opt.targets = {"X=10%"};
  std::ostringstream out, err;
  EXPECT_EQ(cli::run_plan(opt, out, err), 2);
  EXPECT_NE(err.str().find("--target"), std::string::npos) << err.str();
  opt.targets = {"R=10%"};  // the model has no ramp
  EXPECT_EQ(cli::run_plan(opt, out, err), 2);
  EXPECT_NE(err.str().find("nothing to plan"), std::string::npos) << err.str();
}

}  // namespace
}  // namespace allanlot
