// Identification against the independent reference data (../shared/reference)
// and against data simulated by podid with known parameters.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "podid/core/noise.hpp"
#include "podid/core/simulate.hpp"
#include "podid/ident/identify.hpp"
#include "podid/ident/landscape.hpp"
#include "podid/ident/objective.hpp"
#include "reference_case.hpp"
#include "test_support.hpp"

namespace podid::ident {
namespace {

using testing::DataPath;
using testing::ReferenceDocument;

/// Objective options with the named presets as weightings.
ObjectiveOptions Presets(const std::vector<std::string>& names) {
  ObjectiveOptions options;
  options.weightings.clear();
  for (const std::string& name : names) options.weightings.push_back({name, ObjectiveWeights::Preset(name)});
  return options;
}

/// Identify minimising the objective's weighting named `preset`.
IdentifySummary IdentifyFrom(const ObjectiveFunction& objective, const std::string& preset,
                             double start) {
  IdentifyOptions options;
  options.weighting = -1;
  for (int k = 0; k < objective.weighting_count(); ++k) {
    if (objective.options().weightings[k].name == preset) options.weighting = k;
  }
  options.start = Eigen::VectorXd::Constant(1, start);
  return Identify(objective, options);
}

using testing::kKnlRelativeTolerance;
using testing::kTrueKnl;

TEST(IdentifyReferenceTest, FullObjectiveFromFortyOnShortRecord) {
  const ObjectiveFunction objective(ReferenceDocument(), ReadCsv(DataPath("measured_knl50_T0.1.csv")),
                                    Presets({"full"}));
  const IdentifySummary summary = IdentifyFrom(objective, "full", 40.0);
  std::cout << summary.BriefReport() << "\n";
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.FullReport();
  EXPECT_NEAR(summary.parameters[0] / kTrueKnl, 1.0, kKnlRelativeTolerance);
  EXPECT_EQ(summary.failed_evaluations, 0);
  EXPECT_LT(summary.final_objective, summary.initial_objective);
  EXPECT_EQ(static_cast<int>(summary.history.size()), summary.evaluations);
}

TEST(IdentifyReferenceTest, WaveletObjectiveFromEveryStartOnLongRecord) {
  const ObjectiveFunction objective(ReferenceDocument(), ReadCsv(DataPath("measured_knl50_T1.0.csv")),
                                    Presets({"wavelet", "full"}));
  for (double start : {5.0, 10.0, 25.0, 100.0, 150.0, 200.0}) {
    const IdentifySummary wavelet = IdentifyFrom(objective, "wavelet", start);
    EXPECT_TRUE(wavelet.IsSolutionUsable()) << wavelet.FullReport();
    EXPECT_NEAR(wavelet.parameters[0] / kTrueKnl, 1.0, kKnlRelativeTolerance) << "start " << start;
    // The paper's eq. 19 objective, reported for comparison (not asserted:
    // the paper says it must start near the optimum).
    const IdentifySummary full = IdentifyFrom(objective, "full", start);
    std::cout << "start " << start << ": wavelet -> " << wavelet.parameters[0] << " ("
              << wavelet.evaluations << " evaluations), full -> " << full.parameters[0] << " ("
              << full.evaluations << " evaluations)\n";
  }
}

TEST(ObjectiveTest, ParameterIndexFindsANameOrNamesTheChoices) {
  const ObjectiveFunction objective(ReferenceDocument(), ReadCsv(DataPath("measured_knl50_T0.1.csv")),
                                    Presets({"full"}));
  EXPECT_EQ(objective.ParameterIndex("knl", "--start"), 0);
  try {
    objective.ParameterIndex("k3", "--start k3");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "--start k3: expected a parameter name (knl), got \"k3\"");
  }
}

TEST(ObjectiveTest, VanishesAtTheTruthOnNoiseFreeSimulatedData) {
  // Data simulated by podid itself at knl = 50 without noise: every term is
  // zero at knl = 50 up to the POD's round-off.
  constexpr double kTolerance = 1e-18;
  const CaseDocument document = ReferenceDocument({"time.duration=0.5"});
  const TimeSeries data = Simulate(document.ToSpec(), SimulateOptions{false}).sensors;
  ObjectiveOptions all_terms;
  all_terms.SetWeights(ObjectiveWeights{1.0, 1.0, 1.0, 1.0});
  const ObjectiveFunction objective(document, data, all_terms);
  const TermValues at_truth = objective.Evaluate(Eigen::VectorXd::Constant(1, 50.0)).terms;
  ASSERT_FALSE(at_truth.failed) << at_truth.failure;
  EXPECT_LE(at_truth.u, kTolerance);
  EXPECT_LE(at_truth.s, kTolerance);
  EXPECT_LE(at_truth.v, 1e-12);  // V has N = 2501 entries: round-off adds up
  EXPECT_LE(at_truth.f, 1e-12);
  const TermValues away = objective.Evaluate(Eigen::VectorXd::Constant(1, 60.0)).terms;
  EXPECT_GT(away.u, 1e-9);
  EXPECT_GT(away.s, 1e-9);
  EXPECT_GT(away.v, 1e-6);
  EXPECT_GT(away.f, 1e-6);
}

TEST(ObjectiveTest, TimeFreeIgnoresTheSignOfTheMotionAndFullDoesNot) {
  // Mirroring the measured motion (X -> -X) leaves the POMs (after the sign
  // convention) and the singular values unchanged, and flips V: the
  // time-free objective cannot tell the two motions apart, the full one can.
  constexpr double kRelativeTolerance = 1e-12;
  TimeSeries data = ReadCsv(DataPath("measured_knl50_T0.1.csv"));
  const ObjectiveOptions options = Presets({"time-free", "full"});  // one simulation for both
  const ObjectiveFunction plain(ReferenceDocument(), data, options);
  data.values = -data.values;
  const ObjectiveFunction mirrored(ReferenceDocument(), data, options);
  for (double knl : {20.0, 50.0, 90.0}) {
    const Eigen::VectorXd x = Eigen::VectorXd::Constant(1, knl);
    const Evaluation p = plain.Evaluate(x), m = mirrored.Evaluate(x);
    ASSERT_FALSE(p.failed() || m.failed()) << p.failure() << m.failure();
    const double a = p.values[0], b = m.values[0];
    EXPECT_NEAR(a / b, 1.0, kRelativeTolerance) << "knl " << knl;
    const double c = p.values[1], d = m.values[1];
    EXPECT_GT(d, c + 1.0) << "knl " << knl;  // dV of opposite unit vectors is near 4
  }
}

TEST(IdentifyTwoParametersTest, KnlAndFirstModeDampingFromNoisyPodidData) {
  // Truth: knl = 50, zeta_1 = 1 %; podid-simulated 1 s record with 1 % noise.
  constexpr double kRelativeTolerance = 0.01;  // issue 5's bound for both
  CaseDocument document = ReferenceDocument({"time.duration=1.0"});
  const TimeSeries data = [&] {
    CaseDocument noisy = document;
    ApplySetArguments(noisy, {"noise.relative=0.01", "noise.seed=7"});
    return Simulate(noisy.ToSpec()).sensors;
  }();
  ParameterSpec knl{"knl", "nonlinearity.0.k3", 1e8, 30.0, 0.0, 200.0};
  ParameterSpec zeta{"zeta1", "damping.modal_ratios.0", 0.01, 1.5, 0.2, 3.0};
  const ObjectiveFunction objective(document, data, Presets({"wavelet"}), {knl, zeta});
  IdentifyOptions options;
  const IdentifySummary summary = Identify(objective, options);
  std::cout << summary.BriefReport() << "\n";
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.FullReport();
  EXPECT_NEAR(summary.parameters[0] / 50.0, 1.0, kRelativeTolerance);
  EXPECT_NEAR(summary.parameters[1] / 1.0, 1.0, kRelativeTolerance);
}

TEST(IdentifyTest, MultistartRunsEveryStartAndKeepsTheBest) {
  const ObjectiveFunction objective(ReferenceDocument(), ReadCsv(DataPath("measured_knl50_T0.1.csv")),
                                    ObjectiveOptions{});
  IdentifyOptions options;
  options.multistart = 4;
  options.start = Eigen::VectorXd::Constant(1, 190.0);
  const IdentifySummary summary = Identify(objective, options);
  EXPECT_EQ(summary.starts, 4);
  EXPECT_NEAR(summary.parameters[0] / kTrueKnl, 1.0, kKnlRelativeTolerance);
  for (const IterationRecord& r : summary.history) EXPECT_GE(r.objective, summary.final_objective);
}

TEST(IdentifyTest, BudgetExhaustedKeepsTheBestPoint) {
  const ObjectiveFunction objective(ReferenceDocument(), ReadCsv(DataPath("measured_knl50_T0.1.csv")),
                                    ObjectiveOptions{});
  IdentifyOptions options;
  options.max_evaluations = 3;
  const IdentifySummary summary = Identify(objective, options);
  EXPECT_EQ(summary.termination, Termination::kMaxEvaluations) << summary.message;
  EXPECT_EQ(summary.evaluations, 3);
  double best = summary.history.front().objective;
  for (const IterationRecord& r : summary.history) best = std::min(best, r.objective);
  EXPECT_EQ(summary.final_objective, best);
  EXPECT_NE(summary.message.find("MAXEVAL"), std::string::npos) << summary.message;
}

TEST(IdentifyTest, GlobalAlgorithmsRun) {
  const ObjectiveFunction objective(ReferenceDocument(), ReadCsv(DataPath("measured_knl50_T0.1.csv")),
                                    ObjectiveOptions{});
  for (const char* name : {"GN_DIRECT_L", "GN_CRS2_LM", "GN_ISRES", "GN_MLSL_LDS", "LN_NELDERMEAD",
                           "LN_SBPLX", "LN_COBYLA"}) {
    IdentifyOptions options;
    options.algorithm = ParseAlgorithm(name);
    options.max_evaluations = 150;
    const IdentifySummary summary = Identify(objective, options);
    EXPECT_TRUE(summary.IsSolutionUsable()) << name << ": " << summary.message;
    EXPECT_LE(summary.evaluations, 150 + 10) << name;  // MLSL may overrun by a local run's step
    std::cout << summary.BriefReport() << "\n";
  }
}

TEST(ObjectiveErrorsTest, ClearErrors) {
  const TimeSeries data = ReadCsv(DataPath("measured_knl50_T0.1.csv"));
  // A parameter key the case does not have.
  PODID_EXPECT_THROW_WITH(ObjectiveFunction(ReferenceDocument(), data, ObjectiveOptions{},
                                            {ParameterSpec{"k", "nonlinearity.3.k3", 1.0, 1.0, 0.0, 2.0}}),
                          std::invalid_argument, "nonlinearity.3");
  // A start outside its bounds.
  PODID_EXPECT_THROW_WITH(ObjectiveFunction(ReferenceDocument(), data, ObjectiveOptions{},
                                            {ParameterSpec{"knl", "nonlinearity.0.k3", 1e8, 250.0, 0.0, 200.0}}),
                          std::invalid_argument, "lower <= start <= upper");
  const ObjectiveFunction objective(ReferenceDocument(), data, ObjectiveOptions{});
  IdentifyOptions options;
  options.start = Eigen::VectorXd::Constant(1, -5.0);
  PODID_EXPECT_THROW_WITH(Identify(objective, options), std::invalid_argument, "in its bounds");
  // Channels that do not match the case's sensors.
  TimeSeries renamed = data;
  renamed.channel_names[5] = "x6";
  PODID_EXPECT_THROW_WITH(ObjectiveFunction(ReferenceDocument(), renamed, ObjectiveOptions{}),
                          std::invalid_argument, "expected w1,w2,w3,w4,w5,w6");
  TimeSeries fewer = data;
  fewer.values.conservativeResize(Eigen::NoChange, 5);
  fewer.channel_names.pop_back();
  PODID_EXPECT_THROW_WITH(ObjectiveFunction(ReferenceDocument(), fewer, ObjectiveOptions{}),
                          std::invalid_argument, "got w1,w2,w3,w4,w5");
  // 0.1 s is shorter than the cone of influence at 10 Hz (0.27 s).
  PODID_EXPECT_THROW_WITH(ObjectiveFunction(ReferenceDocument(), data, Presets({"wavelet"})),
                          std::invalid_argument, "lowest frequency");
  // Unknown names.
  PODID_EXPECT_THROW_WITH(ObjectiveWeights::Preset("fast"), std::invalid_argument, "full, time-free, wavelet");
  PODID_EXPECT_THROW_WITH(ParseAlgorithm("LN_FOO"), std::invalid_argument, "LN_BOBYQA");
  PODID_EXPECT_THROW_WITH(ObjectiveWeights::Parse("U,X"), std::invalid_argument,
                          "terms: expected a list of U, S, V, IF, got \"X\"");
  PODID_EXPECT_THROW_WITH(ObjectiveWeights::Parse("U,S", "1"), std::invalid_argument,
                          "weights: expected 2 weights (one per term of terms)");
  // The caller's names (the CLI's options) in the messages.
  PODID_EXPECT_THROW_WITH(ObjectiveWeights::Parse("U,S", "1,x", "--terms", "--weights"),
                          std::invalid_argument,
                          "--weights: expected non-negative numbers, got \"x\"");
  PODID_EXPECT_THROW_WITH(ObjectiveWeights::Parse("U", "0", "--terms", "--weights"),
                          std::invalid_argument,
                          "--terms/--weights: expected at least one term with a positive weight");
  // A repeated term was overwritten by its later weight ("U,U" + "1,5" ran 5 dU).
  PODID_EXPECT_THROW_WITH(ObjectiveWeights::Parse("U,U", "1,5", "--terms", "--weights"),
                          std::invalid_argument, "--terms: expected each term once, got U twice");
  PODID_EXPECT_THROW_WITH(ObjectiveWeights::Parse("S,IF,S"), std::invalid_argument,
                          "terms: expected each term once, got S twice");
  // Weights above kMaxObjectiveWeight made F overflow (1e308: F inf, start nan).
  PODID_EXPECT_THROW_WITH(ObjectiveWeights::Parse("U,S", "1,1e308", "--terms", "--weights"),
                          std::invalid_argument,
                          "--weights: expected weights of at most 1e+12, got \"1e308\"");
  EXPECT_EQ(ObjectiveWeights::Parse("U", "1e12").u, kMaxObjectiveWeight);
}

TEST(ObjectiveTest, FailedSimulationIsAPenaltyNotAnError) {
  // A negative damping ratio is rejected by the case: the evaluation fails
  // with the reason, and the objective value is the documented failure value.
  const TimeSeries data = ReadCsv(DataPath("measured_knl50_T0.1.csv"));
  const ObjectiveFunction objective(ReferenceDocument(), data, ObjectiveOptions{},
                                    {ParameterSpec{"zeta1", "damping.modal_ratios.0", 0.01, 1.0, -1.0, 3.0}});
  const Evaluation e = objective.Evaluate(Eigen::VectorXd::Constant(1, -0.5));
  EXPECT_TRUE(e.failed());
  EXPECT_NE(e.failure().find("damping.modal_ratios"), std::string::npos) << e.failure();
  ASSERT_EQ(e.values.size(), 1u);
  EXPECT_EQ(e.values[0], kDefaultFailureValue);
}

TEST(LandscapeMetricsTest, ParabolaHasOneMinimumAndAFullBasin) {
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(101, -1.0, 1.0);
  const Eigen::VectorXd f = (x.array() - 0.2).square();
  const LandscapeMetrics m = ComputeMetrics(x, f);
  EXPECT_EQ(m.local_minima, 1);
  EXPECT_NEAR(m.global_minimiser, 0.2, 1e-12);
  EXPECT_DOUBLE_EQ(m.basin_fraction, 1.0);
  // Total variation (f(-1) - 0) + (f(1) - 0) over max - min = f(-1).
  EXPECT_NEAR(m.roughness, (1.44 + 0.64) / 1.44, 1e-12);
}

TEST(LandscapeMetricsTest, RippleCountsEveryMinimumAndNarrowsTheBasin) {
  // f = x^2 / 10 + cos(2 pi 5 x) on [-1, 1]: minima where the ripple dips,
  // 10 of them; the global one's basin is one ripple period wide.
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(2001, -1.0, 1.0);
  const Eigen::VectorXd f =
      x.array().square() / 10 - (2 * std::numbers::pi * 5 * x.array()).cos();
  const LandscapeMetrics m = ComputeMetrics(x, f);
  EXPECT_EQ(m.local_minima, 11);  // 11 dips of -cos in [-1, 1], at x = k / 5
  EXPECT_NEAR(m.global_minimiser, 0.0, 1e-12);
  EXPECT_NEAR(m.basin_upper - m.basin_lower, 0.2, 0.01);
  EXPECT_GT(m.roughness, 10.0);
}

TEST(LandscapeTest, ParallelGridMatchesDirectEvaluations) {
  // Each grid value equals a direct, single-threaded evaluation exactly.
  const ObjectiveFunction objective(ReferenceDocument(), ReadCsv(DataPath("measured_knl50_T0.1.csv")),
                                    Presets({"full", "time-free"}));
  LandscapeOptions options;
  options.x = {0, 0.0, 100.0, 21};
  const LandscapeResult result = ComputeLandscape(objective, options);
  ASSERT_EQ(result.termination, LandscapeTermination::kCompleted);
  for (Eigen::Index i = 0; i < result.x.size(); i += 5) {
    const Eigen::VectorXd p = Eigen::VectorXd::Constant(1, result.x[i]);
    for (std::size_t k = 0; k < 2; ++k) {
      EXPECT_EQ(result.values[k](i, 0), objective.Evaluate(p).values[k]);
    }
  }
  ASSERT_EQ(result.metrics.size(), 2u);
  EXPECT_NEAR(result.metrics[0].global_minimiser, 50.0, 5.0);  // grid step 5
}

TEST(LandscapeTest, TwoDimensionalGrid) {
  const ObjectiveFunction objective(
      ReferenceDocument(), ReadCsv(DataPath("measured_knl50_T0.1.csv")), Presets({"time-free"}),
      {ParameterSpec{"knl", "nonlinearity.0.k3", 1e8, 50.0, 0.0, 100.0},
       ParameterSpec{"zeta1", "damping.modal_ratios.0", 0.01, 1.0, 0.5, 2.0}});
  LandscapeOptions options;
  options.x = {0, 30.0, 70.0, 5};
  options.y = LandscapeAxis{1, 0.5, 1.5, 5};
  const LandscapeResult result = ComputeLandscape(objective, options);
  ASSERT_EQ(result.values[0].rows(), 5);
  ASSERT_EQ(result.values[0].cols(), 5);
  Eigen::Index i = 0, j = 0;
  result.values[0].minCoeff(&i, &j);
  EXPECT_EQ(result.x[i], 50.0);
  EXPECT_EQ(result.y[j], 1.0);
}

}  // namespace
}  // namespace podid::ident

namespace podid::ident {
namespace {

// Issue 11 item 4: misuse of ObjectiveFunction is an exception at
// construction or a failed evaluation, never a crash.
TEST(ObjectiveMisuseTest, IsAnErrorOrAFailedEvaluationNeverACrash) {
  const TimeSeries data = ReadCsv(DataPath("measured_knl50_T0.1.csv"));
  ObjectiveOptions none;
  none.weightings.clear();
  PODID_EXPECT_THROW_WITH(ObjectiveFunction(ReferenceDocument(), data, none), std::invalid_argument,
                          "weightings: expected at least one, got none");
  ObjectiveOptions zero;
  zero.SetWeights(ObjectiveWeights{0.0, 0.0, 0.0, 0.0});
  PODID_EXPECT_THROW_WITH(ObjectiveFunction(ReferenceDocument(), data, zero), std::invalid_argument,
                          "expected at least one positive weight");
  const ObjectiveFunction objective(ReferenceDocument(), data, Presets({"full", "time-free"}));
  // A wrong number of values: a failed evaluation with the reason.
  const Evaluation wrong = objective.Evaluate(Eigen::VectorXd::Constant(3, 50.0));
  EXPECT_TRUE(wrong.failed());
  EXPECT_EQ(wrong.failure(), "parameter values: expected 1 values, got 3");
  ASSERT_EQ(wrong.values.size(), 2u);
  EXPECT_EQ(wrong.values[0], kDefaultFailureValue);
  // A workspace used with another objective starts afresh.
  const ObjectiveFunction other(ReferenceDocument(), data, Presets({"time-free"}),
                                {ParameterSpec{"zeta1", "damping.modal_ratios.0", 0.01, 1.0, 0.5, 2.0}});
  EvaluationWorkspace workspace;
  const Eigen::VectorXd x = Eigen::VectorXd::Constant(1, 50.0);
  const Evaluation a = objective.Evaluate(x, &workspace);
  const Evaluation b = other.Evaluate(Eigen::VectorXd::Constant(1, 1.0), &workspace);
  const Evaluation c = objective.Evaluate(x, &workspace);
  ASSERT_FALSE(a.failed() || b.failed() || c.failed());
  EXPECT_EQ(a.values, c.values);
  EXPECT_EQ(b.values[0], a.values[1]);  // knl = 50, zeta1 = 1 %: the same case
  // Identify's weighting must be one of the objective's.
  IdentifyOptions options;
  options.weighting = 2;
  PODID_EXPECT_THROW_WITH(Identify(objective, options), std::invalid_argument,
                          "weighting: expected an index of the objective's weightings in 0..1, got 2");
}

}  // namespace
}  // namespace podid::ident
