// identify's start is evaluated as given, whatever the algorithm, and the
// summary carries each term's share and the failure reasons.
#include <gtest/gtest.h>

#include "podid/core/case_file.hpp"
#include "podid/core/io.hpp"
#include "podid/ident/identify.hpp"
#include "reference_case.hpp"
#include "test_support.hpp"

namespace podid::ident {
namespace {

using testing::DataPath;

ObjectiveFunction TimeFree(const std::vector<std::string>& set = {}) {
  ObjectiveOptions options;
  options.weightings = {{"time-free", ObjectiveWeights::Preset("time-free")}};
  return ObjectiveFunction(testing::ReferenceDocument(set),
                           ReadCsv(DataPath("measured_knl50_T0.1.csv")), options);
}

TEST(IdentifyStartTest, EveryAlgorithmEvaluatesTheStartFirstAsGiven) {
  const ObjectiveFunction objective = TimeFree();
  const double lower = objective.parameters()[0].lower, upper = objective.parameters()[0].upper;
  // A start near the lower bound (within BOBYQA's default first step of a
  // tenth of the box) and DIRECT, which begins at the box centre.
  const double start = lower + 0.02 * (upper - lower);
  for (Algorithm algorithm : {Algorithm::kLnBobyqa, Algorithm::kGnDirectL, Algorithm::kLnNelderMead}) {
    IdentifyOptions options;
    options.algorithm = algorithm;
    options.start = Eigen::VectorXd::Constant(1, start);
    options.max_evaluations = 40;
    const IdentifySummary s = Identify(objective, options);
    ASSERT_FALSE(s.history.empty());
    EXPECT_EQ(s.history.front().parameters[0], start) << ToString(algorithm);
    const Evaluation at_start = objective.Evaluate(options.start);
    EXPECT_EQ(s.initial_objective, at_start.values[0]) << ToString(algorithm);
    // The start is not evaluated twice in a row (NLopt's own first call reuses it).
    if (s.history.size() > 1) {
      EXPECT_NE(s.history[1].parameters[0], start) << ToString(algorithm);
    }
    EXPECT_FALSE(TermContributions(s.initial_terms, s.weights).empty());
  }
}

TEST(IdentifyStartTest, FailedEvaluationsKeepTheirReason) {
  // No static force: a zero response at every point.
  const ObjectiveFunction objective = TimeFree({"initial.static_tip_force=0"});
  IdentifyOptions options;
  options.max_evaluations = 5;
  const IdentifySummary s = Identify(objective, options);
  EXPECT_EQ(s.termination, Termination::kAllEvaluationsFailed);
  ASSERT_FALSE(s.history.empty());
  for (const IterationRecord& r : s.history) {
    EXPECT_TRUE(r.failed);
    EXPECT_FALSE(r.failure.empty());
  }
  EXPECT_FALSE(s.uncertainty.usable);
}

TEST(IdentifyStartTest, TermSharesAddUpToOne) {
  TermValues t;
  t.u = 1.0;
  t.s = 3.0;
  const ObjectiveWeights w{1.0, 2.0, 0.0, 0.0};
  EXPECT_EQ(TermContributions(t, w), "dU 14.3 %, dS 85.7 %");
}

}  // namespace
}  // namespace podid::ident
