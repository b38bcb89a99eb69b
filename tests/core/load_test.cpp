// External forces: sampled loads against their formulas, and a forced
// single-dof oscillator against its closed-form response.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>

#include "podid/core/newmark.hpp"
#include "podid/core/simulate.hpp"
#include "reference_case.hpp"
#include "test_support.hpp"

namespace podid {
namespace {

using testing::ReferenceCase;
constexpr double kPi = std::numbers::pi;
constexpr double kRoundOff = 1e-12;  // sin() of the same argument, formed differently

TEST(LoadTest, HarmonicAndSweepFollowTheirFormulas) {
  const CaseSpec harmonic = ReferenceCase({"force.type=\"harmonic\"", "force.node=6",
                                           "force.amplitude=3", "force.frequency=40"});
  const ExternalLoad h = BuildLoad(harmonic);
  ASSERT_EQ(h.columns(), 1);
  EXPECT_EQ(h.pattern.coeff(TransverseDof(6), 0), 1.0);
  EXPECT_EQ(h.pattern.nonZeros(), 1);
  ASSERT_EQ(h.history.cols(), 501);
  for (int i = 0; i < 501; i += 37) {
    EXPECT_NEAR(h.history(0, i), 3 * std::sin(2 * kPi * 40 * i * 2e-4), kRoundOff);
  }
  const CaseSpec sweep = ReferenceCase({"force.type=\"sweep\"", "force.node=3", "force.amplitude=2",
                                        "force.start_frequency=10", "force.end_frequency=110"});
  const ExternalLoad s = BuildLoad(sweep);
  EXPECT_EQ(s.pattern.coeff(TransverseDof(3), 0), 1.0);
  // Instantaneous frequency f0 + (f1 - f0) t / T: the phase is its integral.
  for (int i = 0; i < 501; i += 41) {
    const double t = i * 2e-4;
    EXPECT_NEAR(s.history(0, i), 2 * std::sin(2 * kPi * (10 * t + 100 * t * t / (2 * 0.1))), kRoundOff);
  }
  EXPECT_EQ(BuildLoad(ReferenceCase()).columns(), 0);  // free vibration
}

TEST(LoadTest, FileForceIsInterpolatedLinearly) {
  const std::string dir = ::testing::TempDir();
  {
    std::ofstream f(dir + "/force.csv");
    f << "t,F\n0,0\n0.05,10\n0.1,0\n";
  }
  {
    std::ofstream f(dir + "/case.toml");
    std::ifstream in(testing::ExamplePath("beam.toml"));
    f << in.rdbuf() << "\n[force]\ntype = \"file\"\nnode = 6\nfile = \"force.csv\"\ncolumn = \"F\"\n";
  }
  const CaseSpec spec = CaseDocument::Load(dir + "/case.toml").ToSpec();
  const ExternalLoad load = BuildLoad(spec);
  ASSERT_EQ(load.history.cols(), 501);
  EXPECT_NEAR(load.history(0, 0), 0.0, kRoundOff);
  EXPECT_NEAR(load.history(0, 125), 5.0, kRoundOff);  // t = 0.025: half-way up
  EXPECT_NEAR(load.history(0, 250), 10.0, kRoundOff);
  EXPECT_NEAR(load.history(0, 375), 5.0, kRoundOff);
}

TEST(LoadTest, ForcedSdofMatchesClosedForm) {
  // Undamped m x'' + k x = F sin(w t) from rest:
  //   x(t) = F / (k - m w^2) (sin(w t) - (w / wn) sin(wn t)).
  // Newmark's error at omega dt = 0.006 is O((omega dt)^2) ~ 4e-5 of the
  // amplitude over these few periods.
  constexpr double kRelativeTolerance = 1e-4;
  const double m = 2.0, k = m * std::pow(2 * kPi * 8.0, 2), w = 2 * kPi * 5.0, force = 3.0;
  const BeamModel model = BeamModel::FromMatrices(Eigen::MatrixXd::Constant(1, 1, m),
                                                  Eigen::MatrixXd::Constant(1, 1, k),
                                                  Eigen::MatrixXd::Zero(1, 1), {});
  NewmarkOptions options;
  options.step_s = 1e-4;
  options.steps = 5000;
  const NewmarkIntegrator integrator(model, options);
  Eigen::VectorXd values_N(options.steps + 1);
  for (int i = 0; i <= options.steps; ++i) values_N[i] = force * std::sin(w * i * options.step_s);
  const ExternalLoad load = ExternalLoad::PointForce(1, 0, values_N);
  Recording recording;
  recording.dofs = {0};
  const SimulationSummary summary =
      integrator.Run(State{Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1)}, load, &recording);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.message;
  const double wn = std::sqrt(k / m), amplitude = force / (k - m * w * w);
  Eigen::VectorXd exact(options.steps + 1);
  for (int i = 0; i <= options.steps; ++i) {
    const double t = i * options.step_s;
    exact[i] = amplitude * (std::sin(w * t) - (w / wn) * std::sin(wn * t));
  }
  EXPECT_LE(testing::RelativeError(recording.displacement.col(0), exact), kRelativeTolerance);
}

}  // namespace
}  // namespace podid
