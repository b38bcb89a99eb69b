// Tests of podid/wavelet/cwt.hpp against references: closed-form Morlet
// facts, and a direct time-domain convolution with the same padding.
#include "podid/wavelet/cwt.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "podid/wavelet/ridge.hpp"
#include "test_support.hpp"

namespace podid::wavelet {
namespace {

using podid::testing::ExpectMatricesNear;
using Complex = std::complex<double>;
constexpr double kPi = std::numbers::pi;

// A test signal with content over the whole grid: two tones, a chirp and a
// deterministic pseudo-random wobble (no exact symmetries to hide errors).
Eigen::VectorXd MixedSignal(Eigen::Index n, double step_s) {
  Eigen::VectorXd x(n);
  unsigned state = 12345u;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) * step_s;
    state = state * 1664525u + 1013904223u;
    const double r = static_cast<double>(state >> 8) / static_cast<double>(1u << 24) - 0.5;
    x(i) = std::cos(2 * kPi * 21.0 * t + 0.3) +
           0.5 * std::sin(2 * kPi * (40.0 * t + 30.0 * t * t)) + 0.2 * r + 0.7;
  }
  return x;
}

// The even extension's index r(m): |m| mirrored at 0 and N - 1 (period 2N - 2).
Eigen::Index Reflect(Eigen::Index m, Eigen::Index n) {
  m = std::abs(m) % (2 * n - 2);
  return m < n ? m : 2 * n - 2 - m;
}

// The padded sequence the header documents (treated as periodic): reflect
// takes x_{r(i)} for i < N + R and x_{r(i - P)} after, R = ceil((P - N) / 2).
Eigen::VectorXd Pad(const Eigen::VectorXd& x, Padding padding, Eigen::Index p) {
  const Eigen::Index n = x.size();
  Eigen::VectorXd out = Eigen::VectorXd::Zero(p);
  out.head(n) = x;
  if (padding == Padding::kReflect) {
    const Eigen::Index r = (p - n + 1) / 2;
    for (Eigen::Index i = n; i < p; ++i) out(i) = x(Reflect(i < n + r ? i : i - p, n));
  }
  return out;
}

// W(s, t_n) = c(s) sum_m xpad_m conj(psi((t_m - t_n) / s)) step, summed over
// the periodic images of the padded sequence; psi from its closed form.
Eigen::MatrixXcd DirectCwt(const Eigen::VectorXd& padded,
                           Eigen::Index n,
                           double step_s,
                           const Eigen::VectorXd& scales_s,
                           const MorletWavelet& wavelet) {
  const Eigen::Index p = padded.size();
  const bool energy = wavelet.normalisation == Normalisation::kEnergy;
  const double k_norm = energy ? std::pow(kPi, -0.25) : std::sqrt(2.0 / kPi);
  const double c =
      wavelet.admissibility_correction ? std::exp(-0.5 * wavelet.omega0 * wavelet.omega0) : 0.0;
  Eigen::MatrixXcd w(n, scales_s.size());
  for (Eigen::Index k = 0; k < scales_s.size(); ++k) {
    const double s = scales_s(k);
    const double gain = step_s * (energy ? 1.0 / std::sqrt(s) : 1.0 / s);
    // kernel(d) = sum over images of conj(psi((d + l P) step / s)), d = 0 .. P-1.
    Eigen::VectorXcd kernel = Eigen::VectorXcd::Zero(p);
    for (Eigen::Index d = 0; d < p; ++d) {
      for (int l = -6; l <= 6; ++l) {
        const double u = static_cast<double>(d + l * p) * step_s / s;
        if (std::abs(u) > 40.0) continue;
        const Complex psi =
            k_norm * (std::polar(1.0, wavelet.omega0 * u) - c) * std::exp(-0.5 * u * u);
        kernel(d) += std::conj(psi);
      }
    }
    for (Eigen::Index i = 0; i < n; ++i) {
      Complex sum = 0.0;
      for (Eigen::Index m = 0; m < p; ++m) sum += padded(m) * kernel((m - i + p) % p);
      w(i, k) = gain * sum;
    }
  }
  return w;
}

TEST(MorletWavelet, RidgeAngularFrequencyMatchesClosedForms) {
  // Closed forms: kappa = omega0 (L1), (omega0 + sqrt(omega0^2 + 2)) / 2 (L2,
  // Torrence & Compo 1998 table 1); the bisection is good to rounding.
  constexpr double kTolerance = 1e-14;
  MorletWavelet w;
  EXPECT_NEAR(w.RidgeAngularFrequency(), 6.0, kTolerance);
  w.normalisation = Normalisation::kEnergy;
  EXPECT_NEAR(w.RidgeAngularFrequency(), 0.5 * (6.0 + std::sqrt(38.0)), kTolerance);
  EXPECT_NEAR(w.ScaleToFrequency_Hz(w.FrequencyToScale_s(33.0)), 33.0, 1e-12);
}

TEST(MorletWavelet, CorrectedRidgeIsTheMaximumOfTheFilter) {
  // With the correction there is no closed form: check kappa maximises
  // n(u) psi^(u) against neighbours 1e-6 away (a relative 1e-12 is well
  // above rounding of psi^ ~ 1 and well below its curvature 1e-12 / 2).
  for (Normalisation norm : {Normalisation::kAmplitude, Normalisation::kEnergy}) {
    MorletWavelet w;
    w.omega0 = 3.0;
    w.admissibility_correction = true;
    w.normalisation = norm;
    ASSERT_TRUE(w.IsValid(nullptr));
    const double kappa = w.RidgeAngularFrequency();
    const auto g = [&](double u) {
      return (norm == Normalisation::kEnergy ? std::sqrt(u) : 1.0) * w.FourierTransform(u);
    };
    EXPECT_GT(g(kappa), g(kappa - 1e-6));
    EXPECT_GT(g(kappa), g(kappa + 1e-6));
    EXPECT_NEAR(w.FourierTransform(0.0), 0.0, 1e-15);  // admissible: psi^(0) = 0
  }
}

TEST(Cwt, UnitCosineMagnitudeUnderEachNormalisation) {
  // A 33 Hz cosine, 1 s at 5 kHz (33 whole periods, so the reflect padding is
  // the cosine itself): on the ridge s w = kappa, |W| = 1 (L1) and
  // pi^(1/4) sqrt(s/2) exp(-(kappa - omega0)^2 / 2) (L2).
  // The grid holds 33 Hz exactly (min frequency). 1e-9 covers the 1e-12 band
  // truncation and the negative-frequency term exp(-72).
  constexpr double kTolerance = 1e-9;
  const double step = 1.0 / 5000.0;
  Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(5001, 0.0, 1.0);
  Eigen::VectorXd x = (2 * kPi * 33.0 * t).array().cos();
  for (Normalisation norm : {Normalisation::kAmplitude, Normalisation::kEnergy}) {
    CwtOptions o;
    o.padding = Padding::kReflect;  // the whole periods continue exactly
    o.wavelet.normalisation = norm;
    o.frequencies.min_frequency_Hz = 33.0;
    o.frequencies.max_frequency_Hz = 66.0;
    o.frequencies.voices_per_octave = 4;
    const Scalogram sg = Cwt(x, step, o);
    const double s = sg.scales_s(0);
    const double kappa = o.wavelet.RidgeAngularFrequency();
    const double expected = norm == Normalisation::kAmplitude
                                ? 1.0
                                : std::pow(kPi, 0.25) * std::sqrt(s / 2.0) *
                                      std::exp(-0.5 * (kappa - 6.0) * (kappa - 6.0));
    EXPECT_NEAR(expected, o.wavelet.UnitCosineMagnitude(s), 1e-14);
    for (Eigen::Index j = 0; j < sg.times(); j += 97) {
      EXPECT_NEAR(std::abs(sg.coefficients(j, 0)), expected, kTolerance * expected) << j;
    }
  }
}

TEST(Cwt, FftPathEqualsDirectConvolution) {
  // The FFT path and the closed-form time-domain convolution on the same
  // padded (periodic) sequence agree to rounding plus the 1e-12 band
  // truncation; 1e-10 of max |W| is the acceptance figure.
  constexpr double kRelativeTolerance = 1e-10;
  const double step = 1e-3;
  const Eigen::VectorXd x = MixedSignal(301, step);
  for (Padding padding : {Padding::kReflect, Padding::kZero, Padding::kPeriodic}) {
    for (Normalisation norm : {Normalisation::kAmplitude, Normalisation::kEnergy}) {
      for (bool corrected : {false, true}) {
        CwtOptions o;
        o.padding = padding;
        o.remove_mean = false;
        o.wavelet.normalisation = norm;
        o.wavelet.admissibility_correction = corrected;
        o.frequencies.min_frequency_Hz = 8.0;
        o.frequencies.max_frequency_Hz = 200.0;  // psi^ negligible at Nyquist (see header)
        o.frequencies.voices_per_octave = 1;
        CwtTransform transform(o);
        Scalogram sg;
        transform.Compute(x, step, &sg);
        const Eigen::MatrixXcd direct = DirectCwt(Pad(x, padding, transform.padded_length()),
                                                  x.size(), step, sg.scales_s, o.wavelet);
        const double scale = direct.cwiseAbs().maxCoeff();
        EXPECT_TRUE(
            ExpectMatricesNear(sg.coefficients.real(), direct.real(), kRelativeTolerance * scale))
            << ToString(padding) << " " << ToString(norm) << " corrected " << corrected;
        EXPECT_TRUE(
            ExpectMatricesNear(sg.coefficients.imag(), direct.imag(), kRelativeTolerance * scale))
            << ToString(padding) << " " << ToString(norm) << " corrected " << corrected;
      }
    }
  }
}

TEST(Cwt, MeanRemovalEqualsTransformOfCentredSignal) {
  // Removing the mean is the same as transforming x - mean(x) (rounding only).
  constexpr double kTolerance = 1e-13;
  const Eigen::VectorXd x = MixedSignal(500, 1e-3);
  CwtOptions with, without;
  without.remove_mean = false;
  const Eigen::VectorXd centred = x.array() - x.mean();
  const Scalogram a = Cwt(x, 1e-3, with), b = Cwt(centred, 1e-3, without);
  EXPECT_TRUE(ExpectMatricesNear(a.coefficients.real(), b.coefficients.real(), kTolerance));
  EXPECT_TRUE(ExpectMatricesNear(a.coefficients.imag(), b.coefficients.imag(), kTolerance));
}

TEST(Cwt, BandLimitedModeIsTheDecimatedFullTransform) {
  // Decimation is exact (no interpolation): the band-limited output at time j
  // is the full output at sample j D, to the band truncation (1e-12) and
  // rounding of length-P vs length-M FFTs.
  constexpr double kTolerance = 1e-11;
  const double step = 2e-4;
  const Eigen::VectorXd x = MixedSignal(5001, step);
  CwtOptions full;
  full.padding = Padding::kReflect;
  CwtOptions band = full;
  band.band_limited = true;
  CwtTransform tb(band);
  Scalogram b;
  tb.Compute(x, step, &b);
  const Scalogram f = Cwt(x, step, full);
  // Minimum 2N - 2 = 10000 (the 10 Hz support is longer than the record);
  // 10240 = 2^11 is the faster length; the widest band (120 Hz) needs 608
  // of its bins, and 640 is the smallest divisor above.
  EXPECT_EQ(tb.padded_length(), 10240);
  EXPECT_EQ(tb.inverse_length(), 640);
  ASSERT_EQ(b.decimation, 16);
  ASSERT_EQ(b.times(), 313);
  const double scale = f.coefficients.cwiseAbs().maxCoeff();
  for (Eigen::Index j = 0; j < b.times(); ++j) {
    EXPECT_DOUBLE_EQ(b.time_s(j), f.time_s(16 * j));
    for (Eigen::Index k = 0; k < b.frequencies(); ++k) {
      ASSERT_LE(std::abs(b.coefficients(j, k) - f.coefficients(16 * j, k)), kTolerance * scale)
          << j << " " << k;
    }
    EXPECT_EQ(b.coi_frequency_Hz(j), f.coi_frequency_Hz(16 * j));
  }
}

TEST(Cwt, FrequencyGridAndConeOfInfluence) {
  FrequencyGrid g;  // 10 .. 120 Hz, 32 voices: 3.585 octaves -> 115 frequencies
  const Eigen::VectorXd f = g.Frequencies_Hz();
  ASSERT_EQ(f.size(), 115);
  EXPECT_DOUBLE_EQ(f(0), 10.0);
  EXPECT_NEAR(f(32), 20.0, 1e-12);
  EXPECT_LE(f(114), 120.0);
  g.spacing = FrequencySpacing::kLinear;
  g.bins = 12;
  EXPECT_NEAR(g.Frequencies_Hz()(11), 120.0, 1e-12);
  EXPECT_NEAR(g.Frequencies_Hz()(1), 20.0, 1e-12);
  // The factories describe the same grids (and are checked by IsValid only).
  EXPECT_EQ(FrequencyGrid::Linear(10.0, 120.0, 12).Frequencies_Hz(), g.Frequencies_Hz());
  EXPECT_EQ(FrequencyGrid::Log(10.0, 120.0, 32).Frequencies_Hz(), f);
  EXPECT_EQ(FrequencyGrid::Log(10.0, 40.0, 4).Frequencies_Hz().size(), 9);  // 2 octaves x 4 + 1
  std::string why;
  EXPECT_FALSE(FrequencyGrid::Linear(10.0, 120.0, 1).IsValid(&why));
  EXPECT_EQ(why, "FrequencyGrid.bins: expected 2..100000, got 1");

  // COI at t = 0.25 s of a 1 s record: sqrt(2) s = 0.25 s <=> f = 6 sqrt(2) / (2 pi 0.25).
  const Eigen::VectorXd x = MixedSignal(1001, 1e-3);
  CwtOptions torrence_compo;
  torrence_compo.coi_factor = 1.0;
  const Scalogram sg = Cwt(x, 1e-3, torrence_compo);
  EXPECT_NEAR(sg.coi_frequency_Hz(250), 6.0 * std::sqrt(2.0) / (2 * kPi * 0.25), 1e-12);
  EXPECT_NEAR(sg.coi_frequency_Hz(750), sg.coi_frequency_Hz(250), 1e-9);
  EXPECT_TRUE(std::isinf(sg.coi_frequency_Hz(0)));
  EXPECT_FALSE(sg.InsideCoi(0, sg.frequencies() - 1));
  EXPECT_TRUE(sg.InsideCoi(500, 0));  // 10 Hz: sqrt(2) s = 0.135 s < 0.5 s
}

TEST(Cwt, ParallelTransformsMatchSerial) {
  // Plans are shared across threads (planning under a mutex); each thread
  // owns its CwtTransform. Identical inputs give bitwise identical outputs.
  const double step = 1e-3;
  std::vector<Eigen::VectorXd> inputs;
  for (int i = 0; i < 4; ++i) inputs.push_back(MixedSignal(700 + 37 * i, step));
  std::vector<Scalogram> serial, parallel(inputs.size());
  for (const auto& x : inputs) serial.push_back(Cwt(x, step));
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    threads.emplace_back([&, i] {
      CwtTransform t(CwtOptions{});
      for (int r = 0; r < 3; ++r) t.Compute(inputs[i], step, &parallel[i]);
    });
  }
  for (auto& th : threads) th.join();
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    EXPECT_TRUE(serial[i].coefficients == parallel[i].coefficients) << i;
  }
}

TEST(Cwt, ShortReflectPaddingEqualsTheEvenExtension) {
  // When the lowest frequency's support (7.43 s for band_tolerance 1e-12) is
  // shorter than the record, reflect padding needs only N + 2 support
  // samples: the one jump of the shorter padded sequence lies outside every
  // coefficient's support, so W equals the transform of the infinite even
  // extension (here: the direct convolution over the period-(2N - 2) even
  // extension) to the band truncation, 1e-10 of max |W| as above.
  constexpr double kRelativeTolerance = 1e-10;
  const double step = 1e-3;
  const Eigen::VectorXd x = MixedSignal(1500, step);
  CwtOptions o;
  o.padding = Padding::kReflect;
  o.remove_mean = false;
  o.frequencies.min_frequency_Hz = 60.0;  // s = 15.9 ms: support 118 samples
  o.frequencies.max_frequency_Hz = 240.0;
  o.frequencies.voices_per_octave = 2;
  CwtTransform transform(o);
  Scalogram sg;
  transform.Compute(x, step, &sg);
  EXPECT_LT(transform.padded_length(), 2 * 1500 - 2);
  EXPECT_GE(transform.padded_length(), 1500 + 2 * 118);
  const Eigen::MatrixXcd direct =
      DirectCwt(Pad(x, Padding::kReflect, 2 * 1500 - 2), x.size(), step, sg.scales_s, o.wavelet);
  const double scale = direct.cwiseAbs().maxCoeff();
  EXPECT_TRUE(
      ExpectMatricesNear(sg.coefficients.real(), direct.real(), kRelativeTolerance * scale));
  EXPECT_TRUE(
      ExpectMatricesNear(sg.coefficients.imag(), direct.imag(), kRelativeTolerance * scale));
}

TEST(Cwt, ReflectPaddingOfARecordShorterThanTheSupport) {
  // 5 kHz down to 10 Hz: s = 477 samples, support 3548 (band tolerance) and
  // 2512 (the padding's 1e-6 envelope radius, 5.26 s) on each side, both more
  // than the record's half. A fast length just above 2N - 2 put the jump
  // 1.1 s from the data (2.7e-2 of max |W| inside the cone for 1001
  // samples); now:
  //   1001 samples: N + 2 x 2512 > 2 (2N - 2), so P = 2N - 2 = 2000, one whole
  //     period without a jump: W equals the even extension's to the 1e-10
  //     of FftPathEqualsDirectConvolution, everywhere;
  //   2001 samples: P >= N + 2 x 2512, the jump where every envelope is below
  //     1e-6 of its peak. kBorderTolerance 1e-6 of max |W| bounds the border
  //     coefficients (the envelope's mass beyond 5.26 s is 1.5e-7 of its
  //     total, times a jump of at most twice the signal's range); inside the
  //     cone (coi_factor 1, 1.41 s from each end) it is exp(-(6.67)^2 / 2) =
  //     2e-10 of the peak: 1e-10 of max |W| as everywhere else.
  constexpr double kRelativeTolerance = 1e-10;
  constexpr double kBorderTolerance = 1e-6;
  const double step = 2e-4;
  for (Eigen::Index n : {1001, 2001}) {
    const Eigen::VectorXd x = MixedSignal(n, step);
    CwtOptions o;
    o.padding = Padding::kReflect;
    o.remove_mean = false;
    o.coi_factor = 1.0;
    o.frequencies.min_frequency_Hz = 10.0;
    o.frequencies.max_frequency_Hz = 120.0;
    o.frequencies.voices_per_octave = 1;
    CwtTransform transform(o);
    Scalogram sg;
    transform.Compute(x, step, &sg);
    if (n == 1001) {
      EXPECT_EQ(transform.padded_length(), 2 * n - 2);
    } else {
      EXPECT_GE(transform.padded_length(), n + 2 * 2512);
    }
    const Eigen::MatrixXcd even =
        DirectCwt(Pad(x, Padding::kReflect, 2 * n - 2), n, step, sg.scales_s, o.wavelet);
    const double scale = even.cwiseAbs().maxCoeff();
    double inside = 0.0, all = 0.0;
    for (Eigen::Index k = 0; k < even.cols(); ++k) {
      for (Eigen::Index i = 0; i < n; ++i) {
        const double e = std::abs(sg.coefficients(i, k) - even(i, k)) / scale;
        all = std::max(all, e);
        if (sg.frequencies_Hz(k) >= sg.coi_frequency_Hz(i)) inside = std::max(inside, e);
      }
    }
    EXPECT_LE(inside, kRelativeTolerance) << n;
    EXPECT_LE(all, n == 1001 ? kRelativeTolerance : kBorderTolerance) << n;
    std::printf("%d samples, P = %d: max |W - W_even| / max |W| %.2g, inside the cone %.2g\n",
                static_cast<int>(n), static_cast<int>(transform.padded_length()), all, inside);
  }
}

TEST(Cwt, ZeroPaddingOfARecordShorterThanTheSupport) {
  // The transform of the record followed by zeros for ever: the direct sum
  // over the record alone (DirectCwt on the record and 2 supports of zeros,
  // whose periodic images are then beyond every envelope) is the reference.
  // 5 kHz down to 10 Hz: support 3548 samples on each side, more than the
  // 1001-sample record. P = N + min(N, support), rounded to 2048, let the
  // wavelets of the lowest scales reach the record's periodic copy (1.4e-2 of
  // max |W| at the borders, 8.2e-9 inside the cone of coi_factor 1). Now:
  //   coi_factor 0 (no cone, every coefficient counts): P >= N + support,
  //     rounding plus the 1e-12 band truncation everywhere (1e-10 of max |W|
  //     as FftPathEqualsDirectConvolution);
  //   coi_factor 2: the zeros stop at the support of the largest scale with
  //     a sample inside the cone (2 sqrt(2) s <= 0.1 s: 1314 samples), the
  //     same 1e-10 inside the cone;
  //   6001 samples: the support is shorter than the record, exact everywhere.
  constexpr double kRelativeTolerance = 1e-10;
  constexpr Eigen::Index kSupport = 3548;
  const double step = 2e-4;
  struct Run {
    Eigen::Index n;
    double coi_factor;
    Eigen::Index min_padded;
    bool everywhere;
  };
  for (const Run run : {Run{1001, 0.0, 1001 + kSupport, true}, Run{1001, 2.0, 1001 + 1314, false},
                        Run{6001, 2.0, 6001 + kSupport, true}}) {
    const Eigen::VectorXd x = MixedSignal(run.n, step);
    CwtOptions o;
    o.padding = Padding::kZero;
    o.remove_mean = false;
    o.coi_factor = run.coi_factor;
    o.frequencies.min_frequency_Hz = 10.0;
    o.frequencies.max_frequency_Hz = 120.0;
    o.frequencies.voices_per_octave = 1;
    CwtTransform transform(o);
    Scalogram sg;
    transform.Compute(x, step, &sg);
    EXPECT_GE(transform.padded_length(), run.min_padded) << run.n;
    const Eigen::MatrixXcd linear = DirectCwt(Pad(x, Padding::kZero, run.n + 2 * kSupport + 2),
                                              run.n, step, sg.scales_s, o.wavelet);
    const double scale = linear.cwiseAbs().maxCoeff();
    double inside = 0.0, all = 0.0;
    for (Eigen::Index k = 0; k < linear.cols(); ++k) {
      for (Eigen::Index i = 0; i < run.n; ++i) {
        const double e = std::abs(sg.coefficients(i, k) - linear(i, k)) / scale;
        all = std::max(all, e);
        if (sg.frequencies_Hz(k) >= sg.coi_frequency_Hz(i)) inside = std::max(inside, e);
      }
    }
    EXPECT_LE(inside, kRelativeTolerance) << run.n << " coi " << run.coi_factor;
    if (run.everywhere) {
      EXPECT_LE(all, kRelativeTolerance) << run.n << " coi " << run.coi_factor;
    }
    std::printf(
        "%d samples, coi_factor %g, P = %d: max |W - W_linear| / max |W| %.2g, inside the "
        "cone %.2g\n",
        static_cast<int>(run.n), run.coi_factor, static_cast<int>(transform.padded_length()), all,
        inside);
  }
}

TEST(Cwt, CoiFactorZeroMarksEverySampleInside) {
  // "0 means no cone": the end samples too, where the distance to the end is
  // 0 (they were marked outside, their cone frequency inf), in the whole
  // scalogram and in the streamed ridge alike.
  const double step = 1e-3;
  const Eigen::VectorXd x = MixedSignal(1001, step);
  CwtOptions o;
  o.coi_factor = 0.0;
  o.frequencies.min_frequency_Hz = 10.0;
  o.frequencies.max_frequency_Hz = 120.0;
  CwtTransform transform(o);
  Scalogram sg;
  transform.Compute(x, step, &sg);
  EXPECT_EQ(sg.coi_frequency_Hz.size(), x.size());
  EXPECT_EQ(sg.coi_frequency_Hz.maxCoeff(), 0.0);
  RidgeFrequencyOptions ro;
  ro.cwt.coi_factor = 0.0;
  const RidgeTrack track = RidgeFrequencyEstimator(ro).Estimate(x, step);
  EXPECT_EQ(track.InsideCoiCount(), track.size());
}

TEST(Cwt, PaddedLengthsHaveOnlyFactors2357) {
  // 10^4 samples used to pad to 2N - 2 = 19998 = 2 3^2 11 101 (9x slower
  // than fCWT in the issue); every padded length is now 7-smooth, at least
  // the documented minimum and at most 25 % above it.
  const auto smooth = [](Eigen::Index n) {
    for (Eigen::Index p : {2, 3, 5, 7}) {
      while (n % p == 0) n /= p;
    }
    return n == 1;
  };
  for (Eigen::Index n : {10000, 100000, 4999, 12345}) {
    for (Padding padding : {Padding::kReflect, Padding::kZero}) {
      CwtOptions o;
      o.padding = padding;
      o.frequencies.min_frequency_Hz = 1.0;
      o.frequencies.max_frequency_Hz = 32.0;
      const FftLengths lengths = CwtTransform(o).Lengths(n, 1.0 / 64.0);
      ASSERT_EQ(lengths.real_forward.size(), 1u);
      const Eigen::Index p = lengths.real_forward[0];
      // 1 Hz at 64 Hz: s = 61.1 samples, support ceil(7.43 s) = 454 samples;
      // reflect pads to the envelope's 1e-6 radius, ceil(5.26 s) = 322 samples.
      const Eigen::Index minimum =
          padding == Padding::kReflect ? n + 2 * 322 : n + std::min(n, 454L);
      EXPECT_TRUE(smooth(p)) << p;
      EXPECT_GE(p, minimum) << n;
      EXPECT_LE(p, minimum + minimum / 4 + 8) << n;
    }
  }
}

TEST(Cwt, ThreadsOverScalesGiveTheSameCoefficients) {
  // Each scale is one independent inverse FFT: any split over threads gives
  // bitwise the same result.
  const Eigen::VectorXd x = MixedSignal(3000, 1e-3);
  CwtOptions o;
  const Scalogram serial = Cwt(x, 1e-3, o);
  for (int threads : {2, 3, 7}) {
    o.threads = threads;
    EXPECT_TRUE(Cwt(x, 1e-3, o).coefficients == serial.coefficients) << threads;
  }
  o.threads = 0;
  PODID_EXPECT_THROW_WITH(CwtTransform{o}, std::invalid_argument,
                          "CwtOptions.threads: expected 1..256, got 0");
}

TEST(Cwt, BadInputNamesWhatWasExpected) {
  const Eigen::VectorXd x = MixedSignal(100, 1e-3);
  PODID_EXPECT_THROW_WITH(Cwt(Eigen::VectorXd(), 1e-3), std::invalid_argument,
                          "expected at least 4 samples");
  PODID_EXPECT_THROW_WITH(Cwt(Eigen::VectorXd::Constant(50, 2.0), 1e-3), std::invalid_argument,
                          "expected a non-constant signal");
  Eigen::VectorXd bad = x;
  bad(3) = std::nan("");
  PODID_EXPECT_THROW_WITH(Cwt(bad, 1e-3), std::invalid_argument, "expected finite values");
  bad(3) = INFINITY;
  PODID_EXPECT_THROW_WITH(Cwt(bad, 1e-3), std::invalid_argument, "expected finite values");
  PODID_EXPECT_THROW_WITH(Cwt(x, 0.0), std::invalid_argument,
                          "step_s: expected a finite value between 1e-15 s and 1e15 s, got 0");
  PODID_EXPECT_THROW_WITH(Cwt(x, -1e-3), std::invalid_argument, "step_s");
  // Subnormal: a Nyquist frequency of inf accepted every band before.
  PODID_EXPECT_THROW_WITH(Cwt(x, 1e-320), std::invalid_argument,
                          "step_s: expected a finite value between 1e-15 s and 1e15 s, "
                          "got 9.999888672e-321");
  PODID_EXPECT_THROW_WITH(Cwt(x, 0.01), std::invalid_argument,
                          "expected <= the Nyquist frequency");  // 120 Hz > 50 Hz
  CwtOptions o;
  o.wavelet.omega0 = 4.0;
  PODID_EXPECT_THROW_WITH(Cwt(x, 1e-3, o), std::invalid_argument,
                          "omega0: expected >= 5 (or admissibility_correction = true), got 4");
  o.wavelet.admissibility_correction = true;
  EXPECT_NO_THROW(Cwt(x, 1e-3, o));
  o = CwtOptions{};
  o.frequencies.min_frequency_Hz = 0.0;
  PODID_EXPECT_THROW_WITH(Cwt(x, 1e-3, o), std::invalid_argument,
                          "min_frequency_Hz: expected a finite value > 0, got 0");
  o.frequencies.min_frequency_Hz = 1e-320;  // subnormal: 120 / f_min overflows
  PODID_EXPECT_THROW_WITH(Cwt(x, 1e-3, o), std::invalid_argument,
                          "expected a finite ratio max_frequency_Hz / min_frequency_Hz, got 120 / "
                          "9.999888672e-321");
  o.frequencies.min_frequency_Hz = 1e-3;  // 16.9 octaves x 32 voices: 542 frequencies
  EXPECT_NO_THROW(o.frequencies.Frequencies_Hz());
  o.frequencies.voices_per_octave = 1024;  // 17,300 frequencies
  EXPECT_NO_THROW(o.frequencies.Frequencies_Hz());
  o.frequencies.min_frequency_Hz = 1e-300;  // 1003 octaves x 1024 voices
  PODID_EXPECT_THROW_WITH(o.frequencies.Frequencies_Hz(), std::invalid_argument,
                          "expected at most 100000 frequencies");
  o = CwtOptions{};
  o.frequencies.max_frequency_Hz = -5.0;
  PODID_EXPECT_THROW_WITH(CwtTransform{o}, std::invalid_argument, "max_frequency_Hz: expected");
  o = CwtOptions{};
  o.frequencies.voices_per_octave = 0;
  PODID_EXPECT_THROW_WITH(CwtTransform{o}, std::invalid_argument, "voices_per_octave");
  o = CwtOptions{};
  o.band_tolerance = 0.5;
  PODID_EXPECT_THROW_WITH(CwtTransform{o}, std::invalid_argument, "band_tolerance");
  // The cone: 0 (none) to kMaxCoiFactor; 1e308 made its frequencies inf.
  o = CwtOptions{};
  for (const double c : {0.0, kMaxCoiFactor}) {
    o.coi_factor = c;
    EXPECT_TRUE(o.IsValid(nullptr)) << c;
  }
  for (const double c : {-1.0, 10.5, 1e308, std::numeric_limits<double>::quiet_NaN()}) {
    o.coi_factor = c;
    PODID_EXPECT_THROW_WITH(CwtTransform{o}, std::invalid_argument,
                            "CwtOptions.coi_factor: expected a value in [0, 10], got");
  }
  PODID_EXPECT_THROW_WITH(ParsePadding("mirror"), std::invalid_argument,
                          "expected one of reflect, zero, periodic");
  for (const CwtOutput output :
       {CwtOutput::kComplex, CwtOutput::kMagnitudeFloat, CwtOutput::kComplexFloat}) {
    EXPECT_EQ(ParseCwtOutput(ToString(output)), output);
  }
  PODID_EXPECT_THROW_WITH(
      ParseCwtOutput("float"), std::invalid_argument,
      "output: expected one of complex, magnitude, complex-float, got \"float\"");
}

}  // namespace
}  // namespace podid::wavelet

namespace podid::wavelet {
namespace {

MorletWavelet Morse(double gamma, double beta, Normalisation norm = Normalisation::kAmplitude) {
  MorletWavelet w;
  w.family = WaveletFamily::kMorse;
  w.gamma = gamma;
  w.beta = beta;
  w.normalisation = norm;
  return w;
}

TEST(MorseWavelet, MatchesTheAnalyticFormulaAndPeak) {
  // MATLAB's normalisation (cwtfilterbank, Lilly & Olhede 2009):
  // psi^(u) = 2 (e gamma / beta)^(beta / gamma) u^beta exp(-u^gamma), written
  // here in a different order than the library's log form; peak 2 at
  // u_p = (beta / gamma)^(1 / gamma) (1.88207 for MATLAB's default 3, 20).
  // 1e-13 relative: a few roundings of exp/pow of arguments up to ~100.
  constexpr double kTolerance = 1e-13;
  for (auto [gamma, beta] : {std::pair{3.0, 20.0}, std::pair{2.0, 4.0}, std::pair{1.0, 10.0}}) {
    const MorletWavelet w = Morse(gamma, beta);
    ASSERT_TRUE(w.IsValid(nullptr));
    const double a = 2.0 * std::pow(std::exp(1.0) * gamma / beta, beta / gamma);
    for (double u : {0.3, 1.0, 1.88207, 2.5, 4.0}) {
      const double expected = a * std::pow(u, beta) * std::exp(-std::pow(u, gamma));
      EXPECT_NEAR(w.FourierTransform(u), expected, kTolerance * std::max(expected, 1e-300))
          << gamma << " " << beta << " " << u;
    }
    EXPECT_EQ(w.FourierTransform(0.0), 0.0);
    EXPECT_EQ(w.FourierTransform(-1.0), 0.0);
    const double peak = std::pow(beta / gamma, 1.0 / gamma);
    EXPECT_NEAR(w.RidgeAngularFrequency(), peak, kTolerance * peak);
    EXPECT_NEAR(w.FourierTransform(peak), 2.0, kTolerance);
    EXPECT_LT(w.FourierTransform(peak * (1 + 1e-4)), 2.0);
    EXPECT_LT(w.FourierTransform(peak * (1 - 1e-4)), 2.0);
    EXPECT_NEAR(w.UnitCosineMagnitude(0.01), 1.0, kTolerance);
  }
  EXPECT_NEAR(Morse(3.0, 20.0).RidgeAngularFrequency(), 1.8820720577620569, 1e-15);
}

TEST(MorseWavelet, EnergyNormalisationHasUnitEnergyAndItsOwnRidge) {
  // integral |psi(t)|^2 dt = integral psi^(u)^2 du / (2 pi) = 1, by a fine
  // trapezoid sum (1e-8: 2e5 panels over the band). The L2 ridge maximises
  // sqrt(u) psi^(u): u = ((beta + 1/2) / gamma)^(1 / gamma).
  constexpr double kTolerance = 1e-8;
  const MorletWavelet w = Morse(3.0, 20.0, Normalisation::kEnergy);
  double lo = 0.0, hi = 0.0;
  w.Band(1e-15, &lo, &hi);
  const int panels = 200000;
  const double h = (hi - lo) / panels;
  double energy = 0.0;
  for (int i = 0; i <= panels; ++i) {
    const double v = w.FourierTransform(lo + h * i);
    energy += ((i == 0 || i == panels) ? 0.5 : 1.0) * v * v * h;
  }
  EXPECT_NEAR(energy / (2.0 * kPi), 1.0, kTolerance);
  const double kappa = std::pow(20.5 / 3.0, 1.0 / 3.0);
  EXPECT_NEAR(w.RidgeAngularFrequency(), kappa, 1e-14 * kappa);
  const auto g = [&](double u) { return std::sqrt(u) * w.FourierTransform(u); };
  EXPECT_GT(g(kappa), g(kappa * (1 + 1e-4)));
  EXPECT_GT(g(kappa), g(kappa * (1 - 1e-4)));
}

TEST(MorseWavelet, BandEdgesAreAtTheTolerance) {
  // psi^(lo) = psi^(hi) = tolerance * peak (bisection to rounding), and the
  // Morlet band is omega0 -+ sqrt(2 ln(1 / tolerance)) as before.
  const MorletWavelet w = Morse(3.0, 20.0);
  double lo = 0.0, hi = 0.0;
  w.Band(1e-12, &lo, &hi);
  EXPECT_NEAR(w.FourierTransform(lo) / 2.0, 1e-12, 1e-12 * 1e-9);
  EXPECT_NEAR(w.FourierTransform(hi) / 2.0, 1e-12, 1e-12 * 1e-9);
  EXPECT_LT(lo, w.RidgeAngularFrequency());
  EXPECT_GT(hi, w.RidgeAngularFrequency());
  MorletWavelet morlet;
  morlet.Band(1e-12, &lo, &hi);
  EXPECT_NEAR(hi, 6.0 + std::sqrt(2.0 * std::log(1e12)), 1e-12);
  EXPECT_NEAR(morlet.TimeSpread(), std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(morlet.ConeOfInfluenceTime_s(0.1), MorletWavelet::ConeOfInfluence_s(0.1), 1e-15);
  // Morse's time spread: sigma_t^2 = beta gamma / u_p^2 / 4 * (1 + O(1/P^2))
  // is not closed; check it is the RMS width of |psi(t)|^2 from a direct
  // inverse Fourier sum instead (1e-4: 801 time points over +-20 ~ +-10 sigma_t,
  // 2001 frequency points).
  const double sigma = w.TimeSpread();
  double num = 0.0, den = 0.0;
  w.Band(1e-14, &lo, &hi);
  const int nu = 2001;
  const double du = (hi - lo) / (nu - 1);
  for (int it = -400; it <= 400; ++it) {
    const double t = it * 0.05;
    Complex psi(0.0, 0.0);
    for (int iu = 0; iu < nu; ++iu) {
      const double u = lo + du * iu;
      psi += w.FourierTransform(u) * std::exp(Complex(0.0, u * t)) * du;
    }
    num += t * t * std::norm(psi);
    den += std::norm(psi);
  }
  EXPECT_NEAR(sigma, std::sqrt(num / den), 1e-4 * sigma);
}

TEST(MorseWavelet, ToneOnItsRidgeHasUnitMagnitudeAndExactPhaseIf) {
  // 33 Hz cosine with 33 whole periods (reflect padding continues it): on the
  // grid frequency 33 Hz |W| = 1 with MATLAB's L1 normalisation (1e-9 for the
  // band truncation), and the phase derivative gives 33 Hz (1e-9).
  constexpr double kTolerance = 1e-9;
  const double step = 1.0 / 5000.0;
  Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(5001, 0.0, 1.0);
  Eigen::VectorXd x = (2 * kPi * 33.0 * t).array().cos();
  CwtOptions o;
  o.padding = Padding::kReflect;  // the whole periods continue exactly
  o.wavelet = Morse(3.0, 20.0);
  o.frequencies.min_frequency_Hz = 33.0;
  o.frequencies.max_frequency_Hz = 66.0;
  o.frequencies.voices_per_octave = 4;
  CwtTransform transform(o);
  Scalogram sg;
  transform.Compute(x, step, &sg);
  Eigen::VectorXcd dw;
  transform.TimeDerivative(0, &dw);
  int checked = 0;
  for (Eigen::Index j = 0; j < sg.times(); j += 97) {
    if (!sg.InsideCoi(j, 0)) continue;
    const Complex w = sg.coefficients(j, 0);
    EXPECT_NEAR(std::abs(w), 1.0, kTolerance) << j;
    EXPECT_NEAR((std::conj(w) * dw(j)).imag() / (2 * kPi * std::norm(w)), 33.0, kTolerance * 33.0);
    ++checked;
  }
  EXPECT_GT(checked, 20);
}

TEST(MorseWavelet, BadParametersNameWhatWasExpected) {
  std::string why;
  EXPECT_FALSE(Morse(0.5, 20.0).IsValid(&why));
  EXPECT_NE(why.find("gamma: expected a value in [1, 20], got 0.5"), std::string::npos) << why;
  EXPECT_FALSE(Morse(3.0, 0.0).IsValid(&why));
  EXPECT_NE(why.find("beta: expected a value in [1, 500], got 0"), std::string::npos) << why;
  EXPECT_FALSE(Morse(1.0, 400.0).IsValid(&why));
  EXPECT_NE(why.find("beta / gamma: expected <= 100"), std::string::npos) << why;
  EXPECT_EQ(ParseWaveletFamily("morse"), WaveletFamily::kMorse);
  EXPECT_THROW(ParseWaveletFamily("mexh"), std::invalid_argument);
}

}  // namespace
}  // namespace podid::wavelet

namespace podid::wavelet {
namespace {

TEST(ScaleConvention, PeakIsMatlabAndPyWaveletsCentreFrequency) {
  // MATLAB (cwt: f = omega_peak / (2 pi s)) and PyWavelets (scale2frequency
  // of cmor2.0-C: C / s, C = omega0 / (2 pi)) label a scale by the peak of
  // psi^; Torrence & Compo by the ridge of n(s) psi^(s w). For kEnergy Morlet
  // omega0 = 6 the ridge is (6 + sqrt(38)) / 2 = 6.0822: 1.37 % apart in s,
  // 1.35 % of the ridge frequency. For kAmplitude they coincide.
  constexpr double kTolerance = 1e-14;
  MorletWavelet w;
  w.normalisation = Normalisation::kEnergy;
  w.convention = ScaleConvention::kPeak;
  EXPECT_NEAR(w.ScaleToFrequency_Hz(0.01), 6.0 / (2 * kPi * 0.01), kTolerance * 100);
  w.convention = ScaleConvention::kRidge;
  EXPECT_NEAR(w.ScaleToFrequency_Hz(0.01), 0.5 * (6.0 + std::sqrt(38.0)) / (2 * kPi * 0.01),
              kTolerance * 100);
  MorletWavelet amplitude;
  amplitude.convention = ScaleConvention::kPeak;
  EXPECT_EQ(amplitude.FrequencyToScale_s(33.0), MorletWavelet{}.FrequencyToScale_s(33.0));
  MorletWavelet morse;
  morse.family = WaveletFamily::kMorse;
  morse.normalisation = Normalisation::kEnergy;
  morse.convention = ScaleConvention::kPeak;
  EXPECT_NEAR(morse.ScaleFrequencyConstant(), std::pow(20.0 / 3.0, 1.0 / 3.0), kTolerance);

  // The transform's scales follow the convention, and a tone's ridge (at
  // s = 6.0822 / (2 pi 33) whatever the labels) carries the label
  // 6 / 6.0822 times its frequency under kPeak with kEnergy: the grid's
  // largest |W| is within half a bin (1.1 %) of it.
  CwtOptions o;
  o.wavelet = w;
  o.wavelet.convention = ScaleConvention::kPeak;
  o.frequencies.min_frequency_Hz = 30.0;
  o.frequencies.max_frequency_Hz = 40.0;
  const double step = 1.0 / 5000.0;
  const Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(5001, 0.0, 1.0);
  const Eigen::VectorXd x = (2 * kPi * 33.0 * t).array().cos();
  const Scalogram sg = Cwt(x, step, o);
  for (Eigen::Index k = 0; k < sg.frequencies(); ++k) {
    EXPECT_NEAR(sg.scales_s(k), 6.0 / (2 * kPi * sg.frequencies_Hz(k)), kTolerance * sg.scales_s(k));
  }
  Eigen::Index best = 0;
  const Eigen::Index mid = sg.times() / 2;
  sg.coefficients.row(mid).cwiseAbs().maxCoeff(&best);
  const double label = sg.frequencies_Hz(best);
  EXPECT_NEAR(label / 33.0, 6.0 / (0.5 * (6.0 + std::sqrt(38.0))), 0.011);
}

}  // namespace
}  // namespace podid::wavelet
