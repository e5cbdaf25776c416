// The vocabulary of the paper's eq. (3), owned here and nowhere else: the five terms, their
// names and order, the power of seconds in each coefficient's unit, and the coefficients of a
// channel.
//
//   avar(tau) = R^2 tau^2/2 + K^2 tau/3 + B^2 (2 ln2/pi) + N^2/tau + 3 Q^2/tau^2
//
// Coefficients are in the channel's units u and seconds (docs/formats.md "Units and
// conventions"): R [u/s], K [u/s^0.5], B [u], N [u*s^0.5], Q [u*s].
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <stdexcept>
#include <string_view>

namespace allanlot::kernels {

/// The five coefficients of eq. (3). Arrays of per-term values are indexed by
/// static_cast<int>(Term) in this order.
enum class Term { R, K, B, N, Q };

/// Number of terms of eq. (3).
inline constexpr int kNumTerms = 5;

/// "R", "K", "B", "N", "Q".
std::string_view term_name(Term t);
/// Inverse of term_name; nullopt for anything else.
std::optional<Term> parse_term(std::string_view name);
/// R, K, B, N, Q: the order results are written in.
std::span<const Term> all_terms();

/// The power of seconds a coefficient carries beyond the channel's unit u, as a unit suffix:
/// "/s" (R), "/s^0.5" (K), "" (B), "*s^0.5" (N), "*s" (Q).
std::string_view seconds_suffix(Term t);

/// The five coefficients of eq. (3), in the channel's units u and seconds; all >= 0.
struct NoiseTerms {
  double R = 0;  // rate ramp [u/s]: y(t) = R t, avar = R^2 tau^2 / 2
  double K = 0;  // rate random walk [u/s^0.5]: avar = K^2 tau / 3
  double B = 0;  // flicker (bias instability) [u]: avar = B^2 2 ln2 / pi
  double N = 0;  // white rate noise [u*s^0.5] (ARW, VRW): avar = N^2 / tau
  double Q = 0;  // quantization [u*s]: avar = 3 Q^2 / tau^2
  friend bool operator==(const NoiseTerms&, const NoiseTerms&) = default;
};

/// The coefficient of term t in `terms`.
inline double& coefficient(NoiseTerms& terms, Term t) {
  switch (t) {
  case Term::R:
    return terms.R;
  case Term::K:
    return terms.K;
  case Term::B:
    return terms.B;
  case Term::N:
    return terms.N;
  case Term::Q:
    return terms.Q;
  }
  throw std::logic_error("terms: bad term");
}
inline double coefficient(const NoiseTerms& terms, Term t) {
  return coefficient(const_cast<NoiseTerms&>(terms), t);
}

}  // namespace allanlot::kernels
