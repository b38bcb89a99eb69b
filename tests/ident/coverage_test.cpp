// The 95 % intervals of identified parameters against the truth over Monte
// Carlo copies of a podid-simulated record (issue 12 item 7): the reference
// beam, knl = 50, 1 % noise as in the shared data, 50 copies.
#include <gtest/gtest.h>

#include <iostream>

#include "podid/core/case_file.hpp"
#include "podid/core/noise.hpp"
#include "podid/core/simulate.hpp"
#include "podid/ident/identify.hpp"
#include "podid/ident/objective_uncertainty.hpp"
#include "test_support.hpp"

namespace podid::ident {
namespace {

using testing::ExamplePath;

TEST(CoverageTest, NinetyFivePercentIntervalsHoldTheTruthInNinetyToNinetyNinePercentOfCopies) {
  // 50 copies: the coverage rate's binomial standard deviation is 3 %, so a
  // calibrated 95 % interval lands in 90-99 % (the bounds) unless it
  // is off by more than about 1.5 standard deviations.
  constexpr int kCopies = 50;
  constexpr double kMinCoverage = 0.90, kMaxCoverage = 0.99;
  constexpr double kTrueKnl = 50.0;
  const CaseDocument document = CaseDocument::Load(ExamplePath("beam.toml"));
  SimulateOptions clean;
  clean.add_noise = false;
  const SimulationResult truth = Simulate(document.ToSpec(), clean);
  ASSERT_TRUE(truth.summary.IsSolutionUsable());
  ObjectiveOptions options;
  options.weightings = {{"full", ObjectiveWeights::Preset("full")}};
  int covered = 0, usable = 0;
  double width = 0.0;
  for (int copy = 0; copy < kCopies; ++copy) {
    TimeSeries measured = truth.sensors;
    AddNoise(measured, 0.01, 1000 + copy);  // 1 % of max |x(0)|, as the shared data
    const ObjectiveFunction objective(document, measured, options);
    IdentifyOptions identify;
    identify.start = Eigen::VectorXd::Constant(1, 40.0);
    const IdentifySummary summary = Identify(objective, identify);
    ASSERT_TRUE(summary.IsSolutionUsable()) << summary.message;
    const ParameterUncertainty u = ObjectiveUncertainty(objective, summary.parameters, 0, {}, copy + 1);
    if (!u.usable) continue;
    ++usable;
    width += u.upper[0] - u.lower[0];
    covered += u.lower[0] <= kTrueKnl && kTrueKnl <= u.upper[0];
  }
  std::cout << "coverage " << covered << "/" << usable << " usable of " << kCopies
            << " copies, mean 95 % interval width " << width / usable << "\n";
  EXPECT_EQ(usable, kCopies);
  EXPECT_GE(covered, kMinCoverage * usable);
  EXPECT_LE(covered, kMaxCoverage * usable);
}

}  // namespace
}  // namespace podid::ident
