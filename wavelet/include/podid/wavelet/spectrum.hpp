#pragma once
// Two spectral facts the objective needs about a POD time mode before it
// tracks the mode's ridge (ident/objective.hpp, "several modes"):
//   - where the mode's energy is: the peak of its Hann-windowed periodogram,
//     so that each mode's ridge band can follow its own frequency;
//   - how large white noise is in the transform: the expected |W| of
//     unit-variance white noise at each analysis frequency, so that ridge
//     samples of a mode that has decayed into the measurement noise can be
//     told from signal.

#include <Eigen/Core>
#include <vector>

#include "podid/wavelet/cwt.hpp"

namespace podid::wavelet {

/// Frequency (Hz) of the largest bin of the smoothed periodogram of `signal`
/// (dim N >= 8, sampled every step_s > 0; its mean removed, Hann window) with
/// min_Hz <= f <= max_Hz (0 <= min_Hz < max_Hz) and f outside a factor
/// 2^exclude_octaves of each frequency in exclude_Hz, refined by a parabola
/// through the log power of the neighbouring bins. The power is averaged over
/// +-1 % of each bin's frequency (at least one bin each side): a decaying
/// mode's line is several bins wide, a white-noise bin is not, so single noisy
/// bins do not win. Throws std::invalid_argument for bad arguments, a
/// non-finite signal or a range holding no bin; returns NaN when no bin is
/// left or the signal has no power there.
double SpectralPeak_Hz(const Eigen::Ref<const Eigen::VectorXd>& signal, double step_s,
                       double min_Hz, double max_Hz, const std::vector<double>& exclude_Hz = {},
                       double exclude_octaves = 0.25);

/// The root-mean-square |W| that white noise of unit variance per sample
/// produces at each frequency of options.frequencies (dim n_freq, ascending
/// like Scalogram::frequencies_Hz), in the transform's units, for a record of
/// `samples` samples at step_s: sqrt(sum_n |psi_f[n]|^2), the energy of the
/// frequency's discrete filter at the zero-padded length, from its gains by
/// Parseval (CwtTransform::WhiteNoiseMagnitude: no transform, memory of the
/// filters only; the same values with or without band_limited). It equals
/// the transform of a unit impulse at the record's middle summed over the
/// record's times wherever the filter fits in half the record, i.e. inside
/// the cone, and exceeds it by up to 5e-7 where Nyquist cuts a band (the
/// cut's ringing leaves the record; tests/wavelet/spectrum_test.cpp). Noise
/// of variance q gives sqrt(q) times these. Throws std::invalid_argument for
/// samples < 4, a bad step, a frequency above Nyquist or more than 2^27
/// padded points.
Eigen::VectorXd WhiteNoiseMagnitude(const CwtOptions& options, Eigen::Index samples, double step_s);

}  // namespace podid::wavelet
