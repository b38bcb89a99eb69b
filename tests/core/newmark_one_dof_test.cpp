// The one-dof loop of the dense condensed integrator (lib/src/newmark_one_dof.hpp)
// against the closed form of Newmark's own recurrence for a linear
// oscillator, and against the modal path (NewmarkOptions::modal_portable,
// which newmark_modal_test.cpp holds to a long-double Newmark) and the
// generic dense step on nonlinear, forced, sub-stepped and failing runs: the
// same equations, round-off apart.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "podid/core/newmark.hpp"

namespace podid {
namespace {

constexpr double kPi = std::numbers::pi;

NonlinearitySpec Polynomial(double k1, double k3) {
  NonlinearitySpec s;
  s.type = NonlinearType::kPolynomial;
  s.dof = 1;
  s.k1_N_per_m = k1;
  s.k3_N_per_m3 = k3;
  return s;
}

BeamModel OneDof(double m, double c, double k, const std::vector<NonlinearitySpec>& elements) {
  return BeamModel::FromMatrices(Eigen::MatrixXd::Constant(1, 1, m), Eigen::MatrixXd::Constant(1, 1, k),
                                 Eigen::MatrixXd::Constant(1, 1, c), elements);
}

NewmarkOptions Options(double step_s, int steps, int stride = 1) {
  NewmarkOptions options;
  options.step_s = step_s;
  options.steps = steps;
  options.record_stride = stride;
  return options;
}

struct Outcome {
  SimulationSummary summary;
  Recording recording;
};

Outcome Simulate(const NewmarkIntegrator& integrator, const State& initial, const ExternalLoad& load) {
  Outcome run;
  run.recording.dofs = {0};
  run.recording.record_velocity = run.recording.record_acceleration = true;
  NewmarkWorkspace workspace(integrator);
  run.summary = integrator.Run(initial, load, &run.recording, &workspace);
  return run;
}

State At(double x, double v) { return {Eigen::VectorXd::Constant(1, x), Eigen::VectorXd::Constant(1, v)}; }

double MaxAbs(const Eigen::MatrixXd& a) { return a.cwiseAbs().maxCoeff(); }

TEST(NewmarkOneDofTest, ChosenForOneDofModelsOnly) {
  const NewmarkOptions options = Options(1e-3, 10);
  const NewmarkIntegrator one(OneDof(1.0, 0.1, 0.0, {Polynomial(100.0, 1e3)}), options);
  EXPECT_TRUE(one.one_dof());
  EXPECT_FALSE(one.modal());
  EXPECT_NE(one.modal_status().find("one-dof"), std::string::npos) << one.modal_status();
  NewmarkOptions modal = options;
  modal.modal_portable = true;  // the modal path when asked for, as before
  const NewmarkIntegrator asked(OneDof(1.0, 0.1, 0.0, {Polynomial(100.0, 1e3)}), modal);
  EXPECT_FALSE(asked.one_dof());
  EXPECT_TRUE(asked.modal()) << asked.modal_status();
  NewmarkOptions full = options;
  full.type = IntegratorType::kNewmark;  // full Newton keeps its own loop
  EXPECT_FALSE(NewmarkIntegrator(OneDof(1.0, 0.1, 0.0, {Polynomial(100.0, 1e3)}), full).one_dof());
  // Two dofs, one nonlinear: the condensation has work to do.
  Eigen::MatrixXd m = Eigen::MatrixXd::Identity(2, 2), k(2, 2);
  k << 2.0, -1.0, -1.0, 2.0;
  NonlinearitySpec cubic = Polynomial(0.0, 1e3);
  EXPECT_FALSE(NewmarkIntegrator(BeamModel::FromMatrices(m, k, 0.01 * m, {cubic}), options).one_dof());
}

// Newmark's average-acceleration rule on m x'' + c x' + k x = 0 is the
// recurrence s_(n+1) = (I - h J / 2)^-1 (I + h J / 2) s_n on s = (x, x'),
// J = [0 1; -k/m -c/m]: with mu an eigenvalue of J (eigenvector (1, mu)), the
// discrete solution is x_n = sum alpha lambda^n, lambda = (1 + h mu / 2) /
// (1 - h mu / 2). Undamped, |lambda| = 1 and the phase 2 atan(w h / 2) a
// step: the frequency error of the scheme, not of the loop. With the default
// Newton tolerance (1e-10 of the step's force scale) a step may keep its
// predictor that far from the solution, 7e-8 of the amplitude after these
// 20,000 steps; at 1e-14 every step takes its correction and what is left is
// round-off, about n eps of the amplitude after n steps (4e-12; measured
// 8e-12, against 2.4e-10 with K rounded into Shat, newmark_one_dof.cpp): 1e-10 of
// the amplitude (a step of the wrong length, h (1 + 1e-9), fails it).
TEST(NewmarkOneDofTest, LinearOscillatorFollowsNewmarksClosedForm) {
  constexpr double kTolerance = 1e-10;
  constexpr int kSteps = 20000;
  const double m = 2.0, k = m * std::pow(2 * kPi * 7.0, 2), h = 2e-4, x0 = 3e-3, v0 = 0.2;
  for (const double c : {0.0, 2.0 * 0.03 * std::sqrt(k * m)}) {
    SCOPED_TRACE("c = " + std::to_string(c));
    // The linear stiffness as K, and again as the polynomial's k1 with K = 0
    // (the Silverbox's model): the same equation.
    for (const bool in_element : {false, true}) {
      const BeamModel model =
          in_element ? OneDof(m, c, 0.0, {Polynomial(k, 0.0)}) : OneDof(m, c, k, {Polynomial(0.0, 0.0)});
      NewmarkOptions options = Options(h, kSteps);
      options.tolerance = 1e-14;
      const NewmarkIntegrator integrator(model, options);
      ASSERT_TRUE(integrator.one_dof());
      const Outcome run = Simulate(integrator, At(x0, v0), ExternalLoad{});
      ASSERT_TRUE(run.summary.IsSolutionUsable()) << run.summary.message;
      const std::complex<double> root = std::sqrt(std::complex<double>(c * c - 4 * m * k, 0.0));
      const std::complex<double> mu1 = (-c + root) / (2 * m), mu2 = (-c - root) / (2 * m);
      const std::complex<double> l1 = (1.0 + h * mu1 / 2.0) / (1.0 - h * mu1 / 2.0);
      const std::complex<double> l2 = (1.0 + h * mu2 / 2.0) / (1.0 - h * mu2 / 2.0);
      // alpha1 + alpha2 = x0, alpha1 mu1 + alpha2 mu2 = v0.
      const std::complex<double> alpha1 = (v0 - mu2 * x0) / (mu1 - mu2), alpha2 = x0 - alpha1;
      double worst = 0.0;
      for (int n = 0; n <= kSteps; ++n) {
        const double exact = (alpha1 * std::pow(l1, n) + alpha2 * std::pow(l2, n)).real();
        worst = std::max(worst, std::abs(run.recording.displacement(n, 0) - exact));
      }
      EXPECT_LE(worst, kTolerance * std::abs(alpha1) * 2.0) << "amplitude " << 2.0 * std::abs(alpha1);
      EXPECT_EQ(run.summary.steps_completed, kSteps);
    }
  }
}

// A Duffing oscillator with friction, forced through a load history and
// sub-stepped (every 4th step recorded): the one-dof loop against the modal
// loop and the generic dense step (modal_portable with modal false), the
// same equations with other roundings of bhat and the predictor.
// All converge each step to the Newton tolerance 1e-10 of the step's force
// scale, so they may differ by that much a step in principle; measured they
// agree to 4e-12 (modal) and 2e-12 (dense) of the amplitude. 1e-9 relative
// to each quantity's largest value over 8000 steps; the same Newton
// iteration count.
TEST(NewmarkOneDofTest, NonlinearForcedRunMatchesTheModalAndDensePaths) {
  constexpr double kTolerance = 1e-9;
  const double m = 1.0, k = std::pow(2 * kPi * 20.0, 2), h = 1.0 / 4096.0;
  NonlinearitySpec friction;
  friction.type = NonlinearType::kFriction;
  friction.dof = 1;
  friction.friction_coefficient = 0.3;
  friction.normal_force_N = 2.0;
  friction.regularisation_velocity_m_per_s = 1e-3;
  const BeamModel model = OneDof(m, 0.5, 0.0, {Polynomial(k, 4e7), friction});
  const int steps = 8000;
  Eigen::VectorXd force(steps + 1);
  for (int i = 0; i <= steps; ++i) force[i] = 40.0 * std::sin(2 * kPi * 23.0 * i * h) + (i % 97 == 0 ? 5.0 : 0.0);
  const ExternalLoad load = ExternalLoad::PointForce(1, 0, force);
  NewmarkOptions options = Options(h, steps, 4);
  const NewmarkIntegrator one(model, options);
  options.modal_portable = true;
  const NewmarkIntegrator modal(model, options);
  options.modal = false;  // and modal_portable: the generic dense step
  const NewmarkIntegrator dense(model, options);
  ASSERT_TRUE(one.one_dof() && modal.modal());
  ASSERT_FALSE(dense.one_dof() || dense.modal());
  const Outcome a = Simulate(one, At(1e-3, 0.0), load);
  EXPECT_GT(a.summary.newton_iterations, steps);  // the cubic takes more than one correction
  EXPECT_EQ(a.summary.rows_recorded, steps / 4 + 1);
  for (const NewmarkIntegrator* other : {&modal, &dense}) {
    SCOPED_TRACE(other == &modal ? "modal" : "dense");
    const Outcome b = Simulate(*other, At(1e-3, 0.0), load);
    ASSERT_TRUE(a.summary.IsSolutionUsable()) << a.summary.message;
    ASSERT_TRUE(b.summary.IsSolutionUsable()) << b.summary.message;
    EXPECT_EQ(a.summary.newton_iterations, b.summary.newton_iterations);
    EXPECT_EQ(a.recording.displacement.rows(), b.recording.displacement.rows());
    for (const auto& [x, y] : {std::pair{&a.recording.displacement, &b.recording.displacement},
                               std::pair{&a.recording.velocity, &b.recording.velocity},
                               std::pair{&a.recording.acceleration, &b.recording.acceleration}}) {
      EXPECT_LE(MaxAbs(*x - *y), kTolerance * MaxAbs(*y));
    }
  }
}

// Failures end both loops at the same step with the same status and keep
// the same rows; a Newton failure's residual agrees to round-off.
TEST(NewmarkOneDofTest, FailuresMatchTheModalPath) {
  const double h = 1e-3;
  const int steps = 2000;
  Eigen::VectorXd ramp(steps + 1);
  for (int i = 0; i <= steps; ++i) ramp[i] = 50.0 * i * h;
  const ExternalLoad load = ExternalLoad::PointForce(1, 0, ramp);
  struct Case {
    const char* name;
    double max_displacement;
    int max_iterations;
    SimulationTermination expected;
  };
  for (const Case& e : {Case{"diverged", 0.05, 50, SimulationTermination::kDiverged},
                        Case{"newton", 1e6, 1, SimulationTermination::kNewtonFailed}}) {
    SCOPED_TRACE(e.name);
    // A softening cubic: the ramp drives it past its turning point.
    const BeamModel model = OneDof(1.0, 1.0, 0.0, {Polynomial(1e3, -1e5)});
    NewmarkOptions options = Options(h, steps, 2);
    options.max_displacement = e.max_displacement;
    options.max_iterations = e.max_iterations;
    const NewmarkIntegrator one(model, options);
    options.modal_portable = true;
    const NewmarkIntegrator modal(model, options);
    const Outcome a = Simulate(one, At(0.0, 0.0), load), b = Simulate(modal, At(0.0, 0.0), load);
    EXPECT_EQ(a.summary.termination, e.expected) << a.summary.message;
    EXPECT_EQ(b.summary.termination, e.expected) << b.summary.message;
    EXPECT_GT(a.summary.steps_completed, 0);
    EXPECT_LT(a.summary.steps_completed, steps);
    EXPECT_EQ(a.summary.steps_completed, b.summary.steps_completed);
    EXPECT_EQ(a.summary.rows_recorded, b.summary.rows_recorded);
    EXPECT_EQ(a.summary.failure_time_s, b.summary.failure_time_s);
    if (e.expected == SimulationTermination::kNewtonFailed) {
      // The failed step's residual, round-off apart (1.04049e-10 and 1.0405e-10).
      EXPECT_NEAR(a.summary.failure_residual, b.summary.failure_residual, 1e-3 * b.summary.failure_residual);
    }
  }
}

}  // namespace
}  // namespace podid
