#pragma once
// Small value types shared by the environment interface and its helpers (no MuJoCo here).

#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace srics::env {

// A point or displacement on the table plane, in metres.
using Vec2 = std::array<double, 2>;

// Euclidean distance between two points of the plane.
inline double Distance(const Vec2& a, const Vec2& b) { return std::hypot(a[0] - b[0], a[1] - b[1]); }

// The random generator of every sampler. std::mt19937_64 is fully specified by the C++
// standard, so a seed gives the same numbers on every platform.
using Rng = std::mt19937_64;

// Uniform double in [lo, hi) built from 53 random bits (the standard distributions are
// implementation-defined; this is not, so trajectories are bit-identical everywhere).
inline double Uniform(Rng& rng, double lo, double hi) {
  const double unit = static_cast<double>(rng() >> 11) * 0x1.0p-53;
  return lo + (hi - lo) * unit;
}

// Uniform integer in [0, n) (n > 0), by rejection so that it is unbiased and portable.
inline uint64_t UniformIndex(Rng& rng, uint64_t n) {
  const uint64_t limit = UINT64_MAX - UINT64_MAX % n;
  uint64_t x;
  do {
    x = rng();
  } while (x >= limit);
  return x % n;
}

}  // namespace srics::env
