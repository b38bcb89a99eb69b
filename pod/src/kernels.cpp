// The direct method's hot products for few sensors (kernels.hpp). Loops are
// written so that GCC vectorises them across samples without reassociating
// sums it may not: eight independent partial sums per dot product, and in
// Y b one output sample per lane.
#include "kernels.hpp"

#include <algorithm>

#include "podid/core/error.hpp"
#include "podid/core/target_clones.hpp"

namespace podid::internal {
namespace {

using Eigen::Index;

// Rows per block of the Gram product: 16 columns x 256 rows = 32 KiB, so a
// block's columns, once centred, are read from L1 by the M (M + 1) / 2 dot
// products.
constexpr Index kRowBlock = 256;
constexpr int kLanes = 8;

[[gnu::always_inline]] inline void CentredGramKernel(
    const double* mean, double* y, Index n, Index m, double* gram) {
  for (Index j = 0; j < m; ++j) std::fill(gram + j * m + j, gram + (j + 1) * m, 0.0);
  for (Index r0 = 0; r0 < n; r0 += kRowBlock) {
    const Index len = std::min(kRowBlock, n - r0);
    for (Index i = 0; i < m; ++i) {
      double* yi = y + i * n + r0;
      for (Index r = 0; r < len; ++r) yi[r] -= mean[i];
    }
    for (Index j = 0; j < m; ++j) {
      const double* yj = y + j * n + r0;
      for (Index i = j; i < m; ++i) {
        const double* yi = y + i * n + r0;
        double lanes[kLanes] = {};
        Index r = 0;
        for (; r + kLanes <= len; r += kLanes) {
          for (int l = 0; l < kLanes; ++l) lanes[l] += yi[r + l] * yj[r + l];
        }
        double sum = 0.0;
        for (; r < len; ++r) sum += yi[r] * yj[r];
        for (int l = 0; l < kLanes; ++l) sum += lanes[l];
        gram[j * m + i] += sum;
      }
    }
  }
}

// M fixed, so that the M coefficients of a column of b stay in registers.
template <int M>
[[gnu::always_inline]] inline void TimesKernel(
    const double* y, Index n, const double* b, Index k, double* v) {
  for (Index j = 0; j < k; ++j) {
    double bj[M];
    for (int i = 0; i < M; ++i) bj[i] = b[j * M + i];
    double* vj = v + j * n;
    for (Index r = 0; r < n; ++r) {
      double sum = 0.0;
      for (int i = 0; i < M; ++i) sum += y[i * n + r] * bj[i];
      vj[r] = sum;
    }
  }
}

PODID_CLONES_V3 void CentredGramDispatch(
    const double* mean, double* y, Index n, Index m, double* gram) {
  CentredGramKernel(mean, y, n, m, gram);
}

PODID_CLONES_V3 void TimesDispatch(
    const double* y, Index n, Index m, const double* b, Index k, double* v) {
  switch (m) {
    case 1:
      return TimesKernel<1>(y, n, b, k, v);
    case 2:
      return TimesKernel<2>(y, n, b, k, v);
    case 3:
      return TimesKernel<3>(y, n, b, k, v);
    case 4:
      return TimesKernel<4>(y, n, b, k, v);
    case 5:
      return TimesKernel<5>(y, n, b, k, v);
    case 6:
      return TimesKernel<6>(y, n, b, k, v);
    case 7:
      return TimesKernel<7>(y, n, b, k, v);
    case 8:
      return TimesKernel<8>(y, n, b, k, v);
    case 9:
      return TimesKernel<9>(y, n, b, k, v);
    case 10:
      return TimesKernel<10>(y, n, b, k, v);
    case 11:
      return TimesKernel<11>(y, n, b, k, v);
    case 12:
      return TimesKernel<12>(y, n, b, k, v);
    case 13:
      return TimesKernel<13>(y, n, b, k, v);
    case 14:
      return TimesKernel<14>(y, n, b, k, v);
    case 15:
      return TimesKernel<15>(y, n, b, k, v);
    case 16:
      return TimesKernel<16>(y, n, b, k, v);
    default:
      PODID_CHECK_MSG(false, "SmallTimesSmall: M outside 1..16");
  }
}

}  // namespace

void SmallCentredGramLower(const Eigen::VectorXd& mean, Eigen::MatrixXd& y, Eigen::MatrixXd& gram) {
  PODID_CHECK(y.cols() >= 1 && y.cols() <= kSmallKernelMaxSensors && mean.size() == y.cols());
  PODID_CHECK(gram.rows() == y.cols() && gram.cols() == y.cols());
  CentredGramDispatch(mean.data(), y.data(), y.rows(), y.cols(), gram.data());
}

void SmallTimesSmall(const Eigen::MatrixXd& y, const Eigen::MatrixXd& b, Eigen::MatrixXd& v) {
  PODID_CHECK(y.cols() >= 1 && y.cols() <= kSmallKernelMaxSensors && b.rows() == y.cols());
  PODID_CHECK(v.rows() == y.rows() && v.cols() == b.cols());
  TimesDispatch(y.data(), y.rows(), y.cols(), b.data(), b.cols(), v.data());
}

}  // namespace podid::internal
