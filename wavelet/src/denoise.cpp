#include "podid/wavelet/denoise.hpp"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_wavelet.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

#include "podid/core/error.hpp"
#include "signal_check.hpp"

namespace podid::wavelet {
namespace {

struct WaveletFree {
  void operator()(gsl_wavelet* w) const { gsl_wavelet_free(w); }
};
struct WorkspaceFree {
  void operator()(gsl_wavelet_workspace* w) const { gsl_wavelet_workspace_free(w); }
};

double Median(std::vector<double> values) {
  PODID_CHECK(!values.empty());
  const std::size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid), values.end());
  double median = values[mid];
  if (values.size() % 2 == 0) {
    median = 0.5 * (median + *std::max_element(values.begin(),
                                               values.begin() + static_cast<std::ptrdiff_t>(mid)));
  }
  return median;
}

}  // namespace

const char* ToString(ThresholdRule rule) { return rule == ThresholdRule::kSoft ? "soft" : "hard"; }

ThresholdRule ParseThresholdRule(std::string_view name) {
  if (name == "soft") return ThresholdRule::kSoft;
  if (name == "hard") return ThresholdRule::kHard;
  ThrowInvalid("threshold rule", "one of soft, hard", Excerpt(name));
}

bool DenoiseOptions::IsValid(std::string* why) const {
  std::string message;
  if (daubechies_order < 4 || daubechies_order > 20 || daubechies_order % 2 != 0) {
    message = "DenoiseOptions.daubechies_order: expected an even number in 4..20, got " +
              ToText(daubechies_order);
  } else if (levels < 0) {
    message = "DenoiseOptions.levels: expected >= 0 (0 = all), got " + ToText(levels);
  } else if (!std::isfinite(threshold_scale) || threshold_scale <= 0.0) {
    message = "DenoiseOptions.threshold_scale: expected a finite value > 0, got " +
              ToText(threshold_scale);
  } else if (!std::isfinite(noise_sigma) || noise_sigma < 0.0) {
    message = "DenoiseOptions.noise_sigma: expected a finite value >= 0 (0 = estimate), got " +
              ToText(noise_sigma);
  } else if (rule != ThresholdRule::kSoft && rule != ThresholdRule::kHard) {
    // An int cast to the enum was read as kHard.
    message = "DenoiseOptions.rule: expected kSoft or kHard, got " + ToText(static_cast<int>(rule));
  }
  if (message.empty()) return true;
  if (why != nullptr) *why = message;
  return false;
}

Eigen::VectorXd Denoise(const Eigen::Ref<const Eigen::VectorXd>& signal,
                        const DenoiseOptions& options,
                        DenoiseSummary* summary) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument(why);
  const Eigen::Index n = signal.size();
  if (n < 8) ThrowInvalid("Denoise: signal", "at least 8 samples", ToText(n) + " samples");
  if (!signal.allFinite()) ThrowInvalid("Denoise: signal", "finite values", "NaN or Inf");

  Eigen::Index p = 1;
  int depth = 0;
  while (p < n) {
    p *= 2;
    ++depth;
  }
  // Scaled by 2^-e (exact) to a peak in [1, 2), as Cwt does: a tone of
  // 1.7e308 overflowed in the transform and came back inf, and 1e-310's
  // subnormals lost their bits in it. Other inputs give the same bits as
  // unscaled: every step commutes with a power of two.
  const int exponent = internal::PeakExponent(signal);
  // Mirror extension x_0 .. x_{N-1}, x_{N-2}, ... (period 2N - 2) up to P.
  std::vector<double> data(static_cast<std::size_t>(p));
  const Eigen::Index period = std::max<Eigen::Index>(2 * n - 2, 1);
  for (Eigen::Index i = 0; i < p; ++i) {
    const Eigen::Index r = i % period;
    data[static_cast<std::size_t>(i)] = std::ldexp(signal(r < n ? r : period - r), -exponent);
  }

  std::unique_ptr<gsl_wavelet, WaveletFree> wavelet(gsl_wavelet_alloc(
      gsl_wavelet_daubechies, static_cast<std::size_t>(options.daubechies_order)));
  std::unique_ptr<gsl_wavelet_workspace, WorkspaceFree> workspace(
      gsl_wavelet_workspace_alloc(static_cast<std::size_t>(p)));
  PODID_CHECK(wavelet != nullptr && workspace != nullptr);
  PODID_CHECK(gsl_wavelet_transform_forward(wavelet.get(), data.data(), 1,
                                            static_cast<std::size_t>(p),
                                            workspace.get()) == GSL_SUCCESS);

  // GSL layout: data[0] is the scaling coefficient, level j (1 = coarsest)
  // holds 2^(j-1) details at [2^(j-1), 2^j); the finest level is [P/2, P).
  const int levels = options.levels == 0 ? depth : std::min(options.levels, depth);
  const Eigen::Index first = p >> levels;
  // sigma and lambda in units of 2^e here, in signal units in the summary.
  double sigma = std::ldexp(options.noise_sigma, -exponent);
  if (options.noise_sigma == 0.0) {
    std::vector<double> finest;
    finest.reserve(static_cast<std::size_t>(p / 2));
    for (Eigen::Index i = p / 2; i < p; ++i) {
      finest.push_back(std::abs(data[static_cast<std::size_t>(i)]));
    }
    sigma = Median(std::move(finest)) / 0.6744897501960817;  // Phi^-1(3/4)
  }
  const double root = std::sqrt(2.0 * std::log(static_cast<double>(n)));
  const double lambda = options.threshold_scale * sigma * root;
  Eigen::Index zeroed = 0;
  for (Eigen::Index i = first; i < p; ++i) {
    double& d = data[static_cast<std::size_t>(i)];
    if (std::abs(d) <= lambda) {
      d = 0.0;
      ++zeroed;
    } else if (options.rule == ThresholdRule::kSoft) {
      d -= std::copysign(lambda, d);
    }
  }
  PODID_CHECK(gsl_wavelet_transform_inverse(wavelet.get(), data.data(), 1,
                                            static_cast<std::size_t>(p),
                                            workspace.get()) == GSL_SUCCESS);
  Eigen::VectorXd denoised(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    denoised(i) = std::ldexp(data[static_cast<std::size_t>(i)], exponent);
  }
  // Finite input, and still infinite: the denoised signal itself exceeds the
  // largest double (a step of 1.8e308 rings above it when details are cut).
  if (!denoised.allFinite()) {
    throw std::overflow_error(
        "Denoise: the denoised signal overflowed double precision (above 1.8e308); scale the "
        "signal down");
  }
  if (summary != nullptr) {
    // A given sigma as given; lambda from it in signal units (inf only if
    // the true value exceeds the largest double).
    const double signal_sigma =
        options.noise_sigma == 0.0 ? std::ldexp(sigma, exponent) : options.noise_sigma;
    summary->noise_sigma = signal_sigma;
    summary->threshold = options.threshold_scale * signal_sigma * root;
    summary->levels = levels;
    summary->padded_length = p;
    summary->coefficients = p - first;
    summary->zeroed_coefficients = zeroed;
  }
  return denoised;
}

}  // namespace podid::wavelet
