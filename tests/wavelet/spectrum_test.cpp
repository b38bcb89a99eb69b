// SpectralPeak_Hz and WhiteNoiseMagnitude (podid/wavelet/spectrum.hpp).
#include "podid/wavelet/spectrum.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

namespace podid::wavelet {
namespace {

constexpr double kPi = std::numbers::pi;

Eigen::VectorXd Tones(int n, double step_s, double f1, double a1, double f2, double a2) {
  Eigen::VectorXd x(n);
  for (int i = 0; i < n; ++i) {
    const double t = i * step_s;
    x[i] = a1 * std::cos(2 * kPi * f1 * t) + a2 * std::sin(2 * kPi * f2 * t);
  }
  return x;
}

TEST(SpectralPeakTest, FindsTheStrongerToneAndTheOtherWhenItIsExcluded) {
  // 1 s at 2 kHz: 1 Hz bins; tones between bins. The parabolic refinement of
  // the smoothed log power keeps a Hann-windowed tone within 0.3 Hz (found
  // 0.1-0.2 Hz); 0.5 Hz is half a bin.
  constexpr double kToleranceHz = 0.5;
  const Eigen::VectorXd x = Tones(2000, 5e-4, 40.3, 1.0, 231.7, 0.3);
  EXPECT_NEAR(SpectralPeak_Hz(x, 5e-4, 0.0, 1000.0), 40.3, kToleranceHz);
  EXPECT_NEAR(SpectralPeak_Hz(x, 5e-4, 0.0, 1000.0, {40.0}), 231.7, kToleranceHz);
  EXPECT_NEAR(SpectralPeak_Hz(x, 5e-4, 100.0, 1000.0), 231.7, kToleranceHz);
  // Excluding both leaves noise-free leakage only: some bin, never a tone's.
  const double rest = SpectralPeak_Hz(x, 5e-4, 0.0, 1000.0, {40.3, 231.7});
  EXPECT_GT(std::abs(std::log2(rest / 40.3)), 0.25);
  EXPECT_GT(std::abs(std::log2(rest / 231.7)), 0.25);
}

TEST(SpectralPeakTest, FindsADecayingLineUnderWhiteNoise) {
  // A 207 Hz line decaying with 1 % damping (as the reference beam's second
  // mode) under white noise of the same total energy: a bin of the noise is
  // higher than some of the line's bins, the smoothed line is not.
  const double step = 2e-4, zeta = 0.01, f = 207.0;
  std::mt19937_64 engine(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::VectorXd x(5001);
  for (int i = 0; i < x.size(); ++i) {
    const double t = i * step;
    x[i] = std::exp(-zeta * 2 * kPi * f * t) * std::cos(2 * kPi * f * t);
  }
  const double rms = std::sqrt(x.squaredNorm() / x.size());
  for (int i = 0; i < x.size(); ++i) x[i] += rms * normal(engine);
  // 1 %: the line is 2 zeta f = 4 Hz wide; its peak sits within a bin (0.2 Hz).
  EXPECT_NEAR(SpectralPeak_Hz(x, step, 0.0, 2375.0) / f, 1.0, 0.01);
}

TEST(SpectralPeakTest, RefusesBadArguments) {
  const Eigen::VectorXd x = Tones(100, 1e-3, 50.0, 1.0, 120.0, 1.0);
  EXPECT_THROW(SpectralPeak_Hz(x.head(4), 1e-3, 0.0, 100.0), std::invalid_argument);
  EXPECT_THROW(SpectralPeak_Hz(x, 0.0, 0.0, 100.0), std::invalid_argument);
  EXPECT_THROW(SpectralPeak_Hz(x, 1e-3, 100.0, 50.0), std::invalid_argument);
  EXPECT_THROW(SpectralPeak_Hz(x, 1e-3, 2.0, 3.0), std::invalid_argument);  // no 10 Hz bin in 2..3 Hz
  Eigen::VectorXd bad = x;
  bad[3] = std::nan("");
  EXPECT_THROW(SpectralPeak_Hz(bad, 1e-3, 0.0, 100.0), std::invalid_argument);
  EXPECT_TRUE(std::isnan(SpectralPeak_Hz(Eigen::VectorXd::Zero(64), 1e-3, 0.0, 400.0)));
}

// 1000 samples of a 50 Hz unit sine at 1 ms: 50 cycles, on bin 50 of 1 Hz.
Eigen::VectorXd Tone() {
  Eigen::VectorXd x(1000);
  for (int i = 0; i < x.size(); ++i) x[i] = std::sin(2 * kPi * 50.0 * i * 1e-3);
  return x;
}

TEST(SpectralPeakTest, TheAmplitudeDoesNotMoveThePeak) {
  // Closed form: 50 Hz. The tone sits on a bin, so only the Hann window's
  // 1000 / 999 stretch and the image at -50 Hz make the neighbours unequal:
  // measured 4.2e-9 Hz off: 1e-8.
  constexpr double kOnBinHz = 1e-8;
  const Eigen::VectorXd tone = Tone();
  const double unit = SpectralPeak_Hz(tone, 1e-3, 0.0, 500.0);
  EXPECT_NEAR(unit, 50.0, kOnBinHz);
  // 2^k x is the same input after the internal scaling: the same bits. (No
  // sample falls below the normal range: the smallest |x| is ~1e-14 = 2^-46.)
  for (int k : {-960, -565, 531, 1023}) {
    EXPECT_EQ(SpectralPeak_Hz(std::ldexp(1.0, k) * tone, 1e-3, 0.0, 500.0), unit) << "2^" << k;
  }
  // The amplitudes that returned NaN (|X|^2 overflowed or flushed to 0).
  // Their products round, so the peak moves by round-off only (measured 0):
  // 1e-12 Hz.
  constexpr double kRoundedHz = 1e-12;
  for (double a : {1e160, 1e200, 1e308, 1e-170}) {
    const double peak = SpectralPeak_Hz(a * tone, 1e-3, 0.0, 500.0);
    EXPECT_NEAR(peak, unit, kRoundedHz) << a;
  }
  // 1e-320 is subnormal: the samples keep ~11 bits (1e-320 / 2^-1074 ~ 2^11).
  // The rounding repeats with the tone's 20-sample period, so it lands on
  // the harmonics of 50 Hz and leaves the line symmetric: measured 2.3e-13
  // Hz off the unit tone's peak; 1e-11 Hz.
  constexpr double kElevenBitsHz = 1e-11;
  EXPECT_NEAR(SpectralPeak_Hz(1e-320 * tone, 1e-3, 0.0, 500.0), unit, kElevenBitsHz);
}

TEST(SpectralPeakTest, ABandBeyondIntsRangeIsClampedToTheBins) {
  const Eigen::VectorXd tone = Tone();
  const double unit = SpectralPeak_Hz(tone, 1e-3, 0.0, 500.0);
  // 0..500 Hz already holds every bin: wider bands are the same search.
  for (double max_Hz : {3e9, 1e300, std::numeric_limits<double>::max()}) {
    EXPECT_EQ(SpectralPeak_Hz(tone, 1e-3, 0.0, max_Hz), unit) << max_Hz;
  }
  EXPECT_THROW(SpectralPeak_Hz(tone, 1e-3, 3e9, 4e9), std::invalid_argument);  // above Nyquist
  // A step of 1e300 s: the same bin and offset, in units of 1 / (N step).
  // Rounding of the bin width and of the product: 4 ulps (EXPECT_DOUBLE_EQ).
  EXPECT_DOUBLE_EQ(SpectralPeak_Hz(tone, 1e300, 0.0, 1.0) * (1000 * 1e300), unit);
  // At 1e307 s, N step overflows; the bin is then 1 / step / N = 1e-310 Hz,
  // a subnormal with a spacing of 2^-1074 / 1e-310 = 5e-14 of it: 1e-12.
  constexpr double kSubnormalBin = 1e-12;
  const double slow = SpectralPeak_Hz(tone, 1e307, 0.0, 1.0);
  EXPECT_NEAR(slow * 1e307 * 1000 / unit, 1.0, kSubnormalBin);
}

TEST(WhiteNoiseMagnitudeTest, MatchesTheTransformOfWhiteNoise) {
  // The impulse's filter energy against the mean |W|^2 of a long white-noise
  // record (unit variance), inside the cone. The mean over M effectively
  // independent coefficients has a relative standard error of 1/sqrt(M); at
  // the lowest frequency, 20 Hz, the filter lasts about 2 sigma_t s = 0.07 s,
  // so 40 s give M > 500 and an error below 5 %: 10 % is two of them.
  constexpr double kRelativeTolerance = 0.10;
  const double step = 1e-3;
  CwtOptions options;
  options.frequencies.min_frequency_Hz = 20.0;
  options.frequencies.max_frequency_Hz = 400.0;
  options.frequencies.voices_per_octave = 4;
  const Eigen::Index n = 40000;
  std::mt19937_64 engine(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::VectorXd noise(n);
  for (Eigen::Index i = 0; i < n; ++i) noise[i] = normal(engine);
  const Scalogram s = Cwt(noise, step, options);
  const Eigen::VectorXd expected = WhiteNoiseMagnitude(options, n, step);
  ASSERT_EQ(expected.size(), s.frequencies());
  for (Eigen::Index k = 0; k < s.frequencies(); ++k) {
    double sum = 0.0;
    int count = 0;
    for (Eigen::Index j = 0; j < s.times(); ++j) {
      if (!s.InsideCoi(j, k)) continue;
      sum += std::norm(s.coefficients(j, k) * s.coefficient_scale);
      ++count;
    }
    ASSERT_GT(count, 0);
    EXPECT_NEAR(std::sqrt(sum / count) / expected[k], 1.0, kRelativeTolerance) << s.frequencies_Hz[k] << " Hz";
  }
  // Band-limited output has the same W (and so the same noise level).
  options.band_limited = true;
  EXPECT_TRUE(WhiteNoiseMagnitude(options, n, step).isApprox(expected, 1e-9));
}

TEST(WhiteNoiseMagnitudeTest, EqualsTheImpulseTransformsEnergy) {
  // The filters' energies by Parseval against what they replace: the
  // full-rate, zero-padded transform of a unit impulse at the record's middle,
  // |W|^2 summed over the record's times. That sum misses the filter's
  // energy beyond half the record from the impulse, so it is a lower bound
  // to round-off (~1e-15 log2 P: 1e-12). The Gaussian bands fit well inside
  // (the lowest frequency, 20 Hz, lasts about 0.07 s of the 8 s), except
  // where Nyquist cuts a band: the cut rings as 1/t, and measured the sum
  // then misses up to 4.7e-7 of the energy (Morlet at 380 Hz, Nyquist 500
  // Hz; 0 to round-off below 300 Hz): 1e-6 above.
  constexpr double kRoundOff = 1e-12;
  constexpr double kTailsMissed = 1e-6;
  const double step = 1e-3;
  const Eigen::Index n = 8000;
  for (const bool morse : {false, true}) {
    CwtOptions options;
    options.frequencies.min_frequency_Hz = 20.0;
    options.frequencies.max_frequency_Hz = 400.0;
    options.frequencies.voices_per_octave = 8;
    if (morse) options.wavelet.family = WaveletFamily::kMorse;  // gamma 3, beta 20
    CwtOptions impulse_options = options;
    impulse_options.padding = Padding::kZero;
    impulse_options.remove_mean = false;
    Eigen::VectorXd impulse = Eigen::VectorXd::Zero(n);
    impulse[n / 2] = 1.0;
    const Scalogram s = Cwt(impulse, step, impulse_options);
    const Eigen::VectorXd expected = s.coefficients.colwise().norm().transpose() * s.coefficient_scale;
    const Eigen::VectorXd magnitude = WhiteNoiseMagnitude(options, n, step);
    ASSERT_EQ(magnitude.size(), expected.size());
    for (Eigen::Index k = 0; k < expected.size(); ++k) {
      const double ratio = magnitude[k] / expected[k];
      EXPECT_GE(ratio, 1.0 - kRoundOff) << (morse ? "Morse " : "Morlet ") << s.frequencies_Hz[k] << " Hz";
      EXPECT_LE(ratio, 1.0 + (s.frequencies_Hz[k] < 300.0 ? kRoundOff : kTailsMissed))
          << (morse ? "Morse " : "Morlet ") << s.frequencies_Hz[k] << " Hz";
    }
  }
  EXPECT_THROW(WhiteNoiseMagnitude(CwtOptions{}, 3, step), std::invalid_argument);
  EXPECT_THROW(WhiteNoiseMagnitude(CwtOptions{}, n, 0.0), std::invalid_argument);
  EXPECT_THROW(WhiteNoiseMagnitude(CwtOptions{}, Eigen::Index{1} << 28, step), std::invalid_argument);
  CwtOptions above;
  above.frequencies.max_frequency_Hz = 600.0;  // Nyquist 500 Hz
  EXPECT_THROW(WhiteNoiseMagnitude(above, n, step), std::invalid_argument);
}

}  // namespace
}  // namespace podid::wavelet
