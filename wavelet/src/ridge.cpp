#include "podid/wavelet/ridge.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "podid/core/error.hpp"
#include "ridge_cost.hpp"
#include "ridge_programme.hpp"
#include "ridge_sample.hpp"
#include "scalogram_check.hpp"

namespace podid::wavelet {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool Fail(std::string* why, std::string message) {
  if (why != nullptr) *why = std::move(message);
  return false;
}

}  // namespace

const char* ToString(RidgeMethod method) {
  return method == RidgeMethod::kMaximum ? "max" : "penalised";
}
const char* ToString(FrequencyEstimator estimator) {
  return estimator == FrequencyEstimator::kPhase ? "phase" : "scale";
}

RidgeMethod ParseRidgeMethod(std::string_view name) {
  if (name == "max") return RidgeMethod::kMaximum;
  if (name == "penalised" || name == "penalized") return RidgeMethod::kPenalised;
  ThrowInvalid("ridge method", "one of max, penalised", Excerpt(name));
}

FrequencyEstimator ParseFrequencyEstimator(std::string_view name) {
  if (name == "phase") return FrequencyEstimator::kPhase;
  if (name == "scale") return FrequencyEstimator::kScale;
  ThrowInvalid("frequency estimator", "one of phase, scale", Excerpt(name));
}

bool RidgeOptions::IsValid(std::string* why) const {
  if (!std::isfinite(penalty_s) || penalty_s < 0.0) {
    return Fail(why,
                "RidgeOptions.penalty_s: expected a finite value >= 0, got " + ToText(penalty_s));
  }
  if (ridges < 1 || ridges > kMaxRidges) {
    return Fail(
        why, "RidgeOptions.ridges: expected 1.." + ToText(kMaxRidges) + ", got " + ToText(ridges));
  }
  if (!std::isfinite(separation_octaves) || separation_octaves <= 0.0) {
    return Fail(why, "RidgeOptions.separation_octaves: expected a finite value > 0, got " +
                         ToText(separation_octaves));
  }
  if (!(min_relative_magnitude >= 0.0 && min_relative_magnitude < 1.0)) {
    return Fail(why, "RidgeOptions.min_relative_magnitude: expected a value in [0, 1), got " +
                         ToText(min_relative_magnitude));
  }
  // Enums are ints underneath: another value gave all-NaN frequencies.
  if (method != RidgeMethod::kMaximum && method != RidgeMethod::kPenalised) {
    return Fail(why, "RidgeOptions.method: expected kMaximum or kPenalised, got " +
                         ToText(static_cast<int>(method)));
  }
  if (estimator != FrequencyEstimator::kPhase && estimator != FrequencyEstimator::kScale) {
    return Fail(why, "RidgeOptions.estimator: expected kPhase or kScale, got " +
                         ToText(static_cast<int>(estimator)));
  }
  return true;
}

std::vector<Eigen::VectorXi> FindRidges(const Scalogram& scalogram, const RidgeOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument(why);
  const Eigen::Index times = scalogram.times(), freqs = scalogram.frequencies();
  internal::CheckComplexScalogram(scalogram, "FindRidges: scalogram");
  // cost(k, j) = -log|W(j, k)| + const, frequency-major for the per-time
  // sweeps. W is first scaled by a power of 2 (exact) to a peak of about 1 so
  // that |W|^2 neither overflows nor underflows (any finite W, e.g. from a
  // 1e300 signal); a non-finite coefficient is a forbidden cell (+inf).
  bool all_finite = true;
  const double scale = internal::UnitScale(scalogram.coefficients, &all_finite);
  // Blocks of kBlock times: -log|W| of each frequency's contiguous segment
  // (a vectorised logarithm), stored frequency-major (the block of cost stays
  // in cache).
  constexpr Eigen::Index kBlock = 64;
  Eigen::MatrixXd cost(freqs, times);
  Eigen::ArrayXd segment(kBlock);
  for (Eigen::Index j0 = 0; j0 < times; j0 += kBlock) {
    const Eigen::Index count = std::min(kBlock, times - j0);
    for (Eigen::Index k = 0; k < freqs; ++k) {
      internal::RidgeCost(scalogram.coefficients.col(k).data() + j0, count, scale, segment.data());
      for (Eigen::Index i = 0; i < count; ++i) cost(k, j0 + i) = segment(i);
    }
  }
  if (!all_finite) {  // a non-finite coefficient is a forbidden cell
    for (Eigen::Index j = 0; j < times; ++j) {
      for (Eigen::Index k = 0; k < freqs; ++k) {
        const std::complex<double> w = scalogram.coefficients(j, k);
        if (!std::isfinite(w.real()) || !std::isfinite(w.imag())) cost(k, j) = kInf;
      }
    }
  }
  const Eigen::VectorXd x = scalogram.frequencies_Hz.array().log();
  internal::CheckRidgePenalty(options.penalty_s, scalogram.step_s, x);
  const double lambda = options.penalty_s / scalogram.step_s;
  const double half_width = options.separation_octaves * std::numbers::ln2;
  std::vector<Eigen::VectorXi> paths;
  for (int r = 0; r < options.ridges; ++r) {
    internal::RidgeProgramme programme(x, lambda, options.method == RidgeMethod::kMaximum);
    programme.Reset(times);
    programme.PushLast(cost.data(), times, 1, freqs);
    Eigen::VectorXi path = programme.Path();
    for (Eigen::Index j = 0; j < times && r + 1 < options.ridges; ++j) {
      if (path(j) < 0) continue;
      const Eigen::Index c = path(j);
      // Exclude the ridge's own peak: both flanks while |W| keeps falling
      // (else the next ridge would sit on this one's skirt) ...
      Eigen::Index hi = c, lo = c;
      while (hi + 1 < freqs && cost(hi + 1, j) >= cost(hi, j)) ++hi;
      while (lo > 0 && cost(lo - 1, j) >= cost(lo, j)) --lo;
      // ... and at least separation_octaves either side.
      for (Eigen::Index k = 0; k < freqs; ++k) {
        if ((k >= lo && k <= hi) || std::abs(x(k) - x(c)) < half_width) cost(k, j) = kInf;
      }
    }
    paths.push_back(std::move(path));
  }
  return paths;
}

RidgeTrack TrackRidge(const Scalogram& scalogram,
                      const Eigen::VectorXi& path,
                      const RidgeOptions& options,
                      const CwtTransform* transform) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument(why);
  const Eigen::Index times = scalogram.times(), freqs = scalogram.frequencies();
  internal::CheckComplexScalogram(scalogram, "TrackRidge: scalogram");
  if (path.size() != times) {
    ThrowInvalid("TrackRidge: path", "one index per output time (" + ToText(times) + ")",
                 ToText(path.size()));
  }
  for (Eigen::Index j = 0; j < times; ++j) {
    if (path(j) < -1 || path(j) >= freqs) {
      ThrowInvalid("TrackRidge: path(" + ToText(j) + ")",
                   "-1 (no ridge) or a frequency index 0.." + ToText(freqs - 1), ToText(path(j)));
    }
  }
  if (options.estimator == FrequencyEstimator::kPhase && transform == nullptr) {
    ThrowInvalid("TrackRidge: transform", "the CwtTransform that computed the scalogram (kPhase)",
                 "null");
  }
  if (options.estimator == FrequencyEstimator::kPhase) {
    internal::CheckProduced(*transform, scalogram, "TrackRidge: transform (kPhase)");
  }
  const MorletWavelet& wavelet = scalogram.wavelet;
  const double kappa = wavelet.RidgeAngularFrequency();
  RidgeTrack track;
  track.time_s = scalogram.time_s;
  track.frequency_index = path;
  track.frequency_Hz.setConstant(times, kNaN);
  track.grid_frequency_Hz.setConstant(times, kNaN);
  track.amplitude.setConstant(times, kNaN);
  track.inside_coi.setConstant(times, false);
  const auto& s = scalogram.scales_s;
  const auto& w = scalogram.coefficients;
  std::vector<internal::RidgeSample> samples(static_cast<std::size_t>(times));
  for (Eigen::Index j = 0; j < times; ++j) {
    const int k = path(j);
    if (k < 0) continue;
    track.inside_coi(j) = scalogram.InsideCoi(j, k);
    track.grid_frequency_Hz(j) = scalogram.frequencies_Hz(k);
    const internal::RidgeSample& r = samples[static_cast<std::size_t>(j)] =
        internal::RefineRidgeSample(wavelet, s, k, w(j, k > 0 ? k - 1 : k), w(j, k),
                                    w(j, k + 1 < freqs ? k + 1 : k), scalogram.coefficient_scale,
                                    options.parabolic_refinement);
    track.amplitude(j) = r.amplitude;
    if (options.estimator == FrequencyEstimator::kScale) {
      track.frequency_Hz(j) = options.parabolic_refinement
                                  ? kappa / (2.0 * std::numbers::pi * r.vertex_s)
                                  : scalogram.frequencies_Hz(k);
    }
  }
  if (options.estimator == FrequencyEstimator::kPhase) {
    // Phase IF at the path's scales and the neighbour towards the vertex,
    // interpolated linearly in s to the vertex: the IF of a chirp drifts with
    // the scale offset, a tone's does not.
    std::vector<int> used;
    for (Eigen::Index j = 0; j < times; ++j) {
      if (path(j) < 0) continue;
      used.push_back(path(j));
      used.push_back(samples[static_cast<std::size_t>(j)].neighbour);
    }
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    const auto slot = [&](int k) {
      return std::lower_bound(used.begin(), used.end(), k) - used.begin();
    };
    Eigen::MatrixXd frequency(times, static_cast<Eigen::Index>(used.size()));
    Eigen::VectorXcd derivative;
    for (std::size_t u = 0; u < used.size(); ++u) {
      const int k = used[u];
      transform->TimeDerivative(k, &derivative);
      PODID_CHECK(derivative.size() == times);
      for (Eigen::Index j = 0; j < times; ++j) {
        frequency(j, static_cast<Eigen::Index>(u)) = internal::PhaseFrequency_Hz(w(j, k), derivative(j));
      }
    }
    for (Eigen::Index j = 0; j < times; ++j) {
      const int k = path(j);
      if (k < 0) continue;
      const internal::RidgeSample& r = samples[static_cast<std::size_t>(j)];
      const double fk = frequency(j, slot(k));
      track.frequency_Hz(j) =
          r.neighbour == k ? fk
                           : fk + (frequency(j, slot(r.neighbour)) - fk) * (r.vertex_s - s(k)) /
                                      (s(r.neighbour) - s(k));
    }
  }
  // Screening: where |W| on the path is a negligible fraction of the path's
  // peak, the phase (and so the IF) is rounding noise.
  track.screened.setConstant(times, false);
  double peak = 0.0;
  for (Eigen::Index j = 0; j < times; ++j) {
    if (path(j) >= 0) peak = std::max(peak, std::abs(w(j, path(j))));
  }
  for (Eigen::Index j = 0; j < times; ++j) {
    if (path(j) < 0) continue;
    if (std::abs(w(j, path(j))) <= options.min_relative_magnitude * peak) {
      track.screened(j) = true;
      track.inside_coi(j) = false;
      track.frequency_Hz(j) = kNaN;
    }
  }
  internal::CheckTrackFinite(track, "TrackRidge");
  return track;
}

namespace internal {

namespace {

// |W|^2 is safe to form (no overflow, no subnormal) for |re|, |im| within
// these: sqrt of the largest double / 2 and of the smallest normal * 2^54.
constexpr double kSafeHigh = 0x1p+510, kSafeLow = 0x1p-480;

bool SquaresAreSafe(std::complex<double> w) {
  const double top = std::max(std::abs(w.real()), std::abs(w.imag()));
  return top < kSafeHigh && top > kSafeLow;
}

// log|W|: half the log of |W|^2 where that is safe (std::abs is hypot,
// 3 of the ridge track's 10 libm calls a sample), else log(hypot).
double LogMagnitude(std::complex<double> w) {
  return SquaresAreSafe(w) ? 0.5 * std::log(std::norm(w)) : std::log(std::abs(w));
}

}  // namespace

RidgeSample RefineRidgeSample(const MorletWavelet& wavelet,
                              const Eigen::VectorXd& s,
                              int k,
                              std::complex<double> wa,
                              std::complex<double> wb,
                              std::complex<double> wc,
                              double unit,
                              bool parabolic_refinement) {
  const Eigen::Index freqs = s.size();
  const double yb = LogMagnitude(wb);
  double scale = s(k), peak = yb;
  if (k > 0 && k + 1 < freqs && std::isfinite(yb)) {
    const double ya = LogMagnitude(wa);
    const double yc = LogMagnitude(wc);
    if (std::isfinite(ya) && std::isfinite(yc) && yb >= ya && yb >= yc && (yb > ya || yb > yc)) {
      // Parabola through (s_{k-1}, ya), (s_k, yb), (s_{k+1}, yc) (divided differences).
      const double a = s(k - 1), b = s(k), c = s(k + 1);
      const double d1 = (yb - ya) / (b - a), d2 = (yc - yb) / (c - b);
      const double curvature = (d2 - d1) / (c - a);
      if (curvature < 0.0) {
        scale = 0.5 * (a + b) - d1 / (2.0 * curvature);
        peak = ya + d1 * (scale - a) + curvature * (scale - a) * (scale - b);
      }
    }
  }
  RidgeSample r;
  r.vertex_s = scale;
  r.amplitude = std::exp(peak) * unit / wavelet.UnitCosineMagnitude(scale);
  r.neighbour = k;
  if (parabolic_refinement && scale != s(k)) {
    const int n = scale > s(k) ? k - 1 : k + 1;  // scales descend with k
    if (n >= 0 && n < freqs) r.neighbour = n;
  }
  return r;
}

double PhaseFrequency_Hz(std::complex<double> w, std::complex<double> dw_dt) {
  if (w == 0.0) return kNaN;
  // Im(dw conj(w)) / |w|^2 without the complex division's scaling (a libgcc
  // call, __divdc3) where nothing can overflow or underflow.
  if (SquaresAreSafe(w) && SquaresAreSafe(dw_dt)) {
    return (dw_dt.imag() * w.real() - dw_dt.real() * w.imag()) /
           (std::norm(w) * (2.0 * std::numbers::pi));
  }
  return std::imag(dw_dt / w) / (2.0 * std::numbers::pi);
}

}  // namespace internal

bool RidgeFrequencyOptions::IsValid(std::string* why) const {
  if (!(block_cells >= 1024.0 && block_cells <= 67108864.0)) {
    return Fail(why, "RidgeFrequencyOptions.block_cells: expected 2^10..2^26, got " + ToText(block_cells));
  }
  return cwt.IsValid(why) && ridge.IsValid(why);
}

RidgeTrack RidgeFrequency(const Eigen::Ref<const Eigen::VectorXd>& signal,
                          double step_s,
                          const RidgeFrequencyOptions& options) {
  RidgeFrequencyEstimator estimator(options);
  return estimator.Estimate(signal, step_s);
}

}  // namespace podid::wavelet
