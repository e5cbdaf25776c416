// The Groslambert codeviation of two phase records measured against the same reference: the
// overlapping Allan variance's cross term, a statistic of two recordings (docs/statistics.md
// "Two recordings: gcodev and the three-cornered hat").
#pragma once

#include "kernels/allan/allan.hpp"

#include <cstdint>
#include <span>

namespace allanlot::kernels {

/// Groslambert codeviation (Allan covariance), Vernotte et al., "Three-cornered hat versus
/// Allan covariance", Proc. IFCS 2016; Lantz et al., IEEE UFFC 66 (2019) (arXiv:1904.05849),
/// the overlapping form of SP1065 eq. (11) with one factor of each record:
///
///   Gcod(tau) = 1 / (2 tau^2 n) * sum_{i=0}^{N-2m-1} (x_{i+2m} - 2 x_{i+m} + x_i)
///                                                     (y_{i+2m} - 2 y_{i+m} + y_i)
///
/// with n = N - 2m on gap-free records. Returned as a signed deviation:
/// dev = sign(Gcod) sqrt(|Gcod|), the form SigmaTheta's GCoDev prints (negative when the clock
/// the two records share enters them with opposite signs, e.g. GCoDev(CA, AB) for clock A).
/// AllanTools' gcodev returns |dev|. gcodev(x, x) is oadev(x), to the rounding of the sum.
///
/// Conventions of allan.hpp: x and y hold N phase points each (PhaseData, mean rate removed,
/// which no second difference sees), tau = m tau0, deviation in rate units; a term is left out
/// when either record misses an increment inside its span x_i .. x_{i+2m}, and n counts the
/// terms used; an m without terms gives no row; m_list is taken as given (the caller applies
/// max_m(Stat::Oadev, N)). Cost O(N) per m. Parallel over fixed chunks of 2^16 terms per m
/// (detail/chunked.hpp), each summed by one thread in sixteen interleaved partial sums reduced
/// in a fixed tree, and the chunks added in chunk order: bit-identical for any thread count.
/// Preconditions (std::invalid_argument naming the parameter): x and y have the same number of
/// phase points and the same tau0_s; every m >= 1.
StatResult gcodev(const PhaseData& x, const PhaseData& y, std::span<const std::int64_t> m_list,
                  int nthreads = 0);

}  // namespace allanlot::kernels
