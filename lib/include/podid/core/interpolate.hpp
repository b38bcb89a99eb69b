#pragma once
// Band-limited interpolation of a uniformly sampled signal onto a grid
// `factor` times finer (sub-stepping a measured force). Units: those of x.

#include <Eigen/Core>

namespace podid {

/// Samples x_0..x_{N-1} at t_i = i dt -> y_j at t_j = j dt / factor,
/// j = 0..(N - 1) factor, with y_{i factor} = x_i (to round-off).
/// Method: the straight line through x_0 and x_{N-1} is removed (the rest
/// starts and ends at 0, so its periodic extension is continuous), the rest is
/// zero-padded to a length P >= N with factors 2, 3, 5 only, interpolated by
/// periodic sinc (FFT zero-padding of its spectrum to P factor bins; the
/// Nyquist bin of an even P split between +- Nyquist) and the line added back.
/// Exact for any signal whose detrended, padded sequence has no content at or
/// above Nyquist; a tone well below Nyquist is reproduced in the interior to
/// the truncation of its spectral leakage. factor >= 1; N <= 1 or factor 1
/// returns x (N = 1: the constant).
Eigen::VectorXd InterpolateBandLimited(const Eigen::VectorXd& x, int factor);

}  // namespace podid
