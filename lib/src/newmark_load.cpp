// The load's part of the Newmark integrator (newmark.hpp): a sum of sparse
// patterns times histories (ExternalLoad), prepared once per Run() and added
// allocation-free at every step. Kept apart from the time loop's file.
#include <vector>

#include "podid/core/error.hpp"
#include "podid/core/newmark.hpp"

namespace podid {

ExternalLoad ExternalLoad::PointForce(int n_dofs, int dof, const Eigen::VectorXd& values_N) {
  if (dof < 0 || dof >= n_dofs) ThrowInvalid("external load dof", "a dof in 0.." + ToText(n_dofs - 1), ToText(dof));
  ExternalLoad load;
  load.pattern.resize(n_dofs, 1);
  load.pattern.insert(dof, 0) = 1.0;
  load.pattern.makeCompressed();
  load.history = values_N.transpose();
  return load;
}

void NewmarkIntegrator::AddLoad(NewmarkWorkspace& w, Eigen::VectorXd& rhs) {
  // Column by column (K is small): no temporary, and a point force adds
  // 1.0 * F to its dof exactly.
  const Eigen::SparseMatrix<double>& p = w.load_pattern;
  for (int k = 0; k < p.outerSize(); ++k) {
    const double h = w.load_now[k];
    for (Eigen::SparseMatrix<double>::InnerIterator it(p, k); it; ++it) rhs[it.row()] += it.value() * h;
  }
}

void NewmarkIntegrator::PrepareLoad(const ExternalLoad& load, NewmarkWorkspace& w) const {
  // The load in the permuted order, and on the dense condensed path how each
  // column enters y = S_b^-1 rhs_b and bhat = rhs_a - S_ab y (eqs. 28-29).
  const bool has_load = load.columns() > 0;
  const int columns = load.columns();
  w.load_now.setZero(columns);
  w.load_pattern.resize(n_, columns);
  if (has_load) {
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(static_cast<std::size_t>(load.pattern.nonZeros()));
    for (int k = 0; k < load.pattern.outerSize(); ++k)
      for (Eigen::SparseMatrix<double>::InnerIterator it(load.pattern, k); it; ++it)
        t.emplace_back(inv_perm_[it.row()], k, it.value());
    w.load_pattern.setFromTriplets(t.begin(), t.end());
    w.load_now = load.history.col(0);
  }
  w.load_y.setZero(nb_, columns);
  w.load_bhat.setZero(na_, columns);
  if (has_load && options_.type == IntegratorType::kModifiedNewmark && !sparse_) {
    const Eigen::MatrixXd dense = Eigen::MatrixXd(w.load_pattern);
    w.load_y.noalias() = sbb_inv_ * dense.bottomRows(nb_);
    w.load_bhat = dense.topRows(na_);
    w.load_bhat.noalias() -= sab_ * w.load_y;
  }
}

}  // namespace podid
