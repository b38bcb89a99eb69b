#include "podid/wavelet/ridge.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "podid/core/error.hpp"

namespace podid::wavelet {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Floor of |W|^2 (relative to the peak 1) in the ridge cost: far below any
// coefficient that can matter, far above the subnormal range.
constexpr double kTiny = 1e-300;

bool Fail(std::string* why, std::string message) {
  if (why != nullptr) *why = std::move(message);
  return false;
}

// Minimises sum_j cost(k_j, j) + lambda sum_j (x_{k_j} - x_{k_{j-1}})^2 over
// paths; costs are finite or +inf (a forbidden cell), and a column of +inf
// gives -1 there (the path restarts after it).
Eigen::VectorXi PenalisedPath(const Eigen::MatrixXd& cost,
                              const Eigen::VectorXd& x,
                              double lambda) {
  const Eigen::Index freqs = cost.rows(), times = cost.cols();
  Eigen::MatrixXi back(freqs, times);
  Eigen::VectorXi best(times);
  Eigen::VectorXd prev(freqs), next(freqs);
  std::vector<Eigen::Index> v(static_cast<std::size_t>(freqs));
  std::vector<double> z(static_cast<std::size_t>(freqs + 1));
  const auto argmin = [&](const Eigen::VectorXd& total) {
    int k_best = -1;
    double value = kInf;
    for (Eigen::Index k = 0; k < freqs; ++k) {
      if (total(k) < value) {
        value = total(k);
        k_best = static_cast<int>(k);
      }
    }
    return k_best;
  };
  prev = cost.col(0);
  back.col(0).setConstant(-1);
  best(0) = argmin(prev);
  for (Eigen::Index j = 1; j < times; ++j) {
    if (best(j - 1) < 0) {  // nothing reachable before: start afresh
      next = cost.col(j);
      back.col(j).setConstant(-1);
    } else if (lambda == 0.0) {
      const double floor = prev(best(j - 1));
      next = cost.col(j).array() + floor;
      back.col(j).setConstant(best(j - 1));
    } else {
      // Lower envelope of the parabolas prev(p) + lambda (x - x_p)^2.
      Eigen::Index top = -1;
      for (Eigen::Index p = 0; p < freqs; ++p) {
        if (!std::isfinite(prev(p))) continue;
        const double hp = prev(p) + lambda * x(p) * x(p);
        double s = -kInf;
        while (top >= 0) {
          const Eigen::Index q = v[static_cast<std::size_t>(top)];
          s = (hp - (prev(q) + lambda * x(q) * x(q))) / (2.0 * lambda * (x(p) - x(q)));
          if (s <= z[static_cast<std::size_t>(top)]) {
            --top;
          } else {
            break;
          }
        }
        ++top;
        v[static_cast<std::size_t>(top)] = p;
        z[static_cast<std::size_t>(top)] = top == 0 ? -kInf : s;
      }
      PODID_CHECK(top >= 0);  // best(j - 1) >= 0: prev has a finite entry
      z[static_cast<std::size_t>(top + 1)] = kInf;
      Eigen::Index e = 0;
      for (Eigen::Index q = 0; q < freqs; ++q) {
        while (z[static_cast<std::size_t>(e + 1)] < x(q)) ++e;
        const Eigen::Index p = v[static_cast<std::size_t>(e)];
        const double dx = x(q) - x(p);
        next(q) = cost(q, j) + prev(p) + lambda * dx * dx;
        back(q, j) = static_cast<int>(p);
      }
    }
    std::swap(prev, next);
    best(j) = argmin(prev);
  }
  Eigen::VectorXi path(times);
  int k = best(times - 1);
  for (Eigen::Index j = times - 1; j >= 0; --j) {
    path(j) = k;
    if (j > 0) k = k >= 0 ? back(k, j) : best(j - 1);
  }
  return path;
}

Eigen::VectorXi MaximumPath(const Eigen::MatrixXd& cost) {
  Eigen::VectorXi path(cost.cols());
  for (Eigen::Index j = 0; j < cost.cols(); ++j) {
    int k_best = -1;
    double value = kInf;
    for (Eigen::Index k = 0; k < cost.rows(); ++k) {
      if (cost(k, j) < value) {
        value = cost(k, j);
        k_best = static_cast<int>(k);
      }
    }
    path(j) = k_best;
  }
  return path;
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
  ThrowInvalid("ridge method", "one of max, penalised", "\"" + std::string(name) + "\"");
}

FrequencyEstimator ParseFrequencyEstimator(std::string_view name) {
  if (name == "phase") return FrequencyEstimator::kPhase;
  if (name == "scale") return FrequencyEstimator::kScale;
  ThrowInvalid("frequency estimator", "one of phase, scale", "\"" + std::string(name) + "\"");
}

bool RidgeOptions::IsValid(std::string* why) const {
  if (!std::isfinite(penalty_s) || penalty_s < 0.0) {
    return Fail(why,
                "RidgeOptions.penalty_s: expected a finite value >= 0, got " + ToText(penalty_s));
  }
  if (ridges < 1 || ridges > 16) {
    return Fail(why, "RidgeOptions.ridges: expected 1..16, got " + ToText(ridges));
  }
  if (!std::isfinite(separation_octaves) || separation_octaves <= 0.0) {
    return Fail(why, "RidgeOptions.separation_octaves: expected a finite value > 0, got " +
                         ToText(separation_octaves));
  }
  if (!(min_relative_magnitude >= 0.0 && min_relative_magnitude < 1.0)) {
    return Fail(why, "RidgeOptions.min_relative_magnitude: expected a value in [0, 1), got " +
                         ToText(min_relative_magnitude));
  }
  return true;
}

std::vector<Eigen::VectorXi> FindRidges(const Scalogram& scalogram, const RidgeOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument(why);
  const Eigen::Index times = scalogram.times(), freqs = scalogram.frequencies();
  if (times < 1 || freqs < 1 || scalogram.coefficients.rows() != times ||
      scalogram.coefficients.cols() != freqs) {
    ThrowInvalid("FindRidges: scalogram",
                 "a computed scalogram with complex coefficients (CwtOutput::kComplex)",
                 ToText(scalogram.coefficients.rows()) + " x " +
                     ToText(scalogram.coefficients.cols()) + " coefficients");
  }
  // cost(k, j) = -log|W(j, k)| + const, frequency-major for the per-time
  // sweeps. W is first scaled by a power of 2 (exact) to a peak of about 1 so
  // that |W|^2 neither overflows nor underflows (any finite W, e.g. from a
  // 1e300 signal); a non-finite coefficient is a forbidden cell (+inf).
  const Eigen::Map<const Eigen::ArrayXd> parts(
      reinterpret_cast<const double*>(scalogram.coefficients.data()), 2 * times * freqs);
  double top = parts.abs().template maxCoeff<Eigen::PropagateNaN>();
  const bool all_finite = std::isfinite(top);
  if (!all_finite) {
    top = 0.0;
    for (Eigen::Index i = 0; i < parts.size(); ++i) {
      if (std::isfinite(parts(i))) top = std::max(top, std::abs(parts(i)));
    }
  }
  int exponent = 0;
  std::frexp(top, &exponent);
  const double scale = std::ldexp(1.0, -exponent);
  // Blocks of kBlock times: |W|^2 of each frequency's contiguous segment,
  // then Eigen's vectorised log on a plain array, stored frequency-major
  // (the block of cost stays in cache).
  constexpr Eigen::Index kBlock = 64;
  Eigen::MatrixXd cost(freqs, times);
  Eigen::ArrayXd power(kBlock);
  for (Eigen::Index j0 = 0; j0 < times; j0 += kBlock) {
    const Eigen::Index count = std::min(kBlock, times - j0);
    for (Eigen::Index k = 0; k < freqs; ++k) {
      const double* w = reinterpret_cast<const double*>(scalogram.coefficients.col(k).data() + j0);
      for (Eigen::Index i = 0; i < count; ++i) {
        const double re = w[2 * i] * scale, im = w[2 * i + 1] * scale;
        power(i) = std::max(re * re + im * im, kTiny);
      }
      power.head(count) = -0.5 * power.head(count).log();
      for (Eigen::Index i = 0; i < count; ++i) cost(k, j0 + i) = power(i);
    }
  }
  if (!all_finite) {
    for (Eigen::Index i = 0; i < cost.size(); ++i) {
      if (!std::isfinite(cost.data()[i])) cost.data()[i] = kInf;
    }
  }
  const Eigen::VectorXd x = scalogram.frequencies_Hz.array().log();
  const double lambda = options.penalty_s / scalogram.step_s;
  const double half_width = options.separation_octaves * std::numbers::ln2;
  std::vector<Eigen::VectorXi> paths;
  for (int r = 0; r < options.ridges; ++r) {
    Eigen::VectorXi path = options.method == RidgeMethod::kMaximum ? MaximumPath(cost)
                                                                   : PenalisedPath(cost, x, lambda);
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
  if (scalogram.coefficients.rows() != times || scalogram.coefficients.cols() != freqs) {
    ThrowInvalid("TrackRidge: scalogram",
                 "a computed scalogram with complex coefficients (CwtOutput::kComplex)",
                 ToText(scalogram.coefficients.rows()) + " x " +
                     ToText(scalogram.coefficients.cols()) + " coefficients");
  }
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
  const MorletWavelet& wavelet = scalogram.wavelet;
  const double kappa = wavelet.RidgeAngularFrequency();
  RidgeTrack track;
  track.time_s = scalogram.time_s;
  track.frequency_index = path;
  track.frequency_Hz.setConstant(times, kNaN);
  track.grid_frequency_Hz.setConstant(times, kNaN);
  track.amplitude.setConstant(times, kNaN);
  track.inside_coi.setConstant(times, false);
  const double unit = scalogram.coefficient_scale;
  const auto& s = scalogram.scales_s;
  // The refined (vertex) scale at each time, or the grid scale.
  Eigen::VectorXd vertex_s = Eigen::VectorXd::Constant(times, kNaN);
  for (Eigen::Index j = 0; j < times; ++j) {
    const int k = path(j);
    if (k < 0) continue;
    track.inside_coi(j) = scalogram.InsideCoi(j, k);
    track.grid_frequency_Hz(j) = scalogram.frequencies_Hz(k);
    const double yb = std::log(std::abs(scalogram.coefficients(j, k)));
    double scale = s(k), peak = yb;
    if (k > 0 && k + 1 < freqs && std::isfinite(yb)) {
      // std::abs is hypot: no overflow for any finite W.
      const double ya = std::log(std::abs(scalogram.coefficients(j, k - 1)));
      const double yc = std::log(std::abs(scalogram.coefficients(j, k + 1)));
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
    vertex_s(j) = scale;
    track.amplitude(j) = std::exp(peak) * unit / wavelet.UnitCosineMagnitude(scale);
    if (options.estimator == FrequencyEstimator::kScale) {
      track.frequency_Hz(j) = options.parabolic_refinement
                                  ? kappa / (2.0 * std::numbers::pi * scale)
                                  : scalogram.frequencies_Hz(k);
    }
  }
  if (options.estimator == FrequencyEstimator::kPhase) {
    // Phase IF at the path's scales and the neighbour towards the vertex,
    // interpolated linearly in s to the vertex: the IF of a chirp drifts with
    // the scale offset, a tone's does not.
    const auto neighbour = [&](Eigen::Index j) -> int {
      const int k = path(j);
      if (options.parabolic_refinement == false || vertex_s(j) == s(k)) return k;
      const int n = vertex_s(j) > s(k) ? k - 1 : k + 1;  // scales descend with k
      return n >= 0 && n < freqs ? n : k;
    };
    std::vector<int> used;
    for (Eigen::Index j = 0; j < times; ++j) {
      if (path(j) < 0) continue;
      used.push_back(path(j));
      used.push_back(neighbour(j));
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
        // Im(conj(W) dW/dt) / |W|^2 = Im((dW/dt) / W): the complex division
        // scales internally, so it neither overflows nor underflows.
        const std::complex<double> w = scalogram.coefficients(j, k);
        frequency(j, static_cast<Eigen::Index>(u)) =
            w != 0.0 ? std::imag(derivative(j) / w) / (2.0 * std::numbers::pi) : kNaN;
      }
    }
    for (Eigen::Index j = 0; j < times; ++j) {
      const int k = path(j);
      if (k < 0) continue;
      const int n = neighbour(j);
      const double fk = frequency(j, slot(k));
      if (n == k) {
        track.frequency_Hz(j) = fk;
      } else {
        const double fn = frequency(j, slot(n));
        track.frequency_Hz(j) = fk + (fn - fk) * (vertex_s(j) - s(k)) / (s(n) - s(k));
      }
    }
  }
  // Screening: where |W| on the path is a negligible fraction of the path's
  // peak, the phase (and so the IF) is rounding noise.
  track.screened.setConstant(times, false);
  double peak = 0.0;
  for (Eigen::Index j = 0; j < times; ++j) {
    if (path(j) >= 0) peak = std::max(peak, std::abs(scalogram.coefficients(j, path(j))));
  }
  for (Eigen::Index j = 0; j < times; ++j) {
    if (path(j) < 0) continue;
    if (std::abs(scalogram.coefficients(j, path(j))) <= options.min_relative_magnitude * peak) {
      track.screened(j) = true;
      track.inside_coi(j) = false;
      track.frequency_Hz(j) = kNaN;
    }
  }
  return track;
}

bool RidgeFrequencyOptions::IsValid(std::string* why) const {
  return cwt.IsValid(why) && ridge.IsValid(why);
}

RidgeFrequencyEstimator::RidgeFrequencyEstimator(const RidgeFrequencyOptions& options)
    : options_(options), transform_(options.cwt) {
  std::string why;
  if (!options_.IsValid(&why)) throw std::invalid_argument(why);
  options_.ridge.ridges = 1;
}

const RidgeTrack& RidgeFrequencyEstimator::Estimate(const Eigen::Ref<const Eigen::VectorXd>& signal,
                                                    double step_s) {
  transform_.Compute(signal, step_s, &scalogram_);
  const std::vector<Eigen::VectorXi> paths = FindRidges(scalogram_, options_.ridge);
  track_ = TrackRidge(scalogram_, paths.front(), options_.ridge, &transform_);
  return track_;
}

RidgeTrack RidgeFrequency(const Eigen::Ref<const Eigen::VectorXd>& signal,
                          double step_s,
                          const RidgeFrequencyOptions& options) {
  RidgeFrequencyEstimator estimator(options);
  return estimator.Estimate(signal, step_s);
}

}  // namespace podid::wavelet
