// Newmark integrators against the independent DOP853 data, closed-form
// single-dof results, energy conservation and each other.
#include "podid/core/newmark.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <numbers>
#include <vector>

#include "podid/core/error.hpp"
#include "podid/core/simulate.hpp"
#include "reference_case.hpp"
#include "test_support.hpp"

namespace podid {
namespace {

using testing::ReferenceCase;
using testing::ReferenceData;
using testing::RelativeError;
constexpr double kPi = std::numbers::pi;

// Relative L2 error over all channels of a simulation at `step_s` against the
// reference data, compared at the data's samples (every k-th step).
double ErrorAgainstReference(double step_s) {
  const TimeSeries reference = ReferenceData("clean_knl50_T0.1.csv");
  const CaseSpec spec = ReferenceCase({"time.step=" + ToText(step_s)});
  const SimulationResult sim = Simulate(spec);
  EXPECT_TRUE(sim.summary.IsSolutionUsable()) << sim.summary.message;
  const int every = static_cast<int>(std::lround(reference.step_s() / step_s));
  EXPECT_EQ((sim.sensors.samples() - 1), (reference.samples() - 1) * every);
  Eigen::MatrixXd sampled(reference.samples(), reference.channels());
  for (Eigen::Index i = 0; i < reference.samples(); ++i) sampled.row(i) = sim.sensors.values.row(i * every);
  return RelativeError(sampled, reference.values);
}

TEST(NewmarkReferenceTest, MatchesIndependentIntegrationAndConvergesAtSecondOrder) {
  // Issue 2's acceptance bounds; Newmark's error is its period error, which is
  // O(dt^2) and grows with frequency (the reference README).
  constexpr double kBoundAt2e4 = 0.012;
  constexpr double kBoundAt5e5 = 0.0008;
  // Second order: each halving divides the error by ~4 (3.6..4.4 allows the
  // higher-order terms at the coarse step).
  constexpr double kMinRatio = 3.6, kMaxRatio = 4.4;
  const double e1 = ErrorAgainstReference(2e-4);
  const double e2 = ErrorAgainstReference(1e-4);
  const double e3 = ErrorAgainstReference(5e-5);
  std::cout << "relative L2 error vs DOP853: dt=2e-4: " << e1 << ", 1e-4: " << e2 << ", 5e-5: " << e3
            << " (ratios " << e1 / e2 << ", " << e2 / e3 << ")\n";
  EXPECT_LE(e1, kBoundAt2e4);
  EXPECT_LE(e3, kBoundAt5e5);
  EXPECT_GT(e1 / e2, kMinRatio);
  EXPECT_LT(e1 / e2, kMaxRatio);
  EXPECT_GT(e2 / e3, kMinRatio);
  EXPECT_LT(e2 / e3, kMaxRatio);
}

double CompareIntegrators(const std::vector<std::string>& overrides) {
  std::vector<std::string> full = overrides, modified = overrides;
  // Tight Newton tolerance so both land on the same discrete solution.
  full.push_back("integrator.tolerance=1e-13");
  modified.push_back("integrator.tolerance=1e-13");
  full.push_back("integrator.type=\"newmark\"");
  modified.push_back("integrator.type=\"modified\"");
  const SimulationResult a = Simulate(ReferenceCase(full));
  const SimulationResult b = Simulate(ReferenceCase(modified));
  EXPECT_TRUE(a.summary.IsSolutionUsable()) << a.summary.message;
  EXPECT_TRUE(b.summary.IsSolutionUsable()) << b.summary.message;
  EXPECT_EQ(a.summary.integrator, IntegratorType::kNewmark);
  EXPECT_EQ(b.summary.integrator, IntegratorType::kModifiedNewmark);
  return RelativeError(b.sensors.values, a.sensors.values);
}

TEST(NewmarkAgreementTest, CondensedEqualsFullNewtonOnReferenceCase) {
  // Both solve eq. 23 exactly (eq. 29 is its Schur complement): issue 2 asks 1e-9.
  constexpr double kRelativeTolerance = 1e-9;
  const double error = CompareIntegrators({});
  std::cout << "reference case: condensed vs full Newton relative difference " << error << "\n";
  EXPECT_LE(error, kRelativeTolerance);
}

TEST(NewmarkAgreementTest, CondensedEqualsFullNewtonWithTwoElementsAtTwoNodes) {
  constexpr double kRelativeTolerance = 1e-9;
  const double error = CompareIntegrators({
      "nonlinearity.1.type=\"polynomial\"", "nonlinearity.1.node=3", "nonlinearity.1.k1=2000",
      "nonlinearity.1.k2=1e6", "nonlinearity.1.k3=1e10",  //
      "nonlinearity.2.type=\"friction\"", "nonlinearity.2.node=5", "nonlinearity.2.mu=0.3",
      "nonlinearity.2.normal_force=2.0", "nonlinearity.2.velocity_scale=1e-3"});
  std::cout << "polynomial + friction + cubic: relative difference " << error << "\n";
  EXPECT_LE(error, kRelativeTolerance);
}

TEST(NewmarkAgreementTest, SimdKernelEqualsPortableKernel) {
  // The dense condensed product with AVX2 + FMA (when this CPU has them) vs the
  // portable kernel: the same sums, rounded differently, each step's Newton
  // stopping at 1e-10: 1e-9 as above. 12, 14 and 20 dofs cover the kernels'
  // row blocks (16, 12, 8 and 4 rows, single rows).
  constexpr double kRelativeTolerance = 1e-9;
  for (const int elements : {6, 7, 10}) {
    const CaseSpec spec = ReferenceCase({"beam.elements=" + ToText(elements)});
    const BeamModel model = BeamModel::Build(spec);
    const State initial = InitialState(spec, model);
    Recording simd, portable;
    simd.dofs = portable.dofs = SensorDofs(spec);
    NewmarkOptions options = NewmarkOptions::FromCase(spec);
    options.modal = false;  // the dense condensation's kernels (the modal path: newmark_modal_test.cpp)
    const SimulationSummary a = NewmarkIntegrator(model, options).Run(initial, BuildLoad(spec), &simd);
    options.cpu_dispatch = false;
    const SimulationSummary b =
        NewmarkIntegrator(model, options).Run(initial, BuildLoad(spec), &portable);
    ASSERT_TRUE(a.IsSolutionUsable()) << a.message;
    ASSERT_TRUE(b.IsSolutionUsable()) << b.message;
    const double error = RelativeError(simd.displacement, portable.displacement);
    std::cout << model.dofs() << " dofs: SIMD vs portable kernel relative difference " << error << "\n";
    EXPECT_LE(error, kRelativeTolerance);
  }
}

TEST(NewmarkAgreementTest, FusedOneDofStepEqualsTheSparseCondensedPath) {
  // The dense path with one nonlinear dof runs the fused step (product,
  // scalar Newton, eq. 28 and the update in one kernel); the sparse path
  // (dense_dof_limit = 0) solves the same equations with LDL^T solves and
  // vector code: each step's Newton stops at 1e-10 and the errors propagate
  // over 5000 steps, 1e-8 relative (as the sparse-vs-dense test). With a
  // force, both kernels, and velocities and accelerations recorded.
  constexpr double kRelativeTolerance = 1e-8;
  const CaseSpec spec = ReferenceCase({"time.duration=1.0", "force.type=\"harmonic\"", "force.node=3",
                                       "force.amplitude=1", "force.frequency=30"});
  const BeamModel model = BeamModel::Build(spec);
  const State initial = InitialState(spec, model);
  const ExternalLoad load = BuildLoad(spec);
  for (const bool cpu_dispatch : {true, false}) {
    NewmarkOptions options = NewmarkOptions::FromCase(spec);
    options.cpu_dispatch = cpu_dispatch;
    options.modal = false;  // the dense fused step (the modal path: newmark_modal_test.cpp)
    const NewmarkIntegrator fused(model, options);
    options.dense_dof_limit = 0;
    const NewmarkIntegrator sparse(model, options);
    ASSERT_FALSE(fused.sparse());
    ASSERT_TRUE(sparse.sparse());
    ASSERT_EQ(fused.nonlinear_dofs(), 1);
    Recording a, b;
    for (int d = 0; d < model.dofs(); ++d) a.dofs.push_back(d);
    a.record_velocity = a.record_acceleration = true;
    b = a;
    const SimulationSummary sa = fused.Run(initial, load, &a), sb = sparse.Run(initial, load, &b);
    ASSERT_TRUE(sa.IsSolutionUsable()) << sa.message;
    ASSERT_TRUE(sb.IsSolutionUsable()) << sb.message;
    // Rounding may move a step whose residual sits at the tolerance: 1 % of the steps.
    EXPECT_LE(std::abs(sa.newton_iterations - sb.newton_iterations), sa.steps_completed / 100);
    EXPECT_LE(RelativeError(a.displacement, b.displacement), kRelativeTolerance);
    EXPECT_LE(RelativeError(a.velocity, b.velocity), kRelativeTolerance);
    EXPECT_LE(RelativeError(a.acceleration, b.acceleration), kRelativeTolerance);
  }
}

// A single-dof oscillator m x'' + c x' + k x = f_nl, built from 1 x 1 matrices.
BeamModel Sdof(double mass, double stiffness, const std::vector<NonlinearitySpec>& elements = {}) {
  return BeamModel::FromMatrices(Eigen::MatrixXd::Constant(1, 1, mass),
                                 Eigen::MatrixXd::Constant(1, 1, stiffness), Eigen::MatrixXd::Zero(1, 1),
                                 elements);
}

Recording RunSdof(const BeamModel& model, double x0, double step_s, int steps,
              IntegratorType type = IntegratorType::kModifiedNewmark) {
  NewmarkOptions options;
  options.type = type;
  options.step_s = step_s;
  options.steps = steps;
  options.tolerance = 1e-12;
  const NewmarkIntegrator integrator(model, options);
  State initial{Eigen::VectorXd::Zero(model.dofs()), Eigen::VectorXd::Zero(model.dofs())};
  initial.displacement[0] = x0;
  Recording recording;
  recording.dofs = {0};
  recording.record_velocity = true;
  const SimulationSummary summary = integrator.Run(initial, ExternalLoad{}, &recording);
  EXPECT_TRUE(summary.IsSolutionUsable()) << summary.message;
  return recording;
}

// Mean period from the downward zero crossings (linear interpolation).
double MeasuredPeriod(const Eigen::VectorXd& x, double step_s) {
  std::vector<double> crossings;
  for (Eigen::Index i = 1; i < x.size(); ++i) {
    if (x[i - 1] > 0 && x[i] <= 0) crossings.push_back((i - 1 + x[i - 1] / (x[i - 1] - x[i])) * step_s);
  }
  EXPECT_GE(crossings.size(), 3u);
  return (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
}

TEST(NewmarkSdofTest, PeriodErrorIsOmegaDtSquaredOverTwelve) {
  // Average-acceleration Newmark lengthens the period by (omega dt)^2 / 12 to
  // leading order; issue 2 asks for a 5 % match.
  constexpr double kRelativeTolerance = 0.05;
  const double omega = 2 * kPi * 10.0;
  for (double omega_dt : {0.05, 0.1, 0.2}) {
    const double dt = omega_dt / omega;
    const int steps = static_cast<int>(60 * 2 * kPi / omega_dt);  // 60 periods
    const Recording r = RunSdof(Sdof(1.0, omega * omega), 1.0, dt, steps);
    const double elongation = MeasuredPeriod(r.displacement.col(0), dt) / (2 * kPi / omega) - 1.0;
    const double predicted = omega_dt * omega_dt / 12.0;
    EXPECT_NEAR(elongation / predicted, 1.0, kRelativeTolerance) << "omega dt = " << omega_dt;
  }
}

TEST(NewmarkSdofTest, SubstepsCutThePeriodErrorByTheirSquare) {
  // integrator.substeps = k: Newmark at dt / k, every k-th sample kept. The
  // phase error, (omega dt / k)^2 / 12 per radian (0.04 rad after 2 periods
  // at k = 1: sin(phase) ~ phase to 3e-4), falls as k^-2: the measured order
  // log2(e(k) / e(2k)) is 2 within 0.05 (the elongation's next term is
  // O((omega dt)^4), 1e-3 relative here).
  constexpr double kOrderTolerance = 0.05;
  const double omega = 2 * kPi * 10.0, omega_dt = 0.2, dt = omega_dt / omega;
  const int samples = static_cast<int>(2 * 2 * kPi / omega_dt);
  double error[3] = {0, 0, 0};
  for (int i = 0; i < 3; ++i) {
    const int k = 1 << i;
    NewmarkOptions options;
    options.step_s = dt / k;
    options.steps = samples * k;
    options.record_stride = k;
    options.tolerance = 1e-12;
    const BeamModel model = Sdof(1.0, omega * omega);
    const NewmarkIntegrator integrator(model, options);
    const State initial{Eigen::VectorXd::Ones(1), Eigen::VectorXd::Zero(1)};
    Recording recording;
    recording.dofs = {0};
    const SimulationSummary summary = integrator.Run(initial, ExternalLoad{}, &recording);
    ASSERT_TRUE(summary.IsSolutionUsable());
    ASSERT_EQ(recording.displacement.rows(), samples + 1);  // the data's grid, not k times more
    ASSERT_EQ(summary.rows_recorded, samples + 1);
    for (int n = 0; n <= samples; ++n)
      error[i] = std::max(error[i], std::abs(recording.displacement(n, 0) - std::cos(omega * n * dt)));
  }
  std::cout << "[ figure   ] SDOF max error over 2 periods (omega dt = 0.2): k=1 " << error[0]
            << ", k=2 " << error[1] << ", k=4 " << error[2] << "\n";
  EXPECT_NEAR(std::log2(error[0] / error[1]), 2.0, kOrderTolerance);
  EXPECT_NEAR(std::log2(error[1] / error[2]), 2.0, kOrderTolerance);
}

TEST(NewmarkOptionsTest, RecordStrideMustDivideTheSteps) {
  NewmarkOptions options;
  options.step_s = 1e-3;
  options.steps = 10;
  options.record_stride = 3;
  std::string why;
  EXPECT_FALSE(options.IsValid(&why));
  EXPECT_EQ(why, "record_stride: expected >= 1 dividing steps (10), got 3");
}

TEST(NewmarkEnergyTest, UndampedLinearBeamKeepsEnergy) {
  // The trapezoidal rule conserves E = (v'Mv + x'Kx)/2 exactly for a linear
  // undamped system; what remains is round-off accumulated over 1e4 steps.
  constexpr double kRelativeTolerance = 1e-10;
  const CaseSpec spec = ReferenceCase({"damping.modal_ratios=[0, 0]", "nonlinearity.0.k3=0"});
  const BeamModel model = BeamModel::Build(spec);
  NewmarkOptions options;
  options.step_s = 2e-4;
  options.steps = 10000;
  const NewmarkIntegrator integrator(model, options);
  Recording recording;
  for (int d = 0; d < model.dofs(); ++d) recording.dofs.push_back(d);
  recording.record_velocity = true;
  const SimulationSummary summary = integrator.Run(InitialState(spec, model), ExternalLoad{}, &recording);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.message;
  auto energy = [&](Eigen::Index i) {
    const Eigen::VectorXd x = recording.displacement.row(i).transpose();
    const Eigen::VectorXd v = recording.velocity.row(i).transpose();
    return 0.5 * (v.dot(Eigen::VectorXd(model.mass() * v)) + x.dot(Eigen::VectorXd(model.stiffness() * x)));
  };
  const double e0 = energy(0);
  double worst = 0;
  for (Eigen::Index i = 0; i < recording.displacement.rows(); ++i)
    worst = std::max(worst, std::abs(energy(i) / e0 - 1.0));
  std::cout << "worst relative energy drift over 1e4 steps: " << worst << "\n";
  EXPECT_LE(worst, kRelativeTolerance);
}

TEST(NewmarkGapTest, FrequencyBelowAndAboveContact) {
  // Single dof with a symmetric clearance g and contact stiffness kc.
  const double m = 1.0, k = std::pow(2 * kPi * 5.0, 2), kc = 3.0 * k, g = 0.01;
  NonlinearitySpec gap;
  gap.type = NonlinearType::kGap;
  gap.node = 1;
  gap.gap_m = g;
  gap.contact_stiffness_N_per_m = kc;
  const BeamModel model = Sdof(m, k, {gap});
  const double w1 = std::sqrt(k / m), w2 = std::sqrt((k + kc) / m);
  const double dt = 1e-4;  // omega dt <= 0.0063: Newmark's period error < 4e-6
  // Matches the closed form to a discretisation error below 1e-4 (period
  // error plus the contact instant, located within one step).
  constexpr double kRelativeTolerance = 1e-4;

  // Below contact (amplitude < g): the linear period.
  const Recording below = RunSdof(model, 0.5 * g, dt, 20000);
  EXPECT_NEAR(MeasuredPeriod(below.displacement.col(0), dt) * w1 / (2 * kPi), 1.0, kRelativeTolerance);

  // Above contact, released at X0 > g: a quarter period is the time in contact
  // (harmonic at w2 about x_e = kc g / (k + kc)) plus the free flight to x = 0.
  const double x0 = 3.0 * g, xe = kc * g / (k + kc);
  const double t1 = std::acos((g - xe) / (x0 - xe)) / w2;
  const double v1 = -(x0 - xe) * w2 * std::sin(w2 * t1);
  const double t2 = std::atan(-g * w1 / v1) / w1;
  const double period = 4 * (t1 + t2);
  const Recording above = RunSdof(model, x0, dt, 20000);
  EXPECT_NEAR(MeasuredPeriod(above.displacement.col(0), dt) / period, 1.0, kRelativeTolerance);
  // The gap shortens the period noticeably (sanity of the test itself).
  EXPECT_LT(period, 0.9 * 2 * kPi / w1);
}

TEST(NewmarkFrictionTest, AmplitudeDecaysLinearlyByFourMuNOverK) {
  // Coulomb friction: each cycle loses 4 mu N / k of amplitude. The tanh
  // regularisation (v_reg = 1e-4 of the peak velocity) perturbs it by < 1 %.
  constexpr double kRelativeTolerance = 0.01;
  const double m = 1.0, k = std::pow(2 * kPi * 5.0, 2), slip = 2.0;  // mu N = 2 N
  NonlinearitySpec friction;
  friction.type = NonlinearType::kFriction;
  friction.node = 1;
  friction.friction_coefficient = 0.5;
  friction.normal_force_N = slip / 0.5;
  const double x0 = 0.1;
  friction.regularisation_velocity_m_per_s = 1e-4 * x0 * std::sqrt(k / m);
  const double dt = 2e-5;
  const Recording r = RunSdof(Sdof(m, k, {friction}), x0, dt, 50000);
  // Successive positive peaks.
  std::vector<double> peaks;
  const Eigen::VectorXd x = r.displacement.col(0);
  for (Eigen::Index i = 1; i + 1 < x.size(); ++i)
    if (x[i] > x[i - 1] && x[i] >= x[i + 1] && x[i] > 0) peaks.push_back(x[i]);
  ASSERT_GE(peaks.size(), 4u);
  const double expected = 4 * slip / k;
  for (std::size_t i = 0; i + 1 < 4; ++i) {
    EXPECT_NEAR((peaks[i] - peaks[i + 1]) / expected, 1.0, kRelativeTolerance) << "cycle " << i;
  }
}

void ExpectFailureReported(const SimulationResult& sim, SimulationTermination expected) {
  EXPECT_FALSE(sim.summary.IsSolutionUsable());
  EXPECT_EQ(sim.summary.termination, expected) << sim.summary.message;
  EXPECT_NE(sim.summary.message.find("at t = "), std::string::npos) << sim.summary.message;
  EXPECT_LT(sim.summary.steps_completed, sim.summary.steps_requested);
  EXPECT_EQ(sim.sensors.samples(), sim.summary.steps_completed + 1);  // the partial history
  EXPECT_TRUE(sim.sensors.values.allFinite());
  std::cout << sim.summary.BriefReport() << "\n  " << sim.summary.message << "\n";
}

TEST(NewmarkFailureTest, NewtonFailureOnNearDiscontinuousFrictionIsReported) {
  // dt far too large for the friction regularisation: tanh(v / 1e-9) is a step
  // function at this scale, and Newton cycles instead of converging.
  const SimulationResult sim = Simulate(ReferenceCase(
      {"nonlinearity.1.type=\"friction\"", "nonlinearity.1.node=6", "nonlinearity.1.mu=1",
       "nonlinearity.1.normal_force=5", "nonlinearity.1.velocity_scale=1e-9"}));
  ExpectFailureReported(sim, SimulationTermination::kNewtonFailed);
  EXPECT_TRUE(std::isfinite(sim.summary.failure_residual));
}

TEST(NewmarkFailureTest, OverflowIsReportedAsNonFinite) {
  // A tip released at 1e200 m: k3 w^3 overflows to Inf at t = 0.
  CaseSpec spec = ReferenceCase();
  spec.initial.type = InitialType::kExplicit;
  spec.initial.displacement = Eigen::VectorXd::Zero(12);
  spec.initial.displacement[TransverseDof(6)] = 1e200;
  spec.initial.velocity = Eigen::VectorXd::Zero(12);
  const SimulationResult sim = Simulate(spec);
  ExpectFailureReported(sim, SimulationTermination::kNonFinite);
}

TEST(NewmarkOptionsTest, InvalidOptionsAreRejected) {
  NewmarkOptions options;
  std::string why;
  EXPECT_FALSE(options.IsValid(&why));  // step 0
  EXPECT_NE(why.find("step"), std::string::npos);
  options.step_s = 1e-3;
  options.steps = 10;
  EXPECT_TRUE(options.IsValid(&why));
  options.beta = 0.0;
  EXPECT_FALSE(options.IsValid(&why));
  EXPECT_NE(why.find("expected"), std::string::npos);
  PODID_EXPECT_THROW_WITH(NewmarkIntegrator(Sdof(1, 1), options), std::invalid_argument, "beta");
}

}  // namespace
}  // namespace podid
