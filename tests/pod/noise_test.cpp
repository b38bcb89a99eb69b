// Noise-corrected singular values against the clean data's own.
#include "podid/pod/noise.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numbers>
#include <random>

namespace podid {
namespace {

TEST(NoiseTest, DifferenceEstimatorAndCorrectedSigmasMatchTheCleanData) {
  // Rank-2 "structure" (two decaying modes well inside the band, omega dt <=
  // 0.13) on 6 sensors, 5000 samples, white noise of 5 % of the peak with a
  // different level per sensor.
  constexpr Eigen::Index kSensors = 6, kSamples = 5000;
  // The variance estimate's own spread: the median of 5000 chi-square values
  // is within ~3 % (1 / sqrt(N) scaled by the chi-square density), plus the
  // signal's residual second difference.
  constexpr double kVarianceTolerance = 0.06;
  // The corrected sigma_k vs the clean one: what remains is the noise's
  // random part (the cross term 2 u^T Y_c E^T u and E E^T's fluctuation,
  // ~1/sqrt(N) of the corrected energy), 0.1-0.2 % here; the correction must
  // remove most of the bias (3/4 on mode 1, 99 % on mode 2 with this seed; 60 %
  // leaves room for the random part).
  constexpr double kCorrectedTolerance = 3e-3;
  constexpr double kMinBiasRemoved = 0.6;
  const double dt = 1e-3, pi = std::numbers::pi;
  Eigen::MatrixXd clean(kSensors, kSamples);
  for (Eigen::Index i = 0; i < kSensors; ++i) {
    const double u1 = std::sin(pi * (i + 1) / 7.0), u2 = std::sin(2 * pi * (i + 1) / 7.0);
    for (Eigen::Index n = 0; n < kSamples; ++n) {
      const double t = n * dt;
      clean(i, n) = u1 * std::exp(-0.5 * t) * std::cos(2 * pi * 5 * t) +
                    0.3 * u2 * std::exp(-1.0 * t) * std::cos(2 * pi * 21 * t);
    }
  }
  std::mt19937_64 rng(3);
  Eigen::VectorXd variance(kSensors);
  Eigen::MatrixXd noisy = clean;
  for (Eigen::Index i = 0; i < kSensors; ++i) {
    const double std = 0.05 * clean.cwiseAbs().maxCoeff() * (0.5 + 0.2 * i);
    variance[i] = std * std;
    std::normal_distribution<double> normal(0.0, std);
    for (Eigen::Index n = 0; n < kSamples; ++n) noisy(i, n) += normal(rng);
  }
  const Eigen::VectorXd estimated = DifferenceNoiseVariance(noisy);
  for (Eigen::Index i = 0; i < kSensors; ++i) {
    EXPECT_NEAR(estimated[i] / variance[i], 1.0, kVarianceTolerance) << "sensor " << i;
  }
  PodOptions options;
  options.method = PodMethod::kSvd;
  const PodResult c = PodSolver(options).Compute(clean);
  const PodResult m = PodSolver(options).Compute(noisy);
  const Eigen::VectorXd corrected = NoiseCorrectedSingularValues(m, estimated);
  for (int k = 0; k < 2; ++k) {
    const double before = m.singular_values[k] / c.singular_values[k] - 1.0;
    const double after = corrected[k] / c.singular_values[k] - 1.0;
    std::cout << "mode " << k + 1 << ": sigma bias " << before << " -> " << after << "\n";
    EXPECT_GT(before, 2 * kCorrectedTolerance) << "the noise must bias the raw sigma for the test to mean anything";
    EXPECT_LT(std::abs(after), kCorrectedTolerance);
    EXPECT_LT(std::abs(after), (1.0 - kMinBiasRemoved) * before);
  }
}

TEST(NoiseTest, BadInput) {
  EXPECT_THROW(DifferenceNoiseVariance(Eigen::MatrixXd::Zero(2, 7)), std::invalid_argument);
  PodResult r;
  r.sensors = 3;
  EXPECT_THROW(NoiseCorrectedSingularValues(r, Eigen::VectorXd::Zero(2)), std::invalid_argument);
}

}  // namespace
}  // namespace podid
