#pragma once
// The checks of what reads a Scalogram (ridges, inverse, synchrosqueezing):
// a Scalogram is a plain struct that a caller may fill or resize by hand, its
// vectors are indexed by time and frequency, and its dW/dt is its
// transform's last Compute()'s.

#include <cmath>
#include <string>

#include "podid/core/error.hpp"
#include "podid/wavelet/cwt.hpp"

namespace podid::wavelet::internal {

/// Throws std::invalid_argument naming `where` unless scales_s has one entry
/// per frequency, coi_frequency_Hz one per output time and frequencies_Hz
/// ascends from above 0, as Compute() writes them, and the scalars it is read
/// with are too: its wavelet valid (a hand-set NaN beta hung the inverse), its
/// step and coefficient_scale finite and > 0 (a negative step aborted the
/// ridge), its decimation >= 1.
inline void CheckScalogramShape(const Scalogram& scalogram, const char* where) {
  std::string why;
  if (!scalogram.wavelet.IsValid(&why)) ThrowInvalid(where, "a valid wavelet", why);
  if (!(std::isfinite(scalogram.step_s) && scalogram.step_s > 0.0)) {
    ThrowInvalid(where, "step_s finite and > 0, as Compute() writes it", ToText(scalogram.step_s));
  }
  if (!(std::isfinite(scalogram.coefficient_scale) && scalogram.coefficient_scale > 0.0)) {
    ThrowInvalid(where, "coefficient_scale finite and > 0, as Compute() writes it",
                 ToText(scalogram.coefficient_scale));
  }
  if (scalogram.decimation < 1) {
    ThrowInvalid(where, "decimation >= 1, as Compute() writes it", ToText(scalogram.decimation));
  }
  const Eigen::Index times = scalogram.times(), freqs = scalogram.frequencies();
  for (Eigen::Index k = 0; k < freqs; ++k) {
    const double f = scalogram.frequencies_Hz(k);
    if (!(f > (k > 0 ? scalogram.frequencies_Hz(k - 1) : 0.0)) || !std::isfinite(f)) {
      ThrowInvalid(where, "frequencies_Hz finite, > 0 and ascending, as Compute() writes them",
                   "frequencies_Hz(" + ToText(k) + ") = " + ToText(f));
    }
  }
  if (scalogram.scales_s.size() != freqs || scalogram.coi_frequency_Hz.size() != times) {
    ThrowInvalid(where,
                 "scales_s (" + ToText(freqs) + " frequencies) and coi_frequency_Hz (" +
                     ToText(times) + " times) of the scalogram's own sizes, as Compute() writes them",
                 ToText(scalogram.scales_s.size()) + " scales and " +
                     ToText(scalogram.coi_frequency_Hz.size()) + " cone frequencies");
  }
}

/// CheckScalogramShape, after the coefficients: complex (CwtOutput::kComplex,
/// the only output with a phase), one row per output time and one column per
/// frequency. What reads W (ridges, inverse, synchrosqueezing) calls it first.
inline void CheckComplexScalogram(const Scalogram& scalogram, const char* where) {
  const Eigen::Index times = scalogram.times(), freqs = scalogram.frequencies();
  if (times < 1 || freqs < 1 || scalogram.coefficients.rows() != times ||
      scalogram.coefficients.cols() != freqs) {
    ThrowInvalid(where,
                 "a computed scalogram with complex coefficients (CwtOutput::kComplex), " +
                     ToText(times) + " x " + ToText(freqs) + " as time_s and frequencies_Hz",
                 ToText(scalogram.coefficients.rows()) + " x " +
                     ToText(scalogram.coefficients.cols()) + " coefficients");
  }
  CheckScalogramShape(scalogram, where);
}

/// TimeDerivative's values belong to the scalogram only if the transform's
/// last Compute() wrote it (CwtTransform::Produced): else what reads them
/// (the reassignment, the phase IF) would use another signal's dW/dt, or
/// index past it for another length. Throws std::invalid_argument naming `where`.
inline void CheckProduced(const CwtTransform& transform,
                          const Scalogram& scalogram,
                          const char* where) {
  if (!transform.Produced(scalogram)) {
    ThrowInvalid(where, "the CwtTransform whose last Compute() wrote the scalogram",
                 "one that did not (another transform, or it has computed since)");
  }
}

}  // namespace podid::wavelet::internal
