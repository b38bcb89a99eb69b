#pragma once
// Sampled time histories: a uniform time vector plus named channels.
// Units are SI (time in s, displacements in m).

#include <Eigen/Core>
#include <cmath>
#include <string>
#include <vector>

namespace podid {

/// Whether step_s can be a sampling step: finite, > 0, and its rate 1 / step_s
/// finite too (a subnormal step such as 1e-320 s has an infinite rate, which
/// every frequency derived from it would inherit). The readers, the case
/// file's data.step and the wavelet transforms check it.
inline bool IsSamplingStep(double step_s) {
  return step_s > 0.0 && std::isfinite(step_s) && std::isfinite(1.0 / step_s);
}
/// The same for a sampling rate: finite, > 0, and its step 1 / rate_Hz a sampling step.
inline bool IsSamplingRate(double rate_Hz) {
  return rate_Hz > 0.0 && std::isfinite(rate_Hz) && IsSamplingStep(1.0 / rate_Hz);
}

struct TimeSeries {
  Eigen::VectorXd time_s;                  ///< (dim n_samples) uniform, increasing
  std::vector<std::string> channel_names;  ///< (dim n_channels), e.g. "w1".."w6"
  Eigen::MatrixXd values;                  ///< (n_samples x n_channels)
  /// (dim n_channels, or empty when unknown) each channel's unit as the file
  /// states it ("m/s^2", "N"; "" for one the file does not name).
  std::vector<std::string> units;

  Eigen::Index samples() const { return values.rows(); }
  Eigen::Index channels() const { return values.cols(); }
  /// Sampling step (s); requires at least 2 samples.
  double step_s() const;
  /// The paper's snapshot matrix X (eq. 17): (n_channels x n_samples).
  Eigen::MatrixXd SnapshotMatrix() const { return values.transpose(); }
  /// Index of a channel by name, or -1.
  int ChannelIndex(const std::string& name) const;
};

}  // namespace podid
