// Gaussian noise: the generator against an independent implementation, the
// sample statistics, and AddNoise's scaling and reproducibility.
#include "podid/core/noise.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "test_support.hpp"

namespace podid {
namespace {

// Reference values from an independent Python implementation of MT19937-64
// (Matsumoto & Nishimura's algorithm, written out in full and checked against
// the standard's 10000th output 9981545732273789042), (x >> 11) * 2^-53 and
// Marsaglia's polar method; tests/data/README.md has the script.
// Uniforms are exact (integer arithmetic and one exact scaling); normals go
// through log() and sqrt(): allow a few ulp for another libm.
constexpr double kNormalTolerance = 4e-16;

TEST(NormalGenerator, StandardEngineMatchesTheStandardsCheckValue) {
  std::mt19937_64 engine;  // default seed 5489
  engine.discard(9999);
  EXPECT_EQ(engine(), 9981545732273789042ULL);
}

TEST(NormalGenerator, UniformsMatchTheIndependentImplementation) {
  NormalGenerator generator(1);
  EXPECT_EQ(generator.Uniform(), 0.13387664401253263);
  EXPECT_EQ(generator.Uniform(), 0.13640703636619722);
  EXPECT_EQ(generator.Uniform(), 0.4512149038445381);
}

TEST(NormalGenerator, NormalsMatchTheIndependentImplementation) {
  const double seed1[] = {-0.039399956754155314, -0.38683176162103955, -0.24894784633514516,
                          0.6868236391793252,    -0.05464685232137162, -0.7951462437094919};
  NormalGenerator g1(1);
  for (double expected : seed1) EXPECT_NEAR(g1.Normal(), expected, kNormalTolerance);
  const double seed42[] = {1.2938204232729367, 0.7049882664208599, 0.3979773961837887,
                           -0.5740948067202614};
  NormalGenerator g42(42);
  for (double expected : seed42) EXPECT_NEAR(g42.Normal(), expected, kNormalTolerance);
}

TEST(NormalGenerator, SampleMeanAndStandardDeviation) {
  constexpr int kSamples = 200000;
  // Standard errors: mean 1/sqrt(n) = 2.2e-3, std 1/sqrt(2n) = 1.6e-3; allow ~5 of them.
  constexpr double kMeanTolerance = 0.011;
  constexpr double kStdTolerance = 0.008;
  NormalGenerator generator(7);
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < kSamples; ++i) {
    const double z = generator.Normal();
    sum += z;
    sum2 += z * z;
  }
  const double mean = sum / kSamples;
  const double std_dev = std::sqrt(sum2 / kSamples - mean * mean);
  EXPECT_NEAR(mean, 0.0, kMeanTolerance);
  EXPECT_NEAR(std_dev, 1.0, kStdTolerance);
}

TimeSeries Example() {
  TimeSeries series;
  series.time_s = Eigen::VectorXd::LinSpaced(1000, 0.0, 0.999);
  series.channel_names = {"w1", "w2"};
  series.values = Eigen::MatrixXd::Zero(1000, 2);
  series.values(0, 0) = 0.5;
  series.values(0, 1) = -2.0;  // max |x(t = 0)| = 2
  return series;
}

TEST(AddNoise, ScaleOrderAndReproducibility) {
  TimeSeries series = Example();
  const TimeSeries clean = series;
  EXPECT_EQ(NoiseStandardDeviation(series, 0.01), 0.02);
  AddNoise(series, 0.01, 3);
  // Row-major order: sample by sample, channel by channel.
  NormalGenerator generator(3);
  Eigen::MatrixXd expected = clean.values;
  for (Eigen::Index i = 0; i < expected.rows(); ++i) {
    for (Eigen::Index j = 0; j < expected.cols(); ++j) expected(i, j) += 0.02 * generator.Normal();
  }
  EXPECT_EQ(series.values, expected);
  TimeSeries again = Example();
  AddNoise(again, 0.01, 3);
  EXPECT_EQ(again.values, series.values);
  TimeSeries other = Example();
  AddNoise(other, 0.01, 4);
  EXPECT_NE(other.values, series.values);
  // The noise's sample std over 2000 values: standard error 1.6 %, allow ~5.
  constexpr double kRelativeStdTolerance = 0.08;
  const Eigen::MatrixXd noise = series.values - clean.values;
  const double std_dev = std::sqrt(noise.squaredNorm() / static_cast<double>(noise.size()));
  EXPECT_NEAR(std_dev / 0.02, 1.0, kRelativeStdTolerance);
}

TEST(AddNoise, ZeroLeavesTheSeriesAndNegativeIsRejected) {
  TimeSeries series = Example();
  AddNoise(series, 0.0, 1);
  EXPECT_EQ(series.values, Example().values);
  PODID_EXPECT_THROW_WITH(AddNoise(series, -0.1, 1), std::invalid_argument,
                          "noise.relative: expected a finite number >= 0, got -0.1");
  PODID_EXPECT_THROW_WITH(AddNoise(series, std::nan(""), 1), std::invalid_argument,
                          "noise.relative: expected a finite number >= 0, got nan");
  // A level whose noise overflows is refused before any value changes (it
  // wrote a file of inf): 1e308 x the first sample's max |x|.
  PODID_EXPECT_THROW_WITH(AddNoise(series, 1e308, 1), std::invalid_argument,
                          "noise.relative: expected a level whose noise stays finite, got 1e+308");
  EXPECT_EQ(series.values, Example().values);
}

}  // namespace
}  // namespace podid
