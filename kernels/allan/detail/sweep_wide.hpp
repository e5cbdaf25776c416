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

template <class Term>
double sum16(const Term& t, std::int64_t b, std::int64_t e) {
  constexpr int kRegs = kLanes / W;
  V acc[kRegs] = {};
  std::int64_t k = b;
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

double second(const double* x, std::int64_t m, std::int64_t b, std::int64_t e) {
  return sum16(Second{x, m}, b, e);
}
double third(const double* x, std::int64_t m, std::int64_t b, std::int64_t e) {
  return sum16(Third{x, m}, b, e);
}
double modified(const std::uint64_t* s, std::int64_t m, double q, std::int64_t b, std::int64_t e) {
  return sum16(Modified{s, m, q}, b, e);
}
