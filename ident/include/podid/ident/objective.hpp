#pragma once
// Objectives comparing measured and simulated decompositions (the paper's
// section 3, eq. 19, and section 4.3.2). Over the first K POMs (modes):
//   dU  = sum_k sum_i (U_sim(i,k) - U_meas(i,k))^2                  POM components
//   dS  = sum_k ((sigma_sim,k - sigma_meas,k) / sigma_meas,k)^2      relative (default)
//       = sum_k (sigma_sim,k - sigma_meas,k)^2                       raw, as eq. 19
//   dV  = sum_k sum_n (V_sim(n,k) - V_meas(n,k))^2                   right-singular vectors
//   dIF = sum_k D sum_j ((f_sim,k(t_j) - f_meas,k(t_j)) / f_meas,k(t_j))^2
//         the instantaneous frequency of V's column k along its Morlet (or Morse) ridge,
//         over the output times j where both ridges are inside the cone of
//         influence. Sec. 4.3.2 puts the IFs "in place of the right-singular
//         vectors": like dV, dIF is a sum over the record's samples (D = the
//         ridge's decimation, the input samples per output time), of the
//         relative IF difference (IFs in Hz are not unit vectors).
// F = w_U dU + w_S dS + w_V dV + w_IF dIF. Presets: full = U + S + V (eq. 19),
// time-free = U + S (fig. 4), wavelet = U + S + IF (figs. 5-6).
// Before differencing, the simulated decomposition is aligned to the measured
// one (signs and MAC mode matching, AlignToReference). The measured POD and
// ridges are computed once, in the constructor.

#include <Eigen/Core>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "podid/core/case_file.hpp"
#include "podid/core/model_parameter.hpp"
#include "podid/core/simulate.hpp"
#include "podid/core/simulator.hpp"
#include "podid/core/time_series.hpp"
#include "podid/pod/pod.hpp"
#include "podid/wavelet/ridge.hpp"

namespace podid::ident {

/// Largest weight ObjectiveWeights::Parse accepts. The terms are relative
/// differences of order 1 (up to ~1e4 with many modes), so a weighted sum of
/// four stays near 1e16, far from overflow: 1e308 weights made F infinite
/// and the start nan. (A sum that still is not finite is a failed evaluation.)
inline constexpr double kMaxObjectiveWeight = 1e12;

/// Weights of the four terms; a zero weight skips the term's computation.
struct ObjectiveWeights {
  double u = 1.0;
  double s = 1.0;
  double v = 0.0;
  double f = 0.0;  ///< dIF

  bool NeedsRidges() const { return f != 0.0; }
  /// "full", "time-free", "wavelet"; throws std::invalid_argument naming the choices.
  static ObjectiveWeights Preset(std::string_view name);
  /// `terms` like "U,S,IF" (each at most once) and optional `weights` like
  /// "1,1,0.5" (default all 1, each at most kMaxObjectiveWeight).
  /// Throws std::invalid_argument naming them `terms_name` and `weights_name`
  /// (the caller's names: the CLI's --terms and --weights).
  static ObjectiveWeights Parse(std::string_view terms,
                                std::string_view weights = {},
                                std::string_view terms_name = "terms",
                                std::string_view weights_name = "weights");
  /// "dU + dS + 0.5 dIF": the weighted terms, each weight shown when not 1.
  std::string ToString() const;
};

/// A weighting with a name (for reports, landscapes): "full", "wavelet", ...
struct NamedObjective {
  std::string name;
  ObjectiveWeights weights;
};

/// The objective value of an evaluation that failed (simulation diverged, a
/// parameter value the case rejects, a weighted sum that is not finite):
/// larger than most finite objectives of a usable simulation, finite so
/// optimisers keep going. Identify raises it to twice the largest value seen
/// in the start when that is more (objectives of many modes reach 1e4).
inline constexpr double kDefaultFailureValue = 1e3;

/// A frequency band in Hz; both 0 (the default) means "follow the mode".
struct FrequencyBand {
  double min_Hz = 0.0;
  double max_Hz = 0.0;
  bool follow() const { return min_Hz == 0.0 && max_Hz == 0.0; }
};

struct ObjectiveOptions {
  /// The weightings of the terms (>= 1). One evaluation computes the union of
  /// their terms from one simulation and gives one value per weighting
  /// (Evaluation::values); what the terms need (the measured ridges when a
  /// weighting has IF) is prepared when the objective is built. Identify
  /// minimises one of them (IdentifyOptions::weighting).
  std::vector<NamedObjective> weightings{{"full", ObjectiveWeights::Preset("full")}};
  int modes = 1;                 ///< K, the leading POMs compared (>= 1, <= sensors)
  bool relative_sigma = true;    ///< dS relative to the measured sigmas (false: raw, eq. 19)
  /// Subtract each channel's time mean before the POD of both records (eq. 1,
  /// the paper's choice). false keeps the means, so that a constant offset
  /// of the response is compared: with one channel dS + r dV is then the
  /// output error ||x_sim - x_meas||^2 / ||x_meas||^2, r = ||x_sim|| / ||x_meas||
  /// (relative sigma; docs/method.md).
  bool remove_mean = true;
  /// Compare with the measured sigmas less the energy of white measurement
  /// noise, sqrt(sigma_k^2 - N u_k^T diag(v) u_k), v per sensor from second
  /// differences (podid/pod/noise.hpp): a noisy sigma against a clean
  /// simulated one biases dS (see notes() for the correction made).
  /// kAuto: corrected when modes > 1 (a higher mode's sigma is close to the
  /// noise floor: on the shared 1 s record, sigma_2 is 1.14e-3 measured
  /// against 7.7e-4 clean; sigma_1 moves by 0.02 % only).
  enum class SigmaNoise { kAuto, kCorrected, kRaw };
  SigmaNoise noise_corrected_sigma = SigmaNoise::kAuto;
  bool CorrectsSigma() const {
    return noise_corrected_sigma == SigmaNoise::kCorrected ||
           (noise_corrected_sigma == SigmaNoise::kAuto && modes > 1);
  }
  double failure_value = kDefaultFailureValue;  ///< see kDefaultFailureValue, > 0
  /// The IF extraction (used when a weighting needs it): 10-120 Hz, 32 voices,
  /// band-limited Morlet CWT (ridge.cwt.wavelet: Morse too), penalised ridge.
  wavelet::RidgeFrequencyOptions ridge;
  /// Several modes: the IF band of mode k + 1 (index k). Mode 1 always uses
  /// `ridge`'s band; a mode >= 2 without an entry here (or with follow()) gets
  /// a band of the same width in octaves centred on the peak of its measured
  /// time mode's periodogram (mode_ridges.hpp).
  std::vector<FrequencyBand> mode_bands;
  /// Measured ridge samples whose |W| is below ridge_min_snr times the rms |W|
  /// of the record's white noise (estimated per sensor from second
  /// differences, podid/pod/noise.hpp) are not compared: a mode that has
  /// decayed into the noise has a ridge that follows the noise. 3 is where a
  /// complex Gaussian noise coefficient exceeds it with probability
  /// exp(-9) = 1.2e-4. 0 compares every sample inside the cone.
  double ridge_min_snr = 3.0;
  /// Modes 2..K whose measured energy is less than this fraction signal
  /// (sigma_k,corrected^2 / sigma_k^2, the noise estimated as for
  /// noise_corrected_sigma) are not compared, nor the modes after them (see
  /// compared_modes() and notes()): their POM, sigma and ridge are the noise's
  /// (on the shared 1 s record mode 3 is 1.4 % signal, mode 2 44 %). 0
  /// compares all K.
  double min_signal_fraction = 0.1;
  /// A single weighting: weightings = {{weights.ToString(), weights}}.
  void SetWeights(const ObjectiveWeights& weights);
  bool IsValid(std::string* why) const;
};

/// The four terms of one evaluation (NaN for a term not computed).
struct TermValues {
  double u = std::numeric_limits<double>::quiet_NaN();
  double s = std::numeric_limits<double>::quiet_NaN();
  double v = std::numeric_limits<double>::quiet_NaN();
  double f = std::numeric_limits<double>::quiet_NaN();
  bool failed = false;
  std::string failure;  ///< why, when failed

  /// sum of weight * term, or failure_value when failed (or not finite).
  double Combine(const ObjectiveWeights& weights, double failure_value) const;
};

/// One evaluation: the terms (the union over the weightings) and the value of
/// each weighting (ObjectiveOptions::weightings order; failure_value for every
/// weighting when the evaluation failed).
struct Evaluation {
  TermValues terms;
  std::vector<double> values;
  /// The method the simulated POD used (kAuto resolved; kAuto when no POD was
  /// computed): kSvd means the Gram method was not accurate enough (bench/).
  PodMethod pod_method = PodMethod::kAuto;
  bool failed() const { return terms.failed; }
  const std::string& failure() const { return terms.failure; }
};

/// Per-thread state of ObjectiveFunction::Evaluate: the cached simulation
/// (podid::Simulator: only what a parameter change invalidates is rebuilt),
/// the POD and ridge buffers. Bound to the objective that first uses it; used
/// with another objective it starts afresh.
class EvaluationWorkspace {
 public:
  EvaluationWorkspace();
  ~EvaluationWorkspace();
  EvaluationWorkspace(EvaluationWorkspace&&) noexcept;
  EvaluationWorkspace& operator=(EvaluationWorkspace&&) noexcept;

 private:
  friend class ObjectiveFunction;
  unsigned long long owner = 0;  ///< ObjectiveFunction id
  std::unique_ptr<Simulator> simulator;
  Eigen::VectorXd document_values;  ///< the kDocument parameters' values simulated
  std::unique_ptr<PodSolver> pod;
  PodResult pod_result;        ///< the simulated POD, aligned to the measured one (no V)
  Eigen::MatrixXd time_modes;  ///< its compared modes' V (PodSolver::TimeModes)
  PodAlignment alignment;  ///< AlignToReference's buffers
  std::unique_ptr<wavelet::RidgeFrequencyEstimator> ridge;
  std::vector<std::unique_ptr<wavelet::RidgeFrequencyEstimator>> mode_ridges;
};

class ObjectiveFunction {
 public:
  /// Binds the case (its [[identify.parameter]]s, unless `parameters` is
  /// non-empty) to the measured data. The data's step and duration replace the
  /// case's [time] (see notes()); the case's sensor channel names must equal
  /// the data's. Each parameter key is resolved once into a typed
  /// ModelParameter (model_parameter.hpp). Throws std::invalid_argument for
  /// invalid options (e.g. no weighting), channels that do not match, no
  /// parameters, a parameter key the case cannot take, or a record too short
  /// for the ridge's lowest frequency when a weighting has IF.
  ObjectiveFunction(const CaseDocument& case_document, const TimeSeries& measured,
                    const ObjectiveOptions& options, std::vector<ParameterSpec> parameters = {});
  ObjectiveFunction(const ObjectiveFunction& other);
  ObjectiveFunction& operator=(const ObjectiveFunction&) = delete;
  ~ObjectiveFunction();

  int parameter_count() const { return static_cast<int>(parameters_.size()); }
  const std::vector<ParameterSpec>& parameters() const { return parameters_; }
  /// The index of the parameter named `name`. Throws std::invalid_argument
  /// "<where>: expected a parameter name (a, b), got "name"" otherwise.
  int ParameterIndex(std::string_view name, std::string_view where) const;
  /// The parameters' typed bindings (same order as parameters()).
  const std::vector<ModelParameter>& bindings() const { return bindings_; }
  /// The parameters' start values (dim parameter_count()).
  Eigen::VectorXd StartValues() const;
  const ObjectiveOptions& options() const { return options_; }
  int weighting_count() const { return static_cast<int>(options_.weightings.size()); }
  const TimeSeries& measured() const { return measured_; }
  const PodResult& measured_pod() const { return measured_pod_; }
  /// The modes compared: options().modes less the trailing ones found to be
  /// measurement noise (ObjectiveOptions::min_signal_fraction), >= 1.
  int compared_modes() const { return compared_modes_; }
  /// The measured IF tracks of the compared modes (empty without IF).
  const std::vector<wavelet::RidgeTrack>& measured_ridges() const { return measured_ridges_; }
  /// The ridge options of mode k (0-based): options().ridge's band for mode 1,
  /// the mode's own band for the others (ObjectiveOptions::mode_bands).
  const wavelet::RidgeFrequencyOptions& mode_ridge_options(int k) const { return mode_ridge_options_.at(k); }
  /// Messages about adjustments made to the case (time step from the data...).
  const std::vector<std::string>& notes() const { return notes_; }

  /// The terms and every weighting's value at `values` (dim
  /// parameter_count()). Thread-safe with one workspace per thread. Never
  /// throws: a wrong number of values, a value the case rejects, a numerical
  /// failure or any exception of the simulation, POD or wavelet stages (e.g.
  /// the POD of an all-zero response, std::bad_alloc) marks the result failed
  /// with the reason, so that it may be called from NLopt's C callback and
  /// from OpenMP regions. A null workspace uses a temporary one.
  Evaluation Evaluate(const Eigen::VectorXd& values, EvaluationWorkspace* workspace) const noexcept;
  Evaluation Evaluate(const Eigen::VectorXd& values) const noexcept;

  /// The case at `values` (for reports and plots). Throws
  /// std::invalid_argument for a value the case rejects.
  CaseSpec SpecAt(const Eigen::VectorXd& values) const;
  /// The noise-free simulation at `values`, built afresh, its sensors with the
  /// [data] conditioning applied (as Conditioned(): what Evaluate compares).
  SimulationResult SimulateAt(const Eigen::VectorXd& values) const;
  /// The same from the workspace's cached simulator (as Evaluate: a typed
  /// parameter rebuilds only what it invalidates; a file force is not
  /// interpolated again). Null workspace: built afresh. Throws
  /// std::invalid_argument for a value the case rejects.
  SimulationResult SimulateAt(const Eigen::VectorXd& values, EvaluationWorkspace* workspace) const;
  /// The POD of a simulated response as Evaluate computes it: mean removed,
  /// time modes, all modes (for the MAC matching of swapped modes), the
  /// compared ones accurate. (Evaluate itself skips the time modes and forms
  /// those of the compared modes after the alignment, PodSolver::TimeModes:
  /// the same values.)
  PodOptions ResponsePodOptions() const;
  /// Simulated sensors as Evaluate compares them: with the measured record's
  /// [data] conditioning (detrend, filter) applied (ConditionSimulated).
  TimeSeries Conditioned(const TimeSeries& simulated) const;

 private:
  void EvaluateOrThrow(const Eigen::VectorXd& values, EvaluationWorkspace* workspace,
                       Evaluation* result) const;
  bool PrepareSimulator(const Eigen::VectorXd& values, EvaluationWorkspace* workspace, std::string* why) const;
  /// The base case with the kDocument parameters set from `values`.
  CaseSpec DocumentSpecAt(const Eigen::VectorXd& values) const;

  unsigned long long id_ = 0;
  CaseDocument document_;
  CaseSpec base_spec_;
  TimeSeries measured_;
  ObjectiveOptions options_;
  ObjectiveWeights needed_{0.0, 0.0, 0.0, 0.0};  ///< the union of the weightings' terms
  std::vector<ParameterSpec> parameters_;
  std::vector<ModelParameter> bindings_;
  bool has_document_parameters_ = false;
  PodResult measured_pod_;
  int compared_modes_ = 1;
  std::vector<wavelet::RidgeFrequencyOptions> mode_ridge_options_;
  std::vector<wavelet::RidgeTrack> measured_ridges_;
  std::vector<std::string> notes_;
};

}  // namespace podid::ident
