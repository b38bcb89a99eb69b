// ObjectiveOptions::remove_mean = false (--keep-mean): the records' means are
// compared, and with one channel dS + r dV is the output error (objective.hpp).
#include <gtest/gtest.h>

#include <cmath>

#include "podid/core/case_file.hpp"
#include "podid/core/simulate.hpp"
#include "podid/ident/objective.hpp"
#include "test_support.hpp"

namespace podid::ident {
namespace {

// The one-dof Duffing oscillator released from 0.1 m (examples/duffing/),
// "measured" at k3 = 1e5 N/m^3 and shifted by a constant offset.
constexpr double kOffset_m = 0.01;

struct Fixture {
  CaseDocument document = CaseDocument::Load(podid::testing::ExamplePath("duffing/duffing.toml"));
  TimeSeries measured;
  Fixture() {
    SimulateOptions options;
    options.add_noise = false;
    measured = Simulate(document.ToSpec(), options).sensors;
    measured.values.array() += kOffset_m;
  }
  ObjectiveFunction Objective(bool remove_mean) const {
    ObjectiveOptions options;
    options.SetWeights(ObjectiveWeights::Parse("S,V"));
    options.remove_mean = remove_mean;
    return ObjectiveFunction(document, measured, options);
  }
};

TEST(KeepMeanTest, OneChannelSAndVAreTheOutputErrorWithTheMean) {
  const Fixture f;
  const ObjectiveFunction objective = f.Objective(false);
  for (const double k3_scaled : {5.0, 10.0, 20.0}) {  // x 1e4 N/m^3 (the case's scale)
    const Eigen::VectorXd theta = Eigen::VectorXd::Constant(1, k3_scaled);
    const Evaluation e = objective.Evaluate(theta);
    ASSERT_FALSE(e.failed()) << e.failure();
    // The output error from the two records directly, not through the POD.
    const Eigen::VectorXd sim = objective.SimulateAt(theta).sensors.values.col(0);
    const Eigen::VectorXd meas = f.measured.values.col(0);
    const double error = (sim - meas).squaredNorm() / meas.squaredNorm();
    const double r = sim.norm() / meas.norm();
    // ||a - b||^2 / ||b||^2 = (r - 1)^2 + r ||a/|a| - b/|b|||^2 exactly; the
    // two sides differ by the SVD's and the norms' round-off, relative 1e-10
    // of the error (>= 1e-4 here) at most.
    constexpr double kRoundOffRelative = 1e-10;
    EXPECT_NEAR(e.terms.s + r * e.terms.v, error, kRoundOffRelative * error) << "k3 " << k3_scaled;
  }
}

TEST(KeepMeanTest, AnOffsetIsSeenOnlyWithTheMeanKept) {
  const Fixture f;
  const Eigen::VectorXd truth = Eigen::VectorXd::Constant(1, 10.0);  // k3 = 1e5
  // Mean removed (eq. 1): the offset vanishes with the mean, the true k3 fits
  // to round-off (the mean of a 20001-sample record, ~1e-16 relative).
  constexpr double kRoundOff = 1e-20;
  const Evaluation removed = f.Objective(true).Evaluate(truth);
  ASSERT_FALSE(removed.failed()) << removed.failure();
  EXPECT_LT(removed.values[0], kRoundOff);
  // Kept: the offset is a residual of ||offset||^2 / ||x_meas||^2 (output
  // error, previous test) - 1e-2 m against a response of ~1e-2 m rms: O(1).
  const Evaluation kept = f.Objective(false).Evaluate(truth);
  ASSERT_FALSE(kept.failed()) << kept.failure();
  const Eigen::VectorXd meas = f.measured.values.col(0);
  const double expected = kOffset_m * kOffset_m * static_cast<double>(meas.size()) / meas.squaredNorm();
  const Eigen::VectorXd sim = f.Objective(false).SimulateAt(truth).sensors.values.col(0);
  const double r = sim.norm() / meas.norm();
  constexpr double kRoundOffRelative = 1e-10;  // as above
  EXPECT_NEAR(kept.terms.s + r * kept.terms.v, expected, kRoundOffRelative * expected);
}

}  // namespace
}  // namespace podid::ident
