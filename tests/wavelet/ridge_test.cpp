// Tests of podid/wavelet/ridge.hpp against signals with a known instantaneous
// frequency: pure tones, a linear chirp, a decaying tone with known zeta, two
// tones, and a tone in broadband noise.
#include "podid/wavelet/ridge.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "../../wavelet/src/ridge_programme.hpp"  // internal: kMaxRidgeJumpCost
#include "test_support.hpp"

namespace podid::wavelet {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kStep = 1.0 / 5000.0;   // fs = 5 kHz, as the reference data
constexpr Eigen::Index kSamples = 5001;  // 1 s

Eigen::VectorXd Time() { return Eigen::VectorXd::LinSpaced(kSamples, 0.0, 1.0); }

struct Analysis {
  CwtTransform transform;
  Scalogram scalogram;
  explicit Analysis(const CwtOptions& options) : transform(options) {}
};

RidgeTrack MainRidge(const Eigen::VectorXd& x, const CwtOptions& cwt, const RidgeOptions& ridge) {
  Analysis a(cwt);
  a.transform.Compute(x, kStep, &a.scalogram);
  return TrackRidge(a.scalogram, FindRidges(a.scalogram, ridge).front(), ridge, &a.transform);
}

// Max relative error of track.frequency_Hz against f(t) inside the cone.
template <typename F>
double MaxRelativeErrorInsideCoi(const RidgeTrack& track, F&& f) {
  double worst = 0.0;
  for (Eigen::Index j = 0; j < track.size(); ++j) {
    if (!track.inside_coi(j)) continue;
    const double truth = f(track.time_s(j));
    worst = std::max(worst, std::abs(track.frequency_Hz(j) - truth) / truth);
  }
  return worst;
}

// Jumps of more than `bins` grid steps between consecutive ridge samples.
int CountJumps(const RidgeTrack& track, int bins) {
  int jumps = 0;
  for (Eigen::Index j = 1; j < track.size(); ++j) {
    if (std::abs(track.frequency_index(j) - track.frequency_index(j - 1)) > bins) ++jumps;
  }
  return jumps;
}

TEST(Ridge, PureTonePhaseDerivativeIsExact) {
  // 33 Hz (between grid frequencies) at 5 kHz over 1 s. W of a tone is
  // c(s) exp(i w t) at every scale, so the phase derivative is exact.
  // (a) cos(2 pi 33 t) has 33 whole periods: reflect padding continues it
  //     exactly, so the Torrence-Compo cone (coi_factor 1) is clean;
  // (b) an arbitrary phase leaves a kink at each end whose influence at the
  //     cone's border is exp(-coi_factor^2): coi_factor 4 gives exp(-16).
  // 1e-6 is the figure; (a) measures about 1e-11.
  constexpr double kTolerance = 1e-6;
  const Eigen::VectorXd whole = (2 * kPi * 33.0 * Time().array()).cos();
  const Eigen::VectorXd shifted = (2 * kPi * 33.0 * Time().array() + 0.4).sin();
  for (bool band : {false, true}) {
    for (bool kink : {false, true}) {
      CwtOptions cwt;
      cwt.padding = Padding::kReflect;  // (a) continues the whole periods exactly
      cwt.band_limited = band;
      cwt.coi_factor = kink ? 4.0 : 1.0;
      const RidgeTrack track = MainRidge(kink ? shifted : whole, cwt, RidgeOptions{});
      ASSERT_GT(track.InsideCoiCount(), track.size() / 2);
      const double error = MaxRelativeErrorInsideCoi(track, [](double) { return 33.0; });
      EXPECT_LE(error, kTolerance) << "band_limited " << band << " kink " << kink;
      std::printf("tone phase IF: band_limited %d, %s: max relative error %.3g\n", band,
                  kink ? "arbitrary phase, coi_factor 4" : "whole periods, coi_factor 1", error);
    }
  }
}

TEST(Ridge, PureToneRidgeScaleWithinHalfABinThenRefined) {
  // Without refinement the ridge frequency is the nearest grid frequency:
  // within half a log bin, 33 (2^(1/64) - 1) Hz. The parabola through
  // log|W| in s is exact for the L1 Morlet (log|W| = -(s w - omega0)^2 / 2),
  // so 1e-3 (the figure) holds with a wide margin. Same two signals
  // as above.
  constexpr double kRefinedTolerance = 1e-3;
  constexpr double kAmplitudeTolerance = 1e-6;  // refined |W| peak, L1: exactly 1
  const double half_bin_Hz = 33.0 * (std::exp2(1.0 / 64.0) - 1.0);
  for (bool kink : {false, true}) {
    const Eigen::VectorXd x = kink ? Eigen::VectorXd((2 * kPi * 33.0 * Time().array() + 0.4).sin())
                                   : Eigen::VectorXd((2 * kPi * 33.0 * Time().array()).cos());
    CwtOptions cwt;
    cwt.padding = Padding::kReflect;
    cwt.coi_factor = kink ? 4.0 : 1.0;
    RidgeOptions ridge;
    ridge.estimator = FrequencyEstimator::kScale;
    ridge.parabolic_refinement = false;
    const RidgeTrack coarse = MainRidge(x, cwt, ridge);
    ridge.parabolic_refinement = true;
    const RidgeTrack fine = MainRidge(x, cwt, ridge);
    double worst_coarse = 0.0;
    for (Eigen::Index j = 0; j < coarse.size(); ++j) {
      if (coarse.inside_coi(j)) {
        worst_coarse = std::max(worst_coarse, std::abs(coarse.frequency_Hz(j) - 33.0));
      }
    }
    EXPECT_LE(worst_coarse, half_bin_Hz);
    const double refined = MaxRelativeErrorInsideCoi(fine, [](double) { return 33.0; });
    EXPECT_LE(refined, kRefinedTolerance);
    std::printf("tone ridge-scale IF (%s): grid %.4f Hz off (half bin %.4f Hz), refined %.3g\n",
                kink ? "arbitrary phase, coi_factor 4" : "whole periods", worst_coarse, half_bin_Hz,
                refined);
    for (Eigen::Index j = 0; j < fine.size(); ++j) {
      if (fine.inside_coi(j)) {
        ASSERT_NEAR(fine.amplitude(j), 1.0, kAmplitudeTolerance) << j;
      }
    }
  }
}

TEST(Ridge, LinearChirpInstantaneousFrequency) {
  // x = cos(2 pi (20 t + 30 t^2)): f(t) = 20 + 60 t Hz. The Morlet phase IF
  // of a linear chirp is biased by about (beta s^2)^2 Delta / (1 + (beta s^2)^2)
  // with Delta the grid offset (< half a bin): well under the 0.2 %.
  // Reflect padding mirrors the chirp's IF at each end (a V-shaped kink),
  // whose influence at the Torrence-Compo border (coi_factor 1) costs 0.33 %;
  // coi_factor 2 (influence exp(-4)) brings it under 0.2 %. Midway the error
  // is about 4e-6.
  constexpr double kTolerance = 2e-3;
  const Eigen::VectorXd t = Time();
  const Eigen::VectorXd x = (2 * kPi * (20.0 * t.array() + 30.0 * t.array().square())).cos();
  CwtOptions cwt;
  cwt.padding = Padding::kReflect;
  cwt.coi_factor = 2.0;
  const RidgeTrack track = MainRidge(x, cwt, RidgeOptions{});
  const double error = MaxRelativeErrorInsideCoi(track, [](double s) { return 20.0 + 60.0 * s; });
  EXPECT_LE(error, kTolerance);
  EXPECT_NEAR(track.frequency_Hz(2500), 50.0, 1e-4 * 50.0);
  std::printf("chirp IF: max relative error %.3g inside the cone (coi_factor 2), %.3g at 0.5 s\n",
              error, std::abs(track.frequency_Hz(2500) / 50.0 - 1.0));
}

TEST(Ridge, DecayingToneRecoversDampingRatio) {
  // x = exp(-zeta wn t) cos(wd t): at a fixed scale |W| ~ exp(-zeta wn t)
  // exactly, so the least-squares slope of log amplitude inside the cone
  // gives zeta wn; the issue asks for 1 %.
  constexpr double kTolerance = 0.01;
  const double zeta = 0.02, fn = 33.0;
  const double wn = 2 * kPi * fn, wd = wn * std::sqrt(1 - zeta * zeta);
  const Eigen::VectorXd t = Time();
  const Eigen::VectorXd x = (-zeta * wn * t.array()).exp() * (wd * t.array() + 0.3).cos();
  const RidgeTrack track = MainRidge(x, CwtOptions{}, RidgeOptions{});
  double st = 0, sy = 0, stt = 0, sty = 0, sf = 0;
  int count = 0;
  for (Eigen::Index j = 0; j < track.size(); ++j) {
    if (!track.inside_coi(j)) continue;
    const double y = std::log(track.amplitude(j));
    st += track.time_s(j);
    sy += y;
    stt += track.time_s(j) * track.time_s(j);
    sty += track.time_s(j) * y;
    sf += track.frequency_Hz(j);
    ++count;
  }
  const double slope = (count * sty - st * sy) / (count * stt - st * st);
  const double wd_estimate = 2 * kPi * sf / count;
  const double ratio = -slope / wd_estimate;  // zeta / sqrt(1 - zeta^2)
  const double zeta_estimate = ratio / std::sqrt(1 + ratio * ratio);
  EXPECT_NEAR(zeta_estimate, zeta, kTolerance * zeta);
  std::printf("decaying tone: zeta %.6f recovered as %.6f (relative error %.3g)\n", zeta,
              zeta_estimate, std::abs(zeta_estimate - zeta) / zeta);
}

TEST(Ridge, TwoTonesGiveTwoRidges) {
  // 33 Hz and 206 Hz at 10:1 (the beam's first two modes). The weak tone's
  // ridge sees the strong one through psi^(0.96) ~ 3e-6 (x10): 0.1 % holds easily.
  constexpr double kTolerance = 1e-3;
  const Eigen::VectorXd t = Time();
  const Eigen::VectorXd x =
      (2 * kPi * 33.0 * t.array() + 0.2).sin() + 0.1 * (2 * kPi * 206.0 * t.array() + 1.0).sin();
  // Arbitrary phases: coi_factor 4 keeps the reflect kinks out, as for one tone.
  CwtOptions cwt;
  cwt.frequencies.max_frequency_Hz = 400.0;
  cwt.coi_factor = 4.0;
  RidgeOptions ridge;
  ridge.ridges = 2;
  Analysis a(cwt);
  a.transform.Compute(x, kStep, &a.scalogram);
  const auto paths = FindRidges(a.scalogram, ridge);
  ASSERT_EQ(paths.size(), 2u);
  const RidgeTrack first = TrackRidge(a.scalogram, paths[0], ridge, &a.transform);
  const RidgeTrack second = TrackRidge(a.scalogram, paths[1], ridge, &a.transform);
  EXPECT_LE(MaxRelativeErrorInsideCoi(first, [](double) { return 33.0; }), kTolerance);
  EXPECT_LE(MaxRelativeErrorInsideCoi(second, [](double) { return 206.0; }), kTolerance);
  std::printf("two tones: ridge errors %.3g (33 Hz), %.3g (206 Hz)\n",
              MaxRelativeErrorInsideCoi(first, [](double) { return 33.0; }),
              MaxRelativeErrorInsideCoi(second, [](double) { return 206.0; }));
  EXPECT_NEAR(first.amplitude(2500), 1.0, 1e-3);
  EXPECT_NEAR(second.amplitude(2500), 0.1, 1e-3);
}

TEST(Ridge, PenalisedRidgeStaysOnToneInNoiseWhereMaximumJumps) {
  // 33 Hz tone plus white noise whose power in 10-120 Hz equals the tone's
  // (0 dB in band): sigma^2 (110 / 2500) = 1/2. The per-sample maximum wanders
  // to noise peaks; the penalised path pays penalty_s (ln f jump)^2 per jump
  // and stays on the tone.
  const Eigen::VectorXd t = Time();
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, std::sqrt(0.5 * 2500.0 / 110.0));
  Eigen::VectorXd x = (2 * kPi * 33.0 * t.array()).sin();
  for (Eigen::Index i = 0; i < x.size(); ++i) x(i) += normal(rng);
  RidgeOptions max_options;
  max_options.method = RidgeMethod::kMaximum;
  // coi_factor 2: at the Torrence-Compo border the end kinks alone move even
  // a clean tone's ridge by 15 % (see PureTonePhaseDerivativeIsExact).
  CwtOptions cwt;
  cwt.coi_factor = 2.0;
  const RidgeTrack greedy = MainRidge(x, cwt, max_options);
  const RidgeTrack penalised = MainRidge(x, cwt, RidgeOptions{});
  const int greedy_jumps = CountJumps(greedy, 4);  // 4 bins = 1/8 octave
  const int penalised_jumps = CountJumps(penalised, 4);
  // "On the tone": within its peak's half-magnitude width, |f / 33 - 1| < 0.2
  // (|W| = exp(-(6 x 0.2)^2 / 2) = 0.49 there).
  constexpr double kOnTone = 0.2;
  const auto off_tone = [&](const RidgeTrack& track) {
    int count = 0;
    for (Eigen::Index j = 0; j < track.size(); ++j) {
      if (track.inside_coi(j) && std::abs(track.grid_frequency_Hz(j) / 33.0 - 1.0) > kOnTone) {
        ++count;
      }
    }
    return count;
  };
  std::printf(
      "tone in 0 dB noise: jumps > 1/8 octave: max ridge %d, penalised %d; "
      "samples off the tone: max ridge %d, penalised %d\n",
      greedy_jumps, penalised_jumps, off_tone(greedy), off_tone(penalised));
  EXPECT_GE(greedy_jumps, 10);
  EXPECT_GT(off_tone(greedy), 0);
  EXPECT_EQ(penalised_jumps, 0);
  EXPECT_EQ(off_tone(penalised), 0);
}

// The reference beam record's w6 (tests/data/README.md): 5001 samples at 5 kHz.
Eigen::VectorXd ReferenceChannel(const std::string& file, int column) {
  std::ifstream in(podid::testing::DataPath(file));
  EXPECT_TRUE(in.good()) << file;
  std::string line;
  std::getline(in, line);  // header
  std::vector<double> values;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string cell;
    for (int c = 0; c <= column; ++c) std::getline(row, cell, ',');
    values.push_back(std::stod(cell));
  }
  return Eigen::Map<Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
}

TEST(RidgeFrequency, BandLimitedEqualsFullResolutionOnTheBeamRecord) {
  // The identification's call: the IF of a 5001-sample record at 10-120 Hz.
  // The band-limited coefficients are the full ones decimated exactly
  // (cwt_test), so on the same ridge path the IFs agree to rounding; the
  // issue's figure is 1e-4 relative. Also checks the physics: the first mode
  // (~33 Hz) hardens, so its IF falls as the free vibration decays.
  constexpr double kTolerance = 1e-4;
  const Eigen::VectorXd w6 = ReferenceChannel("measured_knl50_T1.0.csv", 6);
  ASSERT_EQ(w6.size(), 5001);
  RidgeFrequencyOptions band_options;  // band_limited by default
  RidgeFrequencyEstimator band(band_options);
  const RidgeTrack fast = band.Estimate(w6, kStep);
  ASSERT_EQ(band.scalogram().decimation, 16);

  CwtOptions full_cwt = band_options.cwt;
  full_cwt.band_limited = false;
  Analysis full(full_cwt);
  full.transform.Compute(w6, kStep, &full.scalogram);
  // Same path, at full resolution.
  Eigen::VectorXi path = Eigen::VectorXi::Constant(full.scalogram.times(), -1);
  for (Eigen::Index j = 0; j < fast.size(); ++j) path(16 * j) = fast.frequency_index(j);
  const RidgeTrack slow = TrackRidge(full.scalogram, path, band_options.ridge, &full.transform);
  // And the full-resolution ridge's own path.
  const RidgeTrack own =
      TrackRidge(full.scalogram, FindRidges(full.scalogram, band_options.ridge).front(),
                 band_options.ridge, &full.transform);
  double same_path = 0.0, own_path = 0.0;
  int own_compared = 0;
  for (Eigen::Index j = 0; j < fast.size(); ++j) {
    if (!fast.inside_coi(j)) continue;
    same_path = std::max(same_path, std::abs(fast.frequency_Hz(j) / slow.frequency_Hz(16 * j) - 1));
    own_path = std::max(own_path, std::abs(fast.frequency_Hz(j) / own.frequency_Hz(16 * j) - 1));
    ++own_compared;
  }
  std::printf(
      "beam w6: band-limited vs full IF, same path %.3g, each its own ridge %.3g "
      "(%d samples inside the cone)\n",
      same_path, own_path, own_compared);
  EXPECT_LE(same_path, kTolerance);
  EXPECT_LE(own_path, kTolerance);
  // Hardening: early IF above late IF, both near the 32.97 Hz linear mode.
  Eigen::Index first = -1, last = -1;
  for (Eigen::Index j = 0; j < fast.size(); ++j) {
    if (fast.inside_coi(j)) {
      if (first < 0) first = j;
      last = j;
    }
  }
  ASSERT_GE(first, 0);
  EXPECT_GT(fast.frequency_Hz(first), fast.frequency_Hz(last));
  EXPECT_GT(fast.frequency_Hz(last), 32.0);
  EXPECT_LT(fast.frequency_Hz(first), 40.0);

  // Reusing the estimator gives the same answer (state is reset per call).
  const RidgeTrack again = band.Estimate(w6, kStep);
  EXPECT_TRUE(again.frequency_Hz == fast.frequency_Hz);
}

TEST(RidgeFrequency, ParallelEstimatorsMatchSerial) {
  const Eigen::VectorXd w6 = ReferenceChannel("measured_knl50_T1.0.csv", 6);
  const Eigen::VectorXd w3 = ReferenceChannel("measured_knl50_T1.0.csv", 3);
  const RidgeTrack a = RidgeFrequency(w6, kStep), b = RidgeFrequency(w3, kStep);
  RidgeTrack pa, pb;
  std::thread ta([&] {
    for (int i = 0; i < 5; ++i) pa = RidgeFrequency(w6, kStep);
  });
  std::thread tb([&] {
    RidgeFrequencyEstimator e;
    for (int i = 0; i < 5; ++i) pb = e.Estimate(w3, kStep);
  });
  ta.join();
  tb.join();
  EXPECT_TRUE(pa.frequency_Hz == a.frequency_Hz);
  EXPECT_TRUE(pb.frequency_Hz == b.frequency_Hz);
}

TEST(Ridge, ScreeningLeavesNoIfWhereAnImpulsesTransformIsNegligible) {
  // 1e-5: at the screening threshold (|W| = 1e-6 of the peak) the transform's
  // ~1e-12 truncation noise is 1e-6 of W. The mean is kept (removing it adds
  // a constant whose W pulls the weakest samples' IF by up to 3e-5).
  constexpr double kTolerance = 1e-5;
  // A unit impulse at 0.1 s: W(s, t) = conj(psi((t0 - t) / s)) / s, whose
  // phase derivative is the analysis frequency omega0 / (2 pi s) where |W| is
  // not negligible (between f_min and f_max), and rounding noise where the
  // Gaussian envelope has fallen below ~1e-12 (it gave -0.046 Hz before
  // screening). With screening every IF inside the cone is within the grid,
  // and the far samples are screened.
  Eigen::VectorXd x = Eigen::VectorXd::Zero(kSamples);
  x(kSamples / 10) = 1.0;
  CwtOptions cwt;
  cwt.padding = Padding::kReflect;
  cwt.remove_mean = false;
  Analysis a(cwt);
  a.transform.Compute(x, kStep, &a.scalogram);
  const RidgeOptions ridge;
  const RidgeTrack track =
      TrackRidge(a.scalogram, FindRidges(a.scalogram, ridge).front(), ridge, &a.transform);
  const double f_min = a.scalogram.frequencies_Hz(0);
  const double f_max = a.scalogram.frequencies_Hz(a.scalogram.frequencies() - 1);
  for (Eigen::Index j = 0; j < track.size(); ++j) {
    if (!track.inside_coi(j)) continue;
    EXPECT_GE(track.frequency_Hz(j), f_min * (1 - kTolerance)) << j;
    EXPECT_LE(track.frequency_Hz(j), f_max * (1 + kTolerance)) << j;
  }
  EXPECT_GT(track.screened.count(), track.size() / 4);
  EXPECT_GT(track.InsideCoiCount(), 0);
  // Screening off: the old behaviour, IFs outside the grid inside the cone.
  RidgeOptions off = ridge;
  off.min_relative_magnitude = 0.0;
  const RidgeTrack raw =
      TrackRidge(a.scalogram, FindRidges(a.scalogram, off).front(), off, &a.transform);
  int outside = 0;
  double lo = 1e300;
  for (Eigen::Index j = 0; j < raw.size(); ++j) {
    if (track.screened(j) && raw.inside_coi(j)) lo = std::min(lo, raw.frequency_Hz(j));
    if (raw.inside_coi(j) && !(raw.frequency_Hz(j) >= f_min * 0.5)) ++outside;
  }

  EXPECT_GT(outside, 0);
  std::printf("impulse: %ld of %ld ridge samples screened; without screening %d IFs inside the "
              "cone below f_min / 2, the lowest %.3g Hz\n",
              static_cast<long>(track.screened.count()), static_cast<long>(track.size()), outside,
              lo);
}

TEST(Ridge, BadInputNamesWhatWasExpected) {
  RidgeOptions o;
  o.penalty_s = -1.0;
  std::string why;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("penalty_s: expected a finite value >= 0, got -1"), std::string::npos);
  const Eigen::VectorXd x = (2 * kPi * 33.0 * Time().array()).cos();
  const Scalogram sg = Cwt(x, kStep);
  PODID_EXPECT_THROW_WITH(FindRidges(sg, o), std::invalid_argument, "penalty_s");
  o = RidgeOptions{};
  o.ridges = 0;
  PODID_EXPECT_THROW_WITH(FindRidges(sg, o), std::invalid_argument, "ridges: expected 1..16");
  o = RidgeOptions{};
  o.separation_octaves = 0.0;
  PODID_EXPECT_THROW_WITH(FindRidges(sg, o), std::invalid_argument, "separation_octaves");
  PODID_EXPECT_THROW_WITH(FindRidges(Scalogram{}, RidgeOptions{}), std::invalid_argument,
                          "expected a computed scalogram");
  PODID_EXPECT_THROW_WITH(TrackRidge(sg, Eigen::VectorXi::Zero(3), RidgeOptions{}, nullptr),
                          std::invalid_argument, "one index per output time");
  PODID_EXPECT_THROW_WITH(
      TrackRidge(sg, Eigen::VectorXi::Zero(sg.times()), RidgeOptions{}, nullptr),
      std::invalid_argument, "expected the CwtTransform");
  PODID_EXPECT_THROW_WITH(RidgeFrequency(Eigen::VectorXd::Ones(100), kStep), std::invalid_argument,
                          "expected a non-constant signal");
  PODID_EXPECT_THROW_WITH(ParseRidgeMethod("greedy"), std::invalid_argument,
                          "expected one of max, penalised");
  // A finite penalty whose jump cost penalty_s / step_s (ln f)^2 overflows:
  // lambda = inf made every envelope test inf or NaN (identify --penalty 1e308
  // ran and returned an objective).
  o = RidgeOptions{};
  o.penalty_s = 1e308;
  ASSERT_TRUE(o.IsValid(nullptr));
  PODID_EXPECT_THROW_WITH(FindRidges(sg, o), std::invalid_argument,
                          "RidgeOptions.penalty_s: expected a penalty whose largest jump cost "
                          "penalty_s / step_s x (2 max |ln f|)^2 is at most 1e+296");
  RidgeFrequencyOptions streamed;
  streamed.ridge.penalty_s = 1e308;
  PODID_EXPECT_THROW_WITH(RidgeFrequency(x, kStep, streamed), std::invalid_argument,
                          "RidgeOptions.penalty_s: expected a penalty whose largest jump cost");
  streamed.ridge.penalty_s = 1e290;  // jump cost 4.6e295 at kStep, 10-120 Hz: a path
  EXPECT_EQ(RidgeFrequency(x, kStep, streamed).size(), RidgeFrequency(x, kStep).size());
}

TEST(Ridge, TheLargestAcceptedPenaltyGivesTheFlattestPath) {
  // The ridges of a chirp (20 -> 80 Hz) and a tone (33 Hz) at penalties from
  // 1e152 s (where the envelope's products of size lambda^2 overflowed:
  // podid cwt --penalty 1e152 gave IFs from -1.7 to 622 Hz on a 10-118 Hz
  // grid) to the largest accepted, kMaxRidgeJumpCost step / (2 max ln f)^2:
  // any jump then costs more than every column's cost range together
  // (lambda (ln 2 / 32)^2 >= 2e148 against 5001 columns of at most 30), so
  // the path is the constant k* = argmin_k sum_j -log|W(j, k)|, summed here
  // from W. The streamed estimator (band-limited costs) stays on one row
  // too: the tone's. Above the largest, refused with a message naming
  // penalty_s and the bound.
  const Eigen::VectorXd t = Time();
  const Eigen::VectorXd chirp = (2 * kPi * (20.0 * t.array() + 30.0 * t.array().square())).cos();
  const Eigen::VectorXd tone = (2 * kPi * 33.0 * t.array()).cos();
  double largest = 0.0;
  for (const Eigen::VectorXd* x : {&chirp, &tone}) {
    const Scalogram sg = Cwt(*x, kStep);
    const Eigen::VectorXd ln_f = sg.frequencies_Hz.array().log();
    const double reach = 2.0 * ln_f.cwiseAbs().maxCoeff();
    largest = internal::kMaxRidgeJumpCost / (reach * reach) * kStep * (1.0 - 1e-15);
    Eigen::VectorXd sums = Eigen::VectorXd::Zero(sg.frequencies());
    for (Eigen::Index k = 0; k < sg.frequencies(); ++k) {
      for (Eigen::Index j = 0; j < sg.times(); ++j)
        sums(k) -= std::log(std::abs(sg.coefficients(j, k)));
    }
    Eigen::Index flattest = 0;
    sums.minCoeff(&flattest);
    for (double penalty_s : {1e152, 1e200, largest}) {
      RidgeOptions o;
      o.penalty_s = penalty_s;
      const Eigen::VectorXi path = FindRidges(sg, o).front();
      EXPECT_EQ(path, Eigen::VectorXi::Constant(sg.times(), static_cast<int>(flattest)))
          << "penalty " << penalty_s;
      RidgeFrequencyOptions streamed;
      streamed.ridge.penalty_s = penalty_s;
      const RidgeTrack track = RidgeFrequency(*x, kStep, streamed);
      EXPECT_EQ(track.frequency_index.minCoeff(), track.frequency_index.maxCoeff())
          << "penalty " << penalty_s;
      if (x == &tone) {
        EXPECT_EQ(track.frequency_index(0), flattest) << "penalty " << penalty_s;
      }
    }
  }
  const Scalogram sg = Cwt(tone, kStep);
  RidgeOptions o;
  o.penalty_s = largest * (1.0 + 1e-9);
  PODID_EXPECT_THROW_WITH(FindRidges(sg, o), std::invalid_argument,
                          "RidgeOptions.penalty_s: expected a penalty whose largest jump cost "
                          "penalty_s / step_s x (2 max |ln f|)^2 is at most 1e+296: penalty_s <= ");
  RidgeFrequencyOptions streamed;
  streamed.ridge.penalty_s = largest * (1.0 + 1e-9);
  PODID_EXPECT_THROW_WITH(RidgeFrequency(tone, kStep, streamed), std::invalid_argument,
                          "is at most 1e+296: penalty_s <= ");
}

TEST(Ridge, ThePhaseIfNeedsTheTransformThatWroteTheScalogram) {
  // TrackRidge's phase IF reads the transform's TimeDerivative, which is its
  // last Compute()'s: with another transform's it read past the end of a
  // shorter one (a crash) or took another signal's dW/dt (a wrong IF).
  constexpr const char* kExpected =
      "expected the CwtTransform whose last Compute() wrote the scalogram";
  const Eigen::VectorXd x = (2 * kPi * 33.0 * Time().array()).cos();
  Analysis a{CwtOptions{}}, shorter{CwtOptions{}};
  a.transform.Compute(x, kStep, &a.scalogram);
  shorter.transform.Compute(x.head(1001), kStep, &shorter.scalogram);
  const Eigen::VectorXi path = FindRidges(a.scalogram, RidgeOptions{}).front();
  EXPECT_TRUE(a.transform.Produced(a.scalogram));
  EXPECT_FALSE(shorter.transform.Produced(a.scalogram));
  PODID_EXPECT_THROW_WITH(TrackRidge(a.scalogram, path, RidgeOptions{}, &shorter.transform),
                          std::invalid_argument, kExpected);
  // The same transform after it has transformed another signal of the same
  // length: its dW/dt is that signal's now.
  const Scalogram first = a.scalogram;  // a copy counts as the same output
  EXPECT_TRUE(a.transform.Produced(first));
  const Eigen::VectorXd y = (2 * kPi * 47.0 * Time().array()).cos();
  a.transform.Compute(y, kStep, &a.scalogram);
  EXPECT_FALSE(a.transform.Produced(first));
  PODID_EXPECT_THROW_WITH(TrackRidge(first, path, RidgeOptions{}, &a.transform),
                          std::invalid_argument, kExpected);
  // Invalid input throws before anything changes: y's scalogram stays the
  // transform's output.
  EXPECT_THROW(a.transform.Compute(Eigen::VectorXd::Ones(kSamples), kStep, &a.scalogram),
               std::invalid_argument);
  EXPECT_TRUE(a.transform.Produced(a.scalogram));
  // TimeDerivative itself: a frequency index outside the grid, and a
  // transform never run, are invalid arguments (they aborted).
  Eigen::VectorXcd derivative;
  PODID_EXPECT_THROW_WITH(a.transform.TimeDerivative(a.scalogram.frequencies(), &derivative),
                          std::invalid_argument, "frequency_index: expected 0..");
  PODID_EXPECT_THROW_WITH(CwtTransform(CwtOptions{}).TimeDerivative(0, &derivative),
                          std::invalid_argument, "expected a Compute() that succeeded first");
  // The scale estimator needs no transform: any scalogram will do.
  RidgeOptions by_scale;
  by_scale.estimator = FrequencyEstimator::kScale;
  EXPECT_NO_THROW(TrackRidge(first, path, by_scale, &shorter.transform));
  // The right pair gives the tone's IF, to PureTonePhaseDerivativeIsExact's
  // 1e-6 relative in mid-record.
  constexpr double kTolerance = 1e-6;
  a.transform.Compute(x, kStep, &a.scalogram);
  const RidgeTrack track = TrackRidge(a.scalogram, path, RidgeOptions{}, &a.transform);
  EXPECT_NEAR(track.frequency_Hz(kSamples / 2), 33.0, 33.0 * kTolerance);
}

}  // namespace
}  // namespace podid::wavelet
