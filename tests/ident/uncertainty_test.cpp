// The sandwich covariance against references: the analytic least-squares
// covariance of a linear model, and the coverage of its intervals over Monte
// Carlo copies of a nonlinear fit.
#include "podid/ident/uncertainty.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <iostream>
#include <random>

namespace podid::ident {
namespace {

Eigen::VectorXd Gaussian(Eigen::Index n, double std, std::mt19937_64* rng) {
  std::normal_distribution<double> normal(0.0, std);
  Eigen::VectorXd v(n);
  for (Eigen::Index i = 0; i < n; ++i) v[i] = normal(*rng);
  return v;
}

TEST(SandwichUncertaintyTest, LinearModelGivesTheLeastSquaresCovariance) {
  // f(theta) = A theta with white noise of std sigma on f_m: the sandwich is
  // sigma^2 (A^T A)^-1 exactly; only the Monte Carlo estimate of
  // J^T Sigma J differs, by ~sqrt(2 / D) = 2.2 % per variance at D = 4000.
  constexpr double kMonteCarloTolerance = 0.10;  // 4.5 standard deviations
  constexpr double kSigma = 0.1;
  std::mt19937_64 rng(7);
  const Eigen::Index m = 200;
  Eigen::MatrixXd a(m, 2);
  for (Eigen::Index i = 0; i < m; ++i) a.row(i) << 1.0, i / 100.0;
  const FeatureFunction f = [&a](const Eigen::VectorXd& theta, Eigen::VectorXd* out, std::string*) {
    *out = a * theta;
    return true;
  };
  const FeatureNoiseDraw noise = [&rng](int, Eigen::VectorXd* delta, std::string*) {
    *delta = Gaussian(200, kSigma, &rng);
    return true;
  };
  UncertaintyOptions options;
  options.noise_draws = 4000;
  const Eigen::VectorXd theta = Eigen::Vector2d(1.0, 2.0);
  const ParameterUncertainty u = SandwichUncertainty(f, noise, theta, Eigen::Vector2d(-10, -10),
                                                     Eigen::Vector2d(10, 10), options);
  ASSERT_TRUE(u.usable) << u.message;
  const Eigen::MatrixXd exact = kSigma * kSigma * (a.transpose() * a).inverse();
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(u.covariance(i, i) / exact(i, i), 1.0, kMonteCarloTolerance) << i;
  }
  const double exact_correlation = exact(0, 1) / std::sqrt(exact(0, 0) * exact(1, 1));
  EXPECT_NEAR(u.correlation(0, 1), exact_correlation, kMonteCarloTolerance);
  EXPECT_DOUBLE_EQ(u.correlation(0, 0), 1.0);
  // 95 % interval: t_{0.975, 3999} = 1.9606 standard errors each side.
  EXPECT_NEAR((u.upper[1] - theta[1]) / u.standard_error[1], 1.9606, 1e-3);
}

// y(t) = a exp(-b t) fitted by Gauss-Newton to noisy samples.
Eigen::VectorXd Decay(const Eigen::VectorXd& t, const Eigen::VectorXd& theta) {
  return theta[0] * (-theta[1] * t.array()).exp();
}

TEST(SandwichUncertaintyTest, IntervalsCoverTheTruthInNinetyFivePercentOfCopies) {
  // 200 noisy copies; the 95 % intervals must hold the truth in 90-99 % of
  // them (the binomial standard deviation of the rate is 1.5 %).
  constexpr int kCopies = 200;
  constexpr double kMinCoverage = 0.90, kMaxCoverage = 0.99;
  constexpr double kSigma = 0.02;
  const Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(100, 0.0, 3.0);
  const Eigen::Vector2d truth(1.0, 1.5);
  std::mt19937_64 rng(11);
  int covered_a = 0, covered_b = 0;
  for (int copy = 0; copy < kCopies; ++copy) {
    const Eigen::VectorXd measured = Decay(t, truth) + Gaussian(t.size(), kSigma, &rng);
    Eigen::VectorXd theta = Eigen::Vector2d(0.8, 1.0);
    for (int it = 0; it < 30; ++it) {  // Gauss-Newton
      const Eigen::VectorXd e = (-theta[1] * t.array()).exp();
      Eigen::MatrixXd j(t.size(), 2);
      j.col(0) = e;
      j.col(1) = -theta[0] * t.array() * e.array();
      theta += j.colPivHouseholderQr().solve(measured - Decay(t, theta));
    }
    // The noise level from the fit's residual (as podid estimates it from data).
    const double sigma_hat = std::sqrt((measured - Decay(t, theta)).squaredNorm() / (t.size() - 2));
    const Eigen::VectorXd fitted = Decay(t, theta);
    const FeatureFunction f = [&t](const Eigen::VectorXd& th, Eigen::VectorXd* out, std::string*) {
      *out = Decay(t, th);
      return true;
    };
    const FeatureNoiseDraw noise = [&](int, Eigen::VectorXd* delta, std::string*) {
      *delta = Gaussian(t.size(), sigma_hat, &rng);
      return true;
    };
    const ParameterUncertainty u = SandwichUncertainty(f, noise, theta, Eigen::Vector2d(0, 0),
                                                       Eigen::Vector2d(5, 5), UncertaintyOptions{});
    ASSERT_TRUE(u.usable) << u.message;
    covered_a += u.lower[0] <= truth[0] && truth[0] <= u.upper[0];
    covered_b += u.lower[1] <= truth[1] && truth[1] <= u.upper[1];
  }
  EXPECT_GE(covered_a, kMinCoverage * kCopies);
  EXPECT_LE(covered_a, kMaxCoverage * kCopies);
  EXPECT_GE(covered_b, kMinCoverage * kCopies);
  EXPECT_LE(covered_b, kMaxCoverage * kCopies);
  std::cout << "coverage: a " << covered_a << "/" << kCopies << ", b " << covered_b << "/" << kCopies << "\n";
}

TEST(SandwichUncertaintyTest, UnidentifiableParameterAndBadOptions) {
  // The features ignore theta_2: J^T J is singular, a reason, no throw.
  const FeatureFunction f = [](const Eigen::VectorXd& th, Eigen::VectorXd* out, std::string*) {
    *out = Eigen::Vector3d(th[0], 2 * th[0], 3 * th[0]);
    return true;
  };
  const FeatureNoiseDraw noise = [](int, Eigen::VectorXd* d, std::string*) {
    *d = Eigen::Vector3d(0.1, -0.1, 0.05);
    return true;
  };
  const Eigen::Vector2d theta(1, 1), lo(0, 0), hi(2, 2);
  const ParameterUncertainty u = SandwichUncertainty(f, noise, theta, lo, hi, {});
  EXPECT_FALSE(u.usable);
  EXPECT_NE(u.message.find("singular"), std::string::npos) << u.message;
  const FeatureFunction failing = [](const Eigen::VectorXd&, Eigen::VectorXd*, std::string* why) {
    *why = "simulation diverged";
    return false;
  };
  const ParameterUncertainty v = SandwichUncertainty(failing, noise, theta, lo, hi, {});
  EXPECT_FALSE(v.usable);
  EXPECT_NE(v.message.find("simulation diverged"), std::string::npos) << v.message;
  UncertaintyOptions bad;
  bad.noise_draws = 1;
  EXPECT_THROW(SandwichUncertainty(f, noise, theta, lo, hi, bad), std::invalid_argument);
  EXPECT_THROW(SandwichUncertainty(f, noise, theta, Eigen::VectorXd(1), hi, {}), std::invalid_argument);
}

TEST(SandwichUncertaintyTest, IntervalsThatCrossABoundSaySo) {
  // f = theta (dim 1 per parameter) with noise of std 0.1 on each feature:
  // se = 0.1, intervals theta +- t se with t = t_{0.975, 1999} = 1.961, i.e.
  // +- 0.196. Bounds placed 0.1 from theta on one side, both sides, or 1
  // away on both: the notes name exactly the bounds crossed.
  std::mt19937_64 rng(3);
  const FeatureFunction f = [](const Eigen::VectorXd& th, Eigen::VectorXd* out, std::string*) {
    *out = th;
    return true;
  };
  const FeatureNoiseDraw noise = [&rng](int, Eigen::VectorXd* d, std::string*) {
    *d = Gaussian(3, 0.1, &rng);
    return true;
  };
  UncertaintyOptions options;
  options.noise_draws = 2000;
  const Eigen::Vector3d theta(1, 1, 1), lo(0.9, 0.9, 0), hi(2, 1.1, 2);
  const ParameterUncertainty u = SandwichUncertainty(f, noise, theta, lo, hi, options);
  ASSERT_TRUE(u.usable) << u.message;
  ASSERT_EQ(u.bound_notes.size(), 3u);
  EXPECT_LT(u.lower[0], 0.9);
  EXPECT_EQ(u.bound_notes[0], "below the lower bound 0.9");
  EXPECT_EQ(u.bound_notes[1], "below the lower bound 0.9 and above the upper bound 1.1");
  EXPECT_EQ(u.bound_notes[2], "");
  // The interval itself is the linearised one, not clipped to the bounds.
  EXPECT_NEAR(1.0 - u.lower[0], 1.961 * u.standard_error[0], 1e-3);
}

}  // namespace
}  // namespace podid::ident
