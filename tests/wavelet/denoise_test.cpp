// Tests of podid/wavelet/denoise.hpp: a smooth signal plus white noise of
// known standard deviation.
#include "podid/wavelet/denoise.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "test_support.hpp"

namespace podid::wavelet {
namespace {

constexpr double kPi = std::numbers::pi;

struct Noisy {
  Eigen::VectorXd clean, noisy;
};

// A decaying two-mode response (smooth at 5 kHz) plus N(0, sigma^2) noise.
Noisy MakeSignal(double sigma, unsigned seed) {
  const Eigen::Index n = 5001;  // not a power of two: exercises the padding
  Noisy s{Eigen::VectorXd(n), Eigen::VectorXd(n)};
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, sigma);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / 5000.0;
    s.clean(i) = std::exp(-2.0 * t) * std::cos(2 * kPi * 33.0 * t) +
                 0.3 * std::exp(-5.0 * t) * std::sin(2 * kPi * 207.0 * t);
    s.noisy(i) = s.clean(i) + normal(rng);
  }
  return s;
}

double Rms(const Eigen::VectorXd& v) { return std::sqrt(v.squaredNorm() / v.size()); }

TEST(Denoise, EstimatesNoiseAndReducesTheError) {
  // MAD/0.6745 of the finest details estimates sigma; the smooth part leaks
  // little into them at 5 kHz, so 10 % is generous for 2500 coefficients
  // (the MAD's own sampling error is about 2 %).
  constexpr double kSigmaTolerance = 0.10;
  // Thresholding the three finest levels (312-2500 Hz, above both modes)
  // with db12 leaves under half the noise (measured 0.44 for both rules).
  // Thresholding every level is worse for oscillating signals, which are not
  // sparse at coarse levels: soft shrinks every mode coefficient by lambda
  // (measured 0.95), hard keeps the big ones (0.52).
  constexpr double kErrorRatio = 0.5;
  const double sigma = 0.05;
  const Noisy s = MakeSignal(sigma, 3);
  for (ThresholdRule rule : {ThresholdRule::kSoft, ThresholdRule::kHard}) {
    DenoiseOptions o;
    o.rule = rule;
    o.daubechies_order = 12;
    o.levels = 3;
    DenoiseSummary summary;
    const Eigen::VectorXd out = Denoise(s.noisy, o, &summary);
    ASSERT_EQ(out.size(), s.noisy.size());
    EXPECT_NEAR(summary.noise_sigma, sigma, kSigmaTolerance * sigma);
    EXPECT_NEAR(summary.threshold, summary.noise_sigma * std::sqrt(2 * std::log(5001.0)), 1e-12);
    EXPECT_EQ(summary.padded_length, 8192);
    const double before = Rms(s.noisy - s.clean), after = Rms(out - s.clean);
    std::printf("denoise %s: sigma %.4f (true %.4f), rms error %.4f -> %.4f, zeroed %ld of %ld\n",
                ToString(rule), summary.noise_sigma, sigma, before, after,
                static_cast<long>(summary.zeroed_coefficients),
                static_cast<long>(summary.coefficients));
    EXPECT_LT(after, kErrorRatio * before);
  }
}

TEST(Denoise, PureNoiseIsRemovedAndGivenSigmaIsUsed) {
  // White noise alone: with the universal threshold, max |d| of n Gaussian
  // coefficients exceeds sigma sqrt(2 ln n) rarely, so almost all are zeroed.
  Noisy s = MakeSignal(1.0, 5);
  const Eigen::VectorXd noise = s.noisy - s.clean;
  DenoiseSummary summary;
  DenoiseOptions o;
  o.noise_sigma = 1.0;
  const Eigen::VectorXd out = Denoise(noise, o, &summary);
  EXPECT_EQ(summary.noise_sigma, 1.0);
  EXPECT_GT(summary.zeroed_coefficients, summary.coefficients * 99 / 100);
  EXPECT_LT(Rms(out), 0.2);
}

// Whether every element of a equals 2^k times b's (bit for bit).
bool ScaledExactly(const Eigen::VectorXd& a, const Eigen::VectorXd& b, int k) {
  if (a.size() != b.size()) return false;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    if (a(i) != std::ldexp(b(i), k)) return false;
  }
  return true;
}

TEST(Denoise, ScalingTheInputByAPowerOfTwoScalesTheOutputExactly) {
  // The transform, the median, lambda and the thresholding all commute with
  // 2^k when nothing leaves the normal range: bit-identical results.
  const Eigen::VectorXd x = MakeSignal(0.05, 3).noisy;
  for (ThresholdRule rule : {ThresholdRule::kSoft, ThresholdRule::kHard}) {
    DenoiseOptions o;
    o.rule = rule;
    o.levels = 3;
    DenoiseSummary unit;
    const Eigen::VectorXd out = Denoise(x, o, &unit);
    for (int k : {-1000, -300, 300, 1000}) {
      const Eigen::VectorXd scaled = x * std::ldexp(1.0, k);
      ASSERT_TRUE(ScaledExactly(scaled, x, k)) << "2^" << k << " x rounded";
      DenoiseSummary summary;
      const Eigen::VectorXd y = Denoise(scaled, o, &summary);
      EXPECT_TRUE(ScaledExactly(y, out, k)) << ToString(rule) << " 2^" << k;
      EXPECT_EQ(summary.noise_sigma, std::ldexp(unit.noise_sigma, k));
      EXPECT_EQ(summary.threshold, std::ldexp(unit.threshold, k));
      EXPECT_EQ(summary.zeroed_coefficients, unit.zeroed_coefficients);
    }
  }
}

// 1000 samples of a 50 Hz unit sine at 1 ms.
Eigen::VectorXd Tone() {
  Eigen::VectorXd x(1000);
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    x(i) = std::sin(2 * kPi * 50.0 * static_cast<double>(i) * 1e-3);
  }
  return x;
}

TEST(Denoise, AToneNearTheLargestDoubleIsDenoisedLikeTheUnitTone) {
  // 1.7e308 x tone overflowed in the transform and came back inf. It is
  // 2^1023 times a tone of peak 1.89 (exactly: no sample leaves the normal
  // range), so its output is 2^1023 times that tone's, bit for bit.
  const Eigen::VectorXd big = 1.7e308 * Tone();
  const Eigen::VectorXd unit = std::ldexp(1.0, -1023) * big;
  ASSERT_TRUE(ScaledExactly(big, unit, 1023));
  for (ThresholdRule rule : {ThresholdRule::kSoft, ThresholdRule::kHard}) {
    DenoiseOptions o;
    o.rule = rule;
    const Eigen::VectorXd y = Denoise(big, o);
    ASSERT_TRUE(y.allFinite()) << ToString(rule);
    const Eigen::VectorXd reference = Denoise(unit, o);
    EXPECT_TRUE(ScaledExactly(y, reference, 1023)) << ToString(rule);
  }
}

TEST(Denoise, ASubnormalToneIsDenoisedLikeItsScaledUpCopy) {
  // 1e-310 x tone is subnormal (about 44 bits of the tone kept). Scaling it
  // up by 2^1030 is exact, and so is the internal scaling of both: the same
  // output once rounded back to the subnormals, bit for bit.
  const Eigen::VectorXd tiny = 1e-310 * Tone();
  const Eigen::VectorXd up = tiny.unaryExpr([](double v) { return std::ldexp(v, 1030); });
  ASSERT_TRUE(ScaledExactly(up, tiny, 1030));
  for (ThresholdRule rule : {ThresholdRule::kSoft, ThresholdRule::kHard}) {
    DenoiseOptions o;
    o.rule = rule;
    const Eigen::VectorXd y = Denoise(tiny, o);
    const Eigen::VectorXd reference = Denoise(up, o);
    EXPECT_TRUE(ScaledExactly(y, reference, -1030)) << ToString(rule);
  }
}

TEST(Denoise, AnOutputAboveTheLargestDoubleThrows) {
  // A step cut to its finest-level approximation rings: measured peak
  // 1.25 x the step's height. At the largest double that overshoot is
  // not representable: std::overflow_error, not inf.
  Eigen::VectorXd step(1000);
  for (Eigen::Index i = 0; i < step.size(); ++i) step(i) = i < 501 ? -1.0 : 1.0;
  DenoiseOptions o;
  o.rule = ThresholdRule::kHard;
  o.levels = 1;
  o.noise_sigma = 1.0;
  o.threshold_scale = 1e6;  // every finest detail is zeroed
  const double ring = Denoise(step, o).cwiseAbs().maxCoeff();
  ASSERT_GT(ring, 1.0);
  const double top = std::numeric_limits<double>::max();
  o.noise_sigma = top;
  PODID_EXPECT_THROW_WITH(Denoise(top * step, o), std::overflow_error,
                          "Denoise: the denoised signal overflowed");
}

TEST(Denoise, BadInputNamesWhatWasExpected) {
  const Eigen::VectorXd x = MakeSignal(0.1, 1).noisy;
  DenoiseOptions o;
  o.daubechies_order = 5;
  PODID_EXPECT_THROW_WITH(Denoise(x, o), std::invalid_argument,
                          "daubechies_order: expected an even number in 4..20, got 5");
  o.daubechies_order = 22;
  PODID_EXPECT_THROW_WITH(Denoise(x, o), std::invalid_argument, "daubechies_order");
  o = DenoiseOptions{};
  o.levels = -1;
  PODID_EXPECT_THROW_WITH(Denoise(x, o), std::invalid_argument, "levels: expected >= 0");
  o = DenoiseOptions{};
  o.threshold_scale = 0.0;
  PODID_EXPECT_THROW_WITH(Denoise(x, o), std::invalid_argument, "threshold_scale");
  PODID_EXPECT_THROW_WITH(Denoise(Eigen::VectorXd::Ones(5)), std::invalid_argument,
                          "expected at least 8 samples");
  Eigen::VectorXd bad = x;
  bad(10) = std::nan("");
  PODID_EXPECT_THROW_WITH(Denoise(bad), std::invalid_argument, "expected finite values");
  PODID_EXPECT_THROW_WITH(ParseThresholdRule("medium"), std::invalid_argument,
                          "expected one of soft, hard");
}

}  // namespace
}  // namespace podid::wavelet
