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

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "podid/ident/identify.hpp"
#include "podid/ident/landscape.hpp"
#include "podid/ident/objective.hpp"
#include "reference_case.hpp"
#include "test_support.hpp"

namespace podid::ident {
namespace {

const ObjectiveWeights kTimeFree = ObjectiveWeights::Preset("time-free");

ObjectiveOptions Weighted(const ObjectiveWeights& weights) {
  ObjectiveOptions options;
  options.SetWeights(weights);
  return options;
}

ObjectiveFunction KnlObjective(double lower,
                               double upper,
                               double start,
                               const ObjectiveWeights& weights = kTimeFree) {
  const CaseDocument document = CaseDocument::Load(testing::ExamplePath("beam.toml"));
  ParameterSpec knl;
  knl.name = "knl";
  knl.key = "nonlinearity.0.k3";
  knl.scale = 1e8;
  knl.start = start;
  knl.lower = lower;
  knl.upper = upper;
  return ObjectiveFunction(document, testing::ReferenceData("measured_knl50_T0.1.csv"),
                           Weighted(weights), {knl});
}

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
  const TermValues bad = f.Evaluate(Eigen::VectorXd::Constant(1, -50.0)).terms;
  EXPECT_TRUE(bad.failed);
  EXPECT_FALSE(bad.failure.empty());
  std::printf("knl = -50: %s\n", bad.failure.c_str());
  EXPECT_EQ(bad.Combine(kTimeFree, f.options().failure_value), kDefaultFailureValue);
  // The same objective still evaluates a good point afterwards.
  const TermValues good = f.Evaluate(Eigen::VectorXd::Constant(1, 50.0)).terms;
  EXPECT_FALSE(good.failed) << good.failure;
  EXPECT_LT(good.Combine(kTimeFree, f.options().failure_value), 1.0);
}

TEST(IdentifyFailure, GlobalSearchThroughTheFailingRegionCountsFailuresAndKeepsTheBest) {
  // DIRECT samples the box's centre (50) and its thirds (-50, 150): the left
  // third fails, and the search goes on.
  const ObjectiveFunction f = KnlObjective(-100.0, 200.0, 40.0);
  IdentifyOptions options;
  options.algorithm = Algorithm::kGnDirectL;
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

TEST(IdentifyFailure, AFailedPointIsWorseThanEveryPointSeenBeforeIt) {
  // time-free x 1e6: real values far above failure_value (1e3), as the
  // wavelet objective with 6 modes reaches 1.3e4. A failed point at 1e3 was
  // the search's best guess, and it walked into the failing region.
  ObjectiveWeights heavy = kTimeFree;
  heavy.u *= 1e6;
  heavy.s *= 1e6;
  const ObjectiveFunction f = KnlObjective(-100.0, 200.0, 40.0, heavy);
  IdentifyOptions options;
  options.algorithm = Algorithm::kGnDirectL;
  options.max_evaluations = 30;
  const IdentifySummary summary = Identify(f, options);
  ASSERT_GT(summary.failed_evaluations, 0);
  double worst = 0.0;
  bool above_failure_value = false;
  for (const IterationRecord& r : summary.history) {
    if (r.failed) {
      EXPECT_GE(r.objective, 2.0 * worst) << "evaluation " << r.evaluation;
      EXPECT_GE(r.objective, kDefaultFailureValue);
    } else {
      worst = std::max(worst, r.objective);
      above_failure_value = above_failure_value || r.objective > kDefaultFailureValue;
    }
  }
  EXPECT_TRUE(above_failure_value);  // else this test tests nothing
  ExpectBestPointKept(summary);
}

TEST(ObjectiveFailure, AWeightedSumThatOverflowsIsAFailedEvaluation) {
  ObjectiveWeights huge;
  huge.u = 0.0;
  huge.s = 0.0;
  huge.v = 1e308;
  const ObjectiveFunction f = KnlObjective(-100.0, 200.0, 40.0, huge);
  const Evaluation e = f.Evaluate(Eigen::VectorXd::Constant(1, 200.0));
  EXPECT_TRUE(e.failed());
  EXPECT_NE(e.failure().find("the weighted sum is not finite"), std::string::npos) << e.failure();
  EXPECT_EQ(e.values[0], kDefaultFailureValue);
}

TEST(IdentifyFailure, BudgetExhaustedSaysSoAndKeepsTheBestPoint) {
  const ObjectiveFunction f = KnlObjective(-100.0, 200.0, 40.0);
  IdentifyOptions options;
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
  // No objective value from the penalty (issue 10 item 9).
  EXPECT_TRUE(std::isnan(summary.initial_objective));
  EXPECT_TRUE(std::isnan(summary.final_objective));
}

TEST(LandscapeFailure, FailingPointsAreCountedAndTheOthersComputed) {
  // x = -100, -50, 0, 50, ..., 200: the first two fail.
  const ObjectiveFunction f = KnlObjective(-100.0, 200.0, 40.0);
  LandscapeOptions options;
  options.x = {.parameter = 0, .lower = -100.0, .upper = 200.0, .points = 7};
  const LandscapeResult result = ComputeLandscape(f, options);
  EXPECT_EQ(result.termination, LandscapeTermination::kCompleted) << result.message;
  EXPECT_EQ(result.evaluations, 7);
  EXPECT_EQ(result.failed_evaluations, 2);
  // Failed points are NaN, not the failure value (issue 10 item 9).
  const Eigen::MatrixXd& v = result.values[0];
  EXPECT_TRUE(std::isnan(v(0, 0)));
  EXPECT_TRUE(std::isnan(v(1, 0)));
  for (int i = 2; i < 7; ++i) EXPECT_LT(v(i, 0), kDefaultFailureValue) << "x = " << result.x[i];
  EXPECT_EQ(result.metrics[0].global_minimiser, 50.0);
  EXPECT_NE(result.message.find("(2 failed, NaN)"), std::string::npos) << result.message;
}

// Issue 10 item 9: every point diverging said "completed", wrote the penalty
// 1000 as values and reported a global minimiser.
TEST(LandscapeFailure, EveryPointFailingIsNotCompletedAndHasNoMinimiser) {
  const ObjectiveFunction f = KnlObjective(-100.0, -60.0, -80.0);
  LandscapeOptions options;
  options.x = {.parameter = 0, .lower = -100.0, .upper = -60.0, .points = 3};
  const LandscapeResult result = ComputeLandscape(f, options);
  EXPECT_EQ(result.termination, LandscapeTermination::kNoneSucceeded) << result.message;
  EXPECT_EQ(result.evaluations, 3);
  EXPECT_EQ(result.failed_evaluations, 3);
  EXPECT_TRUE(result.metrics.empty());
  EXPECT_TRUE(result.values[0].array().isNaN().all()) << result.values[0];
  EXPECT_NE(result.message.find("none of the 3 points succeeded; e.g. at knl = -100: "),
            std::string::npos)
      << result.message;
  EXPECT_NE(result.BriefReport().find("no point succeeded"), std::string::npos)
      << result.BriefReport();
}

TEST(LandscapeFailure, MetricsLeaveFailedPointsOut) {
  // f = (x - 2)^2 on x = 0..4 with x = 1 failed (NaN): the curve through
  // x = 0, 2, 3, 4 (f = 4, 0, 1, 4) has one minimum at 2, basin 0..4 and
  // total variation 4 + 1 + 3 = 8 over the range 4.
  Eigen::VectorXd x(5), f(5);
  x << 0, 1, 2, 3, 4;
  f << 4, std::numeric_limits<double>::quiet_NaN(), 0, 1, 4;
  const LandscapeMetrics m = ComputeMetrics(x, f);
  EXPECT_EQ(m.local_minima, 1);
  EXPECT_EQ(m.global_minimiser, 2.0);
  EXPECT_EQ(m.global_minimum, 0.0);
  EXPECT_EQ(m.basin_lower, 0.0);
  EXPECT_EQ(m.basin_upper, 4.0);
  EXPECT_EQ(m.basin_fraction, 1.0);
  constexpr double kRoundoff = 1e-15;  // one division
  EXPECT_NEAR(m.roughness, 8.0 / 4.0, kRoundoff);
  f.setConstant(std::numeric_limits<double>::quiet_NaN());
  PODID_EXPECT_THROW_WITH(ComputeMetrics(x, f), std::invalid_argument,
                          "ComputeMetrics: expected at least one finite value, got none");
}

// Issue 10 item 8: counts are bounded before anything is allocated, and a
// grid whose width overflows (an inf point) is rejected.
TEST(LandscapeFailure, GridSizesAndBoundsAreChecked) {
  const ObjectiveFunction f = KnlObjective(-100.0, 200.0, 40.0);
  LandscapeOptions options;
  options.x = {.parameter = 0, .lower = -1.7e308, .upper = 1.7e308, .points = 3};
  PODID_EXPECT_THROW_WITH(ComputeLandscape(f, options), std::invalid_argument,
                          "landscape options: range: expected a finite width upper - lower, got "
                          "-1.7e+308:1.7e+308");
  options.x = {.parameter = 0, .lower = 0.0, .upper = 1.0, .points = 10'000'000};
  PODID_EXPECT_THROW_WITH(ComputeLandscape(f, options), std::invalid_argument,
                          "range: expected 2 to 1000000 points, got 10000000");
}

TEST(IdentifyFailure, CountsAreBoundedBeforeAllocation) {
  const ObjectiveFunction f = KnlObjective(-100.0, 200.0, 40.0);
  IdentifyOptions options;
  options.multistart = 100'000'000;
  PODID_EXPECT_THROW_WITH(Identify(f, options), std::invalid_argument,
                          "identify options: multistart: expected 1 to 10000, got 100000000");
  options.multistart = 1;
  options.max_evaluations = 2'000'000'000;
  PODID_EXPECT_THROW_WITH(Identify(f, options), std::invalid_argument,
                          "max_evaluations: expected 1 to 1000000, got 2000000000");
  options.multistart = 1000;
  options.max_evaluations = 10'000;
  PODID_EXPECT_THROW_WITH(Identify(f, options), std::invalid_argument,
                          "multistart * max_evaluations: expected at most 1000000 evaluations in "
                          "all, got 1000 * 10000");
}

// An infinite relative tolerance stopped NLopt at its first step (--xtol inf
// ran two evaluations and reported convergence).
TEST(IdentifyFailure, TolerancesAreFinite) {
  const ObjectiveFunction f = KnlObjective(-100.0, 200.0, 40.0);
  IdentifyOptions options;
  options.xtol_rel = std::numeric_limits<double>::infinity();
  PODID_EXPECT_THROW_WITH(Identify(f, options), std::invalid_argument,
                          "identify options: xtol_rel: expected a finite value > 0, got inf");
  options.xtol_rel = 1e-6;
  options.ftol_rel = std::numeric_limits<double>::infinity();
  PODID_EXPECT_THROW_WITH(Identify(f, options), std::invalid_argument,
                          "identify options: ftol_rel: expected a finite value >= 0, got inf");
}

// Issue 10 item 7: with no static tip force the response is zero and the CWT
// of the simulated time mode throws; that used to cross NLopt's C callback
// and an OpenMP region (SIGABRT). Now each such point is a failed evaluation.
ObjectiveFunction ZeroResponseObjective() {
  CaseDocument document = CaseDocument::Load(testing::ExamplePath("beam.toml"));
  document.Set("initial.static_tip_force", "0");
  return ObjectiveFunction(document, testing::ReferenceData("measured_knl50_T1.0.csv"),
                           Weighted(ObjectiveWeights::Preset("wavelet")));
}

TEST(ObjectiveFailure, ExceptionInsideAnEvaluationIsAFailedPoint) {
  const ObjectiveFunction f = ZeroResponseObjective();
  const TermValues terms =
      f.Evaluate(Eigen::VectorXd::Constant(1, 50.0)).terms;
  EXPECT_TRUE(terms.failed);
  EXPECT_FALSE(terms.failure.empty());
  std::printf("zero response: %s\n", terms.failure.c_str());
}

TEST(IdentifyFailure, ExceptionsNeverCrossTheCallbackOrTheParallelRegion) {
  const ObjectiveFunction f = ZeroResponseObjective();
  IdentifyOptions options;
  options.max_evaluations = 5;
  options.multistart = 2;  // the parallel starts
  const IdentifySummary summary = Identify(f, options);
  EXPECT_EQ(summary.termination, Termination::kAllEvaluationsFailed) << summary.FullReport();
  EXPECT_EQ(summary.failed_evaluations, summary.evaluations);
  EXPECT_NE(summary.message.find("every evaluation failed; e.g. at the start: "),
            std::string::npos)
      << summary.message;
}

TEST(LandscapeFailure, ExceptionsNeverCrossTheParallelRegion) {
  const ObjectiveFunction f = ZeroResponseObjective();
  LandscapeOptions options;
  options.x = {.parameter = 0, .lower = 0.0, .upper = 100.0, .points = 4};
  const LandscapeResult result = ComputeLandscape(f, options);
  EXPECT_EQ(result.termination, LandscapeTermination::kNoneSucceeded) << result.message;
  EXPECT_EQ(result.failed_evaluations, 4);
}

TEST(LandscapeFailure, CancelledBeforeTheFirstPointComputesNothing) {
  const ObjectiveFunction f = KnlObjective(-100.0, 200.0, 40.0);
  const std::atomic<bool> cancel{true};
  LandscapeOptions options;
  options.x = {.parameter = 0, .lower = 0.0, .upper = 100.0, .points = 50};
  options.cancel = &cancel;
  const LandscapeResult result = ComputeLandscape(f, options);
  EXPECT_EQ(result.termination, LandscapeTermination::kInterrupted);
  EXPECT_LT(result.evaluations, 50);
}

}  // namespace
}  // namespace podid::ident
