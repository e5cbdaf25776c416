// One diagnosis in progress (diagnose.cpp: the rounds and the driver; conclude.cpp: the final
// refit, the pruning, the test of the given coefficients and the verdict); not part of the
// interface (diagnose.hpp).
#pragma once

#include "kernels/diagnose/internal.hpp"

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace allanlot::kernels::diagnose_detail {

// What a round's choice among its candidates reads (Search::choose): the model as it stands with
// its coefficients fixed and free, the witnesses, and the chi-squares the candidates were judged
// against.
struct RoundView {
  const std::vector<Component>& fixed_now;
  const std::vector<Component>& free_now;
  const Witnesses& seen;
  const TrendWitness& trend;
  double chi2_ref = 0.0, chi2_refit = 0.0;
  int n_free = 0;
};

// The measurement, the criterion and the model as it grows.
struct Search {
  const DiagnoseOptions& opt;
  const ChannelSpec& spec;
  Diagnosis& d;
  Curve cv;
  Bases bases;
  Criterion crit;
  double alpha_tau = 0.0;
  std::optional<PsdResult> periodogram;
  std::vector<double> line_medians;  // line_backgrounds(*periodogram)
  double t_record = 0.0;
  std::vector<Component> given, current;
  std::vector<std::size_t> added_idx;
  bool refit_taken = false;
  std::span<const double> rate;  // the record as measured, for the step's witness
  int threads = 1;
  std::vector<Effect> removed;  // the effects the pruning took away, not named again
  bool witnessed_only = false;  // the verdict's round (verdict_round): witnessed effects alone
  std::string last_criteria;    // the criteria of a verdict's round that named nothing
  Eigen::MatrixXd tau_corr;     // tau_correlation(cv): the correlation of the curve's estimates
  // The change-point test's result for the record with the steps named so far (find_step, a
  // scan of every window at every scale): rounds that name no step ask it again unchanged.
  std::optional<std::pair<std::vector<Step>, StepWitness>> last_jump;

  StepWitness jump_witness(const std::vector<Step>& steps);

  SpectralLine focused_line(const Fit& ref, const std::vector<double>& known_f,
                            const std::vector<double>& known_wide,
                            const SpectralLine& global) const;
  std::vector<double> record_without(const std::vector<Step>& steps) const;
  Curve curve_without(const std::vector<Step>& steps) const;
  std::optional<Curve> curve_without_jump(const StepWitness& jump) const;
  CandidateFit random_walk_without_line(const std::vector<Component>& fixed_now,
                                        const std::vector<Component>& free_now) const;
  std::size_t ramp_or_random_walk(std::vector<CandidateFit>& cands, std::size_t best,
                                  const std::vector<Component>& fixed_now,
                                  const std::vector<Component>& free_now, double chi2_ref,
                                  const TrendWitness& trend, std::string& note) const;
  double witnessed_tolerance() const;
  TrendWitness trend_under(const ChannelSpec& model) const;
  std::size_t witnessed_ramp(std::vector<CandidateFit>& cands,
                             const std::vector<Component>& fixed_now, double chi2_ref,
                             const TrendWitness& tr, double tolerance) const;
  std::size_t not_vetoed(std::vector<CandidateFit>& cands, const std::vector<Component>& fixed_now,
                         double chi2_ref, const TrendWitness& trend, std::string& note) const;

  std::size_t lookalike_step(std::vector<CandidateFit>& cands, std::size_t best,
                             const std::vector<Component>& fixed_now,
                             const std::vector<Component>& free_now, const Witnesses& seen,
                             std::optional<Curve>& without_jump, double chi2_ref, double chi2_refit,
                             int n_free, std::string& note) const;
  std::size_t choose(std::vector<CandidateFit>& cands, const RoundView& r,
                     std::optional<Curve>& without_jump, std::string& note) const;
  SpectralLine line_witness(const Fit& ref) const;
  CandidateFit candidate(Effect e, const std::vector<Component>& fixed_now,
                         const std::vector<Component>& free_now, const Witnesses& seen,
                         double chi2_ref, double chi2_refit, int n_free, int charged = 0) const;
  std::vector<CandidateFit> candidates(const std::vector<Component>& fixed_now,
                                       const std::vector<Component>& free_now,
                                       const Witnesses& seen, double chi2_ref, double chi2_refit,
                                       int n_free) const;
  void keep_witnessed(std::vector<CandidateFit>& cands, const TrendWitness& trend) const;
  bool round(int& iter);
  void run_rounds();
  Fit refit_final();
  Fit search_added(Fit base) const;
  Fit refit_given_fixed(const std::vector<Component>& comps) const;
  std::vector<Component> given_fixed(std::vector<Component> comps) const;
  Fit fit_given_fixed(std::vector<Component> comps, const Curve& on) const;
  double revision_criterion(const Fit& base, const Fit& fixed, int n_given) const;
  bool given_wrong(const Fit& base, const Fit& fixed);
  bool prune(Fit& base, const Fit& fixed_fit, bool free_given);
  bool settle(Fit& base, Fit& fixed_fit);
  void finish();
  void conclude(Fit& base, Fit& fixed_fit);
  void judge();
  void verdict_round();
};

}  // namespace allanlot::kernels::diagnose_detail
