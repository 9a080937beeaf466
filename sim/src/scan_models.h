#pragma once
// Internal to the simulator's scanning radar: the statistical models a rendered scan draws from
// (speckle, multipath, ground clutter, the scatterer field) and Navtech's counts display, inline
// because the renderer calls them per bin.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "radar_ndt/sim/radar_sim.h"
#include "sim_random.h"

namespace radar_ndt {
namespace sim {
namespace detail {

/// Standard normal CDF.
inline double phi(double x) {
  return 0.5 * std::erfc(-x / std::sqrt(2.0));
}

/// Gamma(shape k, scale 1/k) variate with mean 1 (speckle of k looks), Marsaglia–Tsang.
inline double gammaMeanOne(Random& rng, double k) {
  if (k <= 0.0) return 1.0;
  const double boost = k < 1.0 ? std::pow(rng.uniform() + 1e-300, 1.0 / k) : 1.0;
  const double kk = k < 1.0 ? k + 1.0 : k;
  const double d = kk - 1.0 / 3.0, c = 1.0 / std::sqrt(9.0 * d);
  for (;;) {
    double x, v;
    do {
      x = rng.normal();
      v = 1.0 + c * x;
    } while (v <= 0.0);
    v = v * v * v;
    const double u = rng.uniform();
    if (u < 1.0 - 0.0331 * x * x * x * x || std::log(u) < 0.5 * x * x + d * (1.0 - v + std::log(v)))
      return boost * d * v / k;
  }
}

/// Whether a surface mirrors (multipath), decided once per surface from the seed.
inline bool specular(std::uint64_t seed, std::uint32_t id, double probability) {
  std::uint64_t x = seed ^ (0x6a09e667f3bcc909ULL + id * 0x9e3779b97f4a7c15ULL);
  return static_cast<double>(splitmix64(x) >> 11) * 0x1.0p-53 < probability;
}

/// The ground-clutter field at a world point: bilinear between 1 m cells, each cluttered with
/// probability `cover` at an exponentially distributed strength of mean 1 (fixed per seed).
inline double groundClutter(std::uint64_t seed, const Eigen::Vector2d& q, double cover) {
  const double fx = std::floor(q.x()), fy = std::floor(q.y());
  const double ux = q.x() - fx, uy = q.y() - fy;
  const long ix = static_cast<long>(fx), iy = static_cast<long>(fy);
  auto cell = [&](long x, long y) {
    std::uint64_t h = seed * 0xbf58476d1ce4e5b9ULL ^ (static_cast<std::uint64_t>(x) * 0x9e3779b97f4a7c15ULL) ^
                      (static_cast<std::uint64_t>(y) * 0xc2b2ae3d27d4eb4fULL);
    const std::uint64_t r = splitmix64(h);
    const double a = static_cast<double>(r >> 40) * 0x1.0p-24,
                 b = (static_cast<double>(r & 0xffffff) + 0.5) * 0x1.0p-24;
    return a < cover ? -std::log(b) : 0.0;
  };
  return (1 - ux) * (1 - uy) * cell(ix, iy) + ux * (1 - uy) * cell(ix + 1, iy) + (1 - ux) * uy * cell(ix, iy + 1) +
         ux * uy * cell(ix + 1, iy + 1);
}

/// A point scatterer of the fixed scatterer field.
struct Scatterer {
  Eigen::Vector2d p;
  double db;  ///< strength relative to the field's mean level
};

/// The scatterers of the 10 m cell (ix, iy): a Poisson number of them (mean density · 100 m²),
/// uniform in the cell, normal strengths in dB; fixed per seed.
inline void cellScatterers(std::uint64_t seed, long ix, long iy, double density, double sigma_db,
                           std::vector<Scatterer>& out) {
  constexpr double kCell = 10.0;
  std::uint64_t h = seed * 0x94d049bb133111ebULL ^ (static_cast<std::uint64_t>(ix) * 0x9e3779b97f4a7c15ULL) ^
                    (static_cast<std::uint64_t>(iy) * 0xc2b2ae3d27d4eb4fULL) ^ 0x5ca77e4ULL;
  auto uniform = [&h] { return (static_cast<double>(splitmix64(h) >> 11) + 0.5) * 0x1.0p-53; };
  // Poisson by inversion (means up to a few tens).
  const double mean = density * kCell * kCell;
  double u = uniform(), p = std::exp(-mean), cum = p;
  int n = 0;
  while (u > cum && n < 1000) {
    ++n;
    p *= mean / n;
    cum += p;
  }
  for (int i = 0; i < n; ++i) {
    Scatterer s;
    s.p = Eigen::Vector2d((static_cast<double>(ix) + uniform()) * kCell, (static_cast<double>(iy) + uniform()) * kCell);
    s.db = sigma_db * std::sqrt(-2.0 * std::log(uniform())) * std::cos(2.0 * kPi * uniform());
    out.push_back(s);
  }
}

inline bool mirrors(Material m) {
  return m == Material::Building || m == Material::Car || m == Material::Bus || m == Material::Wall;
}

/// 10·log10 of an Exp(1) variate, tabulated on 2^16 quantiles (the noise floor's fast path).
inline const std::vector<float>& exponentialDbTable() {
  static const std::vector<float> table = [] {
    std::vector<float> t(1 << 16);
    for (std::size_t i = 0; i < t.size(); ++i) {
      const double u = (static_cast<double>(i) + 0.5) / t.size();
      t[i] = static_cast<float>(10.0 * std::log10(-std::log(u)));
    }
    return t;
  }();
  return table;
}

/// Exp(1) variates tabulated on 2^16 quantiles (the counts display's noise and speckle).
inline const std::vector<float>& exponentialTable() {
  static const std::vector<float> table = [] {
    std::vector<float> t(1 << 16);
    for (std::size_t i = 0; i < t.size(); ++i)
      t[i] = static_cast<float>(-std::log((static_cast<double>(i) + 0.5) / t.size()));
    return t;
  }();
  return table;
}

/// Navtech's stored value of a count n: ⌊20·log10 n + 0.12⌋, 0 below 1, at most 255.
inline std::uint8_t countByte(double n) {
  static const std::vector<std::uint8_t> table = [] {
    std::vector<std::uint8_t> t(4096, 0);
    for (std::size_t k = 1; k < t.size(); ++k)
      t[k] = static_cast<std::uint8_t>(std::min(255.0, std::floor(20.0 * std::log10(static_cast<double>(k)) + 0.12)));
    return t;
  }();
  if (n < 4096.0) return n >= 1.0 ? table[static_cast<std::size_t>(n)] : 0;
  return static_cast<std::uint8_t>(std::min(255.0, std::floor(20.0 * std::log10(n) + 0.12)));
}

}  // namespace detail
}  // namespace sim
}  // namespace radar_ndt
