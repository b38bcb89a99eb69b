#pragma once
// Signal conditioning of recordings ([data] in the case file, docs/case-file.md;
// the --window, --detrend, --lowpass, ... options, docs/cli.md). The same
// ConditioningOptions are applied, by ConditionRecord(), to the measured record
// and to the simulated sensors, so that both go through the same chain:
//
//   1. channels: keep and order channels by name;
//   2. window:   keep the samples with window_start_s <= t <= window_end_s,
//                half a step of rounding either side (absolute record time;
//                the time stamps are kept);
//   3. detrend:  subtract each channel's mean (constant) or least-squares line
//                (linear), as scipy.signal.detrend;
//   4. filter:   zero-phase Butterworth low-, high- or band-pass: the digital
//                filter of scipy.signal.butter (bilinear transform with
//                pre-warped cutoffs) as second-order sections, run forward and
//                backward with odd-extension padding of 3 (2 n_sections + 1 -
//                first-order sections) samples and steady-state initial
//                conditions, as scipy.signal.sosfiltfilt. The gain is |H|^2 and
//                the phase 0;
//   5. decimate: anti-alias zero-phase Butterworth low-pass of order 8 at
//                0.8 x the new Nyquist frequency (as step 4), then every
//                `decimate`-th sample from the first.
//
// Implemented here: no library of our Debian stack designs IIR filters (GSL
// has FFTs but no Butterworth design; Eigen and FFTW none), and the chain is
// short. Tested against scipy.signal (tests/data/conditioning/).
// Units are SI: times in s, frequencies in Hz.

#include <Eigen/Core>
#include <array>
#include <limits>
#include <string>
#include <vector>

#include "podid/core/time_series.hpp"

namespace podid {

/// Highest Butterworth order (the low-pass prototype's; a band-pass has twice
/// as many poles).
inline constexpr int kMaxFilterOrder = 16;
/// Cutoffs lie in [f, 1 - f] of the Nyquist frequency, f = 1e-5: a pole at
/// ~pi Wn from z = 1 (z = -1 near Nyquist) is stored in its section's a1, a2
/// with a relative error of ~eps / (pi Wn)^2, so the DC gain of a low-pass is
/// off by up to 3.5e-7 at Wn = 1e-5 (orders 1-16; scipy's butter 1e-7), and
/// 1e-9 gave NaN. 1e-5 still passes a 0.05 Hz high-pass at 10 kHz.
inline constexpr double kMinFilterCutoffFraction = 1e-5;
/// Highest decimation factor.
inline constexpr int kMaxDecimation = 1000;
/// Order of decimate's anti-alias low-pass, and its cutoff as a fraction of the
/// decimated Nyquist frequency.
inline constexpr int kDecimationFilterOrder = 8;
inline constexpr double kDecimationCutoffFraction = 0.8;

enum class Detrend { kNone, kConstant, kLinear };
enum class FilterType { kNone, kLowpass, kHighpass, kBandpass };

const char* ToString(Detrend detrend);
const char* ToString(FilterType type);

struct FilterOptions {
  FilterType type = FilterType::kNone;
  int order = 4;         ///< in 1..kMaxFilterOrder
  double low_Hz = 0.0;   ///< highpass and bandpass: lower cutoff, in (0, Nyquist)
  double high_Hz = 0.0;  ///< lowpass and bandpass: upper cutoff, in (0, Nyquist)

  /// The passband as checks read it: between the cutoffs (-3 dB; gain 1/2
  /// through the zero-phase filter), whatever the order. 0 and infinity where
  /// the filter has no edge (kNone: everything).
  double PassbandLow_Hz() const;
  double PassbandHigh_Hz() const;
  /// "below 50 Hz", "above 5 Hz", "5..80 Hz" (kNone: "all frequencies").
  std::string DescribePassband() const;
};

struct ConditioningOptions {
  std::vector<std::string> channels;  ///< empty: all, in the record's order
  double window_start_s = -std::numeric_limits<double>::infinity();
  double window_end_s = std::numeric_limits<double>::infinity();
  Detrend detrend = Detrend::kNone;
  FilterOptions filter;
  int decimate = 1;  ///< in 1..kMaxDecimation

  /// True when ConditionRecord() returns its input unchanged.
  bool IsIdentity() const;
  /// True when the record's time grid stays the same (no window, no decimation).
  bool KeepsTimeGrid() const;
  /// Checks the ranges that do not depend on a record (order, factor, cutoffs
  /// > 0, window start < end). `why` gets "<field>: expected X, got Y".
  bool IsValid(std::string* why) const;
  /// One line, e.g. "window 0.1..1 s, detrend linear, bandpass 5..80 Hz order 4".
  std::string Describe() const;
};

/// Second-order sections of a digital Butterworth filter, one row
/// [b0 b1 b2 1 a1 a2] per section (as scipy.signal.butter(..., output="sos"),
/// up to the pairing of poles and zeros into sections). Cutoffs in Hz,
/// `sample_rate_Hz` > 0; throws std::invalid_argument for an order outside
/// 1..kMaxFilterOrder or a cutoff outside [f, 1 - f] x Nyquist
/// (f = kMinFilterCutoffFraction).
std::vector<std::array<double, 6>> ButterworthSections(const FilterOptions& filter,
                                                       double sample_rate_Hz);

/// Zero-phase filtering of each column of `values` (samples x channels) by the
/// sections (scipy.signal.sosfiltfilt with its default padding). Throws
/// std::invalid_argument when there are not more samples than the padding.
Eigen::MatrixXd FiltFilt(const std::vector<std::array<double, 6>>& sections,
                         const Eigen::MatrixXd& values);

/// Applies the chain above. `where` names the record in messages (a file name,
/// "simulated sensors"). Throws std::invalid_argument("<where>: <what>:
/// expected X, got Y") for an unknown channel, a window holding fewer than 4
/// samples, a cutoff at or above the Nyquist frequency, or a record too short
/// for the filter's padding.
TimeSeries ConditionRecord(const TimeSeries& series,
                           const ConditioningOptions& options,
                           const std::string& where);

}  // namespace podid
