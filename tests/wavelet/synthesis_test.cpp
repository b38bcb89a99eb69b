// Tests of podid/wavelet/synthesis.hpp: the inverse CWT against the signal it
// came from, the synchrosqueezed ridge's IF against a chirp's analytic IF and
// against the CWT ridge's own error.
#include "podid/wavelet/synthesis.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <vector>

#include "podid/wavelet/ridge.hpp"
#include "test_support.hpp"

namespace podid::wavelet {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kStep_s = 1.0 / 1000.0;

Eigen::VectorXd Time(Eigen::Index n) {
  return Eigen::VectorXd::LinSpaced(n, 0.0, static_cast<double>(n - 1) * kStep_s);
}

// The ridge tests' grid: 10-120 Hz, 32 voices per octave, coi_factor 2 (podid cwt's).
CwtOptions TenTo120Hz() {
  CwtOptions o;
  o.frequencies.min_frequency_Hz = 10.0;
  o.frequencies.max_frequency_Hz = 120.0;
  o.coi_factor = 2.0;
  return o;
}

// The synchrosqueezed transform of x on TenTo120Hz's grid (its CWT into *sg).
SynchrosqueezedTransform Squeezed(const Eigen::VectorXd& x, Scalogram* sg) {
  CwtTransform transform(TenTo120Hz());
  transform.Compute(x, kStep_s, sg);
  return Synchrosqueeze(*sg, transform);
}

RidgeOptions Ridges(int count) {
  RidgeOptions o;
  o.ridges = count;
  return o;
}

// Relative RMS of (y - x) over the output times where every grid frequency is
// inside the cone of influence (widened by `widen`).
double RelativeRmsInsideCone(const Scalogram& sg, const Eigen::VectorXd& x,
                             const Eigen::VectorXd& y, Eigen::Index* used, double widen = 1.0) {
  double num = 0.0, den = 0.0;
  *used = 0;
  for (Eigen::Index j = 0; j < sg.times(); ++j) {
    if (!(sg.frequencies_Hz(0) >= widen * sg.coi_frequency_Hz(j))) continue;
    const double e = y(j) - x(j * sg.decimation);
    num += e * e;
    den += x(j * sg.decimation) * x(j * sg.decimation);
    ++*used;
  }
  return std::sqrt(num / den);
}

TEST(ReconstructionConstant, MatchesClosedFormsAndTheDiscreteGrid) {
  // Morlet's C has no elementary form: compare with a Riemann sum of psi^(u)
  // over a 1e-3-fine grid in ln u (for a smooth bump spectrally accurate;
  // 1e-6 allows for the different cut of the 3e-8 tail near u = 0). Morse (L1):
  // C = 2 a Gamma(beta / gamma) / gamma, a = (e gamma / beta)^(beta / gamma).
  // 1e-9: the quadrature's 20000 trapezoid panels, far finer than needed.
  constexpr double kTolerance = 1e-9;
  MorletWavelet morse;
  morse.family = WaveletFamily::kMorse;
  for (double gamma : {3.0, 2.0, 1.5}) {
    for (double beta : {20.0, 7.0}) {
      morse.gamma = gamma;
      morse.beta = beta;
      const double a = std::exp(beta / gamma * (1.0 + std::log(gamma / beta)));
      const double expected = 2.0 * a * std::exp(std::lgamma(beta / gamma)) / gamma;
      EXPECT_NEAR(ReconstructionConstant(morse), expected, kTolerance * expected)
          << gamma << " " << beta;
    }
  }
  MorletWavelet morlet;
  double sum = 0.0;
  const double h = 1e-3;
  for (double v = std::log(1e-3 * 6.0); v < std::log(40.0); v += h) {
    sum += morlet.FourierTransform(std::exp(v)) * h;
  }
  EXPECT_NEAR(ReconstructionConstant(morlet), sum, 1e-6 * sum);
}

TEST(InverseCwt, ReconstructsABandLimitedMultiToneSignal) {
  // Three tones (20, 35.5, 61 Hz, arbitrary phases and amplitudes), 4 s at
  // 1 kHz, analysed on 5-400 Hz: each tone's psi^(2 pi f s) is below 1e-5 of
  // its peak at both ends of the grid, so the single-integral formula holds to
  // about that. 1e-3 relative RMS inside the cone is the figure; the
  // measurement is printed.
  constexpr double kTolerance = 1e-3;
  const Eigen::VectorXd t = Time(4001);
  const Eigen::VectorXd x = (2 * kPi * 20.0 * t.array() + 0.3).cos() +
                            0.5 * (2 * kPi * 35.5 * t.array() + 1.1).sin() +
                            0.25 * (2 * kPi * 61.0 * t.array() - 0.7).cos();
  for (WaveletFamily family : {WaveletFamily::kMorlet, WaveletFamily::kMorse}) {
    for (Normalisation norm : {Normalisation::kAmplitude, Normalisation::kEnergy}) {
      for (bool band : {false, true}) {
        CwtOptions o;
        o.wavelet.family = family;
        o.wavelet.normalisation = norm;
        o.frequencies.min_frequency_Hz = 5.0;
        o.frequencies.max_frequency_Hz = 400.0;
        o.band_limited = band;
        const Scalogram sg = Cwt(x, kStep_s, o);
        const Eigen::VectorXd y = InverseCwt(sg);
        // The tones' sample mean over 4 s (5e-4 of their RMS) is not in the
        // band: the reconstruction is the tones themselves.
        const Eigen::VectorXd& xc = x;
        Eigen::Index used = 0;
        const double error = RelativeRmsInsideCone(sg, xc, y, &used);
        ASSERT_GT(used, sg.times() / 2);
        EXPECT_LE(error, kTolerance) << ToString(family) << " " << ToString(norm) << " " << band;
        Eigen::Index used2 = 0;
        std::printf("inverse CWT %s %s band_limited %d: relative RMS %.3g inside the cone, "
                    "%.3g inside twice the cone\n",
                    ToString(family), ToString(norm), band, error,
                    RelativeRmsInsideCone(sg, xc, y, &used2, 2.0));
      }
    }
  }
}

TEST(InverseCwt, RejectsMagnitudeOnlyScalograms) {
  CwtOptions o;
  o.output = CwtOutput::kMagnitudeFloat;
  const Eigen::VectorXd x = (2 * kPi * 30.0 * Time(1000).array()).cos();
  const Scalogram sg = Cwt(x, kStep_s, o);
  try {
    InverseCwt(sg);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("expected a computed scalogram with complex coefficients"),
              std::string::npos)
        << e.what();
  }
}

TEST(Synthesis, AHandMadeScalogramOfInconsistentSizesIsRefused) {
  // Scalogram and SynchrosqueezedTransform are plain structs that a caller
  // may fill or resize: what reads them by time and frequency index checks
  // their sizes first (a short cone or scale vector, or a field of another
  // shape, read past their ends; descending frequencies aborted
  // Synchrosqueeze).
  const Eigen::VectorXd x = (2 * kPi * 40.0 * Time(1001).array()).cos();
  CwtTransform transform(TenTo120Hz());
  Scalogram sg;
  transform.Compute(x, kStep_s, &sg);
  const Eigen::VectorXi path = FindRidges(sg, RidgeOptions{}).front();
  Scalogram short_cone = sg;
  short_cone.coi_frequency_Hz.resize(3);
  PODID_EXPECT_THROW_WITH(TrackRidge(short_cone, path, RidgeOptions{}, &transform),
                          std::invalid_argument, "got 115 scales and 3 cone frequencies");
  Scalogram short_scales = sg;
  short_scales.scales_s.resize(2);
  PODID_EXPECT_THROW_WITH(InverseCwt(short_scales), std::invalid_argument,
                          "got 2 scales and 1001 cone frequencies");
  Scalogram descending = sg;
  descending.frequencies_Hz.reverseInPlace();
  PODID_EXPECT_THROW_WITH(Synchrosqueeze(descending, transform), std::invalid_argument,
                          "expected frequencies_Hz finite, > 0 and ascending");
  Scalogram short_time = sg;
  short_time.time_s.resize(2);
  PODID_EXPECT_THROW_WITH(FindRidges(short_time, RidgeOptions{}), std::invalid_argument,
                          "2 x 115 as time_s and frequencies_Hz, got 1001 x 115 coefficients");
  SynchrosqueezedTransform sst = Synchrosqueeze(sg, transform);
  sst.reassigned_frequency_Hz.resize(3, 3);
  PODID_EXPECT_THROW_WITH(SynchrosqueezedRidge(sst), std::invalid_argument,
                          "expected reassigned_frequency_Hz of the shape of sst (1001 x 115)");
  PODID_EXPECT_THROW_WITH(SynchrosqueezedRidges(sst, Ridges(2)), std::invalid_argument,
                          "got 3 x 3");
}

TEST(Synchrosqueeze, ChirpRidgeIsAtLeastAsAccurateAsTheCwtRidge) {
  // x = cos(2 pi (20 t + 15 t^2)): f(t) = 20 + 30 t Hz over 2 s at 1 kHz.
  // Both IFs are compared with the analytic one inside the cone (coi_factor 2);
  // the SST ridge must be no worse than the CWT ridge (phase IF with parabolic
  // refinement) and sharper: its energy within one bin of the ridge is a larger
  // share of the column than the CWT's.
  const Eigen::VectorXd t = Time(2001);
  const Eigen::VectorXd x = (2 * kPi * (20.0 * t.array() + 15.0 * t.array().square())).cos();
  CwtTransform transform(TenTo120Hz());
  Scalogram sg;
  transform.Compute(x, kStep_s, &sg);
  const RidgeOptions ridge;
  const RidgeTrack cwt = TrackRidge(sg, FindRidges(sg, ridge).front(), ridge, &transform);
  const SynchrosqueezedTransform sst = Synchrosqueeze(sg, transform);
  const RidgeTrack squeezed = SynchrosqueezedRidge(sst, ridge);
  double cwt_error = 0.0, sst_error = 0.0, cwt_share = 0.0, sst_share = 0.0;
  int used = 0;
  for (Eigen::Index j = 0; j < sg.times(); ++j) {
    if (!cwt.inside_coi(j) || !squeezed.inside_coi(j)) continue;
    const double f = 20.0 + 30.0 * sg.time_s(j);
    cwt_error = std::max(cwt_error, std::abs(cwt.frequency_Hz(j) / f - 1.0));
    sst_error = std::max(sst_error, std::abs(squeezed.frequency_Hz(j) / f - 1.0));
    const auto share = [&](const Eigen::MatrixXcd& c, Eigen::Index k) {
      double near = 0.0;
      for (Eigen::Index l = std::max<Eigen::Index>(0, k - 1);
           l <= std::min<Eigen::Index>(c.cols() - 1, k + 1); ++l) {
        near += std::norm(c(j, l));
      }
      return near / c.row(j).squaredNorm();
    };
    cwt_share += share(sg.coefficients, cwt.frequency_index(j));
    sst_share += share(sst.sst.coefficients, squeezed.frequency_index(j));
    ++used;
  }
  ASSERT_GT(used, 1000);
  std::printf("chirp IF, max relative error inside the cone: CWT ridge %.3g, SST ridge %.3g; "
              "energy within one bin of the ridge: CWT %.3g, SST %.3g\n",
              cwt_error, sst_error, cwt_share / used, sst_share / used);
  EXPECT_LE(sst_error, cwt_error);
  EXPECT_GT(sst_share / used, 2.0 * cwt_share / used);
  // Amplitude of the unit chirp from the SST ridge (within one bin holds most of T).
  EXPECT_NEAR(squeezed.amplitude(sg.times() / 2), 1.0, 0.05);
}

TEST(Synchrosqueeze, TwoRidgesFollowTwoTones) {
  // x = cos(2 pi 20 t) + 0.5 cos(2 pi 60 t), 2 s at 1 kHz: ridge 1 on the
  // stronger tone, ridge 2 on the other, each IF within the other tone's
  // interference of the tone's frequency where both are well inside their
  // cones (0.3-1.7 s). At the 60 Hz scales the 20 Hz tone leaks in with
  // weight r = 2 psi^(2) / psi^(6) = 2 e^-8 (Morlet omega0 6), which moves the
  // phase-derivative IF by up to 40 Hz r / (1 - r) = 0.027 Hz (the CWT ridge
  // moves as much); at the 20 Hz scales the 60 Hz tone's weight is e^-72,
  // so that IF is the tone's to the phase derivative's rounding.
  constexpr double kTolerance20Hz = 1e-6;
  constexpr double kTolerance60Hz = 0.03;
  const Eigen::VectorXd t = Time(2001);
  const Eigen::VectorXd x =
      (2 * kPi * 20.0 * t.array()).cos() + 0.5 * (2 * kPi * 60.0 * t.array()).cos();
  Scalogram sg;
  const SynchrosqueezedTransform sst = Squeezed(x, &sg);
  const RidgeOptions two = Ridges(2);
  const std::vector<RidgeTrack> ridges = SynchrosqueezedRidges(sst, two);
  ASSERT_EQ(ridges.size(), 2u);
  // The first is SynchrosqueezedRidge's, bit for bit.
  const RidgeTrack one = SynchrosqueezedRidge(sst, two);
  EXPECT_TRUE(ridges[0].frequency_index == one.frequency_index);
  EXPECT_TRUE(ridges[0].frequency_Hz.cwiseEqual(one.frequency_Hz).all());
  EXPECT_TRUE(ridges[0].amplitude == one.amplitude);
  int used = 0;
  for (Eigen::Index j = 0; j < sg.times(); ++j) {
    if (sg.time_s(j) < 0.3 || sg.time_s(j) > 1.7) continue;
    EXPECT_NEAR(ridges[0].frequency_Hz(j), 20.0, kTolerance20Hz) << "t " << sg.time_s(j);
    EXPECT_NEAR(ridges[1].frequency_Hz(j), 60.0, kTolerance60Hz) << "t " << sg.time_s(j);
    ASSERT_TRUE(ridges[0].inside_coi(j) && ridges[1].inside_coi(j));
    ++used;
  }
  EXPECT_GT(used, 1300);
  // Amplitudes 1 and 0.5 (within one bin of the ridge holds most of T).
  EXPECT_NEAR(ridges[0].amplitude(sg.times() / 2), 1.0, 0.05);
  EXPECT_NEAR(ridges[1].amplitude(sg.times() / 2), 0.5, 0.025);
}

TEST(Synchrosqueeze, ASecondRidgeWithNoFiniteCellHasNoIf) {
  // One 40 Hz tone: every reassigned coefficient lands within a few bins of
  // 40 Hz, so |T| is exactly 0 elsewhere; with the first ridge's half octave
  // either side excluded, the second ridge's columns have no finite cost and
  // FindRidges gives them -1 (`podid cwt --ridges 2 --synchrosqueeze`
  // indexed |T| at -1 there: a crash). Such times get no IF, as TrackRidge
  // leaves them: NaN frequency and amplitude, outside the cone, not screened.
  const Eigen::VectorXd t = Time(2001);
  const Eigen::VectorXd x = (2 * kPi * 40.0 * t.array()).cos();
  Scalogram sg;
  const SynchrosqueezedTransform sst = Squeezed(x, &sg);
  const RidgeOptions two = Ridges(2);
  const std::vector<Eigen::VectorXi> paths = FindRidges(sst.sst, two);
  ASSERT_EQ(paths.size(), 2u);
  const Eigen::Index missing = (paths[1].array() < 0).count();
  ASSERT_GT(missing, 0) << "the case must have times without a second ridge";
  const std::vector<RidgeTrack> ridges = SynchrosqueezedRidges(sst, two);
  ASSERT_EQ(ridges.size(), 2u);
  EXPECT_TRUE(ridges[1].frequency_index == paths[1]);
  for (Eigen::Index j = 0; j < sg.times(); ++j) {
    if (paths[1](j) >= 0) continue;
    EXPECT_TRUE(std::isnan(ridges[1].frequency_Hz(j))) << "t " << sg.time_s(j);
    EXPECT_TRUE(std::isnan(ridges[1].grid_frequency_Hz(j)));
    EXPECT_TRUE(std::isnan(ridges[1].amplitude(j)));
    EXPECT_FALSE(ridges[1].inside_coi(j));
    EXPECT_FALSE(ridges[1].screened(j));
  }
  // The first ridge is the tone's well inside the cone (0.3-1.7 s, as in
  // TwoRidgesFollowTwoTones): alone, a tone's IF at the fixed point is its
  // frequency to the phase derivative's rounding (that test's 20 Hz tone,
  // which the other leaves at e^-72). Nearer the ends the border effect is
  // up to 0.3 % (docs/wavelet.md).
  constexpr double kToneTolerance_Hz = 1e-6;
  for (Eigen::Index j = 0; j < sg.times(); ++j) {
    if (sg.time_s(j) < 0.3 || sg.time_s(j) > 1.7) continue;
    EXPECT_NEAR(ridges[0].frequency_Hz(j), 40.0, kToneTolerance_Hz) << "t " << sg.time_s(j);
  }
}

TEST(Synchrosqueeze, NeedsTheTransformThatWroteTheScalogram) {
  // The reassignment reads the transform's dW/dt (its last Compute()'s):
  // another transform's read past a shorter record (a crash), a transform
  // never run aborted, and one run since on another signal moved every
  // coefficient by that signal's IF. Each is now an invalid argument, thrown
  // before anything is written.
  constexpr const char* kExpected =
      "expected the CwtTransform whose last Compute() wrote the scalogram";
  const Eigen::VectorXd t = Time(2001);
  const Eigen::VectorXd x = (2 * kPi * 40.0 * t.array()).cos();
  CwtTransform transform(TenTo120Hz()), shorter(TenTo120Hz()), idle(TenTo120Hz());
  Scalogram sg, short_sg;
  transform.Compute(x, kStep_s, &sg);
  shorter.Compute(x.head(501), kStep_s, &short_sg);
  PODID_EXPECT_THROW_WITH(Synchrosqueeze(sg, shorter), std::invalid_argument, kExpected);
  PODID_EXPECT_THROW_WITH(Synchrosqueeze(sg, idle), std::invalid_argument, kExpected);
  SynchrosqueezedTransform out;
  transform.Compute(x, kStep_s, &out.sst);
  const Scalogram w = out.sst;
  transform.Compute((2 * kPi * 70.0 * t.array()).cos(), kStep_s, &sg);
  PODID_EXPECT_THROW_WITH(SynchrosqueezeInPlace(transform, {}, &out), std::invalid_argument,
                          kExpected);
  EXPECT_TRUE(out.sst.coefficients == w.coefficients);  // nothing written
  // T is no CWT output: its phase has no TimeDerivative, so TrackRidge's
  // phase IF refuses it, and squeezing it again is refused too.
  const SynchrosqueezedTransform sst = Synchrosqueeze(sg, transform);
  EXPECT_EQ(sst.sst.computation, 0u);
  const Eigen::VectorXi path = FindRidges(sst.sst, RidgeOptions{}).front();
  PODID_EXPECT_THROW_WITH(TrackRidge(sst.sst, path, RidgeOptions{}, &transform),
                          std::invalid_argument, kExpected);
  SynchrosqueezedTransform again = sst;
  PODID_EXPECT_THROW_WITH(SynchrosqueezeInPlace(transform, {}, &again), std::invalid_argument,
                          kExpected);
  // Out of place into the scalogram itself: refused, not aborted.
  transform.Compute(x, kStep_s, &again.sst);
  PODID_EXPECT_THROW_WITH(Synchrosqueeze(again.sst, transform, {}, &again), std::invalid_argument,
                          "in place: SynchrosqueezeInPlace");
}

TEST(Synchrosqueeze, AnImpulsesRidgeIsScreenedWhereItHasNoIf) {
  // A unit impulse in the middle of 2 s: far from it |W| is rounding noise,
  // no coefficient there is reassigned, and the ridge has no IF. Those
  // samples must be screened (outside the cone), as the CWT ridge's are, and
  // every sample left inside the cone must have a finite, positive IF.
  Eigen::VectorXd x = Eigen::VectorXd::Zero(2001);
  x(1000) = 1.0;
  CwtTransform transform(TenTo120Hz());
  Scalogram sg;
  transform.Compute(x, kStep_s, &sg);
  const RidgeTrack track = SynchrosqueezedRidge(Synchrosqueeze(sg, transform));
  int screened = 0, inside = 0;
  for (Eigen::Index j = 0; j < track.size(); ++j) {
    if (track.screened(j)) {
      ++screened;
      EXPECT_FALSE(track.inside_coi(j));
      EXPECT_TRUE(std::isnan(track.frequency_Hz(j)));
    }
    if (track.inside_coi(j)) {
      ++inside;
      EXPECT_TRUE(std::isfinite(track.frequency_Hz(j)) && track.frequency_Hz(j) > 0.0)
          << "t " << track.time_s(j) << ": " << track.frequency_Hz(j);
    }
  }
  EXPECT_GT(screened, 100);
  EXPECT_GT(inside, 100);
}

TEST(Synchrosqueeze, EqualsTheDefinitionCoefficientByCoefficient) {
  // T written out from its definition, one coefficient at a time: the IF
  // Im(conj(W) dW/dt) / (2 pi |W|^2) of every |W| above 1e-6 of the peak,
  // moved to the grid frequency nearest in ln f (kept where the IF is not
  // positive or beyond half a bin past the grid's ends), times the
  // trapezoid weight in ln s. White noise plus a tone: IFs that jump between
  // neighbouring samples, over many of Synchrosqueeze's blocks of times.
  // 1e-12 of max |T|: the two differ only in how the nearest bin is found
  // (logs here, squares there) and in the order of nothing else.
  constexpr double kTolerance = 1e-12;
  const Eigen::Index n = 4001;
  Eigen::VectorXd x(n);
  std::uint64_t state = 12345;
  for (Eigen::Index i = 0; i < n; ++i) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;  // Knuth's LCG
    const double uniform = static_cast<double>(state >> 11) * 0x1.0p-53;
    x(i) = (uniform - 0.5) + std::cos(2 * kPi * 40.0 * static_cast<double>(i) * kStep_s);
  }
  CwtTransform transform(TenTo120Hz());
  Scalogram sg;
  transform.Compute(x, kStep_s, &sg);
  const SynchrosqueezedTransform sst = Synchrosqueeze(sg, transform);

  const Eigen::Index times = sg.times(), freqs = sg.frequencies();
  const Eigen::VectorXd& f = sg.frequencies_Hz;
  Eigen::VectorXd weight = Eigen::VectorXd::Zero(freqs);
  for (Eigen::Index k = 0; k + 1 < freqs; ++k) {
    const double h = std::log(sg.scales_s(k) / sg.scales_s(k + 1));
    weight(k) += 0.5 * h;
    weight(k + 1) += 0.5 * h;
  }
  const double threshold = 1e-6 * sg.coefficients.cwiseAbs().maxCoeff();
  std::vector<double> ln_grid(static_cast<std::size_t>(freqs));
  for (Eigen::Index q = 0; q < freqs; ++q) ln_grid[static_cast<std::size_t>(q)] = std::log(f(q));
  const double below = std::log(f(0)) - 0.5 * std::log(f(1) / f(0));
  const double above = std::log(f(freqs - 1)) + 0.5 * std::log(f(freqs - 1) / f(freqs - 2));
  Eigen::MatrixXcd expected = Eigen::MatrixXcd::Zero(times, freqs);
  Eigen::VectorXcd derivative;
  int moved_off_diagonal = 0, mismatched_fields = 0;
  for (Eigen::Index k = 0; k < freqs; ++k) {
    transform.TimeDerivative(k, &derivative);
    for (Eigen::Index j = 0; j < times; ++j) {
      const std::complex<double> w = sg.coefficients(j, k);
      if (!(std::abs(w) > threshold)) {
        mismatched_fields += !std::isnan(sst.reassigned_frequency_Hz(j, k));
        continue;
      }
      const double f_Hz = (std::conj(w) * derivative(j)).imag() / (2 * kPi * std::norm(w));
      Eigen::Index l = k;
      if (f_Hz > 0.0) {
        mismatched_fields += !(std::abs(sst.reassigned_frequency_Hz(j, k) - f_Hz) <= 1e-12 * f_Hz);
        const double ln_f = std::log(f_Hz);
        if (ln_f >= below && ln_f <= above) {  // the nearer of the two ln f_q around ln f
          const auto q = std::lower_bound(ln_grid.begin(), ln_grid.end(), ln_f) - ln_grid.begin();
          l = q == freqs ? freqs - 1 : q;
          if (q > 0 && (q == freqs || ln_f - ln_grid[q - 1] < ln_grid[q] - ln_f)) l = q - 1;
        }
      } else {
        mismatched_fields += !std::isnan(sst.reassigned_frequency_Hz(j, k));
      }
      moved_off_diagonal += l != k;
      expected(j, l) += w * weight(k);
    }
  }
  const double peak = expected.cwiseAbs().maxCoeff();
  const double error = (sst.sst.coefficients - expected).cwiseAbs().maxCoeff();
  std::printf(
      "SST against its definition: max |T - T_def| = %.3g of max |T|, %d coefficients moved\n",
      error / peak, moved_off_diagonal);
  EXPECT_LE(error, kTolerance * peak);
  EXPECT_EQ(mismatched_fields, 0);
  EXPECT_GT(moved_off_diagonal, 100000);  // the reassignment did move most of them

  // In place (T over W, block by block): the same bits.
  SynchrosqueezedTransform in_place;
  transform.Compute(x, kStep_s, &in_place.sst);
  SynchrosqueezeInPlace(transform, {}, &in_place);
  EXPECT_TRUE((in_place.sst.coefficients.array() == sst.sst.coefficients.array()).all());
  ASSERT_EQ(in_place.reassigned_frequency_Hz.size(), sst.reassigned_frequency_Hz.size());
  EXPECT_EQ(
      std::memcmp(in_place.reassigned_frequency_Hz.data(), sst.reassigned_frequency_Hz.data(),
                  sizeof(double) * static_cast<std::size_t>(sst.reassigned_frequency_Hz.size())),
      0);
}

TEST(Synchrosqueeze, ReconstructionFromTheSqueezedTransform) {
  // Summing T over frequency reconstructs x like the inverse CWT (the
  // threshold drops only |W| <= 1e-6 max |W|): same 1e-3 figure.
  constexpr double kTolerance = 1e-3;
  const Eigen::VectorXd t = Time(3001);
  const Eigen::VectorXd x =
      (2 * kPi * 25.0 * t.array()).cos() + 0.5 * (2 * kPi * 47.0 * t.array() + 0.5).cos();
  CwtOptions o;
  o.frequencies.min_frequency_Hz = 5.0;
  o.frequencies.max_frequency_Hz = 400.0;
  CwtTransform transform(o);
  Scalogram sg;
  transform.Compute(x, kStep_s, &sg);
  const SynchrosqueezedTransform sst = Synchrosqueeze(sg, transform);
  const Eigen::VectorXd y = sst.sst.coefficients.rowwise().sum().real() *
                            (2.0 / ReconstructionConstant(sg.wavelet));
  const Eigen::VectorXd& xc = x;
  Eigen::Index used = 0;
  const double error = RelativeRmsInsideCone(sg, xc, y, &used);
  Eigen::Index used2 = 0;
  std::printf("SST reconstruction: relative RMS %.3g inside the cone, %.3g inside twice the cone\n",
              error, RelativeRmsInsideCone(sg, xc, y, &used2, 2.0));
  EXPECT_LE(error, kTolerance);
}

}  // namespace
}  // namespace podid::wavelet
