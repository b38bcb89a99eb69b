// Simulations that diverge (issue 7) end in a status naming the time and, for
// Newton, the residual; the history up to the failure is kept. Complements
// newmark_test.cpp (friction regularisation too sharp for dt -> Newton
// failure; a 1e200 m release -> non-finite state).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "podid/core/simulate.hpp"
#include "reference_case.hpp"

namespace podid {
namespace {

using testing::ReferenceCase;

void ExpectReportedWithTime(const SimulationResult& sim, SimulationTermination expected) {
  EXPECT_EQ(sim.summary.termination, expected) << sim.summary.message;
  EXPECT_FALSE(sim.summary.IsSolutionUsable());
  EXPECT_TRUE(std::isfinite(sim.summary.failure_time_s));
  EXPECT_NE(sim.summary.message.find("at t = "), std::string::npos) << sim.summary.message;
  EXPECT_EQ(sim.sensors.samples(), sim.summary.steps_completed + 1);  // the partial history
  EXPECT_TRUE(sim.sensors.values.allFinite());
  std::printf("%s\n", sim.summary.message.c_str());
}

TEST(Divergence, StrongSofteningCubicIsANewtonFailureWithTimeAndResidual) {
  // k3 = -5e9 N/m^3: past w = sqrt(k / 3|k3|) ~ 0.8 mm the tip spring has a
  // negative tangent stiffness and the free vibration from ~2 mm runs away.
  const SimulationResult sim = Simulate(ReferenceCase({"nonlinearity.0.k3=-5e9"}));
  ExpectReportedWithTime(sim, SimulationTermination::kNewtonFailed);
  EXPECT_TRUE(std::isfinite(sim.summary.failure_residual));
  EXPECT_NE(sim.summary.message.find("relative residual"), std::string::npos);
}

TEST(Divergence, SofteningBeyondTheStaticLoadIsAStaticSolveFailure) {
  // knl = -3.5: (2/3) k w* < 20 N, no static deflection carries the tip force.
  const SimulationResult sim = Simulate(ReferenceCase({"nonlinearity.0.k3=-3.5e8"}));
  EXPECT_EQ(sim.summary.termination, SimulationTermination::kStaticSolveFailed)
      << sim.summary.message;
  EXPECT_FALSE(sim.summary.IsSolutionUsable());
  EXPECT_NE(sim.summary.message.find("residual"), std::string::npos) << sim.summary.message;
}

TEST(Divergence, NegativeStiffnessPolynomialRunawayIsReportedAsDiverged) {
  // k1 = -3e6 N/m at the tip: an exponential runaway (it would overflow near
  // t = 0.08 s), stopped once |x| passes NewmarkOptions::max_displacement.
  const SimulationResult sim = Simulate(ReferenceCase(
      {"nonlinearity.0.type=polynomial", "nonlinearity.0.k1=-3e6", "nonlinearity.0.k3=0"}));
  ExpectReportedWithTime(sim, SimulationTermination::kDiverged);
}

TEST(Divergence, HugeHardeningK3StillConverges) {
  // k3 = 1e16 N/m^3 (knl = 1e8): stiff, but Newton converges at dt = 2e-4 s;
  // "k3 huge" is not by itself a failure of the modified Newmark scheme.
  const SimulationResult sim = Simulate(ReferenceCase({"nonlinearity.0.k3=1e16"}));
  EXPECT_TRUE(sim.summary.IsSolutionUsable()) << sim.summary.message;
  EXPECT_TRUE(sim.sensors.values.allFinite());
}

TEST(Divergence, NegativeStiffnessWithoutOverflowIsReportedAsDiverged) {
  // The implicit scheme damps the runaway of an unstable system, so it never
  // overflows; the displacement bound (NewmarkOptions::max_displacement) stops it.
  const SimulationResult sim = Simulate(ReferenceCase(
      {"nonlinearity.0.type=polynomial", "nonlinearity.0.k1=-2e7", "nonlinearity.0.k3=0"}));
  EXPECT_FALSE(sim.summary.IsSolutionUsable()) << sim.summary.message;
  EXPECT_EQ(sim.summary.termination, SimulationTermination::kDiverged) << sim.summary.message;
  EXPECT_NE(sim.summary.message.find("diverged at t = "), std::string::npos) << sim.summary.message;
  EXPECT_TRUE(sim.sensors.values.allFinite());
  EXPECT_LE(sim.sensors.values.cwiseAbs().maxCoeff(), 1e3);
}

}  // namespace
}  // namespace podid
