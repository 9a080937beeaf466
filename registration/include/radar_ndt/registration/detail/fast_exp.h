#pragma once
// exp(x) for the non-positive arguments of the NDT cost, inline and deterministic.

#include <cstdint>
#include <cstring>

namespace radar_ndt {
namespace detail {

#if defined(__GNUC__) || defined(__clang__)
#define RADAR_NDT_ALWAYS_INLINE __attribute__((always_inline)) inline
#else
#define RADAR_NDT_ALWAYS_INLINE inline
#endif

/// exp(x) for x in [-700, 0] (the Gaussian scores and the point weights), relative error below
/// 1e-8; below -700 (and NaN) as at -700, about 1e-304: x·log2(e) split into an integer k and f
/// in [-1/2, 1/2], 2^f by its Taylor series to degree 7, 2^k put in the exponent bits. Inline and
/// about a third of libm's exp in this loop; a pure function, so results stay deterministic.
RADAR_NDT_ALWAYS_INLINE double expNegative(double x) {
  x = x >= -700.0 ? x : -700.0;             // branch-free, so the function stays inlined
  const double t = x * 1.4426950408889634;  // log2(e), t <= 0
  const double k = static_cast<double>(static_cast<std::int64_t>(t - 0.5));  // truncation: t rounded
  const double f = (t - k) * 0.6931471805599453;                             // e^f = 2^(t - k)
  // Degree 7 in Estrin's form (three dependent multiply-adds instead of ten in Horner's): for
  // |f| <= ln2/2 the truncation error is below f⁸/8!·e^|f| < 8e-9 relative.
  const double f2 = f * f, f4 = f2 * f2;
  const double p = ((1.0 + f) + f2 * (0.5 + f * (1.0 / 6.0))) +
                   f4 * (((1.0 / 24.0) + f * (1.0 / 120.0)) + f2 * ((1.0 / 720.0) + f * (1.0 / 5040.0)));
  const std::uint64_t bits = static_cast<std::uint64_t>(static_cast<std::int64_t>(k) + 1023) << 52;
  double scale;
  std::memcpy(&scale, &bits, sizeof(scale));
  return p * scale;
}

#undef RADAR_NDT_ALWAYS_INLINE

}  // namespace detail
}  // namespace radar_ndt
