#include "sparse_step.hpp"

namespace podid::internal {
namespace {

// The forward solve computes its right-hand side on the fly: the rows of
// [M, C] u do not depend on the solve's chain, so they fill its latency.
template <bool kLoad>
void ApplyRows(const SparseStep& s, const double* u, double* rhs) {
  const int* const ms = s.mc.start.data();
  const int* const mi = s.mc.index.data();
  const double* const mv = s.mc.value.data();
  const double* const u1 = u;
  const double* const u2 = u + s.na + s.nb;
  // (M u1 + C u2)_i with a chain for each product.
  const auto product = [&](int i) {
    double m = 0.0, c = 0.0;
    for (int k = ms[i]; k < ms[i + 1]; ++k) {
      m += mv[2 * k] * u1[mi[k]];
      c += mv[2 * k + 1] * u2[mi[k]];
    }
    return m + c;
  };
  for (int i = 0; i < s.na; ++i) rhs[i] = (kLoad ? rhs[i] : 0.0) + product(i);
  // L z = rhs_b (unit diagonal), row i: z_i = rhs_i - sum_j<i L_ij z_j.
  double* const y = rhs + s.na;
  const int* const ls = s.lower.start.data();
  const int* const li = s.lower.index.data();
  const double* const lv = s.lower.value.data();
  for (int i = 0; i < s.nb; ++i) {
    double sum = (kLoad ? y[i] : 0.0) + product(s.na + i);
    for (int k = ls[i]; k < ls[i + 1]; ++k) sum -= lv[k] * y[li[k]];
    y[i] = sum;
  }
  // D L^T y = z, row i of L^T: y_i = z_i / D_i - sum_j>i L_ji y_j.
  const int* const us = s.upper.start.data();
  const int* const ui = s.upper.index.data();
  const double* const uv = s.upper.value.data();
  const double* const d_inverse = s.d_inverse.data();
  for (int i = s.nb - 1; i >= 0; --i) {
    double sum = y[i] * d_inverse[i];
    for (int k = us[i]; k < us[i + 1]; ++k) sum -= uv[k] * y[ui[k]];
    y[i] = sum;
  }
}

}  // namespace

SparseRows PairRows(const Eigen::SparseMatrix<double>& m, const Eigen::SparseMatrix<double>& c) {
  const Eigen::SparseMatrix<double, Eigen::RowMajor> mr = m, cr = c;
  SparseRows rows;
  rows.start.push_back(0);
  for (Eigen::Index i = 0; i < mr.outerSize(); ++i) {
    Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator a(mr, i), b(cr, i);
    // Merge the two sorted rows.
    while (a || b) {
      const Eigen::Index j = !b || (a && a.col() < b.col()) ? a.col() : b.col();
      const bool in_m = a && a.col() == j, in_c = b && b.col() == j;
      rows.index.push_back(static_cast<int>(j));
      rows.value.push_back(in_m ? a.value() : 0.0);
      rows.value.push_back(in_c ? b.value() : 0.0);
      if (in_m) ++a;
      if (in_c) ++b;
    }
    rows.start.push_back(static_cast<int>(rows.index.size()));
  }
  return rows;
}

SparseRows::SparseRows(const Eigen::SparseMatrix<double, Eigen::RowMajor>& m) {
  Eigen::SparseMatrix<double, Eigen::RowMajor> compressed = m;
  compressed.makeCompressed();
  start.assign(compressed.outerIndexPtr(), compressed.outerIndexPtr() + compressed.outerSize() + 1);
  index.assign(compressed.innerIndexPtr(), compressed.innerIndexPtr() + compressed.nonZeros());
  value.assign(compressed.valuePtr(), compressed.valuePtr() + compressed.nonZeros());
}

SparseStep::SparseStep(const Eigen::SparseMatrix<double>& m,
                       const Eigen::SparseMatrix<double>& c,
                       int na,
                       const Eigen::SparseMatrix<double>& lower_factor,
                       const Eigen::VectorXd& d)
    : na(na),
      nb(static_cast<int>(m.cols()) - na),
      mc(PairRows(m, c)),
      lower(Eigen::SparseMatrix<double, Eigen::RowMajor>(lower_factor)),
      upper(Eigen::SparseMatrix<double, Eigen::RowMajor>(lower_factor.transpose())),
      d_inverse(d.data(), d.data() + d.size()) {
  for (double& x : d_inverse) x = 1.0 / x;
}

void SparseStep::Apply(const double* u, bool has_load, double* rhs) const {
  if (has_load) {
    ApplyRows<true>(*this, u, rhs);
  } else {
    ApplyRows<false>(*this, u, rhs);
  }
}

}  // namespace podid::internal
