// Several modes in the objective (issue 13 item 4): each mode's ridge band
// follows the mode, ridge samples and modes buried in the measurement noise
// are not compared, and knl is identified from the shared 1 s record with
// --modes 2 and 3 as with one mode.
#include <gtest/gtest.h>

#include <cmath>

#include "podid/core/beam_model.hpp"
#include "podid/core/io.hpp"
#include "podid/core/simulate.hpp"
#include "podid/ident/identify.hpp"
#include "podid/ident/objective.hpp"
#include "reference_case.hpp"

namespace podid::ident {
namespace {

using testing::DataPath;
using testing::kKnlRelativeTolerance;
using testing::kTrueKnl;
using testing::ReferenceDocument;

ObjectiveOptions WaveletWithModes(int modes) {
  ObjectiveOptions options;
  options.SetWeights(ObjectiveWeights::Preset("wavelet"));
  options.modes = modes;
  return options;
}

double IdentifyKnl(const ObjectiveFunction& objective, double start) {
  IdentifyOptions options;
  options.start = Eigen::VectorXd::Constant(1, start);
  const IdentifySummary summary = Identify(objective, options);
  EXPECT_TRUE(summary.IsSolutionUsable()) << summary.FullReport();
  std::cout << summary.BriefReport() << "\n";
  return summary.parameters[0];
}

// The linear beam's natural frequencies: the reference for where each POD
// time mode's own line must be found.
Eigen::VectorXd LinearFrequencies_Hz() {
  return BeamModel::Build(ReferenceDocument().ToSpec()).Modes(3).frequencies_Hz;
}

TEST(SeveralModesTest, ModeTwoFollowsTheSecondBendingModeAndModeThreeIsNoise) {
  const ObjectiveFunction objective(ReferenceDocument(), ReadCsv(DataPath("measured_knl50_T1.0.csv")),
                                    WaveletWithModes(3));
  for (const std::string& note : objective.notes()) std::cout << note << "\n";
  // Mode 3's measured sigma is 1.4 % signal (the rest white noise): not compared.
  EXPECT_EQ(objective.compared_modes(), 2);
  ASSERT_EQ(objective.measured_ridges().size(), 2u);
  // Mode 1 keeps the given band; mode 2's band is centred on its own line,
  // near the linear beam's second natural frequency (206.7 Hz; the POD time
  // mode of the nonlinear response also carries mode 1's 34 Hz, excluded).
  const auto& band1 = objective.mode_ridge_options(0).cwt.frequencies;
  EXPECT_EQ(band1.min_frequency_Hz, 10.0);
  EXPECT_EQ(band1.max_frequency_Hz, 120.0);
  const auto& band2 = objective.mode_ridge_options(1).cwt.frequencies;
  const double centre_Hz = std::sqrt(band2.min_frequency_Hz * band2.max_frequency_Hz);
  // 2 %: the periodogram's resolution is 1 Hz and a hardening spring raises
  // the measured line above the linear frequency by about 1 %.
  EXPECT_NEAR(centre_Hz / LinearFrequencies_Hz()[1], 1.0, 0.02);
}

TEST(SeveralModesTest, TwoAndThreeModesIdentifyKnlOnTheSharedRecord) {
  const TimeSeries measured = ReadCsv(DataPath("measured_knl50_T1.0.csv"));
  for (int modes : {2, 3}) {
    const ObjectiveFunction objective(ReferenceDocument(), measured, WaveletWithModes(modes));
    EXPECT_NEAR(IdentifyKnl(objective, 25.0) / kTrueKnl, 1.0, kKnlRelativeTolerance) << modes << " modes";
  }
}

TEST(SeveralModesTest, WithoutScreeningTheNoiseModeTwoBiasesKnl) {
  // The same objective comparing every ridge sample of mode 2 (also those
  // where it has decayed into the noise) and mode 2's raw sigma: the bias the
  // screening and the correction remove (knl 49.5 or worse). If this starts
  // passing the 0.5 % bound, the screening is no longer what makes the
  // difference and the test above proves less.
  ObjectiveOptions options = WaveletWithModes(2);
  options.ridge_min_snr = 0.0;
  options.noise_corrected_sigma = ObjectiveOptions::SigmaNoise::kRaw;
  const ObjectiveFunction objective(ReferenceDocument(), ReadCsv(DataPath("measured_knl50_T1.0.csv")), options);
  EXPECT_GT(std::abs(IdentifyKnl(objective, 25.0) / kTrueKnl - 1.0), kKnlRelativeTolerance);
}

TEST(SeveralModesTest, NoiseFreeDataVanishAtTheTruthWithEveryModeCompared) {
  // Data simulated by podid at knl = 50 without noise: nothing is screened,
  // no mode dropped, and every term is zero at the truth (round-off).
  CaseDocument document = ReferenceDocument();
  document.SetNumber("time.duration", 0.5);
  const TimeSeries data = Simulate(document.ToSpec(), SimulateOptions{false}).sensors;
  const ObjectiveFunction objective(document, data, WaveletWithModes(2));
  EXPECT_EQ(objective.compared_modes(), 2);
  const TermValues at_truth = objective.Evaluate(Eigen::VectorXd::Constant(1, kTrueKnl)).terms;
  ASSERT_FALSE(at_truth.failed) << at_truth.failure;
  EXPECT_LE(at_truth.f, 1e-12);  // as VanishesAtTheTruthOnNoiseFreeSimulatedData
  EXPECT_LE(at_truth.u, 1e-12);
  // With two modes the measured sigmas are noise-corrected by default, and on
  // clean data the second-difference estimate of the "noise" is the signal's
  // own curvature, attenuated by (omega dt)^2 (pod/noise.hpp): sigma_2 moves
  // by 2.2e-4 relative here. 1e-6 bounds that at 1e-3.
  EXPECT_LE(at_truth.s, 1e-6);
  EXPECT_GT(objective.Evaluate(Eigen::VectorXd::Constant(1, 60.0)).terms.f, 1e-6);
}

TEST(SeveralModesTest, GivenBandIsUsedAndBadOptionsAreRefused) {
  ObjectiveOptions options = WaveletWithModes(2);
  options.mode_bands = {{}, {150.0, 300.0}};
  const ObjectiveFunction objective(ReferenceDocument(), ReadCsv(DataPath("measured_knl50_T1.0.csv")), options);
  EXPECT_EQ(objective.mode_ridge_options(1).cwt.frequencies.min_frequency_Hz, 150.0);
  EXPECT_EQ(objective.mode_ridge_options(1).cwt.frequencies.max_frequency_Hz, 300.0);

  std::string why;
  ObjectiveOptions bad = WaveletWithModes(2);
  bad.mode_bands = {{10.0, 100.0}};
  EXPECT_FALSE(bad.IsValid(&why));
  EXPECT_NE(why.find("mode_bands[0]"), std::string::npos) << why;
  bad.mode_bands = {{}, {300.0, 150.0}};
  EXPECT_FALSE(bad.IsValid(&why));
  EXPECT_NE(why.find("mode 2"), std::string::npos) << why;
  bad.mode_bands = {{}, {}, {}};
  EXPECT_FALSE(bad.IsValid(&why));
  bad = WaveletWithModes(2);
  bad.min_signal_fraction = 1.0;
  EXPECT_FALSE(bad.IsValid(&why));
  bad = WaveletWithModes(2);
  bad.ridge_min_snr = -1.0;
  EXPECT_FALSE(bad.IsValid(&why));
}

}  // namespace
}  // namespace podid::ident
