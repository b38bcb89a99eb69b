#pragma once
// Gaussian measurement noise, reproducible across compilers and platforms.
//
// Generator: std::mt19937_64 seeded with `seed` (its output sequence is fixed
// by the C++ standard). Uniforms: u = (x >> 11) * 2^-53, in [0, 1), from each
// 64-bit output x. Normals: Marsaglia's polar method on pairs of uniforms,
//   v1 = 2 u1 - 1, v2 = 2 u2 - 1, s = v1^2 + v2^2 (pair rejected unless 0 < s < 1),
//   z1 = v1 sqrt(-2 ln s / s), z2 = v2 sqrt(-2 ln s / s), returned z1 then z2.
// std::normal_distribution is not used: its algorithm is implementation-defined.
// The only libm call is std::log, so values agree across platforms to about
// one ulp (bit-for-bit on glibc).

#include <cstdint>
#include <random>

#include "podid/core/time_series.hpp"

namespace podid {

class NormalGenerator {
 public:
  explicit NormalGenerator(std::uint64_t seed) : engine_(seed) {}
  /// Uniform in [0, 1): (x >> 11) * 2^-53.
  double Uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  /// Standard normal (polar method, see above).
  double Normal();

 private:
  std::mt19937_64 engine_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

/// Noise standard deviation: relative * max_j |values(0, j)| (the largest
/// absolute value over the channels at the first sample).
double NoiseStandardDeviation(const TimeSeries& series, double relative);

/// Adds std * z to every value, z drawn from NormalGenerator(seed) sample by
/// sample and, within a sample, channel by channel (row-major order), with
/// std = NoiseStandardDeviation(series, relative). relative = 0 leaves the
/// series unchanged. Throws std::invalid_argument unless relative >= 0 and
/// finite.
void AddNoise(TimeSeries& series, double relative, std::uint64_t seed);

}  // namespace podid
