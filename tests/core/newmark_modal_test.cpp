// The modal path of the dense condensed integrator (lib/src/newmark_modal.hpp)
// against an independent Newmark in long double (Newton on all dofs, linear
// algebra with a 64-bit significand) and against the dense condensation
// (NewmarkOptions::modal = false, which the other tests hold to the DOP853
// data and full Newton): when it applies, when it does not, and that it
// solves the same equations.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "newmark_modal.hpp"
#include "podid/core/newmark.hpp"
#include "podid/core/simulate.hpp"
#include "reference_case.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

namespace podid {
namespace {

using testing::ReferenceCase;
using testing::RelativeError;
using LongMatrix = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
using LongVector = Eigen::Matrix<long double, Eigen::Dynamic, 1>;

// Newmark (the same gamma, beta, step) with Newton on all dofs, the linear
// algebra in long double: the discrete solution with ~2000 times less
// rounding than any double path. The elements are evaluated in double at the
// rounded state (random rounding of 1e-16 per step, not a bias). Newton runs
// to a correction of 1e-19 relative. Returns the displacements (steps + 1) x n.
Eigen::MatrixXd LongDoubleNewmark(const BeamModel& model, const NewmarkOptions& options, const State& initial,
                                  const ExternalLoad& load) {
  const int n = model.dofs();
  const LongMatrix m = model.DenseMass().cast<long double>(), c = model.DenseDamping().cast<long double>(),
                   k = model.DenseStiffness().cast<long double>();
  const long double dt = options.step_s, g = options.gamma, b = options.beta;
  const long double a0 = 1 / (b * dt * dt), a1 = g / (b * dt), a2 = 1 / (b * dt), a3 = 1 / (2 * b) - 1;
  const LongMatrix s = a0 * m + a1 * c + k;
  const std::vector<int>& nonlinear_dofs = model.nonlinear().dofs();
  const int na = static_cast<int>(nonlinear_dofs.size());
  Eigen::VectorXd xa(na), va(na), fa(na);
  Eigen::MatrixXd ka(na, na), ca(na, na);
  const Eigen::MatrixXd pattern = Eigen::MatrixXd(load.pattern);
  // f_nl + g at step `step`, and the tangents -df/dx, -df/dv (n x n).
  auto force = [&](const LongVector& x, const LongVector& v, int step, LongVector* f, LongMatrix* kt,
                   LongMatrix* ct) {
    for (int j = 0; j < na; ++j) {
      xa[j] = static_cast<double>(x[nonlinear_dofs[j]]);
      va[j] = static_cast<double>(v[nonlinear_dofs[j]]);
    }
    model.nonlinear().Evaluate(xa, va, fa, ka, ca);
    f->setZero(n);
    if (load.columns() > 0) *f += (pattern * load.history.col(step)).cast<long double>();
    kt->setZero(n, n);
    ct->setZero(n, n);
    for (int j = 0; j < na; ++j) {
      (*f)[nonlinear_dofs[j]] += fa[j];
      for (int l = 0; l < na; ++l) {
        (*kt)(nonlinear_dofs[j], nonlinear_dofs[l]) = ka(j, l);
        (*ct)(nonlinear_dofs[j], nonlinear_dofs[l]) = ca(j, l);
      }
    }
  };
  LongVector x = initial.displacement.cast<long double>(), v = initial.velocity.cast<long double>(), f;
  LongMatrix kt, ct;
  force(x, v, 0, &f, &kt, &ct);
  LongVector acc = m.partialPivLu().solve(LongVector(f - k * x - c * v));
  Eigen::MatrixXd out(options.steps + 1, n);
  out.row(0) = x.cast<double>().transpose();
  for (int step = 1; step <= options.steps; ++step) {
    const LongVector rhs =
        m * (a0 * x + a2 * v + a3 * acc) + c * (a1 * x + (g / b - 1) * v + dt * (g / (2 * b) - 1) * acc);
    LongVector x_new = x;
    for (int it = 0; it < 30; ++it) {
      const LongVector v_new = a1 * (x_new - x) + (1 - g / b) * v + dt * (1 - g / (2 * b)) * acc;
      force(x_new, v_new, step, &f, &kt, &ct);
      const LongVector dx = LongMatrix(s + kt + a1 * ct).partialPivLu().solve(LongVector(s * x_new - rhs - f));
      x_new -= dx;
      if (dx.cwiseAbs().maxCoeff() <= 1e-19L * x_new.cwiseAbs().maxCoeff()) break;
    }
    const LongVector a_new = a0 * (x_new - x) - a2 * v - a3 * acc;
    v += dt * ((1 - g) * acc + g * a_new);
    acc = a_new;
    x = x_new;
    out.row(step) = x.cast<double>().transpose();
  }
  return out;
}

struct Runs {
  SimulationSummary modal, dense;
  Recording modal_recording, dense_recording;
  Eigen::MatrixXd reference;  ///< LongDoubleNewmark, when asked
};

// The case's options with the modal path wherever it applies, also on its
// portable loop (n_a != 1, or a CPU without AVX2), which the default leaves
// to the dense step.
NewmarkOptions ModalOptions(const CaseSpec& spec) {
  NewmarkOptions options = NewmarkOptions::FromCase(spec);
  options.modal_portable = true;
  return options;
}

// Both paths on the same model from the case's initial state and load, every
// dof recorded with velocities and accelerations.
Runs RunBoth(const CaseSpec& spec, bool long_double_reference = false) {
  const BeamModel model = BeamModel::Build(spec);
  NewmarkOptions options = ModalOptions(spec);
  const NewmarkIntegrator modal(model, options);
  options.modal = false;
  const NewmarkIntegrator dense(model, options);
  EXPECT_TRUE(modal.modal()) << modal.modal_status();
  EXPECT_FALSE(dense.modal());
  Runs runs;
  for (int d = 0; d < model.dofs(); ++d) runs.modal_recording.dofs.push_back(d);
  runs.modal_recording.record_velocity = runs.modal_recording.record_acceleration = true;
  runs.dense_recording = runs.modal_recording;
  const State initial = InitialState(spec, model);
  const ExternalLoad load = BuildLoad(spec, model);
  runs.modal = modal.Run(initial, load, &runs.modal_recording);
  runs.dense = dense.Run(initial, load, &runs.dense_recording);
  EXPECT_TRUE(runs.modal.IsSolutionUsable()) << runs.modal.message;
  EXPECT_TRUE(runs.dense.IsSolutionUsable()) << runs.dense.message;
  if (long_double_reference) runs.reference = LongDoubleNewmark(model, options, initial, load);
  return runs;
}

// The largest of the relative differences of x, x' and x'' (Frobenius norms).
double Difference(const Runs& runs) {
  const Recording &a = runs.modal_recording, &b = runs.dense_recording;
  const double x = RelativeError(a.displacement, b.displacement);
  const double v = RelativeError(a.velocity, b.velocity);
  const double acc = RelativeError(a.acceleration, b.acceleration);
  std::cout << "modal vs dense relative difference: x " << x << ", x' " << v << ", x'' " << acc << "; Newton "
            << runs.modal.newton_iterations << " vs " << runs.dense.newton_iterations << " iterations\n";
  return std::max({x, v, acc});
}

TEST(NewmarkModalTest, ReferenceBeamTakesTheModalPathAndOtherCasesDoNot) {
  // Rayleigh damping, and no damping: the modes diagonalise C (round-off:
  // kModalCouplingTolerance's comment).
  constexpr double kRoundOffCoupling = 1e-14;  // measured 2.7e-15
  for (const char* ratios : {"[0.01, 0.01]", "[0.0, 0.0]"}) {
    const CaseSpec spec = ReferenceCase({std::string("damping.modal_ratios=") + ratios});
    const NewmarkIntegrator integrator(BeamModel::Build(spec), ModalOptions(spec));
    EXPECT_TRUE(integrator.modal()) << integrator.modal_status();
    std::cout << ratios << ": " << integrator.modal_status() << "\n";
    const std::string& status = integrator.modal_status();
    EXPECT_LE(std::stod(status.substr(status.find("coupling ") + 9)), kRoundOffCoupling);
  }
  // A dashpot on one dof (non-proportional damping) takes the dense path.
  const CaseSpec dashpot = ReferenceCase({"spring.0.node=3", "spring.0.dof=\"w\"", "spring.0.stiffness=0",
                                          "spring.0.damping=5"});
  const BeamModel model = BeamModel::Build(dashpot);
  const NewmarkIntegrator integrator(model, ModalOptions(dashpot));
  EXPECT_FALSE(integrator.modal());
  std::cout << "dashpot: " << integrator.modal_status() << "\n";
  EXPECT_NE(integrator.modal_status().find("non-proportional damping"), std::string::npos)
      << integrator.modal_status();
  // Its response is the dense path's, bit for bit (the same code runs).
  NewmarkOptions options = NewmarkOptions::FromCase(dashpot);
  options.modal = false;
  Recording a, b;
  a.dofs = b.dofs = SensorDofs(dashpot);
  const State initial = InitialState(dashpot, model);
  integrator.Run(initial, ExternalLoad{}, &a);
  NewmarkIntegrator(model, options).Run(initial, ExternalLoad{}, &b);
  EXPECT_TRUE(a.displacement == b.displacement);
  // Neither full Newton nor the sparse path use it.
  NewmarkOptions full = ModalOptions(ReferenceCase());
  full.type = IntegratorType::kNewmark;
  EXPECT_FALSE(NewmarkIntegrator(BeamModel::Build(ReferenceCase()), full).modal());
  NewmarkOptions sparse = ModalOptions(ReferenceCase());
  sparse.dense_dof_limit = 0;
  EXPECT_FALSE(NewmarkIntegrator(BeamModel::Build(ReferenceCase()), sparse).modal());
}

TEST(NewmarkModalTest, DefaultTakesTheModalPathOnlyWithItsAvx2Loop) {
  // The portable modal loops are slower than the dense step (120 against
  // 106 ns a reference step; 2 nonlinear dofs and none: docs/benchmarks.md),
  // so by default the modal path needs its AVX2 loop: one nonlinear dof,
  // cpu_dispatch and a CPU with AVX2. Otherwise the dense step runs, the
  // same bits as modal = false, and modal_status() says why.
#if defined(__GNUC__) && defined(__x86_64__)
  const bool avx2 = __builtin_cpu_supports("avx2");
#else
  const bool avx2 = false;
#endif
  const CaseSpec one = ReferenceCase(
      {"force.type=\"harmonic\"", "force.node=3", "force.amplitude=1", "force.frequency=30"});
  const CaseSpec two = ReferenceCase({"nonlinearity.1.type=\"gap\"", "nonlinearity.1.node=3",
                                      "nonlinearity.1.gap=1e-5", "nonlinearity.1.stiffness=1e5"});
  struct Expected {
    const CaseSpec* spec;
    bool cpu_dispatch, modal;
    const char* reason;  ///< in modal_status() when not modal
  };
  for (const Expected& e : {Expected{&one, true, avx2, "the CPU has no AVX2"},
                            Expected{&one, false, false, "NewmarkOptions::cpu_dispatch is false"},
                            Expected{&two, true, false, "one nonlinear dof"},
                            Expected{&two, false, false, "one nonlinear dof"}}) {
    SCOPED_TRACE(std::string(e.spec == &one ? "one" : "two") + " nonlinear dof(s), cpu_dispatch " +
                 (e.cpu_dispatch ? "true" : "false"));
    const BeamModel model = BeamModel::Build(*e.spec);
    NewmarkOptions options = NewmarkOptions::FromCase(*e.spec);
    options.cpu_dispatch = e.cpu_dispatch;
    const NewmarkIntegrator chosen(model, options);
    EXPECT_EQ(chosen.modal(), e.modal) << chosen.modal_status();
    if (!e.modal) {
      EXPECT_NE(chosen.modal_status().find(e.reason), std::string::npos) << chosen.modal_status();
      EXPECT_NE(chosen.modal_status().find("slower than the dense step"), std::string::npos);
    }
    options.modal_portable = true;  // the modal path applies (Rayleigh damping) when asked for
    EXPECT_TRUE(NewmarkIntegrator(model, options).modal());
    options.modal_portable = false;
    options.modal = false;
    Recording a, b;
    a.dofs = b.dofs = SensorDofs(*e.spec);
    const State initial = InitialState(*e.spec, model);
    const ExternalLoad load = BuildLoad(*e.spec, model);
    ASSERT_TRUE(chosen.Run(initial, load, &a).IsSolutionUsable());
    ASSERT_TRUE(NewmarkIntegrator(model, options).Run(initial, load, &b).IsSolutionUsable());
    if (!e.modal) {
      EXPECT_TRUE(a.displacement == b.displacement);  // the same code ran
    }
  }
}

TEST(NewmarkModalTest, ReferenceBeamAgainstLongDoubleNewmark) {
  // 1 s (5000 steps), Newton to 1e-15 so that the tolerance does not hide
  // rounding. Every double path drifts from the long double solution by
  // rounding in the step's constants (a low mode's frequency is the small
  // part of a0 M + K) and in 5000 steps of the high modes, which Newmark
  // does not damp: measured 1.3e-11 modal, 8.0e-12 dense. 3e-11 bounds both.
  constexpr double kTolerance = 3e-11;
  // Without the cubic spring (k3 = 0) the modal step in increments is the
  // more accurate (1.6e-12 against 9.0e-12 for the dense path, whose S x
  // carries the rounding of a0 M): 3e-12.
  constexpr double kLinearTolerance = 3e-12;
  for (const char* k3 : {"5e9", "0"}) {
    SCOPED_TRACE(k3);
    const Runs runs = RunBoth(
        ReferenceCase({"time.duration=1.0", "integrator.tolerance=1e-15", std::string("nonlinearity.0.k3=") + k3}),
        true);
    const double modal = RelativeError(runs.modal_recording.displacement, runs.reference);
    const double dense = RelativeError(runs.dense_recording.displacement, runs.reference);
    std::cout << "k3 = " << k3 << ": relative difference to the long double Newmark: modal " << modal
              << ", dense " << dense << "\n";
    EXPECT_LE(modal, std::string(k3) == "0" ? kLinearTolerance : kTolerance);
    EXPECT_LE(dense, kTolerance);
  }
}

TEST(NewmarkModalTest, ReferenceCaseEqualsTheDensePath) {
  // The documented case (0.1 s, Newton tolerance 1e-10 and 1e-13): both
  // paths stop Newton at the same iteration in every step, and differ by
  // their rounding (above), 2.8e-12 here: 1e-11.
  constexpr double kRelativeTolerance = 1e-11;
  for (const char* tolerance : {"1e-10", "1e-13"}) {
    SCOPED_TRACE(tolerance);
    const Runs runs = RunBoth(ReferenceCase({std::string("integrator.tolerance=") + tolerance}));
    EXPECT_LE(Difference(runs), kRelativeTolerance);
    EXPECT_EQ(runs.modal.newton_iterations, runs.dense.newton_iterations);
  }
}

// The reference beam with its cubic spring as a joint between nodes 3 and 6
// (two nonlinear dofs), as imported_model_test.cpp builds it.
CaseSpec JointCase(const std::vector<std::string>& overrides = {}) {
  std::string text = testing::ReadText(testing::ExamplePath("beam.toml"));
  const std::string grounded = "node = 6\nk3 = 5.0e9";
  EXPECT_NE(text.find(grounded), std::string::npos);
  text.replace(text.find(grounded), grounded.size(), "nodes = [3, 6]\nk3 = 5.0e12");
  CaseDocument doc = CaseDocument::Parse(text, "joint.toml");
  ApplySetArguments(doc, overrides);
  return doc.ToSpec();
}

TEST(NewmarkModalTest, RayleighDampedJointEqualsTheDensePathAndLongDouble) {
  // Two nonlinear dofs (the n_a x n_a Newton): as above, 0.1 s, Newton to
  // 1e-13; measured 1.6e-11 between the paths (x'), 5e-12 to the reference.
  constexpr double kRelativeTolerance = 5e-11;
  const Runs runs = RunBoth(JointCase({"integrator.tolerance=1e-13"}), true);
  EXPECT_EQ(runs.modal.nonlinear_dofs, 2);
  EXPECT_LE(Difference(runs), kRelativeTolerance);
  const double modal = RelativeError(runs.modal_recording.displacement, runs.reference);
  std::cout << "joint: relative difference to the long double Newmark: modal " << modal << ", dense "
            << RelativeError(runs.dense_recording.displacement, runs.reference) << "\n";
  EXPECT_LE(modal, kRelativeTolerance);
}

TEST(NewmarkModalTest, ForcesBaseExcitationAndSubstepsEqualTheDensePath) {
  // Two point forces, base excitation (the -M r a_g load), 2 substeps, and
  // the gap element that makes two nonlinear dofs; one nonlinear dof with
  // the forces alone. Rounding as above over 0.2 s: 5e-11.
  constexpr double kRelativeTolerance = 5e-11;
  const std::vector<std::string> load = {
      "time.duration=0.2", "integrator.tolerance=1e-13", "force.0.type=\"harmonic\"", "force.0.node=6",
      "force.0.amplitude=1", "force.0.frequency=30", "force.1.type=\"sweep\"", "force.1.node=2",
      "force.1.amplitude=1", "force.1.start_frequency=5", "force.1.end_frequency=50", "base.type=\"harmonic\"",
      "base.amplitude=3", "base.frequency=20", "integrator.substeps=2"};
  std::vector<std::string> gap = load;
  for (const char* set : {"nonlinearity.1.type=\"gap\"", "nonlinearity.1.node=3", "nonlinearity.1.gap=1e-5",
                          "nonlinearity.1.stiffness=1e5"})
    gap.push_back(set);
  for (const auto& overrides : {load, gap}) {
    const Runs runs = RunBoth(ReferenceCase(overrides));
    EXPECT_EQ(runs.modal_recording.displacement.rows(), 2 * 1000 / 2 + 1);
    EXPECT_LE(Difference(runs), kRelativeTolerance);
  }
}

TEST(NewmarkModalTest, LinearModelWithoutElementsEqualsTheDensePath) {
  // No nonlinear dof (n_a = 0): each mode alone. 1e-11 as for the reference case.
  constexpr double kRelativeTolerance = 1e-11;
  const CaseSpec spec = ReferenceCase();
  const BeamModel beam = BeamModel::Build(spec);
  const BeamModel model =
      BeamModel::FromMatrices(beam.DenseMass(), beam.DenseStiffness(), beam.DenseDamping(), {});
  NewmarkOptions options = ModalOptions(spec);
  const NewmarkIntegrator modal(model, options);
  options.modal = false;
  const NewmarkIntegrator dense(model, options);
  ASSERT_TRUE(modal.modal()) << modal.modal_status();
  State initial{Eigen::VectorXd::Zero(model.dofs()), Eigen::VectorXd::Zero(model.dofs())};
  initial.velocity[model.dofs() - 2] = 0.5;
  Recording a, b;
  a.dofs = b.dofs = {1, 5, 10};
  ASSERT_TRUE(modal.Run(initial, ExternalLoad{}, &a).IsSolutionUsable());
  ASSERT_TRUE(dense.Run(initial, ExternalLoad{}, &b).IsSolutionUsable());
  EXPECT_LE(RelativeError(a.displacement, b.displacement), kRelativeTolerance);
}

TEST(NewmarkModalTest, DispatchedLoopGivesThePortableBits) {
  // The AVX2 build of the loop has no FMA in its target: the same roundings
  // in the same order, so the same bits (as the dense update kernels). Its
  // record has its own loop for up to 8 sensors (one or two row blocks in
  // registers): 3, 6 (the case's) and 8 sensors, and 12 through the general loop.
  // The AVX2 loop forms the load's modal share in registers (the portable
  // one through load_next): one force, then two forces and base excitation.
  for (const std::vector<std::string>& overrides :
       {std::vector<std::string>{"force.type=\"harmonic\"", "force.node=3", "force.amplitude=1",
                                 "force.frequency=30"},
        std::vector<std::string>{
            "force.0.type=\"harmonic\"", "force.0.node=6", "force.0.amplitude=1",
            "force.0.frequency=30", "force.1.type=\"sweep\"", "force.1.node=2",
            "force.1.amplitude=1", "force.1.start_frequency=5", "force.1.end_frequency=50",
            "base.type=\"harmonic\"", "base.amplitude=3", "base.frequency=20"}}) {
    const CaseSpec spec = ReferenceCase(overrides);
    const BeamModel model = BeamModel::Build(spec);
    NewmarkOptions options = ModalOptions(spec);
    const State initial = InitialState(spec, model);
    const ExternalLoad load = BuildLoad(spec, model);
    SCOPED_TRACE(std::to_string(load.columns()) + " load columns");
    const NewmarkIntegrator dispatched(model, options);
    options.cpu_dispatch = false;
    const NewmarkIntegrator portable(model, options);
    ASSERT_TRUE(dispatched.modal() && portable.modal()) << portable.modal_status();
    std::vector<int> all;
    for (int d = 0; d < model.dofs(); ++d) all.push_back(d);
    ASSERT_EQ(all.size(), 12u);
    for (const std::vector<int>& dofs :
         {SensorDofs(spec), std::vector<int>(all.begin(), all.begin() + 3),
          std::vector<int>(all.begin(), all.begin() + 8), all}) {
      SCOPED_TRACE(std::to_string(dofs.size()) + " sensors");
      Recording a, b;
      a.dofs = b.dofs = dofs;
      a.record_velocity = b.record_velocity = true;
      a.record_acceleration = b.record_acceleration = dofs.size() == 8;
      ASSERT_TRUE(dispatched.Run(initial, load, &a).IsSolutionUsable());
      ASSERT_TRUE(portable.Run(initial, load, &b).IsSolutionUsable());
      EXPECT_TRUE(a.displacement == b.displacement);
      EXPECT_TRUE(a.velocity == b.velocity);
      EXPECT_TRUE(a.acceleration == b.acceleration);
    }
  }
}

TEST(NewmarkModalTest, DivergenceIsReportedAtTheDensePathsStep) {
  // Negative stiffness at the tip (divergence_test.cpp): the runaway passes
  // max_displacement; the cheap bound sum_i bound_i |q_i| fails first, the
  // exact test on x = phi q decides, at the same step as the dense path.
  const CaseSpec spec =
      ReferenceCase({"nonlinearity.0.type=polynomial", "nonlinearity.0.k1=-2e7", "nonlinearity.0.k3=0"});
  const BeamModel model = BeamModel::Build(spec);
  NewmarkOptions options = ModalOptions(spec);
  const NewmarkIntegrator modal(model, options);
  options.modal = false;
  const NewmarkIntegrator dense(model, options);
  ASSERT_TRUE(modal.modal());
  Recording a, b;
  a.dofs = b.dofs = SensorDofs(spec);
  const State initial = InitialState(spec, model);
  const SimulationSummary sa = modal.Run(initial, ExternalLoad{}, &a), sb = dense.Run(initial, ExternalLoad{}, &b);
  EXPECT_EQ(sa.termination, SimulationTermination::kDiverged) << sa.message;
  EXPECT_EQ(sb.termination, SimulationTermination::kDiverged) << sb.message;
  EXPECT_EQ(sa.steps_completed, sb.steps_completed);
  EXPECT_EQ(sa.failure_time_s, sb.failure_time_s);
  EXPECT_EQ(sa.message, sb.message);
  // The AVX2 loop forms its sensors a block of rows at a time: the rows
  // recorded before the divergence are all written, with the portable loop's bits.
  options.modal = true;
  options.cpu_dispatch = false;
  const NewmarkIntegrator portable(model, options);
  Recording c;
  c.dofs = a.dofs;
  const SimulationSummary sc = portable.Run(initial, ExternalLoad{}, &c);
  ASSERT_GT(sa.rows_recorded, 1);
  EXPECT_EQ(sc.rows_recorded, sa.rows_recorded);
  EXPECT_TRUE(a.displacement.topRows(sa.rows_recorded) == c.displacement.topRows(sc.rows_recorded));
}

}  // namespace
}  // namespace podid
