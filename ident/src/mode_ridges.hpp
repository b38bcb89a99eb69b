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
//     follows noise, and its IF would dominate the term (issue 13 item 4);
//   - the checks of both against the data's conditioning and the record:
//     a band outside the filter's passband is refused, one partly outside it
//     and a ridge compared over less than a few wavelet durations get a note.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "podid/core/conditioning.hpp"
#include "podid/ident/objective.hpp"
#include "podid/pod/pod.hpp"
#include "podid/wavelet/ridge.hpp"

namespace podid::ident::internal {

struct ModeRidges {
  std::vector<wavelet::RidgeFrequencyOptions> options;  ///< per mode
  std::vector<wavelet::RidgeTrack> measured;            ///< per mode, noise-screened
  std::vector<std::string> notes;                       ///< bands chosen, samples screened
};

/// A ridge compared over fewer than this many wavelet durations (the
/// e-folding time 2 sigma_t s at the ridge's frequency, over which its IFs are
/// correlated) gets a note: see mode_ridges.cpp.
inline constexpr double kMinRidgeWaveletDurations = 4.0;

/// The first `modes` modes. `pod`: the measured POD with its raw (not noise-corrected) singular
/// values and time modes; `noise_variance`: white-noise variance per sensor (dim sensors;
/// DifferenceNoiseVariance), or empty for no noise screening; `filter`: the conditioning's filter,
/// applied to the measured and the simulated records alike. Throws std::invalid_argument naming the
/// mode when a band lies outside the filter's passband, a record is too short for a band's cone of
/// influence or no usable ridge sample is left.
ModeRidges PrepareModeRidges(const PodResult& pod,
                             const Eigen::VectorXd& noise_variance,
                             double step_s,
                             int modes,
                             const ObjectiveOptions& options,
                             const FilterOptions& filter = {});

}  // namespace podid::ident::internal
