// Morlet wavelets with omega0 up to kMaxOmega0 = 100 through the transforms
// that keep the whole scalogram: from omega0 = 37.68 (exp(omega0^2 / 2) >
// DBL_MAX) the generated filters' recurrences overflowed and W was NaN or
// exactly 0 (podid cwt --omega0 40 --scalogram). Against the closed form of a
// tone and a direct time-domain convolution with the closed-form psi.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <string>

#include "podid/wavelet/cwt.hpp"

namespace podid::wavelet {
namespace {

using Complex = std::complex<double>;
constexpr double kPi = std::numbers::pi;

// A cosine of kCycles whole periods over kSamples samples, periodic padding:
// its spectrum is bins +-kCycles only, and W at scale s (kAmplitude) is
// exp(-(s w - omega0)^2 / 2) exp(i w t) plus the negative frequency's
// exp(-(s w + omega0)^2 / 2), below exp(-(1.8 omega0)^2 / 2) = 6e-26 on
// this grid (s w >= 0.8 omega0): left out.
constexpr Eigen::Index kSamples = 8192;
constexpr double kStep = 1e-3;
constexpr int kCycles = 1000;  // 122.07 Hz
const double kToneHz = kCycles / (kSamples * kStep);

Eigen::VectorXd Tone() {
  Eigen::VectorXd x(kSamples);
  for (Eigen::Index i = 0; i < kSamples; ++i) {
    x(i) = std::cos(2.0 * kPi * static_cast<double>((kCycles * i) % kSamples) / kSamples);
  }
  return x;
}

// The closed form at scale s and time t (kAmplitude, without the correction),
// its phase w t = 2 pi (kCycles i mod kSamples) / kSamples at sample i = t /
// kStep: w t itself (up to 5e4 rad) carries 7e-12 of rounding.
Complex ClosedForm(double omega0, double scale_s, double t_s) {
  const double w = 2.0 * kPi * kToneHz;
  const double d = scale_s * w - omega0;
  const auto i = std::llround(t_s / kStep);
  const double turns = static_cast<double>((kCycles * i) % kSamples) / kSamples;
  return std::exp(-0.5 * d * d) * std::polar(1.0, 2.0 * kPi * turns);
}

CwtOptions Options(double omega0, bool band_limited, CwtOutput output) {
  CwtOptions o;
  o.wavelet.omega0 = omega0;
  o.padding = Padding::kPeriodic;
  o.band_limited = band_limited;
  o.output = output;
  // 0.8 to 1.25 times the tone: at omega0 = 100 the scale at 0.93 times
  // already sees the tone at 1e-12 of the peak (the band's edge).
  o.frequencies = FrequencyGrid::Log(0.8 * kToneHz, 1.25 * kToneHz, 24);
  return o;
}

// The band keeps the bins down to band_tolerance = 1e-12 of the filter's
// peak: where the closed form is below that, W may be 0 and the error is
// counted above 1e-12 only. Elsewhere W = X_b g_b exp(i w t) from the tone's
// one bin: the generated filter g_b is within 1e-13 of its value
// (scale_filters_test.cpp) and the FFT of 8192 points adds 13 roundings of
// the twiddles, 1.5e-15: kDoubleTolerance = 2e-13 of the peak |W| = 1.
// Seen: at most 8.0e-14 (omega0 40); 1.1e-12, 0.95 and NaN before (37.7, 40, 100).
constexpr double kBandTolerance = 1e-12;
constexpr double kDoubleTolerance = 2e-13;
// The single-precision outputs: each part (or |W|) rounded to 2^-24 = 6e-8
// relative, at most 6e-8 absolute below the peak of 1; twice that.
constexpr double kFloatTolerance = 1.2e-7;

double MaxError(const Scalogram& sg, double omega0) {
  double worst = 0.0;
  for (Eigen::Index k = 0; k < sg.frequencies(); ++k) {
    for (Eigen::Index j = 0; j < sg.times(); ++j) {
      const Complex want = ClosedForm(omega0, sg.scales_s(k), sg.time_s(j));
      double error = 0.0;
      if (sg.coefficients.size() > 0) {
        const Complex got = sg.coefficients(j, k);
        EXPECT_TRUE(std::isfinite(got.real()) && std::isfinite(got.imag()));
        error = std::abs(got - want);
      } else if (sg.coefficients_float.size() > 0) {
        const std::complex<float> got = sg.coefficients_float(j, k);
        EXPECT_TRUE(std::isfinite(got.real()) && std::isfinite(got.imag()));
        error = std::abs(Complex(got.real(), got.imag()) - want);
      } else {
        const float got = sg.magnitude(j, k);
        EXPECT_TRUE(std::isfinite(got));
        error = std::abs(static_cast<double>(got) - std::abs(want));
      }
      if (std::abs(want) < kBandTolerance) error = std::max(0.0, error - kBandTolerance);
      if (!(error <= worst)) worst = error;  // NaN sticks
    }
  }
  return worst;
}

TEST(LargeOmega0, WholeTransformOfAToneEqualsTheClosedForm) {
  const Eigen::VectorXd x = Tone();
  for (double omega0 : {6.0, 37.6, 37.7, 40.0, 60.0, 100.0}) {
    for (bool band_limited : {false, true}) {
      for (CwtOutput output :
           {CwtOutput::kComplex, CwtOutput::kMagnitudeFloat, CwtOutput::kComplexFloat}) {
        CwtTransform transform(Options(omega0, band_limited, output));
        Scalogram sg;
        transform.Compute(x, kStep, &sg);
        ASSERT_EQ(sg.coefficient_scale, 1.0);
        const double error = MaxError(sg, omega0);
        const double tolerance = output == CwtOutput::kComplex ? kDoubleTolerance : kFloatTolerance;
        EXPECT_LE(error, tolerance) << "omega0 " << omega0 << " band_limited " << band_limited
                                    << " output " << ToString(output);
        std::printf("omega0 %5.1f %-12s %-13s max |W - closed form| %.2e\n", omega0,
                    band_limited ? "band-limited" : "full rate", ToString(output), error);
        if (output != CwtOutput::kComplex) continue;
        // dW/dt = i w W for the tone (the synchrosqueezed CWT and the phase IF
        // read it): the same allowances, times w.
        const double w = 2.0 * kPi * kToneHz;
        double worst = 0.0;
        Eigen::VectorXcd derivative;
        for (Eigen::Index k = 0; k < sg.frequencies(); ++k) {
          transform.TimeDerivative(k, &derivative);
          for (Eigen::Index j = 0; j < sg.times(); ++j) {
            const Complex want = Complex(0.0, w) * ClosedForm(omega0, sg.scales_s(k), sg.time_s(j));
            double error = std::abs(derivative(j) - want) / w;
            if (std::abs(want) < w * kBandTolerance) error = std::max(0.0, error - kBandTolerance);
            if (!(error <= worst)) worst = error;
          }
        }
        EXPECT_LE(worst, kDoubleTolerance) << "dW/dt, omega0 " << omega0;
        std::printf("omega0 %5.1f %-12s dW/dt: max |dW/dt - i w W| / w %.2e\n", omega0,
                    band_limited ? "band-limited" : "full rate", worst);
      }
    }
  }
}

// W(s, t_n) = (step / s) sum_m x_m conj(psi((t_m - t_n) / s)) over the
// periodic images (kPeriodic: P = N), psi(u) = sqrt(2 / pi) exp(i omega0 u)
// exp(-u^2 / 2) the kAmplitude Morlet wavelet in closed form (as
// cwt_test.cpp's DirectCwt). Independent of the tone's closed form: a chirp.
Eigen::MatrixXcd DirectCwt(const Eigen::VectorXd& x,
                           double step_s,
                           const Eigen::VectorXd& scales_s,
                           double omega0) {
  const Eigen::Index p = x.size();
  const double k_norm = std::sqrt(2.0 / kPi);
  Eigen::MatrixXcd w(p, scales_s.size());
  for (Eigen::Index k = 0; k < scales_s.size(); ++k) {
    const double s = scales_s(k);
    Eigen::VectorXcd kernel = Eigen::VectorXcd::Zero(p);
    for (Eigen::Index d = 0; d < p; ++d) {
      for (int l = -2; l <= 2; ++l) {
        const double u = static_cast<double>(d + l * p) * step_s / s;
        if (std::abs(u) > 40.0) continue;
        kernel(d) += std::conj(k_norm * std::polar(1.0, omega0 * u) * std::exp(-0.5 * u * u));
      }
    }
    for (Eigen::Index i = 0; i < p; ++i) {
      Complex sum = 0.0;
      for (Eigen::Index m = 0; m < p; ++m) sum += x(m) * kernel((m - i + p) % p);
      w(i, k) = step_s / s * sum;
    }
  }
  return w;
}

TEST(LargeOmega0, WholeTransformOfAChirpEqualsADirectConvolution) {
  // 1024 samples at 1 kHz, a chirp 130 -> 170 Hz (not periodic: periodic
  // padding makes the direct sum the same circular convolution), at 100 to
  // 200 Hz: every band, up to (omega0 + 7.43) / omega0 times the frequency
  // (2.24 at omega0 = 6), stays below Nyquist, which the transform's bands
  // stop at and the sampled kernel's spectrum folds back (6e-7 at 285 Hz,
  // omega0 = 6: a difference of definitions, not an error). Allowance: the
  // dropped bins, below 1e-12 of the filter's peak 2, change W by at most
  // 2e-12 sum |X_b| / P <= 2e-12 ||x|| (Cauchy-Schwarz) = 6.4e-11; the direct
  // sums of 1024 terms round to about 1e-13. Seen: at most 1.7e-13.
  constexpr double kTolerance = 1e-10;
  constexpr Eigen::Index n = 1024;
  constexpr double step = 1e-3;
  Eigen::VectorXd x(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) * step;
    x(i) = std::cos(2.0 * kPi * (130.0 * t + 0.5 * 40.0 / (n * step) * t * t));
  }
  for (double omega0 : {6.0, 37.7, 40.0, 100.0}) {
    for (bool band_limited : {false, true}) {
      CwtOptions o;
      o.wavelet.omega0 = omega0;
      o.padding = Padding::kPeriodic;
      o.remove_mean = false;
      o.band_limited = band_limited;
      o.frequencies = FrequencyGrid::Log(100.0, 200.0, 8);
      CwtTransform transform(o);
      Scalogram sg;
      transform.Compute(x, step, &sg);
      const Eigen::MatrixXcd direct = DirectCwt(x, step, sg.scales_s, omega0);
      double worst = 0.0;
      for (Eigen::Index k = 0; k < sg.frequencies(); ++k) {
        for (Eigen::Index j = 0; j < sg.times(); ++j) {
          const Complex got = sg.coefficients(j, k);
          ASSERT_TRUE(std::isfinite(got.real()) && std::isfinite(got.imag()));
          const double error = std::abs(got - direct(j * sg.decimation, k));
          if (!(error <= worst)) worst = error;
        }
      }
      EXPECT_LE(worst, kTolerance) << "omega0 " << omega0 << " band_limited " << band_limited;
      EXPECT_GT(sg.coefficients.cwiseAbs().maxCoeff(), 0.5);  // the chirp is seen
      std::printf("chirp omega0 %5.1f %-12s max |W - direct| %.2e\n", omega0,
                  band_limited ? "band-limited" : "full rate", worst);
    }
  }
}

}  // namespace
}  // namespace podid::wavelet
