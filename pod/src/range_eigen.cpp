#include "range_eigen.hpp"

#include <Eigen/QR>
#include <cstdint>

#include "podid/core/error.hpp"
#include "podid/core/noise.hpp"

namespace podid::internal {
namespace {

constexpr std::uint64_t kSketchSeed = 1;  // any fixed seed: the results may not depend on it

}  // namespace

bool UseRangeEigen(Eigen::Index n, Eigen::Index r) {
  // From 256 on a side the dense solver takes ~9 ms (66.6 ms at 501,
  // bench/README.md "POD", scaled as n^3); a basis a quarter of n or wider
  // saves little.
  return n >= 256 && 4 * (r + kRangeOversampling) <= n;
}

void RangeEigenSolver::Compute(const Eigen::MatrixXd& gram, Eigen::Index r) {
  const Eigen::Index n = gram.rows();
  const Eigen::Index c = r + kRangeOversampling;
  PODID_CHECK(gram.cols() == n && r >= 1 && c <= n);
  // Standard normal entries (Halko et al.'s Gaussian test matrix) from
  // core's NormalGenerator, a fixed seed: the same bits every run. Drawn
  // once per shape: a reused solver keeps them. Not +-1: a
  // sparse eigenvector such as (e_i + e_j) / sqrt(2) is orthogonal to a +-1
  // column half the time.
  if (omega_.rows() != n || omega_.cols() != c) {
    omega_.resize(n, c);
    NormalGenerator normal(kSketchSeed);
    for (Eigen::Index j = 0; j < c; ++j) {
      for (Eigen::Index i = 0; i < n; ++i) omega_(i, j) = normal.Normal();
    }
  }
  sketch_.resize(n, c);
  sketch_.noalias() = gram.selfadjointView<Eigen::Lower>() * omega_;
  // Q of a Householder QR is orthonormal even where the sketch is rank
  // deficient (rank G < c always): its first c columns span range(sketch).
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(sketch_);
  basis_ = qr.householderQ() * Eigen::MatrixXd::Identity(n, c);
  product_.resize(n, c);
  product_.noalias() = gram.selfadjointView<Eigen::Lower>() * basis_;
  small_.resize(c, c);
  small_.noalias() = basis_.transpose() * product_;
  eigen_.compute(small_, Eigen::ComputeEigenvectors);  // reads the lower triangle
  PODID_CHECK_MSG(eigen_.info() == Eigen::Success, "projected Gram eigensolver did not converge");
  values_.resize(r);
  vectors_.resize(n, r);
  for (Eigen::Index j = 0; j < r; ++j) {
    values_(j) = eigen_.eigenvalues()(c - 1 - j);
    vectors_.col(j).noalias() = basis_ * eigen_.eigenvectors().col(c - 1 - j);
  }
}

}  // namespace podid::internal
