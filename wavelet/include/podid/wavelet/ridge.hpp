#pragma once
// Ridges of a Morlet scalogram, and the instantaneous frequency (IF) and
// amplitude along them. Units are SI: s and Hz.
//
// Ridge extraction (a path k_j, one frequency index per output time j):
//   kMaximum   k_j = argmax_k |W(j, k)|, sample by sample;
//   kPenalised the path over the whole record maximising
//                 sum_j log|W(j, k_j)| - (penalty_s / step_s) sum_j (ln f_{k_j} - ln f_{k_{j-1}})^2
//              by dynamic programming (Carmona, Hwang & Torresani 1999, "Characterization
//              of signals by the ridges of their wavelet transforms"; Iatsenko, McClintock &
//              Stefanovska 2016, "Extraction of instantaneous frequencies from ridges in
//              time-frequency representations of signals", scheme I). The max over
//              the previous frequency is a lower envelope of parabolas in ln f
//              (Felzenszwalb & Huttenlocher 2012), so a step costs O(n_freq), not
//              O(n_freq^2). penalty_s is in seconds, independent of the sampling: a
//              jump of one e-fold in frequency costs as much as holding a log-amplitude
//              advantage of 1 (neper) for penalty_s seconds.
// Several ridges: after each ridge, its peak (at each time, the frequencies on
// both flanks down to where |W| rises again) and at least separation_octaves
// either side are excluded, and the next ridge is extracted.
//
// Along a ridge:
//   kPhase (default)  f = Im(conj(W) dW/dt) / (2 pi |W|^2), the phase
//                     derivative of W, with dW/dt computed spectrally (exact
//                     for a pure tone at any scale). With parabolic_refinement
//                     it is interpolated linearly in s from the ridge's grid
//                     scale to the vertex scale s* below (a chirp's phase IF
//                     drifts with the offset from its ridge; a tone's does not);
//   kScale            f = f_{k_j}, or with parabolic refinement the vertex of
//                     the parabola through log|W| at the scales s_{k-1}, s_k,
//                     s_{k+1} mapped by f = kappa / (2 pi s) (exact for a pure
//                     tone with the kAmplitude wavelet, whose log|W| is
//                     quadratic in s).
//   amplitude         exp(that parabola's peak) / UnitCosineMagnitude(s*), the
//                     amplitude of the cosine the ridge stands for, in signal
//                     units (|W| / UnitCosineMagnitude(s_k) at the grid's ends).

#include <Eigen/Core>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "podid/wavelet/cwt.hpp"

namespace podid::wavelet {

enum class RidgeMethod { kMaximum, kPenalised };
enum class FrequencyEstimator { kPhase, kScale };

/// "max" / "penalised", "phase" / "scale".
const char* ToString(RidgeMethod method);
const char* ToString(FrequencyEstimator estimator);
/// Inverses of ToString; throw std::invalid_argument naming the choices.
RidgeMethod ParseRidgeMethod(std::string_view name);
FrequencyEstimator ParseFrequencyEstimator(std::string_view name);

/// RidgeOptions::ridges' upper bound (podid cwt --ridges, Python's count).
inline constexpr int kMaxRidges = 16;

struct RidgeOptions {
  RidgeMethod method = RidgeMethod::kPenalised;
  double penalty_s = 0.05;          ///< kPenalised, >= 0 (0 gives kMaximum's path)
  int ridges = 1;                   ///< how many ridges, 1..kMaxRidges
  double separation_octaves = 0.5;  ///< exclusion half-width around a found ridge, > 0
  FrequencyEstimator estimator = FrequencyEstimator::kPhase;
  bool parabolic_refinement = true;  ///< refine between grid scales (both estimators)
  /// Screening, in [0, 1): a ridge sample whose |W| is at most this fraction
  /// of the ridge's peak |W| gets no IF (NaN) and counts as outside the cone:
  /// there W is rounding noise (the transform keeps W to ~1e-12 of its peak),
  /// and its phase derivative is meaningless (an impulse gave IFs of -0.046 Hz
  /// inside the cone without it). 1e-6 keeps the IF's relative error from
  /// that noise below ~1e-6.
  double min_relative_magnitude = 1e-6;

  bool IsValid(std::string* why) const;
};

/// One ridge, at the scalogram's output times.
struct RidgeTrack {
  Eigen::VectorXd time_s;             ///< (dim n_times)
  Eigen::VectorXi frequency_index;    ///< (dim n_times) k_j, index into Scalogram::frequencies_Hz
  Eigen::VectorXd grid_frequency_Hz;  ///< (dim n_times) f_{k_j}, the ridge's grid frequency
  Eigen::VectorXd frequency_Hz;       ///< (dim n_times) instantaneous frequency
  Eigen::VectorXd amplitude;          ///< (dim n_times) instantaneous amplitude, signal units
  /// (dim n_times) whether (j, k_j) is inside the cone of influence and not
  /// screened: where the IF is usable.
  Eigen::Array<bool, Eigen::Dynamic, 1> inside_coi;
  /// (dim n_times) whether |W(j, k_j)| was at most RidgeOptions::min_relative_magnitude
  /// of the ridge's peak (then frequency_Hz is NaN).
  Eigen::Array<bool, Eigen::Dynamic, 1> screened;

  Eigen::Index size() const { return time_s.size(); }
  Eigen::Index InsideCoiCount() const { return inside_coi.count(); }
};

/// Ridge paths (frequency index per output time), strongest first.
/// Throws std::invalid_argument if !options.IsValid() or the scalogram is empty.
std::vector<Eigen::VectorXi> FindRidges(const Scalogram& scalogram, const RidgeOptions& options);

/// IF and amplitude along `path`. `transform` must be the one whose last
/// Compute() wrote `scalogram` (kPhase uses its TimeDerivative;
/// CwtTransform::Produced, else std::invalid_argument); it may be null for kScale.
/// An amplitude or IF beyond the largest double (a signal near 1.8e308):
/// std::overflow_error instead of inf.
RidgeTrack TrackRidge(const Scalogram& scalogram,
                      const Eigen::VectorXi& path,
                      const RidgeOptions& options,
                      const CwtTransform* transform);

// ------------------------------------------------------------------------
// The identification entry point: the IF of one signal along its main ridge.

struct RidgeFrequencyOptions {
  /// Defaults: 10-120 Hz, 32 voices per octave, band-limited, and the
  /// objective's reflect padding with coi_factor 1 (CwtOptions' defaults are
  /// zero and 2 since the border measurements; identification keeps its own
  /// until its owner re-measures the identification figures).
  CwtOptions cwt = [] {
    CwtOptions o;
    o.band_limited = true;
    o.padding = Padding::kReflect;
    o.coi_factor = 1.0;
    return o;
  }();
  RidgeOptions ridge;  ///< ridges must be valid (1..16) but is ignored (one ridge)
  /// Keep the whole scalogram (RidgeFrequencyEstimator::scalogram()'s
  /// coefficients, 16 bytes per output cell; the transform, FindRidges and
  /// TrackRidge as written). Otherwise (default) the ridge is streamed:
  /// memory is bounded by blocks, see RidgeFrequencyEstimator.
  bool keep_scalogram = false;
  /// Streamed: output cells (times x frequencies) per block, 2^10..2^26. A
  /// record with at most this many cells is one block (default 2^20, 8 MB of
  /// ridge cost). A longer one is cut into blocks of about this many cells
  /// (more only when the frequencies are so many that a block's FFT length,
  /// rounded up to a fast one, keeps more times) whose inverse FFTs are at least 8 times the
  /// overlap (the wavelet's support at the lowest frequency, on each side) and at least 1024
  /// points, up to 2048 points the length of least FFT cost per kept time: short enough for a
  /// block's costs to stay near the cache (the whole Silverbox record: 41 blocks of 1612 times x
  /// 115 frequencies, 1.5 MB).
  double block_cells = 1048576.0;
  /// Streamed, one block, kPenalised: transform the scales in order of a
  /// bound on their |W| (sum over the band of |X| |psi^|) and stop once the
  /// rest provably cannot hold the optimal path; the same path and IF as
  /// transforming every scale (57 of 115 are left out on the reference
  /// case's 1 s free decay; docs/wavelet.md). False: every scale.
  bool screen_scales = true;

  bool IsValid(std::string* why) const;
};

/// Reusable state for RidgeFrequency: construct once, call Estimate() once
/// per objective evaluation. Buffers and filters are kept between calls with
/// the same length and step, so repeated calls do not re-plan or re-filter.
/// One object per thread (distinct objects run in parallel safely).
///
/// Streamed (unless keep_scalogram): the band-limited transform runs over
/// blocks of output times with an overlap of the wavelet's support at the
/// lowest frequency (one block when the scalogram has at most block_cells
/// cells, as for 5001 samples at 10-120 Hz, or when that support is longer
/// than the record); the dynamic
/// programme takes one time column at a time and keeps a back-pointer per
/// cell (1 byte up to 255 frequencies, 2 up to 65535); the IF is then
/// computed block by block along the chosen path, recomputing W and dW/dt
/// only at the path's scales. Memory: about 1 byte per output cell plus
/// O(block) buffers and the track, instead of 24 bytes per cell. The result
/// equals FindRidges + TrackRidge on the full transform to about
/// band_tolerance (tests StreamedRidge.*); CwtOptions::memory_budget_bytes
/// bounds what one call allocates. With cwt.threads >= 2 the streamed ridge
/// uses a second thread: over several blocks the next block's transform runs
/// beside the dynamic programme (a pipeline), and large shares of scales (a
/// single block's, the IF's recomputed W) are split between the two; the
/// result is the one-thread result bit for bit (test
/// StreamedRidge.TwoThreadsGiveTheSerialTrackBitForBit).
class RidgeFrequencyEstimator {
 public:
  /// Throws std::invalid_argument if !options.IsValid().
  explicit RidgeFrequencyEstimator(const RidgeFrequencyOptions& options = {});
  ~RidgeFrequencyEstimator();
  RidgeFrequencyEstimator(RidgeFrequencyEstimator&&) noexcept;
  RidgeFrequencyEstimator& operator=(RidgeFrequencyEstimator&&) noexcept;

  /// The main ridge of `signal` (dim N >= 4, step step_s). The returned
  /// reference stays valid until the next call. Bad input (as for
  /// CwtTransform::Compute: NaN/Inf, a constant signal, step_s outside
  /// kMinStep_s .. kMaxStep_s, a frequency above Nyquist or below 1e-20
  /// times the sampling rate): std::invalid_argument; an amplitude beyond the
  /// largest double: std::overflow_error. On a moved-from estimator: std::logic_error.
  const RidgeTrack& Estimate(const Eigen::Ref<const Eigen::VectorXd>& signal, double step_s);

  /// The scalogram of the last Estimate() (decimated in band-limited mode):
  /// its grid (times, frequencies, scales, decimation, cone of influence)
  /// always; its coefficients only with keep_scalogram (else empty).
  const Scalogram& scalogram() const;

  /// Blocks of the last streamed Estimate() (0 with keep_scalogram).
  Eigen::Index blocks() const;
  /// Scales whose W the last streamed Estimate() computed to find its ridge
  /// (every one unless screen_scales left some out; 0 with keep_scalogram).
  Eigen::Index transformed_scales() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-shot convenience (builds an estimator per call; reuse a
/// RidgeFrequencyEstimator in loops). Thread-safe.
RidgeTrack RidgeFrequency(const Eigen::Ref<const Eigen::VectorXd>& signal,
                          double step_s,
                          const RidgeFrequencyOptions& options = {});

}  // namespace podid::wavelet
