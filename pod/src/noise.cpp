#include "podid/pod/noise.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "podid/core/error.hpp"

namespace podid {

Eigen::VectorXd DifferenceNoiseVariance(const Eigen::Ref<const Eigen::MatrixXd>& x) {
  // Median of chi-square(1) = 0.454936...: median(d^2) / (6 * it) estimates v.
  constexpr double kChiSquare1Median = 0.45493642311957283;
  if (x.cols() < 8) ThrowInvalid("DifferenceNoiseVariance", "at least 8 samples", ToText(x.cols()));
  if (!x.allFinite()) ThrowInvalid("DifferenceNoiseVariance", "finite values", "NaN or Inf");
  Eigen::VectorXd variance(x.rows());
  std::vector<double> squares(static_cast<std::size_t>(x.cols() - 2));
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    for (Eigen::Index n = 1; n + 1 < x.cols(); ++n) {
      const double d = x(i, n + 1) - 2.0 * x(i, n) + x(i, n - 1);
      squares[static_cast<std::size_t>(n - 1)] = d * d;
    }
    auto middle = squares.begin() + static_cast<std::ptrdiff_t>(squares.size() / 2);
    std::nth_element(squares.begin(), middle, squares.end());
    variance[i] = *middle / (6.0 * kChiSquare1Median);
  }
  return variance;
}

Eigen::VectorXd NoiseCorrectedSingularValues(const PodResult& result,
                                             const Eigen::VectorXd& noise_variance) {
  if (noise_variance.size() != result.sensors) {
    ThrowInvalid("NoiseCorrectedSingularValues: noise_variance", ToText(result.sensors) + " values",
                 ToText(noise_variance.size()));
  }
  const double n = static_cast<double>(result.samples);
  Eigen::VectorXd corrected(result.singular_values.size());
  for (Eigen::Index k = 0; k < corrected.size(); ++k) {
    const double noise_energy = n * result.poms.col(k).array().square().matrix().dot(noise_variance);
    const double s2 = result.singular_values[k] * result.singular_values[k] - noise_energy;
    corrected[k] = std::sqrt(std::max(s2, 0.0));
  }
  return corrected;
}

}  // namespace podid
