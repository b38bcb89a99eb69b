// The wavelet API's contract on values a caller sets (an audit of the public
// API, 2026-12-01): every option and hand-filled struct field is checked with
// a message naming it, sizes are bounded before any arithmetic on them, and
// results beyond double precision are an error, never inf. Each case below
// aborted, hung, overflowed or returned garbage before its fix.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdint>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "podid/wavelet/cwt.hpp"
#include "podid/wavelet/denoise.hpp"
#include "podid/wavelet/plans.hpp"
#include "podid/wavelet/ridge.hpp"
#include "podid/wavelet/synthesis.hpp"
#include "test_support.hpp"

namespace podid::wavelet {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kStep = 1e-3;

// 2 s of a 50 Hz tone of amplitude a at 1 kHz.
Eigen::VectorXd Tone(double amplitude) {
  Eigen::VectorXd x(2000);
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    x(i) = amplitude * std::cos(2.0 * kPi * 50.0 * static_cast<double>(i) * kStep);
  }
  return x;
}

CwtOptions ToneOptions() {
  CwtOptions o;
  o.frequencies = FrequencyGrid::Log(20.0, 200.0, 16);
  return o;
}

std::string Why(const CwtOptions& o) {
  std::string why;
  EXPECT_FALSE(o.IsValid(&why));
  return why;
}

TEST(ApiContract, CorrectedMorletRidgeForEveryAcceptedOmega0) {
  // The ridge's slope was a ratio of two exponentials that underflow from
  // omega0 77.5 on (an abort, for the documented range up to 100). There the
  // correction exp(-u omega0) is below 1e-2000: the corrected wavelet is the
  // plain one, whose ridge has a closed form (omega0 for the amplitude
  // normalisation, (omega0 + sqrt(omega0^2 + 2)) / 2 for energy), to the
  // bisection's rounding (4e-16 relative).
  for (double omega0 : {40.0, 77.5, 80.0, 100.0}) {
    for (Normalisation n : {Normalisation::kAmplitude, Normalisation::kEnergy}) {
      MorletWavelet w;
      w.omega0 = omega0;
      w.normalisation = n;
      const double plain = w.RidgeAngularFrequency();
      w.admissibility_correction = true;
      ASSERT_TRUE(w.IsValid(nullptr));
      EXPECT_NEAR(w.RidgeAngularFrequency(), plain, 1e-14 * plain) << omega0;
      CwtOptions o = ToneOptions();
      o.wavelet = w;
      EXPECT_NO_THROW(CwtTransform{o}) << omega0;
    }
  }
  // The smallest accepted omega0: the ridge maximises n(u) psi^(u) against
  // neighbours 1e-6 away (curvature ~1 there: a change of 1e-12, above psi^'s
  // rounding), and psi^(0) = 0.
  MorletWavelet w;
  w.admissibility_correction = true;
  w.omega0 = kMinCorrectedOmega0;
  for (Normalisation n : {Normalisation::kAmplitude, Normalisation::kEnergy}) {
    w.normalisation = n;
    const double kappa = w.RidgeAngularFrequency();
    const auto g = [&](double u) {
      return (n == Normalisation::kEnergy ? std::sqrt(u) : 1.0) * w.FourierTransform(u);
    };
    EXPECT_GT(g(kappa), g(kappa - 1e-6));
    EXPECT_GT(g(kappa), g(kappa + 1e-6));
    EXPECT_EQ(w.FourierTransform(0.0), 0.0);
  }
  w.omega0 = 0.4;
  std::string why;
  EXPECT_FALSE(w.IsValid(&why));
  EXPECT_NE(why.find("omega0: expected >= 0.5 with admissibility_correction, got 0.4"),
            std::string::npos)
      << why;
}

TEST(ApiContract, EnumsOutsideTheirValuesAreRefused) {
  // Enums are ints underneath: a cast of 7 divided by zero (padding), aborted
  // (output), or was read differently by each file (family, normalisation).
  CwtOptions o = ToneOptions();
  o.padding = static_cast<Padding>(7);
  EXPECT_NE(Why(o).find("CwtOptions.padding: expected kReflect, kZero or kPeriodic, got 7"),
            std::string::npos);
  o = ToneOptions();
  o.output = static_cast<CwtOutput>(7);
  EXPECT_NE(Why(o).find("CwtOptions.output"), std::string::npos);
  o = ToneOptions();
  o.planning = static_cast<FftPlanning>(7);
  EXPECT_NE(Why(o).find("CwtOptions.planning"), std::string::npos);
  o = ToneOptions();
  o.wavelet.family = static_cast<WaveletFamily>(7);
  EXPECT_NE(Why(o).find("MorletWavelet.family"), std::string::npos);
  o = ToneOptions();
  o.wavelet.normalisation = static_cast<Normalisation>(7);
  EXPECT_NE(Why(o).find("MorletWavelet.normalisation"), std::string::npos);
  o = ToneOptions();
  o.wavelet.convention = static_cast<ScaleConvention>(7);
  EXPECT_NE(Why(o).find("MorletWavelet.convention"), std::string::npos);
  o = ToneOptions();
  o.frequencies.spacing = static_cast<FrequencySpacing>(7);
  EXPECT_NE(Why(o).find("FrequencyGrid.spacing"), std::string::npos);
  o = ToneOptions();
  PODID_EXPECT_THROW_WITH(CwtTransform{o}.Compute(Tone(1.0), kStep, nullptr), std::invalid_argument,
                          "expected a Scalogram to write, got null");
  RidgeOptions r;
  r.estimator = static_cast<FrequencyEstimator>(7);
  std::string why;
  EXPECT_FALSE(r.IsValid(&why));
  EXPECT_NE(why.find("RidgeOptions.estimator"), std::string::npos) << why;
  r = RidgeOptions{};
  r.method = static_cast<RidgeMethod>(7);
  EXPECT_FALSE(r.IsValid(&why));
  EXPECT_NE(why.find("RidgeOptions.method"), std::string::npos) << why;
  DenoiseOptions denoise;
  denoise.rule = static_cast<ThresholdRule>(7);  // was read as kHard
  EXPECT_FALSE(denoise.IsValid(&why));
  EXPECT_NE(why.find("DenoiseOptions.rule: expected kSoft or kHard, got 7"), std::string::npos)
      << why;
  PODID_EXPECT_THROW_WITH(MeasureFftPlans(FftLengths{}, static_cast<PlanEffort>(9)),
                          std::invalid_argument, "MeasureFftPlans: effort");
  PODID_EXPECT_THROW_WITH(MergeFftLengths(FftLengths{}, nullptr), std::invalid_argument,
                          "MergeFftLengths");
}

TEST(ApiContract, TheUnusedFamilysParametersAreCheckedToo) {
  // gamma = NaN beside the Morlet family was accepted (the Python bindings
  // passed it on); with the Morse family, NaN bisected forever in Band.
  MorletWavelet w;
  w.gamma = kNaN;
  std::string why;
  EXPECT_FALSE(w.IsValid(&why));
  EXPECT_NE(why.find("MorletWavelet.gamma"), std::string::npos) << why;
  w.family = WaveletFamily::kMorse;
  double lo = 0.0, hi = 0.0;
  PODID_EXPECT_THROW_WITH(w.Band(1e-6, &lo, &hi), std::invalid_argument, "MorletWavelet.gamma");
  PODID_EXPECT_THROW_WITH(w.TimeSpread(), std::invalid_argument, "MorletWavelet.gamma");
  PODID_EXPECT_THROW_WITH(ReconstructionConstant(w), std::invalid_argument, "MorletWavelet.gamma");
  w = MorletWavelet{};
  w.beta = -1.0;
  EXPECT_FALSE(w.IsValid(&why));
  PODID_EXPECT_THROW_WITH(w.Band(0.0, &lo, &hi), std::invalid_argument,
                          "tolerance: expected a value in (0, 1), got 0");
  w = MorletWavelet{};
  w.omega0 = kNaN;
  PODID_EXPECT_THROW_WITH(ReconstructionConstant(w), std::invalid_argument, "omega0");
}

TEST(ApiContract, RecordLengthsAreBoundedBeforeAnyArithmetic) {
  // 2^61 samples aborted, 2^62 hung (signed overflow in the padded length),
  // INT64_MAX returned P = 1. Nothing is allocated for these checks.
  const CwtOptions o = ToneOptions();
  for (const std::int64_t samples :
       {(std::int64_t{1} << 27) + 1, std::int64_t{1} << 61, std::int64_t{1} << 62,
        std::numeric_limits<std::int64_t>::max()}) {
    PODID_EXPECT_THROW_WITH(CwtFftLengths(o, samples, kStep), std::invalid_argument,
                            "at most 2^27 = 134217728 samples");
    PODID_EXPECT_THROW_WITH(CwtTransform{o}.WhiteNoiseMagnitude(samples, kStep),
                            std::invalid_argument, "at most 2^27 = 134217728 samples");
  }
  // Within the record bound, zero padding of 2^26 + 1 samples for a wavelet
  // longer than the record (1e-5 Hz: 5e8 samples) needs a padded length above
  // 2^27 points: Compute() aborted in the FFT planner there.
  CwtOptions low = o;
  low.frequencies = FrequencyGrid::Log(1e-5, 200.0, 1);
  PODID_EXPECT_THROW_WITH(CwtFftLengths(low, (std::int64_t{1} << 26) + 1, kStep),
                          std::invalid_argument, "padded length: expected at most 2^27");
  // Periodic padding takes the record itself: 2^27 samples is the largest.
  CwtOptions periodic = o;
  periodic.padding = Padding::kPeriodic;
  periodic.band_limited = true;
  EXPECT_EQ(CwtFftLengths(periodic, std::int64_t{1} << 27, kStep).complex_forward.front(), 1 << 27);
}

TEST(ApiContract, TheLowestFrequencyIsBoundedByTheSamplingRate) {
  // 1e-300 Hz put a scale of 1e300 s on bin 0 (inside every Morlet band):
  // the energy normalisation's sqrt(s) made 576000 of the float magnitudes
  // inf. The bound is 1e-20 of the sampling rate.
  CwtOptions o = ToneOptions();
  o.wavelet.normalisation = Normalisation::kEnergy;
  o.output = CwtOutput::kMagnitudeFloat;
  o.frequencies = FrequencyGrid::Log(1e-300, 100.0, 1);
  PODID_EXPECT_THROW_WITH(Cwt(Tone(1.0), kStep, o), std::invalid_argument,
                          "min_frequency_Hz: expected >= 1e-20 times the sampling rate 1 / "
                          "step_s, 1e-17 Hz, got 1e-300 Hz");
  // At the bound every float magnitude is finite, as signal_check.hpp's
  // headroom says, at this step and at the largest (the scale grows with it).
  for (const double step : {kStep, kMaxStep_s}) {
    o.frequencies = FrequencyGrid::Log(1e-20 / step, 0.25 / step, 1);
    const Scalogram s = Cwt(Tone(1.0), step, o);
    EXPECT_TRUE(s.magnitude.allFinite()) << step;
    EXPECT_GT(s.magnitude.maxCoeff(), 0.0f) << step;
  }
}

TEST(ApiContract, TheGridCountIsTheCountFrequenciesHzReturns) {
  // IsValid compared v log2(ratio) with the bound, and Frequencies_Hz()
  // returns floor of it + 1: 100001 frequencies passed.
  std::string why;
  EXPECT_FALSE(FrequencyGrid::Log(1.0, std::exp2(100.0), 1000).IsValid(&why));
  EXPECT_NE(why.find("at most 100000 frequencies, got 100001"), std::string::npos) << why;
  EXPECT_TRUE(FrequencyGrid::Log(1.0, std::exp2(99.999), 1000).IsValid(nullptr));
}

TEST(ApiContract, AHandFilledScalogramIsCheckedBeforeItIsRead) {
  CwtTransform transform(ToneOptions());
  Scalogram s;
  transform.Compute(Tone(1.0), kStep, &s);
  const RidgeOptions ridge;
  Scalogram bad = s;
  bad.step_s = -s.step_s;  // aborted the ridge programme
  PODID_EXPECT_THROW_WITH(FindRidges(bad, ridge), std::invalid_argument, "step_s finite and > 0");
  bad = s;
  bad.coefficient_scale = 0.0;
  PODID_EXPECT_THROW_WITH(InverseCwt(bad), std::invalid_argument, "coefficient_scale");
  bad = s;
  bad.wavelet.family = WaveletFamily::kMorse;
  bad.wavelet.beta = kNaN;  // hung the inverse's reconstruction constant
  PODID_EXPECT_THROW_WITH(InverseCwt(bad), std::invalid_argument, "MorletWavelet.beta");
  PODID_EXPECT_THROW_WITH(TrackRidge(bad, FindRidges(s, ridge).front(), ridge, &transform),
                          std::invalid_argument, "MorletWavelet.beta");
}

TEST(ApiContract, AMovedFromTransformIsALogicErrorNotACrash) {
  CwtTransform transform(ToneOptions());
  CwtTransform moved = std::move(transform);
  Scalogram s;
  PODID_EXPECT_THROW_WITH(transform.Compute(Tone(1.0), kStep, &s), std::logic_error,
                          "CwtTransform: used after being moved from");
  EXPECT_THROW(static_cast<void>(transform.padded_length()), std::logic_error);
  EXPECT_NO_THROW(moved.Compute(Tone(1.0), kStep, &s));
  RidgeFrequencyOptions options;
  RidgeFrequencyEstimator estimator(options);
  RidgeFrequencyEstimator other = std::move(estimator);
  PODID_EXPECT_THROW_WITH(estimator.Estimate(Tone(1.0), kStep), std::logic_error,
                          "RidgeFrequencyEstimator: used after being moved from");
}

TEST(ApiContract, ResultsBeyondTheLargestDoubleAreAnOverflowError) {
  // A 50 Hz tone of the largest amplitude: its in-band reconstruction and
  // its ridge's amplitude exceed it by the transform's rounding and the
  // band's ripple (they came back inf). 1e308 stays representable and comes
  // back (synthesis_test checks its value).
  constexpr double kLargest = std::numeric_limits<double>::max();
  const CwtOptions o = ToneOptions();
  CwtTransform transform(o);
  Scalogram s;
  transform.Compute(Tone(kLargest), kStep, &s);
  PODID_EXPECT_THROW_WITH(InverseCwt(s), std::overflow_error,
                          "InverseCwt: the reconstruction overflowed double precision");
  RidgeOptions scale;
  scale.estimator = FrequencyEstimator::kScale;
  PODID_EXPECT_THROW_WITH(TrackRidge(s, FindRidges(s, scale).front(), scale, &transform),
                          std::overflow_error, "TrackRidge: the ridge's amplitude overflowed");
  RidgeFrequencyOptions streamed;
  streamed.cwt = o;
  PODID_EXPECT_THROW_WITH(RidgeFrequency(Tone(kLargest), kStep, streamed), std::overflow_error,
                          "RidgeFrequencyEstimator: the ridge's amplitude overflowed");
  transform.Compute(Tone(1e308), kStep, &s);
  EXPECT_TRUE(InverseCwt(s).allFinite());
}

}  // namespace
}  // namespace podid::wavelet
