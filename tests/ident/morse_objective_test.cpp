// The wavelet objective with a generalised Morse wavelet (issue 13 item 5:
// Morse beside Morlet, here in identification): knl from the shared 1 s
// record, and the record-length check with Morse's own cone of influence.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numbers>
#include <stdexcept>
#include <string>

#include "podid/core/io.hpp"
#include "podid/ident/identify.hpp"
#include "podid/ident/objective.hpp"
#include "reference_case.hpp"

namespace podid::ident {
namespace {

using testing::DataPath;
using testing::kKnlRelativeTolerance;
using testing::kTrueKnl;
using testing::ReferenceDocument;

// MATLAB's default Morse wavelet.
constexpr double kGamma = 3.0, kBeta = 20.0;

ObjectiveOptions MorseWavelet(int modes) {
  ObjectiveOptions options;
  options.SetWeights(ObjectiveWeights::Preset("wavelet"));
  options.modes = modes;
  options.ridge.cwt.wavelet.family = wavelet::WaveletFamily::kMorse;
  options.ridge.cwt.wavelet.gamma = kGamma;
  options.ridge.cwt.wavelet.beta = kBeta;
  return options;
}

// Morse's time spread in closed form (independent of the quadrature in
// MorletWavelet::TimeSpread): with psi^(u) = u^b exp(-u^g),
// psi^'(u) = (b / u - g u^(g - 1)) psi^(u) and
// I(a) = int_0^inf u^(2b + a) exp(-2 u^g) du = Gamma((2b + a + 1) / g) / (g 2^((2b + a + 1) / g)),
// sigma_t^2 = int psi^'^2 / int psi^^2 = (b^2 I(-2) - 2 b g I(g - 2) + g^2 I(2 g - 2)) / I(0).
double MorseTimeSpread(double g, double b) {
  const auto integral = [&](double a) {
    const double p = (2.0 * b + a + 1.0) / g;
    return std::tgamma(p) / (g * std::pow(2.0, p));
  };
  return std::sqrt(
      (b * b * integral(-2.0) - 2.0 * b * g * integral(g - 2.0) + g * g * integral(2.0 * g - 2.0)) /
      integral(0.0));
}

TEST(MorseObjective, IdentifiesKnlOnTheSharedRecordWithOneAndTwoModes) {
  const CaseDocument document = ReferenceDocument();
  const TimeSeries measured = ReadCsv(DataPath("measured_knl50_T1.0.csv"));
  for (int modes : {1, 2}) {
    const ObjectiveFunction objective(document, measured, MorseWavelet(modes));
    EXPECT_EQ(objective.mode_ridge_options(0).cwt.wavelet.family, wavelet::WaveletFamily::kMorse);
    IdentifyOptions options;
    options.start = Eigen::VectorXd::Constant(1, 25.0);
    const IdentifySummary summary = Identify(objective, options);
    ASSERT_TRUE(summary.IsSolutionUsable()) << summary.FullReport();
    std::cout << modes << " modes: " << summary.BriefReport() << "\n";
    EXPECT_NEAR(summary.parameters[0] / kTrueKnl, 1.0, kKnlRelativeTolerance) << modes << " modes";
  }
}

TEST(MorseObjective, TheRecordMustHoldMorsesOwnConeOfInfluence) {
  // The first 0.3 s of the 1 s record: longer than the Morlet cone's needs at
  // 10 Hz (2 x sqrt(2) s, 0.270 s), shorter than Morse's (0.350 s).
  const CaseDocument document = ReferenceDocument();
  TimeSeries measured = ReadCsv(DataPath("measured_knl50_T1.0.csv"));
  const Eigen::Index kept = 1501;  // 0.3 s at 2e-4 s
  measured.time_s.conservativeResize(kept);
  measured.values.conservativeResize(kept, Eigen::NoChange);

  ObjectiveOptions morlet;
  morlet.SetWeights(ObjectiveWeights::Preset("wavelet"));
  EXPECT_NO_THROW(ObjectiveFunction(document, measured, morlet));

  std::string message = "no exception";
  try {
    ObjectiveFunction objective(document, measured, MorseWavelet(1));
  } catch (const std::invalid_argument& e) {
    message = e.what();
  }
  const std::string before = "a record longer than ";
  const std::size_t at = message.find(before);
  ASSERT_NE(at, std::string::npos) << message;
  const double needed_s = std::stod(message.substr(at + before.size()));
  // 2 x cone factor 1 x 2 sigma_t s(10 Hz), s = u_p / (2 pi 10 Hz) on the
  // ridge convention with L1 normalisation: u_p = (beta / gamma)^(1 / gamma).
  const double scale_s = std::pow(kBeta / kGamma, 1.0 / kGamma) / (2.0 * std::numbers::pi * 10.0);
  const double expected_s = 2.0 * 2.0 * MorseTimeSpread(kGamma, kBeta) * scale_s;
  // 1e-7: the message prints 10 digits, and TimeSpread's trapezoid rule over
  // 20,000 panels of a smooth band is accurate far below that.
  EXPECT_NEAR(needed_s, expected_s, 1e-7 * expected_s) << message;
  EXPECT_NE(message.find("10 Hz"), std::string::npos) << message;
}

}  // namespace
}  // namespace podid::ident
