#pragma once
// Standard errors and confidence intervals of identified parameters.
//
// An objective of podid compares features (POM components, singular values,
// time modes, ridge IFs; weighted, see objective.hpp) of the simulated and
// the measured responses: F(theta) = ||f(theta) - f_m||^2 (dim m features).
// Near the minimiser theta^, f(theta) ~ f(theta^) + J (theta - theta^), so a
// perturbation df_m of the measured features moves the minimiser by
//   d theta = (J^T J)^-1 J^T df_m                     (Gauss-Newton)
// and the estimator's covariance is the sandwich
//   Cov(theta^) = (J^T J)^-1 J^T Sigma_m J (J^T J)^-1,   Sigma_m = Cov(f_m).
// J comes from central differences of f; J^T Sigma_m J (p x p) from Monte
// Carlo: the features of the fitted response plus draws of the measurement
// noise, minus the features of the fitted response (FeatureNoiseDraw). This
// holds for any weighting of the terms, not only for least squares on the
// samples, and it needs no assumption on how noise enters U, sigma or V.
//
// Intervals: theta^_i +- t_{(1+c)/2, D-1} se_i (Student's t with the D noise
// draws' degrees of freedom; c = confidence). Correlations: Cov_ij / (se_i se_j).

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

namespace podid::ident {

/// The most Monte Carlo draws (each one POD and ridge of a record).
inline constexpr int kMaxNoiseDraws = 100'000;

struct UncertaintyOptions {
  double confidence = 0.95;     ///< of the intervals, in (0, 1)
  /// Central-difference step for J, relative to each parameter's range
  /// (upper - lower), in (0, 0.1]; one-sided at a bound.
  double relative_step = 1e-4;
  int noise_draws = 40;         ///< D, in [2, kMaxNoiseDraws]
  bool IsValid(std::string* why) const;
};

struct ParameterUncertainty {
  bool usable = false;
  std::string message = "not computed";
  double confidence = 0.95;
  int noise_draws = 0;
  Eigen::VectorXd standard_error;  ///< (dim p), parameter units
  Eigen::VectorXd lower, upper;    ///< (dim p) the confidence interval
  /// (dim p) "" or the bound(s) parameter i's interval crosses, e.g. "below
  /// the lower bound 0": the parameter cannot go there, so the linearised
  /// interval is not its distribution's (a fit against a bound, or a
  /// parameter the data hardly determine). Reports show it beside the interval.
  std::vector<std::string> bound_notes;
  Eigen::MatrixXd covariance;      ///< (p x p)
  Eigen::MatrixXd correlation;     ///< (p x p), unit diagonal
};

/// f(theta) (dim m) into *features; false with *why when it cannot be computed
/// (a failed simulation). Must not throw.
using FeatureFunction =
    std::function<bool(const Eigen::VectorXd& theta, Eigen::VectorXd* features, std::string* why)>;
/// Draw d (0-based) of the measured features' noise perturbation df_m (dim m);
/// false with *why on failure. Must not throw.
using FeatureNoiseDraw = std::function<bool(int draw, Eigen::VectorXd* delta, std::string* why)>;

/// The sandwich covariance at `theta` (dim p, inside [lower, upper]).
/// Invalid options or sizes throw std::invalid_argument; a failed feature
/// evaluation, a singular J^T J (a parameter the features do not see) or a
/// non-finite result is a non-usable result with its reason.
ParameterUncertainty SandwichUncertainty(const FeatureFunction& features,
                                         const FeatureNoiseDraw& noise,
                                         const Eigen::VectorXd& theta,
                                         const Eigen::VectorXd& lower,
                                         const Eigen::VectorXd& upper,
                                         const UncertaintyOptions& options);

}  // namespace podid::ident
