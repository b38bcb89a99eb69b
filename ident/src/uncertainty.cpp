#include "podid/ident/uncertainty.hpp"

#include <gsl/gsl_cdf.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <stdexcept>

#include "podid/core/error.hpp"

namespace podid::ident {

bool UncertaintyOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (!(confidence > 0 && confidence < 1)) return fail("confidence: expected a value in (0, 1), got " + ToText(confidence));
  if (!(relative_step > 0 && relative_step <= 0.1))
    return fail("relative_step: expected a value in (0, 0.1], got " + ToText(relative_step));
  if (noise_draws < 2 || noise_draws > kMaxNoiseDraws)
    return fail("noise_draws: expected 2.." + ToText(kMaxNoiseDraws) + ", got " + ToText(noise_draws));
  return true;
}

ParameterUncertainty SandwichUncertainty(const FeatureFunction& features, const FeatureNoiseDraw& noise,
                                         const Eigen::VectorXd& theta, const Eigen::VectorXd& lower,
                                         const Eigen::VectorXd& upper, const UncertaintyOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument("uncertainty options: " + why);
  const Eigen::Index p = theta.size();
  if (p == 0 || lower.size() != p || upper.size() != p) {
    ThrowInvalid("uncertainty", "theta, lower and upper of one size >= 1",
                 ToText(p) + ", " + ToText(lower.size()) + ", " + ToText(upper.size()));
  }
  ParameterUncertainty result;
  result.confidence = options.confidence;
  auto fail = [&result](const std::string& text) {
    result.usable = false;
    result.message = text;
    return result;
  };

  Eigen::VectorXd f0;
  if (!features(theta, &f0, &why)) return fail("features at the optimum: " + why);
  const Eigen::Index m = f0.size();
  // J by central differences (one-sided at a bound), step h_i = rel * range_i.
  Eigen::MatrixXd jacobian(m, p);
  Eigen::VectorXd fp, fm;
  for (Eigen::Index i = 0; i < p; ++i) {
    const double h = options.relative_step * (upper[i] - lower[i]);
    Eigen::VectorXd plus = theta, minus = theta;
    plus[i] = std::min(theta[i] + h, upper[i]);
    minus[i] = std::max(theta[i] - h, lower[i]);
    if (!(plus[i] > minus[i])) return fail("parameter " + ToText(i + 1) + ": an empty range");
    if (!features(plus, &fp, &why) || !features(minus, &fm, &why)) {
      return fail("features near the optimum (parameter " + ToText(i + 1) + "): " + why);
    }
    if (fp.size() != m || fm.size() != m) return fail("features changed size near the optimum");
    jacobian.col(i) = (fp - fm) / (plus[i] - minus[i]);
  }
  const Eigen::MatrixXd jtj = jacobian.transpose() * jacobian;
  Eigen::LDLT<Eigen::MatrixXd> ldlt(jtj);
  const double scale = jtj.diagonal().maxCoeff();
  if (ldlt.info() != Eigen::Success || !(scale > 0) ||
      ldlt.vectorD().minCoeff() <= 1e-12 * scale) {
    return fail("the features do not determine every parameter at the optimum (J^T J is singular)");
  }
  // J^T Sigma_m J from the draws: mean of (J^T df)(J^T df)^T about its mean.
  Eigen::MatrixXd projected(p, options.noise_draws);
  Eigen::VectorXd delta;
  for (int d = 0; d < options.noise_draws; ++d) {
    if (!noise(d, &delta, &why)) return fail("noise draw " + ToText(d + 1) + ": " + why);
    if (delta.size() != m) return fail("a noise draw of the wrong size");
    projected.col(d) = jacobian.transpose() * delta;
  }
  const Eigen::VectorXd mean = projected.rowwise().mean();
  const Eigen::MatrixXd centred = projected.colwise() - mean;
  const Eigen::MatrixXd middle = centred * centred.transpose() / (options.noise_draws - 1);
  const Eigen::MatrixXd left = ldlt.solve(Eigen::MatrixXd::Identity(p, p));
  result.covariance = left * middle * left;
  result.covariance = 0.5 * (result.covariance + result.covariance.transpose()).eval();
  result.standard_error = result.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
  if (!result.covariance.allFinite()) return fail("a non-finite covariance");
  const double t = gsl_cdf_tdist_Pinv(0.5 * (1.0 + options.confidence), options.noise_draws - 1);
  result.lower = theta - t * result.standard_error;
  result.upper = theta + t * result.standard_error;
  result.bound_notes.assign(static_cast<std::size_t>(p), "");
  for (Eigen::Index i = 0; i < p; ++i) {
    std::string& note = result.bound_notes[static_cast<std::size_t>(i)];
    if (result.lower[i] < lower[i]) note = "below the lower bound " + ToText(lower[i]);
    if (result.upper[i] > upper[i]) {
      note +=
          (note.empty() ? "" : " and ") + std::string("above the upper bound ") + ToText(upper[i]);
    }
  }
  result.correlation = Eigen::MatrixXd::Identity(p, p);
  for (Eigen::Index i = 0; i < p; ++i) {
    for (Eigen::Index j = 0; j < p; ++j) {
      const double s = result.standard_error[i] * result.standard_error[j];
      if (i != j && s > 0) result.correlation(i, j) = result.covariance(i, j) / s;
    }
  }
  result.noise_draws = options.noise_draws;
  result.usable = true;
  result.message = "sandwich covariance from " + ToText(p) + " central differences and " +
                   ToText(options.noise_draws) + " noise draws";
  return result;
}

}  // namespace podid::ident
