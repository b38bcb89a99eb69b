#pragma once
// The measured side of the IF term for each compared mode (objective.hpp,
// "Several modes"), prepared once when an objective is built:
//   - the ridge band: mode 1 uses ObjectiveOptions::ridge's band; mode k >= 2
//     the band given in mode_bands, else the same width in octaves centred
//     (geometrically) on the peak of the measured time mode's periodogram
//     away from the lower modes' peaks, clipped to 0.95 x Nyquist: a fixed
//     10-120 Hz band cannot hold a beam's second mode at 207 Hz;
//   - the measured ridge, with the samples where the mode has decayed into the
//     measurement noise marked unusable (inside_coi false): there the ridge
//     follows noise, and its IF would dominate the term (issue 13 item 4).

#include <Eigen/Core>
#include <string>
#include <vector>

#include "podid/ident/objective.hpp"
#include "podid/pod/pod.hpp"
#include "podid/wavelet/ridge.hpp"

namespace podid::ident::internal {

struct ModeRidges {
  std::vector<wavelet::RidgeFrequencyOptions> options;  ///< per mode
  std::vector<wavelet::RidgeTrack> measured;            ///< per mode, noise-screened
  std::vector<std::string> notes;                       ///< bands chosen, samples screened
};

/// The first `modes` modes. `pod`: the measured POD with its raw (not noise-corrected) singular values
/// and time modes; `noise_variance`: white-noise variance per sensor (dim
/// sensors; DifferenceNoiseVariance), or empty for no noise screening.
/// Throws std::invalid_argument naming the mode when a record is too short
/// for a band's cone of influence or no usable ridge sample is left.
ModeRidges PrepareModeRidges(const PodResult& pod, const Eigen::VectorXd& noise_variance, double step_s,
                             int modes, const ObjectiveOptions& options);

}  // namespace podid::ident::internal
