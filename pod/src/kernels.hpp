#pragma once
// The direct method's two hot products for few sensors (not installed). On
// x86-64 with GCC each is compiled twice, for x86-64-v3 (AVX2, FMA) and the
// baseline, and the loader picks the one the CPU runs (target_clones), so the
// portable build keeps the speed of a -march=native one where the CPU has it;
// elsewhere each is compiled once.

#include <Eigen/Core>

namespace podid::internal {

/// The largest M (sensors) the kernels take.
inline constexpr Eigen::Index kSmallKernelMaxSensors = 16;

/// Centres Y (N x M, M <= kSmallKernelMaxSensors) in place, y_ri -= mean_i,
/// and sets gram (M x M, lower triangle only) = Y^T Y of the centred Y: the
/// eqs. 7-8 covariance times N. Block by block, so that Y is read once.
void SmallCentredGramLower(const Eigen::VectorXd& mean, Eigen::MatrixXd& y, Eigen::MatrixXd& gram);

/// v = Y b for Y (N x M) and b (M x k), M <= kSmallKernelMaxSensors: the time
/// modes V = Y^T Psi diag(1 / sigma) of the direct method, in one pass.
void SmallTimesSmall(const Eigen::MatrixXd& y, const Eigen::MatrixXd& b, Eigen::MatrixXd& v);

}  // namespace podid::internal
