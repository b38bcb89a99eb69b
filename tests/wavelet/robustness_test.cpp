// Hostile input for the wavelet module (issue 10 item 8b): any finite signal
// works, whatever its magnitude; sizes are bounded by a memory budget; the
// ridge never reads outside the scalogram whatever its coefficients hold.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "podid/wavelet/cwt.hpp"
#include "podid/wavelet/ridge.hpp"
#include "test_support.hpp"

namespace podid::wavelet {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kStep = 1.0 / 5000.0;

// 1 s of a 33.3 Hz tone (not a whole number of periods) of amplitude a.
Eigen::VectorXd Tone(double amplitude) {
  Eigen::VectorXd x(5001);
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    x(i) = amplitude * std::cos(2 * kPi * 33.3 * static_cast<double>(i) * kStep + 0.4);
  }
  return x;
}

TEST(ExtremeAmplitudes, RidgeOfAToneIsTheSameAtAnyMagnitude) {
  // The transform scales the signal by a power of 2 (exact), so the IF of
  // a*cos equals the unit tone's to rounding of a*cos itself (1e-16) carried
  // through the FFTs; 1e-10 relative leaves room for that and nothing else.
  // Before the fix 1e200 crashed (|W|^2 overflowed), 1e300 aborted, 1e-150
  // gave an IF of 0 Hz.
  constexpr double kRelativeTolerance = 1e-10;
  RidgeFrequencyOptions options;
  options.cwt.band_limited = false;
  const RidgeTrack unit = RidgeFrequency(Tone(1.0), kStep, options);
  ASSERT_GT(unit.InsideCoiCount(), 3000);
  for (double amplitude : {1e200, 1e300, 1.7e308, 1e-150, 1e-300}) {
    SCOPED_TRACE(amplitude);
    const RidgeTrack track = RidgeFrequency(Tone(amplitude), kStep, options);
    ASSERT_EQ(track.size(), unit.size());
    for (Eigen::Index j = 0; j < track.size(); ++j) {
      ASSERT_EQ(track.frequency_index(j), unit.frequency_index(j)) << j;
      ASSERT_NEAR(track.frequency_Hz(j), unit.frequency_Hz(j),
                  kRelativeTolerance * unit.frequency_Hz(j))
          << j;
      ASSERT_NEAR(track.amplitude(j) / amplitude, unit.amplitude(j),
                  kRelativeTolerance * unit.amplitude(j))
          << j;
    }
  }
}

TEST(ExtremeAmplitudes, CoefficientsStayInSignalUnitsUnlessTheyCannot) {
  // Up to 2^960 the coefficients are W itself (scaled back exactly); beyond,
  // W = coefficient_scale * coefficients with a power-of-2 scale.
  constexpr double kRelativeTolerance = 1e-12;  // rounding of a*cos only
  CwtOptions options;
  const Scalogram unit = Cwt(Tone(1.0), kStep, options);
  const Scalogram big = Cwt(Tone(1e200), kStep, options);
  EXPECT_EQ(big.coefficient_scale, 1.0);
  const Scalogram huge = Cwt(Tone(1e300), kStep, options);
  EXPECT_EQ(huge.coefficient_scale, std::ldexp(1.0, 996));  // 1e300 = 1.67 * 2^996
  const double peak = unit.coefficients.cwiseAbs().maxCoeff();
  for (Eigen::Index k = 0; k < unit.frequencies(); k += 7) {
    for (Eigen::Index j = 0; j < unit.times(); j += 101) {
      EXPECT_NEAR(std::abs(big.coefficients(j, k) / 1e200 - unit.coefficients(j, k)), 0.0,
                  kRelativeTolerance * peak);
      EXPECT_NEAR(std::abs(huge.coefficients(j, k) * (huge.coefficient_scale / 1e300) -
                           unit.coefficients(j, k)),
                  0.0, kRelativeTolerance * peak);
    }
  }
}

TEST(ExtremeAmplitudes, OneHugeSampleInAUnitToneIsAnImpulse) {
  // A 1e200 sample swamps the unit tone (1e-200 of it, below rounding): the
  // result is the impulse's. For an impulse at t0 every scale's coefficient
  // is (step / s) conj(psi((t0 - t) / s)), whose phase derivative is exactly
  // omega0 / s: the IF at any ridge point equals the analysis frequency there
  // (kAmplitude, kappa = omega0). Away from the reflected images (>= 0.7 s,
  // 7 scales at 10 Hz: exp(-26)) that holds to the band truncation, 1e-9.
  // The mean is kept: removing it leaves a constant 2e-4 of the impulse whose
  // tiny W (psi^(0) = 1.5e-8) has IF 0 and shifts the 10 Hz IF by 5e-7.
  constexpr double kRelativeTolerance = 1e-9;
  Eigen::VectorXd spiked = Tone(1.0);
  spiked(2500) = 1e200;
  Eigen::VectorXd impulse = Eigen::VectorXd::Zero(5001);
  impulse(2500) = 1e200;
  RidgeFrequencyOptions options;
  options.cwt.band_limited = false;
  options.cwt.remove_mean = false;
  options.ridge.parabolic_refinement = false;
  const RidgeTrack a = RidgeFrequency(spiked, kStep, options);
  const RidgeTrack b = RidgeFrequency(impulse, kStep, options);
  int checked = 0;
  for (Eigen::Index j = 0; j < a.size(); ++j) {
    // Far from the impulse |W| is below 1e-6 of its peak: screened (no IF).
    ASSERT_EQ(a.screened(j), b.screened(j)) << j;
    if (a.screened(j)) continue;
    ASSERT_TRUE(std::isfinite(a.frequency_Hz(j))) << j;
    ASSERT_NEAR(a.frequency_Hz(j), b.frequency_Hz(j), kRelativeTolerance * b.frequency_Hz(j));
    if (a.time_s(j) < 0.2 || a.time_s(j) > 0.8) continue;
    ASSERT_NEAR(a.frequency_Hz(j), a.grid_frequency_Hz(j), kRelativeTolerance * a.frequency_Hz(j))
        << j;
    ++checked;
  }
  EXPECT_EQ(checked, 3001);
}

TEST(ExtremeAmplitudes, NonFiniteCoefficientsAreNeverARidge) {
  // FindRidges takes any Scalogram: NaN and Inf cells are forbidden, a column
  // of them is "no ridge" (-1) and the path restarts after it. Before the fix
  // PenalisedPath read uninitialised envelope indices (a crash or an index
  // out of range).
  Scalogram sg = Cwt(Tone(1.0), kStep);
  const Eigen::Index mid = sg.times() / 2;
  const double inf = std::numeric_limits<double>::infinity();
  sg.coefficients.row(mid).setConstant(std::complex<double>(inf, 0.0));
  sg.coefficients.row(mid + 1).setConstant(std::complex<double>(std::nan(""), 1.0));
  sg.coefficients(mid + 2, 3) = std::complex<double>(-inf, inf);
  for (RidgeMethod method : {RidgeMethod::kPenalised, RidgeMethod::kMaximum}) {
    RidgeOptions options;
    options.method = method;
    options.ridges = 2;
    const std::vector<Eigen::VectorXi> paths = FindRidges(sg, options);
    ASSERT_EQ(paths.size(), 2u);
    for (const Eigen::VectorXi& path : paths) {
      EXPECT_EQ(path(mid), -1);
      EXPECT_EQ(path(mid + 1), -1);
      EXPECT_NE(path(mid + 2), 3);
      EXPECT_GE(path.minCoeff(), -1);
      EXPECT_LT(path.maxCoeff(), sg.frequencies());
    }
    // The main ridge is the tone's on both sides of the gap.
    EXPECT_NEAR(sg.frequencies_Hz(paths[0](mid - 200)), 33.3, 0.5);
    EXPECT_NEAR(sg.frequencies_Hz(paths[0](mid + 200)), 33.3, 0.5);
  }
}

TEST(ExtremeAmplitudes, TrackRidgeRejectsAPathOutsideTheScalogram) {
  const Scalogram sg = Cwt(Tone(1.0), kStep);
  Eigen::VectorXi path = Eigen::VectorXi::Zero(sg.times());
  path(10) = static_cast<int>(sg.frequencies());
  PODID_EXPECT_THROW_WITH(TrackRidge(sg, path, RidgeOptions{}, nullptr), std::invalid_argument,
                          "TrackRidge: path(10): expected -1 (no ridge) or a frequency index");
}

TEST(MemoryBudget, TooManyBinsIsAnInputErrorBeforeAllocating) {
  // --bins 100000 on 5001 samples: 5001 x 100000 x 16 bytes = 8 GB of
  // coefficients alone. Before the fix: 8 GB then std::bad_alloc.
  CwtOptions options;
  options.frequencies.spacing = FrequencySpacing::kLinear;
  options.frequencies.bins = 100000;
  PODID_EXPECT_THROW_WITH(Cwt(Tone(1.0), kStep, options), std::invalid_argument,
                          "Cwt: memory: expected at most 2147483648 bytes "
                          "(CwtOptions::memory_budget_bytes), got 8");
  options.frequencies.bins = 2000;  // 160 MB: within the default budget
  options.memory_budget_bytes = 100e6;
  PODID_EXPECT_THROW_WITH(Cwt(Tone(1.0), kStep, options), std::invalid_argument,
                          "5001 output times x 2000 frequencies x 16 bytes");
  options.memory_budget_bytes = 1e3;
  PODID_EXPECT_THROW_WITH(CwtTransform{options}, std::invalid_argument,
                          "CwtOptions.memory_budget_bytes: expected 2^16..2^44, got 1000");
  // W's share of a 1 MB limit (16 of the 24 bytes a synchrosqueezed
  // coefficient takes) is a budget, refused for what it cannot hold.
  options.memory_budget_bytes = 1048576.0 * 16.0 / 24.0;
  PODID_EXPECT_THROW_WITH(Cwt(Tone(1.0), kStep, options), std::invalid_argument,
                          "Cwt: memory: expected at most 699050.6667 bytes");
}

TEST(SinglePrecision, MagnitudeOutputIsTheRoundedComplexMagnitude) {
  // CwtOutput::kMagnitudeFloat stores |W| once rounded to float: relative
  // 2^-24 (6e-8) of each value from the rounding, plus double rounding of
  // |W| itself (1e-16); 1e-7 relative is the float's own precision.
  constexpr double kRelativeTolerance = 1e-7;
  CwtOptions options;
  options.frequencies.voices_per_octave = 8;
  const Scalogram full = Cwt(Tone(3.0), kStep, options);
  options.output = CwtOutput::kMagnitudeFloat;
  const Scalogram magnitude = Cwt(Tone(3.0), kStep, options);
  ASSERT_EQ(magnitude.coefficients.size(), 0);
  ASSERT_EQ(magnitude.magnitude.rows(), full.times());
  ASSERT_EQ(magnitude.magnitude.cols(), full.frequencies());
  for (Eigen::Index k = 0; k < full.frequencies(); ++k) {
    for (Eigen::Index j = 0; j < full.times(); ++j) {
      const double expected = std::abs(full.coefficients(j, k));
      ASSERT_NEAR(magnitude.magnitude(j, k), expected, kRelativeTolerance * expected)
          << j << " " << k;
    }
  }
  // 4 bytes per coefficient: 5001 x 20000 fits a budget 16 bytes would not.
  options.frequencies.spacing = FrequencySpacing::kLinear;
  options.frequencies.bins = 20000;
  options.memory_budget_bytes = 1e9;
  EXPECT_NO_THROW(CwtTransform{options}.Lengths(5001, kStep));
  Scalogram big;
  CwtTransform transform(options);
  EXPECT_NO_THROW(transform.Compute(Tone(1.0), kStep, &big));
  options.output = CwtOutput::kComplex;
  PODID_EXPECT_THROW_WITH(Cwt(Tone(1.0), kStep, options), std::invalid_argument,
                          "frequencies x 16 bytes");
  // Ridges need the complex coefficients.
  PODID_EXPECT_THROW_WITH(FindRidges(magnitude, RidgeOptions{}), std::invalid_argument,
                          "expected a computed scalogram with complex coefficients");
}

TEST(SinglePrecision, ComplexFloatOutputIsTheRoundedComplexOutput) {
  // CwtOutput::kComplexFloat computes W in double and rounds each part once:
  // bit for bit the complex output cast to complex<float>, full rate and
  // band-limited, on one thread or three, for a peak of 3000 (2^11: still in
  // signal units, no coefficient_scale).
  CwtOptions options;
  options.frequencies.voices_per_octave = 8;
  const Eigen::VectorXd x = 1000.0 * Tone(3.0);
  for (const bool band_limited : {false, true}) {
    options.band_limited = band_limited;
    options.output = CwtOutput::kComplex;
    const Scalogram full = Cwt(x, kStep, options);
    ASSERT_EQ(full.coefficient_scale, 1.0);
    options.output = CwtOutput::kComplexFloat;
    for (const int threads : {1, 3}) {
      options.threads = threads;
      const Scalogram single = Cwt(x, kStep, options);
      EXPECT_EQ(single.coefficients.size(), 0);
      EXPECT_EQ(single.magnitude.size(), 0);
      EXPECT_EQ(single.coefficient_scale, 1.0);
      EXPECT_TRUE(single.coefficients_float == full.coefficients.cast<std::complex<float>>())
          << "band_limited " << band_limited << ", threads " << threads;
    }
    options.threads = 1;
  }
  // 8 bytes per coefficient: a budget of 12 bytes a cell (the rest, FFT
  // buffers of about 10^4 points, is far below 4 a cell) takes it, not 16.
  options.band_limited = false;
  options.frequencies.spacing = FrequencySpacing::kLinear;
  options.frequencies.bins = 1000;
  options.memory_budget_bytes = 12.0 * 5001.0 * 1000.0;
  EXPECT_EQ(Cwt(Tone(1.0), kStep, options).coefficients_float.size(), 5001 * 1000);
  options.output = CwtOutput::kComplex;
  PODID_EXPECT_THROW_WITH(Cwt(Tone(1.0), kStep, options), std::invalid_argument,
                          "frequencies x 16 bytes");
  // Ridges need the complex double coefficients.
  options = CwtOptions{};
  options.output = CwtOutput::kComplexFloat;
  PODID_EXPECT_THROW_WITH(FindRidges(Cwt(Tone(1.0), kStep, options), RidgeOptions{}),
                          std::invalid_argument,
                          "expected a computed scalogram with complex coefficients");
}

TEST(SinglePrecision, FloatOutputsOfExtremeAmplitudesStayInRange) {
  // Float's range ends at 3.4e38 and its normals at 1.2e-38: a tone of
  // amplitude 1e40 gave |W| = inf as float, one of 1e-100 gave 0. Beyond
  // 2^+-32 the float outputs are in units of coefficient_scale (a power of
  // 2), as the complex output is beyond 2^+-960; scaled back they are the
  // complex |W| to the float's precision (1e-7 relative, as above).
  constexpr double kRelativeTolerance = 1e-7;
  CwtOptions options;
  options.frequencies.voices_per_octave = 4;
  for (const double amplitude : {1e40, 1e12, 1e-12, 1e-100}) {
    const Eigen::VectorXd x = amplitude * Tone(3.0);
    options.output = CwtOutput::kComplex;
    const Scalogram full = Cwt(x, kStep, options);
    ASSERT_EQ(full.coefficient_scale, 1.0);
    const Eigen::ArrayXXd expected = full.coefficients.cwiseAbs().array();
    options.output = CwtOutput::kMagnitudeFloat;
    const Scalogram magnitude = Cwt(x, kStep, options);
    options.output = CwtOutput::kComplexFloat;
    const Scalogram single = Cwt(x, kStep, options);
    for (const Scalogram* sg : {&magnitude, &single}) {
      EXPECT_NE(sg->coefficient_scale, 1.0) << amplitude;
      EXPECT_EQ(std::exp2(std::round(std::log2(sg->coefficient_scale))), sg->coefficient_scale);
    }
    const Eigen::ArrayXXd from_magnitude =
        magnitude.magnitude.cast<double>().array() * magnitude.coefficient_scale;
    const Eigen::ArrayXXd from_single =
        single.coefficients_float.cast<std::complex<double>>().cwiseAbs().array() *
        single.coefficient_scale;
    ASSERT_TRUE(from_magnitude.allFinite() && from_single.allFinite()) << amplitude;
    EXPECT_LE(((from_magnitude - expected).abs() - kRelativeTolerance * expected).maxCoeff(), 0.0)
        << amplitude;
    // Complex float rounds both parts: |W| within twice the float's rounding.
    EXPECT_LE(((from_single - expected).abs() - 2.0 * kRelativeTolerance * expected).maxCoeff(),
              0.0)
        << amplitude;
  }
}

TEST(SinglePrecision, EnergyNormalisedFloatOutputsAtTheExtremeStepsStayInRange) {
  // The energy normalisation multiplies W by sqrt(s): float outputs of a unit
  // tone were 0 in every cell at a step of 1e-200 s and inf at 1e60 s with
  // amplitude 2^32. Steps are 1e-15 .. 1e15 s now, and at both ends the
  // float outputs of the amplitudes still left in signal units (2^-32 and
  // just below 2^33) are the time-scaled transform: for x_i = A cos(2 pi
  // 0.1 i) on frequencies 0.05 / h .. 0.2 / h, W(h, A) = A sqrt(h) W(1 s, 1)
  // exactly, up to rounding (1e-7 relative as above, 2e-7 for complex float).
  constexpr double kRelativeTolerance = 1e-7;
  CwtOptions options;
  options.frequencies.voices_per_octave = 4;
  options.wavelet.normalisation = Normalisation::kEnergy;
  const auto grid = [&options](double step_s) {
    options.frequencies.min_frequency_Hz = 0.05 / step_s;
    options.frequencies.max_frequency_Hz = 0.2 / step_s;
  };
  Eigen::VectorXd x(2001);
  for (Eigen::Index i = 0; i < x.size(); ++i)
    x(i) = std::cos(2.0 * kPi * 0.1 * static_cast<double>(i));
  grid(1.0);
  const Eigen::ArrayXXd unit = Cwt(x, 1.0, options).coefficients.cwiseAbs().array();
  // The smallest cell is 7e-9 of the largest (at a border): 1.5e-25 at
  // 1e-15 s and 2^-32, still far above float's normals (1.2e-38).
  ASSERT_GT(unit.minCoeff(), 1e-9 * unit.maxCoeff());
  for (const double step_s : {1e-15, 1e15}) {
    grid(step_s);
    for (const double amplitude : {std::ldexp(1.0, -32), 0.99 * std::ldexp(1.0, 33)}) {
      SCOPED_TRACE(::testing::Message() << "step " << step_s << " s, amplitude " << amplitude);
      const Eigen::ArrayXXd expected = amplitude * std::sqrt(step_s) * unit;
      options.output = CwtOutput::kMagnitudeFloat;
      const Scalogram magnitude = Cwt(amplitude * x, step_s, options);
      options.output = CwtOutput::kComplexFloat;
      const Scalogram single = Cwt(amplitude * x, step_s, options);
      options.output = CwtOutput::kComplex;
      EXPECT_EQ(magnitude.coefficient_scale, 1.0);
      EXPECT_EQ(single.coefficient_scale, 1.0);
      const Eigen::ArrayXXd from_magnitude = magnitude.magnitude.cast<double>().array();
      const Eigen::ArrayXXd from_single =
          single.coefficients_float.cast<std::complex<double>>().cwiseAbs().array();
      ASSERT_TRUE(from_magnitude.allFinite() && from_single.allFinite());
      EXPECT_LE(((from_magnitude - expected).abs() - kRelativeTolerance * expected).maxCoeff(),
                0.0);
      EXPECT_LE(((from_single - expected).abs() - 2.0 * kRelativeTolerance * expected).maxCoeff(),
                0.0);
    }
  }
  // Just outside, a clear refusal (as for 0, inf or a subnormal step).
  for (const double step_s : {0.99e-15, 1.01e15}) {
    grid(1.0);
    PODID_EXPECT_THROW_WITH(Cwt(x, step_s, options), std::invalid_argument,
                            "Cwt: step_s: expected a finite value between 1e-15 s and 1e15 s");
  }
}

}  // namespace
}  // namespace podid::wavelet
