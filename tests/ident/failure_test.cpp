// Failure paths of the identification (issue 7): a parameter value at which
// the simulation fails is a failed evaluation, counted, and the search goes
// on; an optimiser stopped early (budget, cancel) says so in the summary and
// keeps the best point seen.
//
// The parameter is knl (k3 = 1e8 knl) of the reference case, allowed to go
// negative: a softening spring (k3 < 0) can carry at most (2/3) k w* with
// w* = sqrt(k / (3 |k3|)) and k ~ 9.4e3 N/m at the tip, below the case's
// 20 N of static tip force once knl < -3, so the initial static solve (and the
// evaluation) fails there.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <limits>
#include <string>

#include "podid/ident/identify.hpp"
#include "podid/ident/landscape.hpp"
#include "podid/ident/objective.hpp"
#include "reference_case.hpp"

namespace podid::ident {
namespace {

ObjectiveFunction KnlObjective(double lower, double upper, double start) {
  const CaseDocument document = CaseDocument::Load(testing::ExamplePath("beam.toml"));
  ParameterSpec knl;
  knl.name = "knl";
  knl.key = "nonlinearity.0.k3";
  knl.scale = 1e8;
  knl.start = start;
  knl.lower = lower;
  knl.upper = upper;
  return ObjectiveFunction(document, testing::ReferenceData("measured_knl50_T0.1.csv"),
                           ObjectiveOptions{}, /*weights_needing_ridges=*/false, {knl});
}

const ObjectiveWeights kTimeFree = ObjectiveWeights::Preset("time-free");

/// The best non-failed point of the history, as Identify must report it.
const IterationRecord* BestRecord(const IdentifySummary& summary) {
  const IterationRecord* best = nullptr;
  for (const IterationRecord& r : summary.history) {
    if (!r.failed && (best == nullptr || r.objective < best->objective)) best = &r;
  }
  return best;
}

void ExpectBestPointKept(const IdentifySummary& summary) {
  const IterationRecord* best = BestRecord(summary);
  ASSERT_NE(best, nullptr) << summary.FullReport();
  EXPECT_EQ(summary.final_objective, best->objective);
  EXPECT_EQ(summary.parameters, best->parameters);
  EXPECT_TRUE(summary.IsSolutionUsable()) << summary.FullReport();
}

TEST(ObjectiveFailure, DivergingSimulationIsAFailedEvaluationWithItsReason) {
  const ObjectiveFunction f = KnlObjective(-100.0, 200.0, 40.0);
  const TermValues bad = f.Evaluate(Eigen::VectorXd::Constant(1, -50.0), kTimeFree);
  EXPECT_TRUE(bad.failed);
  EXPECT_FALSE(bad.failure.empty());
  std::printf("knl = -50: %s\n", bad.failure.c_str());
  EXPECT_EQ(bad.Combine(kTimeFree, f.options().failure_value), kDefaultFailureValue);
  // The same objective still evaluates a good point afterwards.
  const TermValues good = f.Evaluate(Eigen::VectorXd::Constant(1, 50.0), kTimeFree);
  EXPECT_FALSE(good.failed) << good.failure;
  EXPECT_LT(good.Combine(kTimeFree, f.options().failure_value), 1.0);
}

TEST(IdentifyFailure, GlobalSearchThroughTheFailingRegionCountsFailuresAndKeepsTheBest) {
  // DIRECT samples the box's centre (50) and its thirds (-50, 150): the left
  // third fails, and the search goes on.
  const ObjectiveFunction f = KnlObjective(-100.0, 200.0, 40.0);
  IdentifyOptions options;
  options.algorithm = Algorithm::kGnDirectL;
  options.weights = kTimeFree;
  options.max_evaluations = 30;
  const IdentifySummary summary = Identify(f, options);
  std::printf("%s\n", summary.BriefReport().c_str());
  EXPECT_GT(summary.failed_evaluations, 0);
  EXPECT_LT(summary.failed_evaluations, summary.evaluations);
  EXPECT_NE(summary.BriefReport().find("failed"), std::string::npos) << summary.BriefReport();
  ExpectBestPointKept(summary);
  // 30 DIRECT points in [-100, 200] come within a few units of knl = 50.
  constexpr double kGridTolerance = 5.0;
  EXPECT_NEAR(summary.parameters[0], 50.0, kGridTolerance);
}

TEST(IdentifyFailure, BudgetExhaustedSaysSoAndKeepsTheBestPoint) {
  const ObjectiveFunction f = KnlObjective(-100.0, 200.0, 40.0);
  IdentifyOptions options;
  options.weights = kTimeFree;
  options.max_evaluations = 4;
  options.xtol_rel = 1e-12;
  options.ftol_rel = 0.0;
  const IdentifySummary summary = Identify(f, options);
  EXPECT_EQ(summary.termination, Termination::kMaxEvaluations) << summary.FullReport();
  EXPECT_EQ(summary.evaluations, 4);
  EXPECT_NE(summary.message.find("MAXEVAL"), std::string::npos) << summary.message;
  EXPECT_NE(summary.message.find("best point seen kept"), std::string::npos) << summary.message;
  ExpectBestPointKept(summary);
}

TEST(IdentifyFailure, OptimiserForcedToStopReturnsItsCodeAndTheBestPoint) {
  // A cancel flag already set: NLopt returns NLOPT_FORCED_STOP (a negative
  // result code) after the first evaluation.
  const ObjectiveFunction f = KnlObjective(-100.0, 200.0, 40.0);
  const std::atomic<bool> cancel{true};
  IdentifyOptions options;
  options.weights = kTimeFree;
  options.cancel = &cancel;
  const IdentifySummary summary = Identify(f, options);
  EXPECT_EQ(summary.termination, Termination::kInterrupted) << summary.FullReport();
  EXPECT_NE(summary.message.find("FORCED_STOP"), std::string::npos) << summary.message;
  EXPECT_EQ(summary.evaluations, 1);
  ASSERT_EQ(summary.parameters.size(), 1);
  EXPECT_EQ(summary.parameters[0], 40.0);
  EXPECT_TRUE(std::isfinite(summary.final_objective));
}

TEST(IdentifyFailure, EveryEvaluationFailingIsReportedWithTheReason) {
  const ObjectiveFunction f = KnlObjective(-100.0, -60.0, -80.0);
  IdentifyOptions options;
  options.weights = kTimeFree;
  options.max_evaluations = 10;
  const IdentifySummary summary = Identify(f, options);
  EXPECT_EQ(summary.termination, Termination::kAllEvaluationsFailed);
  EXPECT_FALSE(summary.IsSolutionUsable());
  EXPECT_EQ(summary.failed_evaluations, summary.evaluations);
  EXPECT_GT(summary.evaluations, 0);
  EXPECT_NE(summary.message.find("every evaluation failed; e.g. at the start: "),
            std::string::npos)
      << summary.message;
  ASSERT_EQ(summary.parameters.size(), 1);
  EXPECT_EQ(summary.parameters[0], -80.0);  // the start, not garbage
}

TEST(LandscapeFailure, FailingPointsAreCountedAndTheOthersComputed) {
  // x = -100, -50, 0, 50, ..., 200: the first two fail.
  const ObjectiveFunction f = KnlObjective(-100.0, 200.0, 40.0);
  LandscapeOptions options;
  options.objectives = {{"time-free", kTimeFree}};
  options.x = {.parameter = 0, .lower = -100.0, .upper = 200.0, .points = 7};
  const LandscapeResult result = ComputeLandscape(f, options);
  EXPECT_EQ(result.termination, LandscapeTermination::kCompleted) << result.message;
  EXPECT_EQ(result.evaluations, 7);
  EXPECT_EQ(result.failed_evaluations, 2);
  const Eigen::MatrixXd& v = result.values[0];
  EXPECT_EQ(v(0, 0), kDefaultFailureValue);
  EXPECT_EQ(v(1, 0), kDefaultFailureValue);
  for (int i = 2; i < 7; ++i) EXPECT_LT(v(i, 0), kDefaultFailureValue) << "x = " << result.x[i];
  EXPECT_EQ(result.metrics[0].global_minimiser, 50.0);
}

TEST(LandscapeFailure, CancelledBeforeTheFirstPointComputesNothing) {
  const ObjectiveFunction f = KnlObjective(-100.0, 200.0, 40.0);
  const std::atomic<bool> cancel{true};
  LandscapeOptions options;
  options.objectives = {{"time-free", kTimeFree}};
  options.x = {.parameter = 0, .lower = 0.0, .upper = 100.0, .points = 50};
  options.cancel = &cancel;
  const LandscapeResult result = ComputeLandscape(f, options);
  EXPECT_EQ(result.termination, LandscapeTermination::kInterrupted);
  EXPECT_LT(result.evaluations, 50);
}

}  // namespace
}  // namespace podid::ident
