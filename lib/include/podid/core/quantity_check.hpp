#pragma once
// Detects a measured quantity that is not the one the case declares
// ([sensors] quantity): accelerations recorded but displacements declared, or
// the reverse (issue 12, item 5). Between displacement x, velocity v = i w x
// and acceleration a = -w^2 x the amplitude spectra differ by w^k, so the
// ratio |measured| / |simulated| of two records of the same motion grows as
// f^k: k = 0 when the quantities agree, +2 for an acceleration record
// compared with simulated displacements, -2 for the reverse, +-1 with
// velocities. Units are SI.

#include <string>

#include "podid/core/case_spec.hpp"
#include "podid/core/time_series.hpp"

namespace podid {

struct QuantityCheck {
  /// False when too few spectral peaks to tell (fewer than
  /// kQuantityCheckMinPeaks, or spanning less than a factor 1.5 in frequency:
  /// one mode alone cannot tell a quantity from a gain).
  bool determined = false;
  /// Least-squares slope k of log10(|measured| / |simulated|) against
  /// log10(f) at the simulated spectrum's peaks (dimensionless; 20 k dB/decade).
  double exponent = 0.0;
  int bins = 0;         ///< peaks used
  double low_Hz = 0.0;  ///< lowest and highest peak
  double high_Hz = 0.0;
  bool mismatch = false;  ///< |exponent| >= 0.5: not the declared quantity
  /// The measured quantity the exponent points to (declared + round(k),
  /// clamped to displacement..acceleration); the declared one without a mismatch.
  SensorQuantity likely = SensorQuantity::kDisplacement;
  std::string message;  ///< one line; empty without a mismatch
};

/// Fewest spectral peaks CheckMeasuredQuantity fits.
inline constexpr int kQuantityCheckMinPeaks = 2;

/// Compares the Hann-windowed power spectra (summed over channels, means
/// removed) of `measured` and `simulated` (same channels; their first
/// min(samples) samples, at measured's step) at the peaks of the simulated
/// one (its modes; a bin that is the largest within +-max(3, k / 20) bins,
/// both spectra above 1e-8 of their largest bin, the measured one more than
/// 10 times its median bin, the white-noise floor, which is subtracted
/// before the ratio). `declared` is the case's quantity.
QuantityCheck CheckMeasuredQuantity(const TimeSeries& measured,
                                    const TimeSeries& simulated,
                                    SensorQuantity declared);

const char* ToString(SensorQuantity quantity);

}  // namespace podid
