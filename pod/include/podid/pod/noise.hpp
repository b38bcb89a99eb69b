#pragma once
// White measurement noise and the singular values (issue 12 item 6).
//
// Measured Y = Y_c + E, centred (M sensors x N samples), E white with variance
// v_i on sensor i and independent of the signal. Then
//   E[Y Y^T] = Y_c Y_c^T + N diag(v),
// so in expectation a mode's sigma_k^2 = u_k^T Y Y^T u_k carries the extra
// N u_k^T diag(v) u_k: noise inflates every singular value, and an objective
// comparing a noisy measured sigma with a clean simulated one is biased
// (about 1 % on accelerations with 2 % noise). Subtracting it:
//   sigma_k,corrected = sqrt(max(sigma_k^2 - N sum_i u_ik^2 v_i, 0)).
//
// v is estimated per sensor from the second differences d_n = x_{n+1} - 2 x_n
// + x_{n-1}: for white noise Var(d) = 6 v, while a signal well inside the
// band (omega dt << 1) is attenuated by (omega dt)^2 (Rice 1984; von Neumann).
// The median of d^2 (over 6 * 0.4549, the median of a chi-square with one
// degree of freedom) makes it robust to the few large d of transients.

#include <Eigen/Core>

#include "podid/pod/pod.hpp"

namespace podid {

/// Per-sensor white-noise variance (dim M, data units^2) of x (M x N, N >= 8)
/// from its second differences. Throws std::invalid_argument for N < 8 or a
/// non-finite value.
Eigen::VectorXd DifferenceNoiseVariance(const Eigen::Ref<const Eigen::MatrixXd>& x);

/// The POD's singular values with the expected noise energy removed (dim k):
/// sqrt(max(sigma_k^2 - N u_k^T diag(noise_variance) u_k, 0)). `result` must be
/// unweighted (U orthonormal); noise_variance has dim result.sensors.
Eigen::VectorXd NoiseCorrectedSingularValues(const PodResult& result,
                                             const Eigen::VectorXd& noise_variance);

}  // namespace podid
