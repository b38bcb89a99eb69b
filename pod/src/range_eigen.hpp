#pragma once
// The leading eigenpairs of a Gram matrix whose rank is bounded by its shape
// (not installed; pod.cpp): C* = Y^T Y (N x N) has rank <= M, and Y Y^T
// (M x M) rank <= N, however large the matrix. Eigen's dense solver costs
// ~n^3 whatever the rank (the snapshot method on 6 x 5001 took ~250 s);
// Rayleigh-Ritz on a basis of the range costs ~n^2 (r + p).

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

namespace podid::internal {

/// Oversampling p of the range basis: its r + p columns span range(G) even
/// where the sketch G Omega is ill-conditioned (Halko, Martinsson & Tropp
/// 2011, sec. 4.2: p = 5-10 suffices for a generic Omega).
inline constexpr Eigen::Index kRangeOversampling = 10;

/// True when RangeEigenSolver pays: an n x n Gram of rank <= r with the basis far
/// narrower than the matrix (and n large enough that ~n^3 matters; below,
/// the dense solver keeps its results bit for bit).
bool UseRangeEigen(Eigen::Index n, Eigen::Index r);

/// The r largest eigenpairs of the symmetric n x n `gram` (lower triangle
/// read) of rank <= r: values (dim r, descending) and orthonormal vectors
/// (n x r). Q = the Householder basis of G Omega (Omega n x (r + p), fixed-seed
/// standard normal entries: the same bits every run), then the eigenpairs
/// (L, W) of B = Q^T G Q give (L, Q W). Exact in exact arithmetic, as
/// range(G) lies in span(Q); in rounding, G Omega carries eigenvector k with
/// weight lambda_k against noise eps lambda_1, so values and vectors have
/// the dense Gram solver's accuracy (eps lambda_1 on lambda_k).
class RangeEigenSolver {
 public:
  void Compute(const Eigen::MatrixXd& gram, Eigen::Index r);
  const Eigen::VectorXd& values() const { return values_; }
  const Eigen::MatrixXd& vectors() const { return vectors_; }

 private:
  Eigen::MatrixXd omega_, sketch_, basis_, product_, small_, vectors_;
  Eigen::VectorXd values_;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen_;
};

}  // namespace podid::internal
