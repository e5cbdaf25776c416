// Deciding while recording: the quantile of each look of a sequential test, so that the chance
// of a wrong decision over all looks stays at the stated rate.
//
// A recording watched at looks t_1 < t_2 < ... <= T (T the longest it may run) is judged at
// each look from the fit of what it holds so far: a limit is decided as soon as the interval
// value -+ k_j sigma lies wholly on one side of it (src/lot/spec.hpp decide). Using the fixed
// quantile at every look would let the chance of a wrong decision grow with the number of
// looks (each look is another chance for the estimate to stray across the limit). The rule
// here is alpha spending (Lan & DeMets, "Discrete sequential boundaries for clinical trials",
// Biometrika 70 (1983) 659-663) with the linear spending function alpha(t) = alpha min(t/T, 1),
// the Pocock-like choice that spends evenly over the recording: look j may err with
// probability a_j = alpha(t_j) - alpha(t_{j-1}), and its quantile is k_j = z_{1 - a_j}, the
// one-sided normal quantile (a wrong decision is the interval missing the true value on the
// side of the limit: passing a unit whose coefficient is above a max needs value + k sigma <=
// max < truth). By Boole's inequality the chance of any wrong decision over all looks is at
// most sum_j a_j = alpha, whatever the dependence between the looks: their fits share the data
// recorded so far, in a way (changing tau grid, reweighted fit) that the usual Brownian-motion
// boundaries of group-sequential designs would only approximate. The price of the bound is a
// wider interval than those boundaries (z at alpha / looks); the gain is that no look is
// trusted beyond what it can show.
#pragma once

namespace allanlot::kernels {

/// alpha min(t / t_max, 1): the error spent by time t (linear spending function).
double spent_alpha(double alpha, double t, double t_max);

/// The interval quantile of a look at t whose previous look was at t_prev (0 for the first):
/// z_{1 - a}, a = spent_alpha(t) - spent_alpha(t_prev); +inf when a is 0 (a look after t_max
/// spends nothing and decides nothing). Throws std::invalid_argument unless 0 < alpha < 1,
/// 0 <= t_prev < t and t_max > 0.
double look_quantile(double alpha, double t_prev, double t, double t_max);

/// z with P(Z <= z) = p for a standard normal Z, 0 < p < 1.
double normal_quantile(double p);

}  // namespace allanlot::kernels
