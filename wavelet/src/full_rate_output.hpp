#pragma once
// Where the full-rate CWT writes (FullRateCwt, BlockedScales).

#include <complex>

namespace podid::wavelet::internal {

/// Exactly one of the three, each times x scales, column-major.
struct FullRateOutput {
  std::complex<double>* complex = nullptr;       ///< W (CwtOutput::kComplex)
  std::complex<float>* complex_float = nullptr;  ///< W rounded to float (kComplexFloat)
  float* magnitude = nullptr;                    ///< |W| rounded to float (kMagnitudeFloat)
};

}  // namespace podid::wavelet::internal
