#include "range_eigen.hpp"

#include <Eigen/QR>
#include <cstdint>

#include "podid/core/error.hpp"

namespace podid::internal {

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
  // Uniform entries in [-1, 1) from a 64-bit LCG (Knuth's MMIX constants,
  // its top 53 bits): fixed, portable bits (std::uniform_real_distribution
  // differs between standard libraries). Not +-1: a sparse eigenvector such
  // as (e_i + e_j) / sqrt(2) is orthogonal to a +-1 column half the time.
  omega_.resize(n, c);
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  for (Eigen::Index j = 0; j < c; ++j) {
    for (Eigen::Index i = 0; i < n; ++i) {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      omega_(i, j) = static_cast<double>(state >> 11) * 0x1.0p-52 - 1.0;
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
