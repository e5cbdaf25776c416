// The contiguous Allan-family terms on W-double vectors, for kernels/allan/sweep_simd.cpp only.
// Included once per SIMD level, inside that level's namespace and `#pragma GCC target`
// region, after the namespace has defined V (W doubles), U (W uint64), I (W int64), W and
// to_double(U); every function here is then compiled for that level alone (no inline function
// of another translation unit is shared, so the linker cannot mix levels). No include guard
// on purpose.
//
// Same terms, same association and the same sixteen lanes and tree as block_sum_baseline in
// kernels/allan/detail/sweep.hpp; the kernels library is built with -ffp-contract=off, so no
// multiply-add is fused and every path rounds alike.

inline V load(const double* p) {
  V v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline U load(const std::uint64_t* p) {
  U v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

struct Second {
  const double* x;
  std::int64_t m;
  V vec(std::int64_t k) const { return load(x + k + 2 * m) - 2.0 * load(x + k + m) + load(x + k); }
  double one(std::int64_t k) const { return x[k + 2 * m] - 2.0 * x[k + m] + x[k]; }
};

struct Third {
  const double* x;
  std::int64_t m;
  V vec(std::int64_t k) const {
    return (load(x + k + 3 * m) - load(x + k)) - 3.0 * (load(x + k + 2 * m) - load(x + k + m));
  }
  double one(std::int64_t k) const {
    return (x[k + 3 * m] - x[k]) - 3.0 * (x[k + 2 * m] - x[k + m]);
  }
};

struct Modified {
  const std::uint64_t* s;
  std::int64_t m;
  double q;
  V vec(std::int64_t j) const {
    const U a = load(s + j + 2 * m) - load(s + j + m);
    const U d = (load(s + j + 3 * m) - load(s + j)) - (a + (a << 1));
    return to_double(d) * q;
  }
  double one(std::int64_t j) const {
    const std::uint64_t a = s[j + 2 * m] - s[j + m];
    const std::uint64_t d = (s[j + 3 * m] - s[j]) - (a + (a << 1));
    return static_cast<double>(static_cast<std::int64_t>(d)) * q;
  }
};

// The block [b, e) of Term continued from term k with the lanes accumulated so far in acc
// (kLanes / W registers): the rest of the vector loop, the scalar tail, the fixed tree.
template <class Term>
double sum16_from(const Term& t, V* acc, std::int64_t k, std::int64_t b, std::int64_t e) {
  constexpr int kRegs = kLanes / W;
  for (; k + kLanes <= e; k += kLanes) {
#pragma GCC unroll 4
    for (int a = 0; a < kRegs; ++a) {
      const V d = t.vec(k + a * W);
      acc[a] += d * d;
    }
  }
  double s[kLanes];
  std::memcpy(s, acc, sizeof s);
  for (; k < e; ++k) {
    const double d = t.one(k);
    s[(k - b) & (kLanes - 1)] += d * d;
  }
  return reduce_lanes(s);
}

template <class Term>
double sum16(const Term& t, std::int64_t b, std::int64_t e) {
  V acc[kLanes / W] = {};
  return sum16_from(t, acc, b, b, e);
}

double second(const double* x, std::int64_t m, std::int64_t b, std::int64_t e) {
  return sum16(Second{x, m}, b, e);
}
double third(const double* x, std::int64_t m, std::int64_t b, std::int64_t e) {
  return sum16(Third{x, m}, b, e);
}
double modified(const std::uint64_t* s, std::int64_t m, double q, std::int64_t b, std::int64_t e) {
  return sum16(Modified{s, m, q}, b, e);
}

// OADEV's and OHDEV's block at one m from one set of loads of the four streams x_k, x_{k+m},
// x_{k+2m}, x_{k+3m} (the two sweeps apart load seven): each difference is formed as Second's
// and Third's, into its own lanes, so both values round exactly as second() and third()
// would. The third differences end first (e3 <= e2); the second's loop then goes on alone.
void second_third(const double* x, std::int64_t m, std::int64_t b, std::int64_t e2, std::int64_t e3,
                  double* s2, double* s3) {
  constexpr int kRegs = kLanes / W;
  V a2[kRegs] = {}, a3[kRegs] = {};
  std::int64_t k = b;
  for (; k + kLanes <= e3; k += kLanes) {
#pragma GCC unroll 4
    for (int a = 0; a < kRegs; ++a) {
      const double* p = x + k + a * W;
      const V x0 = load(p), x1 = load(p + m), x2 = load(p + 2 * m), x3 = load(p + 3 * m);
      const V d2 = x2 - 2.0 * x1 + x0;
      const V d3 = (x3 - x0) - 3.0 * (x2 - x1);
      a2[a] += d2 * d2;
      a3[a] += d3 * d3;
    }
  }
  *s3 = sum16_from(Third{x, m}, a3, k, b, e3);
  *s2 = sum16_from(Second{x, m}, a2, k, b, e2);
}
