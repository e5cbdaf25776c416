// The step effect's process (kernels/simulate/effect_process.hpp): a bias jump's samples, and its
// share of the Allan variance, which depends on the record's length (steps_avar.cpp).
#pragma once

#include "kernels/model/effects/step.hpp"
#include "kernels/simulate/effect_process.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace allanlot::kernels {

template <>
struct EffectProcess<Step> : DeterministicProcess {};

/// Adds `scale` times each step to the samples y (sample i is sample first + i of the record,
/// at rate_hz): sample k averages the rate over [k, k + 1] sample intervals, so a jump at
/// s = time_s rate_hz samples counts for clamp(k + 1 - s, 0, 1) of itself. With scale = -1 it
/// removes the steps exactly (diagnose). The one owner of a step's samples.
void add_steps(std::span<double> y, std::span<const Step> steps, double rate_hz, double scale = 1.0,
               std::size_t first = 0);

/// The overlapping Allan variance at averaging factor m over a record of n_samples (>= 2 m)
/// samples at rate_hz that a step alone gives, exactly as the estimator averages it. With the
/// jump at s = time_s rate_hz samples, the phase is size max(0, t - s) and each second
/// difference (x_{k+2m} - 2 x_{k+m} + x_k) / m is a triangle in u = s - k: size u / m rising
/// over 0 < u <= m, size (2m - u) / m falling to 2m. The variance is the sum of their squares
/// over the windows k = 0 .. n - 2m the record holds, over 2 (n - 2m + 1) (NIST SP1065 eq.
/// (11)); the sums of squares over each run of k are closed forms. Far from the record's ends,
/// size^2 (2 m^2 + 1) / (6 m (n - 2m + 1)), like a random walk's m / 3 growth but set by the
/// record's length: its witness is in the time domain (docs/diagnose.md).
double step_avar_sampled(const Step& step, double rate_hz, std::int64_t m, std::int64_t n_samples);

/// `avar` plus what `steps` add over the record (kernels/simulate/steps_avar.cpp):
/// step_avar_sampled of each, added in order, when no two are within 2 m samples of each other;
/// otherwise their joint share, exactly (their second differences added before squaring: two
/// opposite jumps close together, a bias excursion, add far less than their two shares). A
/// model's Allan variance with its jumps.
double plus_steps_avar(double avar, std::span<const Step> steps, double rate_hz, std::int64_t m,
                       std::int64_t n_samples);

/// The process hooks: add_steps of one step; no share of the continuous model_avar (a single
/// jump's share falls as 1 / (record length), zero over the unbounded record), plus_steps_avar
/// over a finite one; the filter's smoothing of the jump left out (as the ramp's); no density.
void add_effect_block(const Step& st, double rate_hz, std::size_t first, std::span<double> y);
double effect_avar(const Step& st, double rate_hz, double tau);
double plus_record_avar(double avar, std::span<const Step> steps, double rate_hz, std::int64_t m,
                        std::int64_t n_samples);
double filter_change_avar(const Step& st, const FilterAt& at);
void add_effect_psd(const Step& st, double rate_hz, std::span<const double> f_hz,
                    std::vector<double>& out);

}  // namespace allanlot::kernels
