#pragma once
// Discrete wavelet denoising with GSL (Donoho & Johnstone 1994), to clean
// recorded channels before POD. The signal is extended by mirror reflection
// to the next power of two, transformed with a Daubechies wavelet
// (gsl_wavelet_daubechies, `daubechies_order` = its number of coefficients,
// 4 = db2 ... 20 = db10), the detail coefficients of the `levels` finest
// levels are thresholded, and the inverse transform is cropped back to N.
//
// Noise level: sigma = MAD / 0.6745, the median absolute deviation of the
// finest detail coefficients (which white noise dominates), unless given.
// Universal threshold: lambda = threshold_scale * sigma * sqrt(2 ln N).
//   kSoft: d -> sign(d) max(|d| - lambda, 0)   (continuous; shrinks everything)
//   kHard: d -> d if |d| > lambda else 0      (keeps large coefficients intact)
// Units: sigma and lambda are in signal units (the transform is orthonormal).
// Choose `levels` to cover only the band above the signal: level j (1 =
// finest) spans fs / 2^(j+1) .. fs / 2^j. Vibration modes are not sparse at
// coarse levels, and soft thresholding there shrinks every mode coefficient
// by lambda (tests/wavelet/denoise_test.cpp measures this).

#include <Eigen/Core>
#include <string>
#include <string_view>

namespace podid::wavelet {

enum class ThresholdRule { kSoft, kHard };

/// "soft" / "hard"; the inverse throws std::invalid_argument naming the choices.
const char* ToString(ThresholdRule rule);
ThresholdRule ParseThresholdRule(std::string_view name);

struct DenoiseOptions {
  int daubechies_order = 8;  ///< even, 4..20 (GSL's k; db(k/2))
  ThresholdRule rule = ThresholdRule::kSoft;
  int levels = 0;                ///< finest detail levels thresholded; 0 = all
  double threshold_scale = 1.0;  ///< multiplies the universal threshold, > 0
  double noise_sigma = 0.0;      ///< > 0: use this noise std instead of the MAD estimate

  bool IsValid(std::string* why) const;
};

struct DenoiseSummary {
  double noise_sigma = 0.0;              ///< estimated (or given) noise std, signal units
  double threshold = 0.0;                ///< lambda, signal units
  int levels = 0;                        ///< detail levels thresholded
  Eigen::Index padded_length = 0;        ///< power of two >= N
  Eigen::Index coefficients = 0;         ///< detail coefficients examined
  Eigen::Index zeroed_coefficients = 0;  ///< of which |d| <= lambda
};

/// Denoised copy of `signal` (dim N >= 8), of any finite magnitude (scaled by
/// a power of two inside). Throws std::invalid_argument for too short or
/// non-finite signals and invalid options, std::overflow_error when the
/// denoised signal exceeds the largest double (a step near it rings above).
Eigen::VectorXd Denoise(const Eigen::Ref<const Eigen::VectorXd>& signal,
                        const DenoiseOptions& options = {},
                        DenoiseSummary* summary = nullptr);

}  // namespace podid::wavelet
