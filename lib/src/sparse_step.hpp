// The linear algebra of the sparse condensed step (newmark.cpp, models above
// NewmarkOptions::dense_dof_limit dofs): eq. 23's known part
// rhs = M u1 + C u2 (+ g) and y = S_bb^-1 rhs_b of eq. 28, with S_bb = L D L^T
// factorised once. Everything is stored by rows, so that each product and each
// triangular solve is a dot product per row (a gather): Eigen's column-major
// products and solves scatter, a chain through memory per entry.
#pragma once

#include <Eigen/SparseCore>
#include <vector>

namespace podid::internal {

/// A compressed row store: row i holds entries start[i] .. start[i + 1] - 1.
struct SparseRows {
  SparseRows() = default;
  explicit SparseRows(const Eigen::SparseMatrix<double, Eigen::RowMajor>& m);
  std::vector<int> start, index;
  std::vector<double> value;
};

/// M and C on the union of their patterns, by rows: entry k is column
/// index[k] with M's value in value[2 k] and C's in value[2 k + 1] (0 where
/// one has no entry). Rayleigh damping gives both the same pattern, so one
/// index serves two products and each row's sum is two independent chains.
SparseRows PairRows(const Eigen::SparseMatrix<double>& m, const Eigen::SparseMatrix<double>& c);

struct SparseStep {
  /// m, c: M and C in the integrator's order (n x n, `a` dofs first);
  /// lower: the strictly lower part of S_bb's factor L (n_b x n_b) in the
  /// same order (the factor was computed without a further permutation);
  /// d: the factor's D.
  SparseStep(const Eigen::SparseMatrix<double>& m,
             const Eigen::SparseMatrix<double>& c,
             int na,
             const Eigen::SparseMatrix<double>& lower,
             const Eigen::VectorXd& d);

  /// u = [u1; u2] (2 n). On return rhs[0, n_a) = ([M, C] u)_a and
  /// rhs[n_a, n) = y = S_bb^-1 ([M, C] u)_b, each plus rhs's input (the load
  /// g) when has_load; without a load rhs's input is not read.
  void Apply(const double* u, bool has_load, double* rhs) const;

  int na = 0, nb = 0;
  SparseRows mc;     ///< M and C by rows (PairRows)
  SparseRows lower;  ///< L's strictly lower part by rows
  SparseRows upper;  ///< the same by columns: the rows of L^T
  std::vector<double> d_inverse;
};

}  // namespace podid::internal
