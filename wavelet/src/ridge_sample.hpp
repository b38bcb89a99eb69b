#pragma once
// What TrackRidge computes at one ridge sample (podid/wavelet/ridge.hpp,
// "Along a ridge"), shared by TrackRidge and the streamed ridge so that both
// give the same numbers from the same coefficients.

#include <Eigen/Core>
#include <complex>
#include <stdexcept>
#include <string>

#include "podid/wavelet/cwt.hpp"
#include "podid/wavelet/ridge.hpp"

namespace podid::wavelet::internal {

struct RidgeSample {
  double vertex_s = 0.0;   ///< the parabola's vertex scale, or the grid scale s_k
  double amplitude = 0.0;  ///< in the coefficients' units times `unit`
  int neighbour = 0;       ///< the scale index towards the vertex (k if none)
};

/// From the coefficients at k - 1, k, k + 1 (wa and wc are ignored at the
/// grid's ends); `unit` is Scalogram::coefficient_scale.
RidgeSample RefineRidgeSample(const MorletWavelet& wavelet,
                              const Eigen::VectorXd& scales_s,
                              int k,
                              std::complex<double> wa,
                              std::complex<double> wb,
                              std::complex<double> wc,
                              double unit,
                              bool parabolic_refinement);

/// Im(conj(W) dW/dt) / (2 pi |W|^2) = Im((dW/dt) / W) / (2 pi): written out
/// where |W|^2 and the products are far from overflow and underflow, else by
/// the complex division (which scales internally); NaN where W = 0.
double PhaseFrequency_Hz(std::complex<double> w, std::complex<double> dw_dt);

/// Throws std::overflow_error naming `where` if an amplitude or IF of the
/// track is infinite: from finite coefficients times coefficient_scale, the
/// value exceeds the largest double (a signal near 1.8e308), a failure to
/// report rather than a result (podid cwt exits 2 on it).
inline void CheckTrackFinite(const RidgeTrack& track, const char* where) {
  const bool amplitude = track.amplitude.array().isInf().any();
  if (amplitude || track.frequency_Hz.array().isInf().any()) {
    throw std::overflow_error(
        std::string(where) + ": the ridge's " + (amplitude ? "amplitude" : "IF") +
        " overflowed double precision (above 1.8e308); scale the signal down");
  }
}

}  // namespace podid::wavelet::internal
