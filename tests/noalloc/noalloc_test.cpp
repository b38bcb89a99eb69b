// The time loop allocates nothing (Pinocchio's model/workspace split). This
// executable compiles the whole core with EIGEN_RUNTIME_NO_MALLOC and without
// NDEBUG, so an Eigen heap allocation while the integrator has forbidden them
// aborts (see tests/CMakeLists.txt).
#include <gtest/gtest.h>

#include "podid/core/newmark.hpp"
#include "podid/core/simulate.hpp"
#include "reference_case.hpp"

namespace podid {
namespace {

TEST(NoAllocationDeathTest, ForbiddenAllocationAborts) {
  // The mechanism itself works: without this, the tests below prove nothing.
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_DEATH(
      {
        Eigen::internal::set_is_malloc_allowed(false);
        Eigen::VectorXd v(16);
        v.setZero();
      },
      "heap allocation is forbidden");
}

// The reference beam is Rayleigh-damped: the modal path (newmark_modal.hpp)
// with modal_portable (the default takes it with its AVX2 loop only), the
// dense condensation with modal = false.
void RunWithoutAllocation(const std::vector<std::string>& overrides, bool modal = true) {
  const CaseSpec spec = testing::ReferenceCase(overrides);
  const BeamModel model = BeamModel::Build(spec);
  NewmarkOptions options = NewmarkOptions::FromCase(spec);
  options.modal = modal;
  options.modal_portable = modal;
  const NewmarkIntegrator integrator(model, options);
  EXPECT_EQ(integrator.modal(), modal && options.type == IntegratorType::kModifiedNewmark &&
                                    model.dofs() <= options.dense_dof_limit);
  NewmarkWorkspace workspace(integrator);
  Recording recording;
  recording.dofs = SensorDofs(spec);
  const SimulationSummary summary =
      integrator.Run(InitialState(spec, model), BuildLoad(spec), &recording, &workspace);
  EXPECT_TRUE(summary.IsSolutionUsable()) << summary.message;
  EXPECT_GT(summary.newton_iterations, 0);
}

TEST(NoAllocationTest, ModifiedNewmarkLoop) {
  RunWithoutAllocation({});
  RunWithoutAllocation({}, false);
}

TEST(NoAllocationTest, FullNewtonLoop) { RunWithoutAllocation({"integrator.type=\"newmark\""}); }

TEST(NoAllocationTest, TwoNonlinearDofsWithForcing) {
  RunWithoutAllocation({"nonlinearity.1.type=\"gap\"", "nonlinearity.1.node=3", "nonlinearity.1.gap=1e-5",
                        "nonlinearity.1.stiffness=1e5", "force.type=\"harmonic\"", "force.node=6",
                        "force.amplitude=1", "force.frequency=30"});
  RunWithoutAllocation({"nonlinearity.1.type=\"gap\"", "nonlinearity.1.node=3", "nonlinearity.1.gap=1e-5",
                        "nonlinearity.1.stiffness=1e5", "force.type=\"harmonic\"", "force.node=6",
                        "force.amplitude=1", "force.frequency=30"},
                       false);
}

TEST(NoAllocationTest, SeveralForcesAndBaseExcitationWithSubsteps) {
  for (const char* type : {"modified", "newmark"}) {
    RunWithoutAllocation({"force.0.type=\"harmonic\"", "force.0.node=6", "force.0.amplitude=1",
                          "force.0.frequency=30", "force.1.type=\"sweep\"", "force.1.node=2",
                          "force.1.amplitude=1", "force.1.start_frequency=5", "force.1.end_frequency=50",
                          "base.type=\"harmonic\"", "base.amplitude=3", "base.frequency=20",
                          "integrator.substeps=2", std::string("integrator.type=\"") + type + "\""});
  }
  RunWithoutAllocation({"beam.elements=300", "time.duration=0.01", "force.0.type=\"harmonic\"",
                        "force.0.node=100", "force.0.amplitude=1", "force.0.frequency=30",
                        "base.type=\"harmonic\"", "base.amplitude=3", "base.frequency=20"});
}

TEST(NoAllocationTest, SparseCondensedLoop) {
  // 300 elements (600 dofs): the sparse path (kDenseDofLimit) with a force
  // on a linear dof and two nonlinear dofs.
  RunWithoutAllocation({"beam.elements=300", "time.duration=0.01", "nonlinearity.1.type=\"gap\"",
                        "nonlinearity.1.node=150", "nonlinearity.1.gap=1e-5", "nonlinearity.1.stiffness=1e5",
                        "force.type=\"harmonic\"", "force.node=100", "force.amplitude=1",
                        "force.frequency=30"});
}

TEST(NoAllocationTest, OneDofLoop) {
  // A 1x1 Duffing oscillator under a point force, sub-stepped, velocity and
  // acceleration recorded: the one-dof loop (lib/src/newmark_one_dof.cpp).
  NonlinearitySpec cubic;
  cubic.type = NonlinearType::kPolynomial;
  cubic.dof = 1;
  cubic.k1_N_per_m = 1e4;
  cubic.k3_N_per_m3 = 1e8;
  const BeamModel model = BeamModel::FromMatrices(Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Zero(1, 1),
                                                  Eigen::MatrixXd::Constant(1, 1, 2.0), {cubic});
  NewmarkOptions options;
  options.step_s = 1e-4;
  options.steps = 1000;
  options.record_stride = 4;
  const NewmarkIntegrator integrator(model, options);
  ASSERT_TRUE(integrator.one_dof());
  NewmarkWorkspace workspace(integrator);
  Recording recording;
  recording.dofs = {0};
  recording.record_velocity = recording.record_acceleration = true;
  const ExternalLoad load = ExternalLoad::PointForce(1, 0, Eigen::VectorXd::LinSpaced(options.steps + 1, 0.0, 5.0));
  const State initial{Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1)};
  const SimulationSummary summary = integrator.Run(initial, load, &recording, &workspace);
  EXPECT_TRUE(summary.IsSolutionUsable()) << summary.message;
  EXPECT_GT(summary.newton_iterations, 0);
}

}  // namespace
}  // namespace podid
