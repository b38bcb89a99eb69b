#include "podid/core/noise.hpp"

#include <cmath>

#include "podid/core/error.hpp"

namespace podid {

double NormalGenerator::Normal() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  double v1 = 0.0, v2 = 0.0, s = 0.0;
  do {
    v1 = 2.0 * Uniform() - 1.0;
    v2 = 2.0 * Uniform() - 1.0;
    s = v1 * v1 + v2 * v2;
  } while (!(s > 0.0 && s < 1.0));
  const double factor = std::sqrt(-2.0 * std::log(s) / s);
  spare_ = v2 * factor;
  has_spare_ = true;
  return v1 * factor;
}

double NoiseStandardDeviation(const TimeSeries& series, double relative) {
  if (!(relative >= 0.0) || !std::isfinite(relative)) {
    ThrowInvalid("noise.relative", "a finite number >= 0", ToText(relative));
  }
  if (series.values.rows() == 0 || series.values.cols() == 0) return 0.0;
  return relative * series.values.row(0).cwiseAbs().maxCoeff();
}

void AddNoise(TimeSeries& series, double relative, std::uint64_t seed) {
  const double std_dev = NoiseStandardDeviation(series, relative);
  if (relative == 0.0) return;
  // Checked before a value changes: noise.relative = 1e308 wrote a file of
  // inf with exit 0. A polar-method draw |v| sqrt(-2 ln s / s) is at most
  // sqrt(-2 ln s) < 12 (s >= 2^-104), so 16 sigma + max |x| bounds every
  // noisy value.
  const double largest = series.values.size() > 0 ? series.values.cwiseAbs().maxCoeff() : 0.0;
  if (!std::isfinite(std_dev) || !std::isfinite(16.0 * std_dev + largest)) {
    ThrowInvalid("noise.relative", "a level whose noise stays finite",
                 ToText(relative) + " (standard deviation " + ToText(std_dev) + " of a response up to " +
                     ToText(largest) + ")");
  }
  NormalGenerator generator(seed);
  for (Eigen::Index i = 0; i < series.values.rows(); ++i) {
    for (Eigen::Index j = 0; j < series.values.cols(); ++j) {
      series.values(i, j) += std_dev * generator.Normal();
    }
  }
}

}  // namespace podid
