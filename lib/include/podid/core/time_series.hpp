#pragma once
// Sampled time histories: a uniform time vector plus named channels.
// Units are SI (time in s, displacements in m).

#include <Eigen/Core>
#include <string>
#include <vector>

namespace podid {

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
