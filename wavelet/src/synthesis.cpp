// The inverse and synchrosqueezed CWT (podid/wavelet/synthesis.hpp).
#include "podid/wavelet/synthesis.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "podid/core/error.hpp"
#include "ridge_cost.hpp"
#include "ridge_sample.hpp"
#include "scalogram_check.hpp"

namespace podid::wavelet {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Synchrosqueeze's pass 2 works on blocks of T of about this size (rows x
// frequencies x 16 bytes): well inside a 1 MiB L2 cache, beside the
// columns of W and of the field it reads.
constexpr Eigen::Index kSqueezeBlockBytes = 256 * 1024;

// Trapezoid weights in ln s over the scalogram's scales (any order).
Eigen::VectorXd LogScaleWeights(const Eigen::VectorXd& scales_s) {
  const Eigen::Index n = scales_s.size();
  Eigen::VectorXd w = Eigen::VectorXd::Zero(n);
  for (Eigen::Index k = 0; k + 1 < n; ++k) {
    const double h = std::abs(std::log(scales_s(k) / scales_s(k + 1)));
    w(k) += 0.5 * h;
    w(k + 1) += 0.5 * h;
  }
  return w;
}

void CheckComplex(const Scalogram& scalogram, const char* where) {
  if (scalogram.frequencies() < 2) {
    ThrowInvalid(where, "a scalogram with at least 2 frequencies",
                 ToText(scalogram.frequencies()) + " frequencies");
  }
  internal::CheckComplexScalogram(scalogram, where);
}

// 1 / n(s): divides kEnergy coefficients back to kAmplitude's.
double Denormalise(const MorletWavelet& wavelet, double scale_s) {
  return wavelet.normalisation == Normalisation::kEnergy ? 1.0 / std::sqrt(scale_s) : 1.0;
}

// Everything but the coefficients (Synchrosqueeze writes its own).
void CopyAllButCoefficients(const Scalogram& from, Scalogram* to) {
  to->wavelet = from.wavelet;
  to->frequencies_Hz = from.frequencies_Hz;
  to->scales_s = from.scales_s;
  to->time_s = from.time_s;
  to->step_s = from.step_s;
  to->decimation = from.decimation;
  to->input_samples = from.input_samples;
  to->coefficient_scale = from.coefficient_scale;
  to->magnitude = from.magnitude;
  to->coi_frequency_Hz = from.coi_frequency_Hz;
  to->computation = 0;  // T, not the transform's W: no TimeDerivative belongs to it
}

}  // namespace

double ReconstructionConstant(const MorletWavelet& wavelet) {
  double lo = 0.0, hi = 0.0;
  wavelet.Band(1e-14, &lo, &hi);
  lo = std::max(lo, 1e-3 * wavelet.RidgeAngularFrequency());
  // Trapezoid rule in v = ln u: integral psi^(e^v) dv, smooth and decaying
  // at both ends, so the rule converges fast; 20000 panels.
  const int panels = 20000;
  const double a = std::log(lo), h = (std::log(hi) - a) / panels;
  double sum = 0.0;
  for (int i = 0; i <= panels; ++i) {
    sum += ((i == 0 || i == panels) ? 0.5 : 1.0) * wavelet.FourierTransform(std::exp(a + h * i));
  }
  return sum * h;
}

Eigen::VectorXd InverseCwt(const Scalogram& scalogram) {
  CheckComplex(scalogram, "InverseCwt: scalogram");
  const Eigen::VectorXd w = LogScaleWeights(scalogram.scales_s);
  Eigen::VectorXcd sum = Eigen::VectorXcd::Zero(scalogram.times());
  for (Eigen::Index k = 0; k < scalogram.frequencies(); ++k) {
    sum += scalogram.coefficients.col(k) *
           (w(k) * Denormalise(scalogram.wavelet, scalogram.scales_s(k)));
  }
  const double c = ReconstructionConstant(scalogram.wavelet);
  // coefficient_scale last: 2 x a scale near the largest double overflowed
  // (an input of 1e308 came back inf) where the signal itself is finite.
  Eigen::VectorXd x = (sum.real() * (2.0 / c)) * scalogram.coefficient_scale;
  // Still infinite: the in-band signal itself exceeds the largest double.
  if (!x.allFinite()) {
    throw std::overflow_error(
        "InverseCwt: the reconstruction overflowed double precision (above 1.8e308); scale the "
        "signal down");
  }
  return x;
}

bool SynchrosqueezeOptions::IsValid(std::string* why) const {
  if (!(relative_threshold >= 0.0 && relative_threshold < 1.0)) {
    if (why != nullptr) {
      *why = "SynchrosqueezeOptions.relative_threshold: expected a value in [0, 1), got " +
             ToText(relative_threshold);
    }
    return false;
  }
  return true;
}

SynchrosqueezedTransform Synchrosqueeze(const Scalogram& scalogram,
                                        const CwtTransform& transform,
                                        const SynchrosqueezeOptions& options) {
  SynchrosqueezedTransform out;
  Synchrosqueeze(scalogram, transform, options, &out);
  return out;
}

namespace {

// T from the scalogram's W into *t, and the reassignment field into *field.
// t may be &scalogram.coefficients (in place): pass 2 reads a block's rows
// of W before it writes T's, into `scratch` first, and later blocks read
// only later rows.
void SqueezeInto(const Scalogram& scalogram,
                 const CwtTransform& transform,
                 const SynchrosqueezeOptions& options,
                 Eigen::MatrixXcd* t,
                 Eigen::MatrixXd* field) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument("Synchrosqueeze: " + why);
  CheckComplex(scalogram, "Synchrosqueeze: scalogram");
  internal::CheckProduced(transform, scalogram, "Synchrosqueeze: transform");
  const Eigen::Index times = scalogram.times(), freqs = scalogram.frequencies();
  const Eigen::VectorXd w = LogScaleWeights(scalogram.scales_s);
  const Eigen::VectorXd& f = scalogram.frequencies_Hz;
  PODID_CHECK(f(1) > f(0));  // ascending
  // No hypot or log per coefficient (they took 13 % and 5 % of the time):
  // W is scaled by 2^-e (exact) to parts below 1, so |W|^2 cannot overflow,
  // the threshold compares squares, and the grid frequency nearest f in ln f
  // comes from f^2 against products of grid frequencies (f_(l-1) f_l, the
  // geometric midpoint squared).
  const double scale = internal::UnitScale(scalogram.coefficients);
  const double peak2 = (scalogram.coefficients * scale).cwiseAbs2().maxCoeff();
  const double threshold2 = options.relative_threshold * options.relative_threshold * peak2;
  Eigen::VectorXd midpoint2(freqs - 1);
  for (Eigen::Index l = 0; l + 1 < freqs; ++l) midpoint2(l) = f(l) * f(l + 1);
  // Half a bin (in ln f) beyond the grid's ends, squared.
  const double below2 = f(0) * f(0) * (f(0) / f(1));
  const double above2 = f(freqs - 1) * f(freqs - 1) * (f(freqs - 1) / f(freqs - 2));

  const bool in_place = t == &scalogram.coefficients;
  if (!in_place) t->resize(times, freqs);  // no allocation when the sizes repeat
  field->resize(times, freqs);
  const auto above_threshold = [&](Eigen::Index j, Eigen::Index k, std::complex<double>* value) {
    *value = scalogram.coefficients(j, k);
    const double magnitude2 = std::norm(*value * scale);
    return magnitude2 > threshold2 && magnitude2 != 0.0;
  };

  // Pass 1, scale by scale (dW/dt is one inverse FFT of a whole column): the
  // IF of every coefficient above the threshold, f = Im(conj(W) dW/dt) /
  // (2 pi |W|^2); NaN below it, or where f is not positive (such a
  // coefficient stays where it is).
  Eigen::VectorXcd derivative;
  for (Eigen::Index k = 0; k < freqs; ++k) {
    transform.TimeDerivative(k, &derivative);
    for (Eigen::Index j = 0; j < times; ++j) {
      std::complex<double> value;
      double f_Hz = kNaN;
      if (above_threshold(j, k, &value)) {
        const std::complex<double> scaled = value * scale;
        f_Hz =
            (std::conj(scaled) * (derivative(j) * scale)).imag() / (2.0 * kPi * std::norm(scaled));
      }
      (*field)(j, k) = f_Hz > 0.0 ? f_Hz : kNaN;
    }
  }

  // Pass 2, a block of times at a time, so that the block of T the moves
  // land on stays in the L2 cache (scattered over all of T, the adds waited
  // on memory: 38 % of Synchrosqueeze's time on 10^5 samples). Each
  // coefficient of T takes its adds in k order, as a pass over k would.
  Eigen::VectorXd gains(freqs);
  for (Eigen::Index k = 0; k < freqs; ++k) {
    gains(k) = w(k) * Denormalise(scalogram.wavelet, scalogram.scales_s(k));
  }
  const Eigen::Index block = std::max<Eigen::Index>(16, kSqueezeBlockBytes / (16 * freqs));
  Eigen::MatrixXcd scratch(in_place ? std::min(block, times) : 0, in_place ? freqs : 0);
  for (Eigen::Index j0 = 0; j0 < times; j0 += block) {
    const Eigen::Index rows = std::min(block, times - j0);
    using Target = Eigen::Ref<Eigen::MatrixXcd, 0, Eigen::OuterStride<>>;
    Target target = in_place ? Target(scratch.topRows(rows)) : Target(t->middleRows(j0, rows));
    target.setZero();
    for (Eigen::Index k = 0; k < freqs; ++k) {
      const double gain = gains(k);
      Eigen::Index above = 0;  // lower_bound of the last IF: consecutive IFs are close
      for (Eigen::Index j = j0; j < j0 + rows; ++j) {
        std::complex<double> value;
        if (!above_threshold(j, k, &value)) continue;
        const double f_Hz = (*field)(j, k);
        // Nearest grid frequency in ln f. An IF that is not positive or lies
        // beyond the grid's half-bin margins (near a zero of W, where two
        // components cancel, the phase derivative is wild) leaves the
        // coefficient where it is, so sum_l T = sum_k W Delta ln s still holds.
        Eigen::Index l = k;
        if (f_Hz > 0.0) {  // NaN fails
          if (!((above == 0 || f(above - 1) < f_Hz) && (above == freqs || f(above) >= f_Hz))) {
            above = std::lower_bound(f.data(), f.data() + freqs, f_Hz) - f.data();
          }
          const double f2 = f_Hz * f_Hz;
          if (above == freqs) {
            if (f2 <= above2) l = freqs - 1;
          } else if (above == 0) {
            if (f2 >= below2) l = 0;
          } else {
            l = f2 < midpoint2(above - 1) ? above - 1 : above;
          }
        }
        target(j - j0, l) += value * gain;
      }
    }
    if (in_place) t->middleRows(j0, rows) = target;
  }
}

}  // namespace

void Synchrosqueeze(const Scalogram& scalogram,
                    const CwtTransform& transform,
                    const SynchrosqueezeOptions& options,
                    SynchrosqueezedTransform* out) {
  PODID_CHECK(out != nullptr);
  // Into out's own memory: no allocation (and no page to fault in) when
  // the sizes repeat. The scalogram's coefficients are not copied: T is
  // written block by block.
  if (&out->sst == &scalogram) {  // T would overwrite the W it is built from
    ThrowInvalid("Synchrosqueeze: out",
                 "an output apart from the scalogram (in place: SynchrosqueezeInPlace)",
                 "out->sst is the scalogram");
  }
  SqueezeInto(scalogram, transform, options, &out->sst.coefficients, &out->reassigned_frequency_Hz);
  CopyAllButCoefficients(scalogram, &out->sst);
}

void SynchrosqueezeInPlace(const CwtTransform& transform,
                           const SynchrosqueezeOptions& options,
                           SynchrosqueezedTransform* inout) {
  PODID_CHECK(inout != nullptr);
  SqueezeInto(inout->sst, transform, options, &inout->sst.coefficients,
              &inout->reassigned_frequency_Hz);
  inout->sst.computation = 0;  // T now: no TimeDerivative belongs to it
}

namespace {

// The track of one path on |T|: at each time the IF at the reassignment's
// fixed point near the path (synthesis.hpp, SynchrosqueezedRidge).
RidgeTrack TrackSqueezedPath(const SynchrosqueezedTransform& sst,
                             const Eigen::VectorXi& path,
                             const RidgeOptions& options) {
  const Scalogram& s = sst.sst;
  const double c = ReconstructionConstant(s.wavelet);
  RidgeTrack track;
  const Eigen::Index times = s.times(), freqs = s.frequencies();
  track.time_s = s.time_s;
  track.frequency_index = path;
  track.grid_frequency_Hz.resize(times);
  track.frequency_Hz.resize(times);
  track.amplitude.resize(times);
  track.inside_coi.resize(times);
  track.screened.setConstant(times, false);
  const Eigen::MatrixXd& field = sst.reassigned_frequency_Hz;
  constexpr Eigen::Index kReach = 3;  // bins either side of the path searched for the fixed point
  for (Eigen::Index j = 0; j < times; ++j) {
    const Eigen::Index k = path(j);
    if (k < 0) {  // no ridge at this time (every cell +inf: |T| = 0 outside the
                  // earlier ridges' exclusions): no IF, as TrackRidge leaves it
      track.grid_frequency_Hz(j) = track.frequency_Hz(j) = track.amplitude(j) = kNaN;
      track.inside_coi(j) = false;
      continue;
    }
    // g(q) = ln f(s_q, t) - ln f_q decreases through 0 at the fixed point.
    const auto g = [&](Eigen::Index q) { return std::log(field(j, q) / s.frequencies_Hz(q)); };
    double best = kNaN;
    Eigen::Index best_distance = kReach + 1;
    for (Eigen::Index q = std::max<Eigen::Index>(0, k - kReach);
         q < std::min<Eigen::Index>(freqs - 1, k + kReach); ++q) {
      const double g0 = g(q), g1 = g(q + 1);
      if (!(g0 >= 0.0 && g1 <= 0.0 && g0 > g1)) continue;  // NaN fails too
      const Eigen::Index distance = std::min(std::abs(q - k), std::abs(q + 1 - k));
      if (distance >= best_distance) continue;
      best_distance = distance;
      const double w = g0 / (g0 - g1);
      best = field(j, q) + w * (field(j, q + 1) - field(j, q));
    }
    track.grid_frequency_Hz(j) = s.frequencies_Hz(k);
    track.frequency_Hz(j) = std::isfinite(best) ? best : field(j, k);
    std::complex<double> sum(0.0, 0.0);
    for (Eigen::Index l = std::max<Eigen::Index>(0, k - 1);
         l <= std::min<Eigen::Index>(freqs - 1, k + 1); ++l) {
      sum += s.coefficients(j, l);
    }
    // coefficient_scale last, as in InverseCwt: no overflow before the result's.
    track.amplitude(j) = std::abs(sum) * (2.0 / c) * s.coefficient_scale;
    track.inside_coi(j) = s.InsideCoi(j, k);
  }
  // Screening, as TrackRidge screens: where |T| on the path is a negligible
  // fraction of the path's peak, or no coefficient near it had a reassigned
  // frequency (|W| below Synchrosqueeze's threshold: an impulse's far
  // times), there is no usable IF.
  double peak = 0.0;
  for (Eigen::Index j = 0; j < times; ++j) {
    if (path(j) >= 0) peak = std::max(peak, std::abs(s.coefficients(j, path(j))));
  }
  for (Eigen::Index j = 0; j < times; ++j) {
    if (path(j) < 0) continue;
    if (std::isfinite(track.frequency_Hz(j)) &&
        std::abs(s.coefficients(j, path(j))) > options.min_relative_magnitude * peak) {
      continue;
    }
    track.screened(j) = true;
    track.inside_coi(j) = false;
    track.frequency_Hz(j) = kNaN;
  }
  internal::CheckTrackFinite(track, "SynchrosqueezedRidge");
  return track;
}

// The field must be T's: a SynchrosqueezedTransform is a plain struct, which
// a caller may fill (or resize) by hand.
void CheckField(const SynchrosqueezedTransform& sst, const char* where) {
  const Eigen::MatrixXd& field = sst.reassigned_frequency_Hz;
  if (field.rows() != sst.sst.times() || field.cols() != sst.sst.frequencies()) {
    ThrowInvalid(where,
                 "reassigned_frequency_Hz of the shape of sst (" + ToText(sst.sst.times()) + " x " +
                     ToText(sst.sst.frequencies()) + "), as Synchrosqueeze writes it",
                 ToText(field.rows()) + " x " + ToText(field.cols()));
  }
}

}  // namespace

std::vector<RidgeTrack> SynchrosqueezedRidges(const SynchrosqueezedTransform& sst,
                                              const RidgeOptions& options) {
  CheckField(sst, "SynchrosqueezedRidges: sst");
  std::vector<RidgeTrack> tracks;
  for (const Eigen::VectorXi& path : FindRidges(sst.sst, options)) {
    tracks.push_back(TrackSqueezedPath(sst, path, options));
  }
  return tracks;
}

RidgeTrack SynchrosqueezedRidge(const SynchrosqueezedTransform& sst, const RidgeOptions& options) {
  CheckField(sst, "SynchrosqueezedRidge: sst");
  RidgeOptions one = options;
  one.ridges = 1;
  return TrackSqueezedPath(sst, FindRidges(sst.sst, one).front(), options);
}

}  // namespace podid::wavelet
