// ObjectiveFunction::SimulateAt with a workspace (the cached simulator the
// uncertainty and the CLI's reports use) against the fresh simulation.
#include <gtest/gtest.h>

#include "podid/core/case_file.hpp"
#include "podid/core/io.hpp"
#include "podid/ident/objective.hpp"
#include "test_support.hpp"

namespace podid::ident {
namespace {

// The cached simulator keeps the model and its condensation and changes knl
// in place (Simulator::Set); the fresh one rebuilds them. Both solve the same
// equations to Newton's tolerance (1e-10 of the residual scale), so the
// responses agree to far better than 1e-9 of their peak.
constexpr double kSameSimulation = 1e-9;

TEST(SimulateAtTest, CachedSimulatorEqualsAFreshSimulationAlongASequence) {
  const CaseDocument document = CaseDocument::Load(podid::testing::ExamplePath("beam.toml"));
  const TimeSeries measured = ReadCsv(podid::testing::ExamplePath("measured_knl50_T0.1.csv"));
  const ObjectiveFunction objective(document, measured, ObjectiveOptions{});
  EvaluationWorkspace workspace;
  for (const double knl : {40.0, 55.0, 40.0, 0.0}) {
    const Eigen::VectorXd values = Eigen::VectorXd::Constant(1, knl);
    const SimulationResult cached = objective.SimulateAt(values, &workspace);
    const SimulationResult fresh = objective.SimulateAt(values);
    ASSERT_TRUE(cached.summary.IsSolutionUsable()) << cached.summary.message;
    ASSERT_EQ(cached.sensors.values.rows(), fresh.sensors.values.rows());
    ASSERT_EQ(cached.sensors.channel_names, fresh.sensors.channel_names);
    const double peak = fresh.sensors.values.cwiseAbs().maxCoeff();
    ASSERT_GT(peak, 0.0);
    EXPECT_LE((cached.sensors.values - fresh.sensors.values).cwiseAbs().maxCoeff(), kSameSimulation * peak)
        << "knl " << knl;
    EXPECT_LE((cached.sensors.time_s - fresh.sensors.time_s).cwiseAbs().maxCoeff(), 1e-12);
  }
  // A value the case rejects is an error naming it, as without a workspace.
  EXPECT_THROW(objective.SimulateAt(Eigen::VectorXd::Constant(2, 1.0), &workspace), std::invalid_argument);
}

}  // namespace
}  // namespace podid::ident
