// The beam builder against analytic references: end conditions (beta_n L of
// each beam), a cantilever with a tip mass (its frequency equation, solved
// here by bisection), a two-segment beam against a uniform mesh, point masses
// and springs, and the case-file keys that describe them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <string>

#include "podid/core/beam_model.hpp"
#include "podid/core/case_file.hpp"
#include "podid/core/simulate.hpp"
#include "reference_case.hpp"
#include "test_support.hpp"

namespace podid {
namespace {

// A steel beam (the reference's section and material), L = 1 m.
constexpr double kLength = 1.0, kE = 2.05e11, kRho = 7800.0, kArea = 0.196e-3;
const double kI = kArea * kArea / 12.0;

std::string BeamCase(const std::string& beam_extra, int elements = 80,
                     const std::string& rest = "") {
  return "[beam]\nlength = 1.0\nelements = " + std::to_string(elements) +
         "\nyoungs_modulus = 2.05e11\ndensity = 7800.0\narea = 0.196e-3\n" + beam_extra +
         "\n" + rest + "\n[time]\nduration = 0.01\nstep = 1e-4\n";
}

CaseSpec Spec(const std::string& text) { return CaseDocument::Parse(text, "case.toml").ToSpec(); }

/// beta L of a mode from its FE frequency: omega = (beta L)^2 sqrt(EI / (rho A L^4)).
double BetaL(double frequency_Hz) {
  const double omega = 2 * std::numbers::pi * frequency_Hz;
  return std::sqrt(omega / std::sqrt(kE * kI / (kRho * kArea * std::pow(kLength, 4))));
}

// 80 Hermite elements: the first two flexible modes' beta L converge as h^4
// (2.3e-7 for the second mode; 3.7e-6 with 40 elements); the analytic values
// are rounded to 1e-6.
constexpr double kBetaLTolerance = 1e-6;

struct EndCase {
  const char* left;
  const char* right;
  int rigid_modes;
  double beta_l[2];
};

TEST(BeamEnds, EachEndConditionMatchesItsAnalyticBetaL) {
  const double pi = std::numbers::pi;
  const EndCase cases[] = {
      {"clamped", "free", 0, {1.875104, 4.694091}},
      {"pinned", "pinned", 0, {pi, 2 * pi}},
      {"clamped", "pinned", 0, {3.926602, 7.068583}},
      {"clamped", "clamped", 0, {4.730041, 7.853205}},
      {"free", "free", 2, {4.730041, 7.853205}},
      {"pinned", "free", 1, {3.926602, 7.068583}},
  };
  for (const EndCase& c : cases) {
    SCOPED_TRACE(std::string(c.left) + "-" + c.right);
    const CaseSpec spec =
        Spec(BeamCase("left = \"" + std::string(c.left) + "\"\nright = \"" + c.right + "\""));
    const BeamModel model = BeamModel::Build(spec);
    const int held = (std::string(c.left) == "clamped" ? 2 : std::string(c.left) == "pinned" ? 1 : 0) +
                     (std::string(c.right) == "clamped" ? 2 : std::string(c.right) == "pinned" ? 1 : 0);
    EXPECT_EQ(model.dofs(), 2 * 81 - held);
    EXPECT_EQ(spec.dofs(), model.dofs());
    const ModalAnalysis modes = model.Modes();
    // Rigid-body modes: zero up to round-off (sqrt(eps) omega_max: far below
    // the first flexible mode).
    for (int k = 0; k < c.rigid_modes; ++k)
      EXPECT_LT(modes.frequencies_Hz[k], 1e-4 * modes.frequencies_Hz[c.rigid_modes]);
    EXPECT_NEAR(BetaL(modes.frequencies_Hz[c.rigid_modes]), c.beta_l[0], kBetaLTolerance);
    EXPECT_NEAR(BetaL(modes.frequencies_Hz[c.rigid_modes + 1]), c.beta_l[1], kBetaLTolerance);
  }
}

TEST(BeamEnds, DofNumberingKeepsTheClampedDefault) {
  BeamSpec beam;
  beam.elements = 6;
  for (int node = 1; node <= 6; ++node) {
    EXPECT_EQ(BeamDof(beam, node, SensorDof::kW), TransverseDof(node));
    EXPECT_EQ(BeamDof(beam, node, SensorDof::kTheta), RotationDof(node));
  }
  EXPECT_EQ(BeamDof(beam, 0, SensorDof::kW), -1);
  beam.left = BeamEnd::kPinned;
  beam.right = BeamEnd::kPinned;
  EXPECT_EQ(BeamDof(beam, 0, SensorDof::kW), -1);
  EXPECT_EQ(BeamDof(beam, 0, SensorDof::kTheta), 0);
  EXPECT_EQ(BeamDof(beam, 1, SensorDof::kW), 1);
  EXPECT_EQ(BeamDof(beam, 6, SensorDof::kW), -1);
  EXPECT_EQ(BeamDof(beam, 6, SensorDof::kTheta), 11);
  EXPECT_EQ(BeamDofCount(beam), 12);
}

/// The root of f in [a, b] (f(a) f(b) < 0) by bisection to machine precision.
double Bisect(const std::function<double(double)>& f, double a, double b) {
  double fa = f(a);
  for (int i = 0; i < 200 && b - a > 1e-15 * b; ++i) {
    const double m = 0.5 * (a + b), fm = f(m);
    if ((fm < 0) == (fa < 0)) {
      a = m;
      fa = fm;
    } else {
      b = m;
    }
  }
  return 0.5 * (a + b);
}

TEST(BeamMasses, CantileverWithTipMassMatchesItsFrequencyEquation) {
  // Tip mass ratio mu = m / (rho A L): 1 + cos(bL) cosh(bL) + mu bL (cos(bL)
  // sinh(bL) - sin(bL) cosh(bL)) = 0 (Euler-Bernoulli, no rotary inertia).
  const double mu = 0.5;
  const double tip_mass = mu * kRho * kArea * kLength;
  const CaseSpec spec = Spec(BeamCase("", 80, "[[mass]]\nnode = 80\nmass = " + std::to_string(tip_mass)));
  ASSERT_EQ(spec.masses.size(), 1u);
  const ModalAnalysis modes = BeamModel::Build(spec).Modes();
  auto equation = [mu](double x) {
    return 1 + std::cos(x) * std::cosh(x) + mu * x * (std::cos(x) * std::sinh(x) - std::sin(x) * std::cosh(x));
  };
  const double b1 = Bisect(equation, 0.5, 2.5), b2 = Bisect(equation, 3.0, 6.0);
  EXPECT_NEAR(b1, 1.4200, 1e-3);  // sanity: tabulated value for mu = 0.5 (Blevins)
  EXPECT_NEAR(BetaL(modes.frequencies_Hz[0]), b1, kBetaLTolerance);
  EXPECT_NEAR(BetaL(modes.frequencies_Hz[1]), b2, kBetaLTolerance);
}

TEST(BeamSegments, TwoSegmentsMatchAUniformMeshOfTheSameBeam) {
  // 0.25 m in 5 elements + 0.75 m in 30 elements of the same section against
  // 80 uniform elements: the coarse segment's h = 0.05 m leaves frequency
  // errors of order (beta h)^4 / 1000: 2e-8, 2e-6, 1.7e-5 for modes 1-3.
  const double kRelativeTolerance[] = {1e-7, 5e-6, 3e-5};
  const std::string segments =
      "[[beam.segment]]\nlength = 0.25\nelements = 5\n"
      "[[beam.segment]]\nlength = 0.75\nelements = 30\n";
  const std::string text =
      "[beam]\nyoungs_modulus = 2.05e11\ndensity = 7800.0\narea = 0.196e-3\n" + segments +
      "[time]\nduration = 0.01\nstep = 1e-4\n";
  const CaseSpec spec = Spec(text);
  EXPECT_EQ(spec.beam.elements, 35);
  EXPECT_DOUBLE_EQ(spec.beam.length_m, 1.0);
  const ModalAnalysis two = BeamModel::Build(spec).Modes();
  const ModalAnalysis uniform = BeamModel::Build(Spec(BeamCase(""))).Modes();
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(two.frequencies_Hz[k] / uniform.frequencies_Hz[k], 1.0, kRelativeTolerance[k]) << k;
  }
}

TEST(BeamSegments, SegmentsOfOneMaterialEqualTheUniformBeamExactly) {
  // Equal element lengths: the same element matrices, assembled in the same order.
  char moment[64];
  std::snprintf(moment, sizeof(moment), "%.17g", kI);
  const std::string text =
      "[beam]\nyoungs_modulus = 2.05e11\ndensity = 7800.0\n"
      "[[beam.segment]]\nlength = 0.5\nelements = 40\narea = 0.196e-3\n"
      "[[beam.segment]]\nlength = 0.5\nelements = 40\narea = 0.196e-3\n"
      "second_moment = " + std::string(moment) + "\n[time]\nduration = 0.01\nstep = 1e-4\n";
  const BeamModel two = BeamModel::Build(Spec(text));
  const BeamModel one = BeamModel::Build(Spec(BeamCase("")));
  EXPECT_TRUE(testing::ExpectMatricesNear(two.DenseMass(), one.DenseMass(), 0.0));
  EXPECT_TRUE(testing::ExpectMatricesNear(two.DenseStiffness(), one.DenseStiffness(), 0.0));
}

TEST(BeamSegments, AStiffSegmentRaisesTheFrequencies) {
  // A clamped-free beam whose root half is 10x stiffer: between the uniform
  // beam and the beam 10x stiffer everywhere.
  const std::string text =
      "[beam]\ndensity = 7800.0\narea = 0.196e-3\n"
      "[[beam.segment]]\nlength = 0.5\nelements = 10\nyoungs_modulus = 2.05e12\n"
      "[[beam.segment]]\nlength = 0.5\nelements = 10\nyoungs_modulus = 2.05e11\n"
      "[time]\nduration = 0.01\nstep = 1e-4\n";
  const double f = BeamModel::Build(Spec(text)).Modes().frequencies_Hz[0];
  const double f_uniform = BeamModel::Build(Spec(BeamCase("", 20))).Modes().frequencies_Hz[0];
  EXPECT_GT(f, f_uniform);
  EXPECT_LT(f, std::sqrt(10.0) * f_uniform);
}

TEST(BeamSprings, AStiffGroundedSpringPinsTheTip) {
  // A spring far stiffer than the beam at the free end: the clamped-pinned
  // beam's beta_1 L = 3.926602 within the spring's compliance (k = 1e6 x 3 EI / L^3).
  constexpr double kTolerance = 1e-4;
  const double k = 1e6 * 3 * kE * kI;
  const CaseSpec spec = Spec(BeamCase("", 80, "[[spring]]\nnode = 80\ndof = \"w\"\nstiffness = " + std::to_string(k)));
  EXPECT_NEAR(BetaL(BeamModel::Build(spec).Modes().frequencies_Hz[0]), 3.926602, kTolerance);
}

TEST(BeamSprings, SpringDamperAddsToRayleighDamping) {
  const CaseSpec spec =
      Spec(BeamCase("", 6, "[damping]\ntype = \"rayleigh\"\nalpha = 2.0\n[[spring]]\nnode = 6\nstiffness = 10.0\ndamping = 3.0"));
  const BeamModel model = BeamModel::Build(spec);
  const int w6 = TransverseDof(6);
  EXPECT_DOUBLE_EQ(model.damping().coeff(w6, w6), 2.0 * model.mass().coeff(w6, w6) + 3.0);
  EXPECT_DOUBLE_EQ(model.damping().coeff(0, 0), 2.0 * model.mass().coeff(0, 0));
  const BeamModel bare = BeamModel::Build(Spec(BeamCase("", 6)));
  EXPECT_DOUBLE_EQ(model.stiffness().coeff(w6, w6), bare.stiffness().coeff(w6, w6) + 10.0);
}

TEST(BeamMasses, PointMassAndInertiaEnterTheMassMatrix) {
  const CaseSpec spec = Spec(BeamCase("left = \"pinned\"\nright = \"pinned\"", 6,
                                      "[[mass]]\nnode = 3\nmass = 0.5\ninertia = 1e-3"));
  const BeamModel model = BeamModel::Build(spec);
  const BeamModel bare = BeamModel::Build(Spec(BeamCase("left = \"pinned\"\nright = \"pinned\"", 6)));
  const int w = BeamDof(spec.beam, 3, SensorDof::kW), theta = BeamDof(spec.beam, 3, SensorDof::kTheta);
  Eigen::MatrixXd diff = model.DenseMass() - bare.DenseMass();
  EXPECT_DOUBLE_EQ(diff(w, w), 0.5);
  EXPECT_DOUBLE_EQ(diff(theta, theta), 1e-3);
  diff(w, w) = diff(theta, theta) = 0;
  EXPECT_EQ(diff.cwiseAbs().maxCoeff(), 0.0);
}

TEST(BeamCaseFile, PinnedBeamWithMassSimulatesAndMeasuresAcceleration) {
  const CaseSpec spec = Spec(BeamCase(
      "left = \"pinned\"\nright = \"pinned\"", 8,
      "[[mass]]\nnode = 4\nmass = 0.2\n[[nonlinearity]]\ntype = \"cubic\"\nnode = 4\nk3 = 1e9\n"
      "[initial]\nstatic_force = 50.0\nnode = 4\n"
      "[sensors]\nnodes = [2, 4, 6]\nnames = [\"a2\", \"a4\", \"a6\"]\nquantity = \"acceleration\""));
  EXPECT_EQ(spec.sensors.ChannelNames(), (std::vector<std::string>{"a2", "a4", "a6"}));
  SimulationResult result = Simulate(spec);
  ASSERT_TRUE(result.summary.IsSolutionUsable()) << result.summary.message;
  // Released from a static deflection at rest: the initial acceleration is
  // M^-1 (F_static) (the static force removed), nonzero and upward (negative w).
  EXPECT_LT(result.sensors.values(0, 1), 0.0);
  // Average-acceleration Newmark satisfies x_{n+1} - 2 x_n + x_{n-1} =
  // dt^2 (a_{n+1} + 2 a_n + a_{n-1}) / 4 exactly: the recorded accelerations
  // belong to the recorded displacements, to round-off (1e-9 of the scale).
  constexpr double kRelativeTolerance = 1e-9;
  CaseSpec displacement_spec = spec;
  displacement_spec.sensors.quantity = SensorQuantity::kDisplacement;
  const SimulationResult x = Simulate(displacement_spec);
  const Eigen::MatrixXd& xs = x.sensors.values;
  const Eigen::MatrixXd& as = result.sensors.values;
  const double dt = spec.time.step_s;
  double worst = 0.0;
  for (int i = 1; i + 1 < xs.rows(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const double lhs = 4 * (xs(i + 1, c) - 2 * xs(i, c) + xs(i - 1, c)) / (dt * dt);
      worst = std::max(worst, std::abs(lhs - (as(i + 1, c) + 2 * as(i, c) + as(i - 1, c))));
    }
  }
  EXPECT_LT(worst, kRelativeTolerance * as.cwiseAbs().maxCoeff());
  // Velocity likewise: v_{n+1} - v_n = dt (a_n + a_{n+1}) / 2.
  displacement_spec.sensors.quantity = SensorQuantity::kVelocity;
  const Eigen::MatrixXd vs = Simulate(displacement_spec).sensors.values;
  worst = 0.0;
  for (int i = 0; i + 1 < vs.rows(); ++i) {
    worst = std::max(worst, std::abs(vs(i + 1, 1) - vs(i, 1) - 0.5 * dt * (as(i, 1) + as(i + 1, 1))));
  }
  EXPECT_LT(worst, kRelativeTolerance * vs.cwiseAbs().maxCoeff());
}

TEST(BeamCaseFile, Rejections) {
  PODID_EXPECT_THROW_WITH(Spec(BeamCase("left = \"hinged\"")), std::invalid_argument,
                          "case.toml:7: beam.left: expected one of \"clamped\", \"pinned\", \"free\", got \"hinged\"");
  PODID_EXPECT_THROW_WITH(
      BeamModel::Build(Spec(BeamCase("right = \"pinned\"", 6, "[[nonlinearity]]\ntype = \"cubic\"\nnode = 6\nk3 = 1"))),
      std::invalid_argument, "nonlinearity.0.node: expected a node whose w is free (the right end is pinned), got node 6");
  // Beams of 6 elements: the keys added to [beam], the tables after it, a part of the message.
  struct Rejection {
    const char* beam_extra;
    const char* rest;
    const char* needle;
  };
  const Rejection six_elements[] = {
      {"", "[[nonlinearity]]\ntype = \"cubic\"\nnode = 0\nk3 = 1",
       "nonlinearity.0.node: expected an integer in [1, 6], got 0"},
      {"", "[sensors]\nnodes = [6]\ndofs = [3]",
       "sensors.dofs: expected either sensors.nodes or sensors.dofs, got both"},
      {"right = \"pinned\"", "[sensors]\nnodes = [6]",
       "sensors.nodes.0: expected a node whose w is free (not held by the end condition), got 6"},
      {"", "[sensors]\nnames = [\"a\"]",
       "sensors.names: expected an array of 6 strings, got an array of 1"},
      {"", "[[mass]]\nnode = 7\nmass = 1", "mass.0.node: expected an integer in [0, 6], got 7"},
      {"", "[[mass]]\nnode = 2\nmass = -1", "mass.0.mass: expected a number >= 0 (kg), got -1"},
      {"", "[[spring]]\nnode = 0\nstiffness = 1",
       "spring.0.node: expected a node whose spring dof is free (not held by the end condition), "
       "got 0"},
  };
  for (const Rejection& r : six_elements) {
    SCOPED_TRACE(std::string(r.beam_extra) + " | " + r.rest);
    PODID_EXPECT_THROW_WITH(Spec(BeamCase(r.beam_extra, 6, r.rest)), std::invalid_argument,
                            r.needle);
  }
  PODID_EXPECT_THROW_WITH(Spec("[beam]\nyoungs_modulus = 2e11\ndensity = 7800\narea = 1e-4\nlength = 1\n"
                               "[[beam.segment]]\nlength = 1\nelements = 2\n[time]\nduration = 1\nstep = 0.1\n"),
                          std::invalid_argument,
                          "beam.length: expected no beam.length with [[beam.segment]] (each segment has its own), got 1");
  PODID_EXPECT_THROW_WITH(Spec("[beam]\ndensity = 7800\narea = 1e-4\n"
                               "[[beam.segment]]\nlength = 1\nelements = 2\n[time]\nduration = 1\nstep = 0.1\n"),
                          std::invalid_argument,
                          "beam.segment.0.youngs_modulus: expected a modulus here or in [beam] (Pa), got neither");
  // A free-free beam has no static equilibrium under a force.
  PODID_EXPECT_THROW_WITH(Simulate(Spec(BeamCase("left = \"free\"", 6, "[initial]\nstatic_force = 1.0"))),
                          std::invalid_argument, "initial static force: expected a model whose stiffness holds it");
}

TEST(BeamCaseFile, NewValuesAreIdentificationKeys) {
  for (const char* key : {"mass.0.mass", "mass.0.inertia", "spring.0.stiffness", "spring.0.damping",
                          "beam.segment.1.youngs_modulus", "beam.segment.0.density", "initial.static_force"}) {
    EXPECT_TRUE(CaseDocument::IsNumericKey(key)) << key;
  }
  CaseDocument doc = CaseDocument::Parse(BeamCase("", 6, "[[mass]]\nnode = 3\nmass = 0.5"), "case.toml");
  doc.SetNumber("mass.0.mass", 0.75);
  EXPECT_EQ(doc.ToSpec().masses[0].mass_kg, 0.75);
}

}  // namespace
}  // namespace podid

namespace podid {
namespace {

TEST(FineMesh, StaticReleaseSucceedsAt30And300Elements) {
  // Hermite cubics are exact at the nodes for point loads on a uniform beam,
  // so the static tip deflection (with the cubic spring) is the same for
  // every mesh, to the round-off of a solve with cond(K) ~ 1e11 at 300
  // elements (measured 1.5e-8).
  constexpr double kRelativeTolerance = 1e-7;
  const CaseSpec coarse = testing::ReferenceCase({"time.duration=0.004"});
  const double tip = Simulate(coarse).sensors.values(0, 5);
  // Modified (dense at 60 dofs, sparse at 600: kDenseDofLimit) and full
  // Newton solve the same equations: they agree to the Newton tolerance
  // times the conditioning of a step; at 600 dofs full Newton stops at its
  // round-off floor (backward error 2e-13, cond(S) ~ 1e7): measured 1.8e-6.
  constexpr double kIntegratorTolerance = 1e-5;
  for (const int elements : {30, 300}) {
    SCOPED_TRACE(elements);
    Eigen::MatrixXd histories[2];
    int which = 0;
    for (const char* integrator : {"integrator.type=modified", "integrator.type=newmark"}) {
      SCOPED_TRACE(integrator);
      // The cubic spring stays at the tip (node `elements`).
      // A harmonic force on a linear dof exercises the load path too.
      CaseSpec spec = testing::ReferenceCase({"beam.elements=" + std::to_string(elements),
                                              "nonlinearity.0.node=" + std::to_string(elements),
                                              integrator, "time.duration=0.004", "force.type=harmonic",
                                              "force.node=" + std::to_string(elements / 3),
                                              "force.amplitude=5", "force.frequency=200"});
      const int n = spec.beam.elements;
      spec.sensors.nodes = {n / 6, 2 * n / 6, 3 * n / 6, 4 * n / 6, 5 * n / 6, n};
      const SimulationResult r = Simulate(spec);
      EXPECT_TRUE(r.static_solve.converged) << r.static_solve.message;
      ASSERT_TRUE(r.summary.IsSolutionUsable()) << r.summary.message;
      EXPECT_NEAR(r.sensors.values(0, 5) / tip, 1.0, kRelativeTolerance);
      histories[which++] = r.sensors.values;
    }
    EXPECT_TRUE(testing::ExpectMatricesNear(histories[0], histories[1],
                                            kIntegratorTolerance * histories[1].cwiseAbs().maxCoeff()));
  }
}

}  // namespace
}  // namespace podid
