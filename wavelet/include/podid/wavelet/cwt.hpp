#pragma once
// Continuous wavelet transform with the complex Morlet wavelet (or a
// generalised Morse wavelet, see MorletWavelet below), computed with FFTW. Units are SI: times and
// scales in s, frequencies in Hz unless a name says _rad_per_s. The module knows nothing of beams
// or POD: it transforms any uniformly sampled real signal.
//
// The wavelet (omega0 = options.omega0, c = 1 with the admissibility
// correction, else 0):
//   time       psi(t)     = K (exp(i omega0 t) - c exp(-omega0^2 / 2)) exp(-t^2 / 2)
//   frequency  psi^(w)    = K sqrt(2 pi) (exp(-(w - omega0)^2 / 2)
//                                          - c exp(-(w^2 + omega0^2) / 2))
// with psi^(w) = integral psi(t) exp(-i w t) dt. psi^ is real and is taken on
// every frequency, so the wavelet is analytic up to its negative-frequency
// tail, psi^(w < 0) <= K sqrt(2 pi) exp(-omega0^2 / 2) (1.5e-8 of the peak for
// omega0 = 6). This keeps a closed form in time: the FFT path equals a direct
// time-domain convolution with psi (tests/wavelet/cwt_test.cpp).
//
// The transform of x(t) at scale s (s) and time t (s):
//   kAmplitude (L1):  W(s, t) = (1 / s)       integral x(tau) conj(psi((tau - t) / s)) dtau,
//                     K = sqrt(2 / pi), so psi^(omega0) = 2;
//   kEnergy (L2):     W(s, t) = (1 / sqrt(s)) integral x(tau) conj(psi((tau - t) / s)) dtau,
//                     K = pi^(-1/4), so integral |psi|^2 dt = 1 (c = 0).
// In frequency: W^(s, w) = X(w) n(s) psi^(s w), n = 1 (L1) or sqrt(s) (L2).
// For x = cos(2 pi f t) (unit amplitude, omega = 2 pi f) and c = 0:
//   kAmplitude: |W(s, t)| = exp(-(s omega - omega0)^2 / 2), exactly 1 on the ridge
//               s omega = omega0 (so |W| reads directly as the amplitude);
//   kEnergy:    |W(s, t)| = pi^(1/4) sqrt(s / 2) exp(-(s omega - omega0)^2 / 2),
//               in signal units times s^(1/2); the ridge is where sqrt(s) psi^(s omega)
//               peaks, s omega = (omega0 + sqrt(omega0^2 + 2)) / 2 (Torrence & Compo 1998).
// (Both up to the negative-frequency term, below exp(-omega0^2 / 2).)
//
// Scale <-> frequency (exact for the chosen omega0, normalisation and
// correction): kappa = argmax_u n(u) psi^(u) is the ridge's s omega for a pure
// tone, and f_Hz = kappa / (2 pi s). A tone at f therefore peaks exactly at
// s = kappa / (2 pi f); kappa = omega0 for kAmplitude without correction.
//
// Cone of influence: the e-folding time of the Morlet wavelet at scale s is
// sqrt(2) s (Torrence & Compo 1998, sec. 3g); for any wavelet podid uses
// 2 sigma_t s (sigma_t: MorletWavelet::TimeSpread, 1/sqrt(2) for Morlet). A
// coefficient at time t is inside the cone when coi_factor 2 sigma_t s <=
// min(t - t_first, t_last - t); per time
// sample this is a lowest frequency, Scalogram::coi_frequency_Hz. There an
// edge's influence (a jump, or a kink from reflect padding) on |W| has only
// fallen to exp(-1); CwtOptions::coi_factor widens the cone for IF work
// (coi_factor = 4: exp(-16), which the 1e-6 tone test needs).
//
// Algorithm: the signal is scaled by a power of 2 to a peak magnitude in
// [1, 2) (exact, so any finite input works: 1e-300 and 1e300 alike),
// optionally has its mean removed, is padded to length P, one real forward FFT
// gives X_k, and each scale costs one inverse FFT of X_k n(s) psi^(s w_k) over
// the bins where psi^ exceeds band_tolerance times its peak. In time that band
// limit is the Gaussian envelope's support: |t| <= r s with
// r = sqrt(2 ln(1 / band_tolerance)) (7.43 for 1e-12), the "support" below.
// Padding (the padded sequence is treated as periodic, length P, chosen by
// FastFftLength among the sizes with factors 2, 3, 5, 7 only, up to 25 % above
// the minimum, for speed):
//   kReflect  the even extension: sample i of the padded sequence is
//             x_{r(i)} for i < N + R and x_{r(i - P)} after, r(m) = |m| mirrored at
//             the ends (period 2N - 2), R = ceil((P - N) / 2); the minimum P is
//             N + 2 r' s at the lowest frequency, r' the support's radius at 1e-6
//             instead of band_tolerance (5.26 for Morlet): the one jump then lies
//             where every envelope is below 1e-6 of its peak. Or P = 2N - 2 exactly
//             (no jump at all, any factors) where that minimum, rounded up,
//             would exceed 2 (2N - 2);
//   kZero     (default) x_0 .. x_{N-1} followed by zeros, minimum P = N + support
//             (the transform of the record followed by zeros for ever, with
//             no wrap-around, even for a wavelet longer than the record); the
//             zeros stop at the support of the largest scale with a sample
//             inside the cone of influence, if longer than N (coi_factor > 0);
//   kPeriodic x_0 .. x_{N-1}, P = N (no choice of length).
// Full rate (the default): scale k's band of K_k bins is inverted by a pruned
// inverse FFT (wavelet/src/pruned_inverse.hpp): with D_k the largest power of
// 2 (<= 64) dividing P with P / D_k >= K_k, the P outputs are D_k interleaved
// inverse FFTs of length P / D_k of the band twiddled by exp(2 pi i b r / P)
// (exact, no approximation), so low frequencies cost P log(P / D_k).
// Band-limited mode: each scale's product is nonzero only in a band of B_k
// bins, so its inverse FFT can have length M >= max_k B_k with M dividing P;
// that gives W exactly (to band_tolerance) at every D-th sample, D = P / M.
// Identification uses it for ridges: 5001 samples at 10-120 Hz (reflect padding, P = 10240)
// have bands of up to 609 bins, so M = 640.
//
// FFTW plans are made once per length and cached process-wide, with measured
// plans kept on disk (podid/wavelet/plans.hpp); making them is serialised by a
// mutex and executing them is thread-safe. A CwtTransform holds buffers for one
// signal at a time: use one object per caller thread (CwtOptions::threads
// spreads one transform's scales over worker threads).

#include <Eigen/Core>
#include <cmath>
#include <complex>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace podid::wavelet {

enum class Normalisation {
  kAmplitude,  ///< L1: |W| of a unit cosine is 1 on its ridge
  kEnergy,     ///< L2: unit-energy wavelet, |W| grows like sqrt(s)
};
enum class Padding { kReflect, kZero, kPeriodic };
enum class CwtOutput {
  kComplex,         ///< Scalogram::coefficients, complex double (what ridges need)
  kMagnitudeFloat,  ///< Scalogram::magnitude only, |W| in single precision (4 bytes each)
  /// Scalogram::coefficients_float only: W computed in double precision and
  /// rounded once to complex float (8 bytes each, as fCWT's output), phase kept
  kComplexFloat,
};
enum class FftPlanning {
  kEstimate,  ///< measured plans from the wisdom cache, else FFTW_ESTIMATE (no planning cost)
  kMeasure,   ///< measure plans the cache lacks (once per length), then store them there
};
enum class FrequencySpacing {
  kLog,     ///< voices_per_octave frequencies per octave, from min_frequency_Hz up
  kLinear,  ///< bins frequencies evenly from min_frequency_Hz to max_frequency_Hz
};

/// Which s omega labels a scale's frequency, f = c / (2 pi s).
enum class ScaleConvention {
  kRidge,  ///< c = kappa, the ridge of a tone (Torrence & Compo 1998): a tone at f peaks at f's scale
  kPeak,   ///< c = the peak of psi^ (omega0, or Morse's u_p): MATLAB's and PyWavelets' centre frequency
};

enum class WaveletFamily {
  kMorlet,  ///< the complex Morlet wavelet (omega0, admissibility_correction)
  kMorse,   ///< the generalised Morse wavelet (gamma, beta), MATLAB's cwt default
};

/// "amplitude" / "energy", "reflect" / "zero" / "periodic", "log" / "linear",
/// "morlet" / "morse".
const char* ToString(Normalisation normalisation);
const char* ToString(WaveletFamily family);
const char* ToString(Padding padding);
const char* ToString(FrequencySpacing spacing);
const char* ToString(ScaleConvention convention);  ///< "ridge" / "peak"
const char* ToString(CwtOutput output);            ///< "complex" / "magnitude" / "complex-float"
/// Inverses of ToString; throw std::invalid_argument naming the choices.
Normalisation ParseNormalisation(std::string_view name);
CwtOutput ParseCwtOutput(std::string_view name);
ScaleConvention ParseScaleConvention(std::string_view name);
Padding ParsePadding(std::string_view name);
WaveletFamily ParseWaveletFamily(std::string_view name);

/// The mother wavelet (formulas at the top of this file). The struct keeps
/// its historical name; `Wavelet` is the same type.
///
/// Generalised Morse wavelets (Olhede & Walden 2002; Lilly & Olhede 2009,
/// 2012), family = kMorse, with MATLAB's normalisation (cwt, cwtfilterbank:
/// peak value 2 at the peak frequency):
///   psi^(u) = K a(beta, gamma) u^beta exp(-u^gamma) for u > 0, 0 for u <= 0,
///   a = (e gamma / beta)^(beta / gamma), peak at u_p = (beta / gamma)^(1 / gamma)
///   where a u_p^beta exp(-u_p^gamma) = 1;
///   kAmplitude: K = 2 (as MATLAB: |W| of a unit cosine on its ridge is 1);
///   kEnergy:    K such that integral |psi|^2 dt = 1,
///               K^2 a^2 = 2 pi gamma 2^r / Gamma(r), r = (2 beta + 1) / gamma.
/// gamma = 3, beta = 20 (time-bandwidth product P^2 = beta gamma = 60) is
/// MATLAB's default. The ridge's s omega (kappa) is u_p for kAmplitude and
/// ((beta + 1/2) / gamma)^(1 / gamma) for kEnergy. The cone of influence of
/// either family is coi_factor * 2 sigma_t s, sigma_t^2 = integral psi^'(u)^2
/// du / integral psi^(u)^2 du the wavelet's time variance (sigma_t =
/// 1/sqrt(2) for Morlet: Torrence & Compo's sqrt(2) s).
/// MorletWavelet's accepted parameters (IsValid; podid cwt checks its options
/// against the same numbers).
inline constexpr double kMinOmega0 = 5.0;  ///< without the admissibility correction
/// With it: below, psi^ ~ omega0 u exp(-u^2 / 2) no longer changes shape, only
/// shrinks with omega0 towards underflow.
inline constexpr double kMinCorrectedOmega0 = 0.5;
inline constexpr double kMaxOmega0 = 100.0;
inline constexpr double kMinMorseGamma = 1.0, kMaxMorseGamma = 20.0;
inline constexpr double kMinMorseBeta = 1.0, kMaxMorseBeta = 500.0;
inline constexpr double kMaxMorseBetaOverGamma = 100.0;

struct MorletWavelet {
  WaveletFamily family = WaveletFamily::kMorlet;
  double omega0 = 6.0;  ///< kMorlet: centre angular frequency (dimensionless), in [5, 100]
                        ///< ([0.5, 100] corrected)
  bool admissibility_correction = false;  ///< kMorlet: subtract exp(-omega0^2/2): psi^(0) = 0
  double gamma = 3.0;                     ///< kMorse: symmetry, in [1, 20] (either family)
  double beta = 20.0;  ///< kMorse: decay, in [1, 500] (either), beta / gamma <= 100
  Normalisation normalisation = Normalisation::kAmplitude;
  /// How scales map to frequencies. The two agree for kAmplitude (without the
  /// Morlet correction); for kEnergy Morlet omega0 = 6 the ridge is at
  /// s omega = 6.0822, so under kPeak a tone's ridge carries a label 1.35 % below its frequency.
  ScaleConvention convention = ScaleConvention::kRidge;

  /// Every field in range and every enum one of its values. Band, TimeSpread and
  /// RidgeAngularFrequency with the admissibility correction (a bisection)
  /// throw std::invalid_argument with its reason otherwise.
  bool IsValid(std::string* why) const;
  /// The peak of psi^ alone (no n(s)): omega0 (Morlet without correction), u_p (Morse).
  double PeakAngularFrequency() const;
  /// c of the convention: RidgeAngularFrequency() or PeakAngularFrequency().
  double ScaleFrequencyConstant() const;
  /// psi^(u) at u = s w (dimensionless), without the n(s) factor.
  double FourierTransform(double u) const;
  /// kappa = argmax_u n(u) psi^(u): the s omega of a pure tone's ridge.
  double RidgeAngularFrequency() const;
  /// f = c / (2 pi s), c = ScaleFrequencyConstant().
  double ScaleToFrequency_Hz(double scale_s) const;
  /// s = c / (2 pi f).
  double FrequencyToScale_s(double frequency_Hz) const;
  /// |W| of a unit-amplitude cosine at scale s on its ridge (frequency
  /// ScaleToFrequency_Hz(scale_s)): 1 for kAmplitude without correction.
  double UnitCosineMagnitude(double scale_s) const;
  /// [*lo, *hi]: the u where psi^(u) >= tolerance * max psi^ (tolerance in (0, 1)).
  void Band(double tolerance, double* lo, double* hi) const;
  /// sigma_t above (dimensionless, in units of the scale).
  double TimeSpread() const;
  /// e-folding time of the cone of influence at scale s, 2 TimeSpread() s.
  double ConeOfInfluenceTime_s(double scale_s) const;
  /// The Morlet wavelet's e-folding time, sqrt(2) s (kept for existing callers).
  static double ConeOfInfluence_s(double scale_s);
  /// "Morlet omega0 6" / "Morse gamma 3 beta 20".
  std::string Describe() const;
};
using Wavelet = MorletWavelet;

/// Sampling steps every transform accepts (1 fs, a rate of 1 PHz, to 1e15
/// s): within them the energy normalisation's sqrt(s) keeps the outputs in
/// range (docs/wavelet.md, "Algorithm and padding"). Shared with `podid plan`.
inline constexpr double kMinStep_s = 1e-15;
inline constexpr double kMaxStep_s = 1e15;
/// Whether step_s is one a transform accepts (finite, within the two above).
inline bool IsTransformStep(double step_s) {
  return std::isfinite(step_s) && step_s >= kMinStep_s && step_s <= kMaxStep_s;
}

/// The grid's bounds (FrequencyGrid::IsValid), shared with the front-ends'
/// checks of --voices and --bins (podid cwt, podid plan, Python's voices).
inline constexpr int kMaxVoicesPerOctave = 1024;
inline constexpr int kMinLinearBins = 2;
inline constexpr int kMaxFrequencies = 100000;  ///< either spacing

/// Analysis frequencies in Hz, ascending.
struct FrequencyGrid {
  double min_frequency_Hz = 10.0;   ///< > 0
  double max_frequency_Hz = 120.0;  ///< > min, <= Nyquist of the signal
  FrequencySpacing spacing = FrequencySpacing::kLog;
  /// kLog: f_j = min 2^(j / voices) for j = 0 .. floor(voices log2(max / min) + 1e-9);
  /// the top frequency is <= max_frequency_Hz. voices in 1..kMaxVoicesPerOctave, at most
  /// kMaxFrequencies frequencies.
  int voices_per_octave = 32;
  /// kLinear: f_j = min + j (max - min) / (bins - 1), j = 0 .. bins - 1 (bins in
  /// kMinLinearBins..kMaxFrequencies).
  int bins = 200;

  /// The grid `podid cwt --voices` (Log) and `--bins` (Linear) describe; not checked here
  /// (IsValid, or the transform that takes it, says what is wrong).
  static FrequencyGrid Log(double min_Hz, double max_Hz, int voices_per_octave);
  static FrequencyGrid Linear(double min_Hz, double max_Hz, int bins);

  bool IsValid(std::string* why) const;
  /// (dim n_frequencies) ascending; throws std::invalid_argument if !IsValid.
  Eigen::VectorXd Frequencies_Hz() const;
};

/// The widest cone accepted: at c = 6 an edge's influence exp(-c^2) is 2.3e-16,
/// double precision's epsilon; 10 leaves room (0 = no cone).
inline constexpr double kMaxCoiFactor = 10.0;

/// The memory limit the front-ends take (podid cwt --max-memory, Python's
/// max_memory_MB), in MB: each gives CwtOptions::memory_budget_bytes a share of it.
inline constexpr double kMinMemoryLimit_MB = 1.0;
inline constexpr double kMaxMemoryLimit_MB = 16777216.0;  // 2^44 bytes

/// CwtOptions::threads' upper bound (podid cwt --threads shares it).
inline constexpr int kMaxCwtThreads = 256;

struct CwtOptions {
  MorletWavelet wavelet;
  FrequencyGrid frequencies;
  /// Default zero: over 16 end phases the worst IF error inside the cone
  /// (scripts/wavelet_border_errors.py, docs/wavelet.md) is 0.69 % / 4.0 % /
  /// 0.61 % (tone / chirp / decay) against reflect's 4.0 % / 7.5 % / 4.5 %.
  Padding padding = Padding::kZero;
  bool remove_mean = true;  ///< subtract the signal's mean before padding
  /// The cone's half-width is coi_factor * 2 sigma_t s (sqrt(2) s for Morlet), >= 0. 1 is Torrence
  /// & Compo's e-folding time, where an edge's influence on |W| has fallen only to exp(-1); with
  /// coi_factor = c it is exp(-c^2) (c = 4: 1e-7). Default 2: with zero padding the worst IF error
  /// inside the cone over end phases is 0.028 % / 0.27 % / 0.11 % (tone / chirp / decay) against
  /// 0.69 % / 4.0 % / 0.61 % at 1 (scripts/wavelet_border_errors.py). At most kMaxCoiFactor.
  double coi_factor = 2.0;
  /// Output only every D-th sample, D = P / M (see the top of this file).
  bool band_limited = false;
  /// Filter values below band_tolerance times the filter's peak are dropped
  /// (both modes), in (0, 1e-3]. 1e-12 keeps W to about 1e-12 relative.
  double band_tolerance = 1e-12;
  /// Threads over scales in Compute(), 1..256 (each with its own work buffers;
  /// at full rate the threads take contiguous chunks of scales of about equal
  /// cost, 8 per thread, in turn; band-limited, single scales in turn).
  /// RidgeFrequencyEstimator's streamed ridge uses two when this is >= 2
  /// (podid/wavelet/ridge.hpp). Threads the system refuses are done without:
  /// the result is the same.
  int threads = 1;
  FftPlanning planning = FftPlanning::kEstimate;
  CwtOutput output = CwtOutput::kComplex;
  /// Upper bound on what one Compute() allocates, in bytes, in [2^16, 2^44] (a share of a
  /// 1 MB limit stays valid: podid cwt --max-memory 1 --synchrosqueeze gives W 16/24 of it):
  /// the coefficients (n_times x n_freq x 16, 8 for kComplexFloat, 4 for kMagnitudeFloat), the
  /// filters (8 per kept bin; none for Morlet without the admissibility correction: generated) and
  /// the FFT buffers. Checked before allocating; too big is std::invalid_argument naming the sizes.
  /// Default 2 GiB.
  double memory_budget_bytes = 2147483648.0;

  bool IsValid(std::string* why) const;
};

/// The transform of one signal. Row j of `coefficients` is output time
/// time_s(j) = start_time_s + j * step_s; column k is frequency k.
struct Scalogram {
  MorletWavelet wavelet;           ///< the wavelet it was computed with
  Eigen::VectorXd frequencies_Hz;  ///< (dim n_freq) ascending
  Eigen::VectorXd scales_s;        ///< (dim n_freq) s_k = c / (2 pi f_k), descending (c: ScaleConvention)
  Eigen::VectorXd time_s;          ///< (dim n_times) output sample times
  double step_s = 0.0;             ///< output time step: input step * decimation
  int decimation = 1;              ///< D: output sample j is input sample j * D
  Eigen::Index input_samples = 0;  ///< N of the transformed signal
  /// (n_times x n_freq) W / coefficient_scale, units: see the normalisation.
  Eigen::MatrixXcd coefficients;
  /// A power of 2: 1 unless the signal's peak magnitude is at least 2^961 (1.9e289)
  /// or below 2^-960, where W itself could overflow or lose precision; then the
  /// coefficients are W in units of coefficient_scale (peak magnitude about 1).
  /// For the single-precision outputs the bounds are 2^33 (8.6e9) and 2^-32.
  double coefficient_scale = 1.0;
  /// (n_times x n_freq) |W| / coefficient_scale in single precision (relative
  /// rounding 6e-8), filled instead of `coefficients` with
  /// CwtOutput::kMagnitudeFloat (then `coefficients` is empty); else empty.
  Eigen::MatrixXf magnitude;
  /// (n_times x n_freq) W / coefficient_scale rounded to complex float (each
  /// part correctly rounded, 6e-8 relative), filled instead of `coefficients`
  /// with CwtOutput::kComplexFloat; else empty. What reads W (ridges, inverse,
  /// synchrosqueezing) takes the complex double `coefficients` only.
  Eigen::MatrixXcf coefficients_float;
  /// (dim n_times) lowest frequency inside the cone of influence at each output
  /// time, coi_factor c 2 sigma_t / (2 pi distance_to_nearest_edge_s) (c: the scale
  /// convention's constant, 2 sigma_t = sqrt(2) for Morlet); +inf at the edges.
  Eigen::VectorXd coi_frequency_Hz;
  /// Which CwtTransform::Compute() call produced the coefficients (unique in
  /// the process; 0: none, e.g. a synchrosqueezed T). What reads the
  /// transform's state beside them (TimeDerivative: Synchrosqueeze,
  /// TrackRidge's phase IF) checks it with CwtTransform::Produced().
  std::uint64_t computation = 0;

  Eigen::Index times() const { return time_s.size(); }
  Eigen::Index frequencies() const { return frequencies_Hz.size(); }
  bool InsideCoi(Eigen::Index time, Eigen::Index frequency) const {
    return frequencies_Hz(frequency) >= coi_frequency_Hz(time);
  }
};

/// FFT lengths of a transform: the real forward length P, the complex
/// inverse length(s) and, at full rate, the (M, G) pairs of the pruned
/// inverse: batches of G inverses of length M = P / D, G dividing the
/// decimation D (see podid/wavelet/plans.hpp).
struct FftLengths {
  std::vector<int> real_forward;
  std::vector<int> complex_backward;
  std::vector<std::pair<int, int>> interleaved_backward;
  /// The CwtTransform's forward FFT: a complex transform of length P of the
  /// real signal (cheaper to plan than real_forward's; the band-limited ridge
  /// estimator still plans real_forward).
  std::vector<int> complex_forward;
};

/// Reusable transform state: plans, the padded signal's spectrum, the filters
/// (stored or, for one Gaussian, their constants; rebuilt only when the signal
/// length or step changes) and work buffers.
/// Not shareable between threads; use one per thread.
class CwtTransform {
 public:
  /// Throws std::invalid_argument if !options.IsValid().
  explicit CwtTransform(const CwtOptions& options);
  ~CwtTransform();
  CwtTransform(CwtTransform&&) noexcept;
  CwtTransform& operator=(CwtTransform&&) noexcept;
  CwtTransform(const CwtTransform&) = delete;
  CwtTransform& operator=(const CwtTransform&) = delete;

  const CwtOptions& options() const;

  /// Transforms `signal` (dim N >= 4), sampled every step_s from start_time_s,
  /// into *out (resized as needed, so a reused Scalogram does not reallocate).
  /// Throws std::invalid_argument for NaN/Inf, a constant signal, step_s
  /// outside 1e-15 .. 1e15 s, a frequency above Nyquist 1 / (2 step_s) or
  /// below 1e-20 times the sampling rate, more than 2^27 samples or
  /// padded points, sizes above memory_budget_bytes, or a null `out`. A
  /// moved-from transform throws std::logic_error (so do its other members).
  void Compute(const Eigen::Ref<const Eigen::VectorXd>& signal,
               double step_s,
               Scalogram* out,
               double start_time_s = 0.0);

  /// dW/dt (units of W per s, divided by coefficient_scale like the
  /// coefficients) at frequency index k of the last Compute(), at the same
  /// output times (dim n_times); computed spectrally (i w X_k), so it is exact
  /// to band_tolerance. One extra inverse FFT. Throws std::invalid_argument
  /// before a Compute() has succeeded or for k outside 0..n_freq - 1.
  void TimeDerivative(Eigen::Index frequency_index, Eigen::VectorXcd* out) const;

  /// Whether `scalogram` is what this transform's last Compute() wrote (a
  /// copy counts): only then do TimeDerivative's values belong to it. False
  /// for another transform's and for one written before the last Compute();
  /// a Compute() that rejects its input changes nothing, one that throws
  /// after it began (a memory budget) leaves no output valid.
  bool Produced(const Scalogram& scalogram) const;

  /// The FFT lengths Compute() would use for `samples` (>= 4) at step_s
  /// (1e-15 .. 1e15 s); throws std::invalid_argument otherwise, or when the padded length
  /// would exceed 2^27 points. Nothing is planned.
  FftLengths Lengths(Eigen::Index samples, double step_s) const;

  /// The rms |W| that unit-variance white noise gives at each frequency for
  /// a record of `samples` (>= 4) at step_s: sqrt(P sum_b |H_k(b)|^2), the
  /// energy over a period of the padded length of scale k's discrete filter
  /// (Parseval), in the coefficients' units. Nothing is transformed or
  /// planned; memory is the filters' (O(filter bins), not samples x
  /// frequencies). Throws std::invalid_argument like Lengths() and for a
  /// frequency above Nyquist.
  Eigen::VectorXd WhiteNoiseMagnitude(Eigen::Index samples, double step_s) const;

  /// Padded length P and inverse-FFT length M of the last Compute() (0 before).
  Eigen::Index padded_length() const;
  Eigen::Index inverse_length() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-shot convenience: CwtTransform(options).Compute(...).
Scalogram Cwt(const Eigen::Ref<const Eigen::VectorXd>& signal,
              double step_s,
              const CwtOptions& options = {});

}  // namespace podid::wavelet
