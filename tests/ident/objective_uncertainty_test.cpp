// ObjectiveUncertainty (objective_uncertainty.hpp) against the sandwich
// formula computed here from public pieces, on an objective whose [data]
// conditioning filters the records: the features must be those Evaluate
// compares (the simulated sensors conditioned once, as SimulateAt returns
// them), not conditioned a second time.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "podid/core/case_file.hpp"
#include "podid/core/noise.hpp"
#include "podid/core/simulate.hpp"
#include "podid/ident/objective_uncertainty.hpp"
#include "podid/pod/pod.hpp"
#include "test_support.hpp"

namespace podid::ident {
namespace {

using testing::ExamplePath;

TEST(ObjectiveUncertainty, FeaturesOfAFilteredObjectiveAreConditionedOnce) {
  // The reference beam (first mode near 35 Hz) measured through a 4th-order
  // low-pass at 40 Hz: a second pass of the filter takes another 25 % off the
  // mode's amplitude and doubles the filter's slope in dsigma/dknl.
  CaseDocument document = CaseDocument::Load(ExamplePath("beam.toml"));
  document.Set("data.filter", "\"lowpass\"");
  document.Set("data.cutoff", "40.0");
  SimulateOptions clean;
  clean.add_noise = false;
  SimulationResult truth = Simulate(document.ToSpec(), clean);
  ASSERT_TRUE(truth.summary.IsSolutionUsable());
  TimeSeries measured = truth.sensors;
  AddNoise(measured, 0.01, 7);
  // dS alone, one mode: the features are the single number sigma_1 / sigma_1,meas.
  ObjectiveOptions options;
  options.weightings = {{"S", ObjectiveWeights::Parse("S")}};
  const ObjectiveFunction objective(document, measured, options);
  const Eigen::VectorXd knl = Eigen::VectorXd::Constant(1, 50.0);

  // The reference: J by the same central difference, the noise term by an
  // independent Monte Carlo of white noise at the residual's level per
  // channel on the fitted (once-conditioned) response; se = std(delta) / |J|
  // (the spread about the draws' mean: noise also biases sigma upwards).
  constexpr int kDraws = 4000;
  UncertaintyOptions uncertainty;
  uncertainty.noise_draws = kDraws;
  const double h = uncertainty.relative_step * (objective.parameters()[0].upper - objective.parameters()[0].lower);
  PodSolver pod(objective.ResponsePodOptions());
  const double sigma_measured = objective.measured_pod().singular_values[0];
  const auto feature = [&](const TimeSeries& response) {
    return pod.Compute(response).singular_values[0] / sigma_measured;
  };
  const auto at = [&](double value) {
    const SimulationResult r = objective.SimulateAt(Eigen::VectorXd::Constant(1, value));
    EXPECT_TRUE(r.summary.IsSolutionUsable());
    return r.sensors;
  };
  const double jacobian = (feature(at(knl[0] + h)) - feature(at(knl[0] - h))) / (2.0 * h);
  const TimeSeries fit = at(knl[0]);
  const double fit_feature = feature(fit);
  const Eigen::MatrixXd& y = fit.values;
  const Eigen::RowVectorXd noise_std =
      ((objective.measured().values - y).colwise().squaredNorm() / static_cast<double>(y.rows())).cwiseSqrt();
  std::mt19937_64 engine(12345);
  std::normal_distribution<double> normal(0.0, 1.0);
  TimeSeries noisy = fit;
  double sum = 0.0, sum_squares = 0.0;
  for (int d = 0; d < kDraws; ++d) {
    for (Eigen::Index n = 0; n < y.rows(); ++n)
      for (Eigen::Index c = 0; c < y.cols(); ++c) noisy.values(n, c) = y(n, c) + noise_std[c] * normal(engine);
    const double delta = feature(noisy) - fit_feature;
    sum += delta;
    sum_squares += delta * delta;
  }
  const double variance = (sum_squares - sum * sum / kDraws) / (kDraws - 1);
  const double reference_se = std::sqrt(variance) / std::abs(jacobian);

  const ParameterUncertainty u = ObjectiveUncertainty(objective, knl, 0, uncertainty, 1);
  ASSERT_TRUE(u.usable) << u.message;
  // Two Monte Carlo estimates of a standard deviation from 4000 draws each: each within
  // 1/sqrt(2 D) = 1.1 % (one standard deviation), their ratio within 1.6 %;
  // 8 % is five of those. Here 0.996; conditioning twice gave 3.56.
  constexpr double kMonteCarloTolerance = 0.08;
  EXPECT_NEAR(u.standard_error[0] / reference_se, 1.0, kMonteCarloTolerance)
      << "standard error " << u.standard_error[0] << " against " << reference_se;
}

}  // namespace
}  // namespace podid::ident
