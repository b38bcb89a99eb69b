#pragma once
// The inverse CWT and the synchrosqueezed CWT of a Scalogram
// (podid/wavelet/cwt.hpp). Units are SI: s and Hz.
//
// Inverse (the single-integral formula, Farge 1992; Delprat et al. 1992;
// MATLAB's icwt): for a wavelet with psi^(u) = 0 for u < 0 (Morse, and Morlet
// up to its 1.5e-8 negative tail) and kAmplitude,
//   integral_0^inf W(s, t) ds / s = C x_+(t),  C = integral_0^inf psi^(u) du / u,
// x_+ the positive-frequency part of x, so x(t) = 2 Re(integral W ds / s) / C.
// With kEnergy W is divided by sqrt(s) first. The integral over ln s is the
// trapezoid rule over the scalogram's scales; it reconstructs the components
// of x whose frequencies f satisfy psi^(2 pi f s) ~ 0 at both ends of the grid
// (frequencies well inside the grid); a constant offset (DC) is not in any
// band and is not reconstructed.
// Inside the cone of influence the result is x; near the ends the padding shows.
//
// Synchrosqueezing (Daubechies, Lu & Wu 2011; Thakur et al. 2013): each
// coefficient W(s_k, t) with |W| > threshold is moved, weighted by Delta ln s_k,
// to the grid frequency nearest (in ln f) to its instantaneous frequency
//   f(s_k, t) = Im(conj(W) dW/dt) / (2 pi |W|^2),
// giving T(f_l, t) on the scalogram's own frequency grid. A coefficient whose
// IF is not positive or lies more than half a bin outside the grid (near a
// zero of W, where two components cancel) stays at its own frequency. Summing
// T over l gives the same 2 Re(sum) / C reconstruction (up to the dropped
// |W| <= threshold). The ridge of |T| is sharper than the CWT's: a tone concentrates
// in one or two bins instead of a band of width ~ 1 / (2 sigma_t) in ln f.

#include <Eigen/Core>
#include <vector>

#include "podid/wavelet/cwt.hpp"
#include "podid/wavelet/ridge.hpp"

namespace podid::wavelet {

/// C = integral_0^inf psi^(u) du / u of the (un-normalised-by-n(s)) wavelet, by
/// quadrature over the u where psi^ >= 1e-14 of its peak and u >= 1e-3 kappa
/// (Morlet's psi^(0) = 3e-8 makes the integral diverge like 3e-8 ln(1/u): the
/// cut costs < 1e-6 relative).
double ReconstructionConstant(const MorletWavelet& wavelet);

/// The in-band part of x at the scalogram's output times (dim n_times), signal units.
/// Needs complex coefficients and at least 2 frequencies; std::invalid_argument otherwise.
/// std::overflow_error where the result exceeds the largest double (a signal near 1.8e308).
Eigen::VectorXd InverseCwt(const Scalogram& scalogram);

struct SynchrosqueezeOptions {
  /// Coefficients with |W| <= threshold * max |W| are dropped from T (their
  /// IF is noise), in [0, 1).
  double relative_threshold = 1e-6;
  bool IsValid(std::string* why) const;
};

/// A synchrosqueezed transform: T on the scalogram's grid and the
/// reassignment field it was built from.
struct SynchrosqueezedTransform {
  /// coefficients(j, l) = T(f_l, t_j) (W's units times ln-scale), everything
  /// else copied from the scalogram it came from.
  Scalogram sst;
  /// (n_times x n_freq) the IF f(s_k, t_j) of each CWT coefficient (the
  /// frequency it was moved to), Hz; NaN where |W| <= threshold or the IF is
  /// not positive.
  Eigen::MatrixXd reassigned_frequency_Hz;
};

/// `transform` must be the one whose last Compute() wrote `scalogram` (its
/// TimeDerivative gives dW/dt; CwtTransform::Produced); the scalogram needs
/// complex coefficients. Else std::invalid_argument. The result's sst has
/// computation 0: T has no TimeDerivative.
SynchrosqueezedTransform Synchrosqueeze(const Scalogram& scalogram,
                                        const CwtTransform& transform,
                                        const SynchrosqueezeOptions& options = {});
/// The same into *out, reusing its memory: nothing is allocated when the
/// sizes repeat (a record's channels, an evaluation loop).
void Synchrosqueeze(const Scalogram& scalogram,
                    const CwtTransform& transform,
                    const SynchrosqueezeOptions& options,
                    SynchrosqueezedTransform* out);
/// The same in place: on entry inout->sst is the scalogram `transform`
/// computed (CwtTransform::Compute(x, step, &inout->sst)); on return its
/// coefficients are T, bit for bit Synchrosqueeze's. No second n_times x
/// n_freq complex matrix: 24 bytes a coefficient with the field instead of
/// 40 (podid cwt --synchrosqueeze). Invalid options, or a scalogram without
/// complex coefficients, throw before anything is written.
void SynchrosqueezeInPlace(const CwtTransform& transform,
                           const SynchrosqueezeOptions& options,
                           SynchrosqueezedTransform* inout);

/// The IF along the strongest ridge of a synchrosqueezed transform. The path
/// is FindRidges(sst.sst, options) on |T|; at each time the IF is the fixed
/// point of the reassignment near the path's bin l: the grid frequency where
/// the reassigned frequency equals the analysis frequency, f(s, t) = f_s
/// (Chassande-Mottin, Daubechies, Auger & Flandrin 1997: ridges are the fixed
/// points of the reassignment), found by linear interpolation between the two
/// grid scales within 3 bins of l where ln f(s_k, t) - ln f_k changes sign
/// (the pair nearest l). It is exact for a tone (f(s, t) = f at every s) and
/// for a linear chirp to first order (f(s, t) - f is proportional to f_s - f),
/// and not quantised to the grid. Where no sign change is found, the IF of
/// the path's own cell. amplitude = 2 |T(l-1) + T(l) + T(l+1)| / C.
/// Screened (no IF, outside the cone) as TrackRidge screens: where |T(l)| is
/// at most options.min_relative_magnitude of the path's peak, or no
/// coefficient there had a reassigned frequency (|W| below the threshold).
/// An amplitude beyond the largest double: std::overflow_error (so for SynchrosqueezedRidges).
RidgeTrack SynchrosqueezedRidge(const SynchrosqueezedTransform& sst,
                                const RidgeOptions& options = {});

/// options.ridges ridges of |T| (FindRidges: strongest first, each excluding
/// options.separation_octaves either side of those before it), each tracked
/// as SynchrosqueezedRidge tracks the strongest; the first is
/// SynchrosqueezedRidge's. |T| is 0 away from the components, so a later
/// ridge may have times with no cell left (frequency_index -1): there, as
/// TrackRidge leaves such times, frequency_Hz, grid_frequency_Hz and
/// amplitude are NaN and the time is outside the cone (not screened).
std::vector<RidgeTrack> SynchrosqueezedRidges(const SynchrosqueezedTransform& sst,
                                              const RidgeOptions& options = {});

}  // namespace podid::wavelet
