#pragma once
// Objectives comparing measured and simulated decompositions (the paper's
// section 3, eq. 19, and section 4.3.2). Over the first K POMs (modes):
//   dU  = sum_k sum_i (U_sim(i,k) - U_meas(i,k))^2                  POM components
//   dS  = sum_k ((sigma_sim,k - sigma_meas,k) / sigma_meas,k)^2      relative (default)
//       = sum_k (sigma_sim,k - sigma_meas,k)^2                       raw, as eq. 19
//   dV  = sum_k sum_n (V_sim(n,k) - V_meas(n,k))^2                   right-singular vectors
//   dIF = sum_k D sum_j ((f_sim,k(t_j) - f_meas,k(t_j)) / f_meas,k(t_j))^2
//         the instantaneous frequency of V's column k along its Morlet ridge,
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
#include "podid/core/simulate.hpp"
#include "podid/core/time_series.hpp"
#include "podid/pod/pod.hpp"
#include "podid/wavelet/ridge.hpp"

namespace podid::ident {

/// Weights of the four terms; a zero weight skips the term's computation.
struct ObjectiveWeights {
  double u = 1.0;
  double s = 1.0;
  double v = 0.0;
  double f = 0.0;  ///< dIF

  bool NeedsRidges() const { return f != 0.0; }
  /// "full", "time-free", "wavelet"; throws std::invalid_argument naming the choices.
  static ObjectiveWeights Preset(std::string_view name);
  /// `terms` like "U,S,IF" and optional `weights` like "1,1,0.5" (default all 1).
  static ObjectiveWeights Parse(std::string_view terms, std::string_view weights = {});
  /// "U+S+IF" style description with weights when not 1.
  std::string ToString() const;
};

/// The objective value of an evaluation that failed (simulation diverged, a
/// parameter value the case rejects): larger than any finite objective of a
/// usable simulation in practice, finite so optimisers keep going.
inline constexpr double kDefaultFailureValue = 1e3;

struct ObjectiveOptions {
  int modes = 1;                 ///< K, the leading POMs compared (>= 1, <= sensors)
  bool relative_sigma = true;    ///< dS relative to the measured sigmas (false: raw, eq. 19)
  double failure_value = kDefaultFailureValue;  ///< see kDefaultFailureValue, > 0
  /// The IF extraction (used when a weight needs it): 10-120 Hz, 32 voices,
  /// band-limited Morlet CWT, penalised ridge.
  wavelet::RidgeFrequencyOptions ridge;
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

  /// sum of weight * term, or failure_value when failed.
  double Combine(const ObjectiveWeights& weights, double failure_value) const;
};

/// One identified parameter bound to its case key.
struct Parameter {
  ParameterSpec spec;  ///< name, key, scale, start, lower, upper (case value = scale * value)
};

/// Per-thread buffers of ObjectiveFunction::Evaluate.
class EvaluationWorkspace {
 public:
  EvaluationWorkspace() = default;

 private:
  friend class ObjectiveFunction;
  std::unique_ptr<PodSolver> pod;
  std::unique_ptr<wavelet::RidgeFrequencyEstimator> ridge;
};

class ObjectiveFunction {
 public:
  /// Binds the case (its [[identify.parameter]]s, unless `parameters` is
  /// non-empty) to the measured data. The data's step and duration replace the
  /// case's [time] (see notes()); the case's sensor channel names must equal
  /// the data's. Throws std::invalid_argument for channels that do not match,
  /// no parameters, a parameter key the case cannot take, or a record too short
  /// for the ridge's lowest frequency when `weights_needing_ridges`.
  ObjectiveFunction(const CaseDocument& case_document, const TimeSeries& measured,
                    const ObjectiveOptions& options, bool weights_needing_ridges,
                    std::vector<ParameterSpec> parameters = {});

  int parameter_count() const { return static_cast<int>(parameters_.size()); }
  const std::vector<ParameterSpec>& parameters() const { return parameters_; }
  /// The parameters' start values (dim parameter_count()).
  Eigen::VectorXd StartValues() const;
  const ObjectiveOptions& options() const { return options_; }
  const TimeSeries& measured() const { return measured_; }
  const PodResult& measured_pod() const { return measured_pod_; }
  /// The measured IF tracks of the first K modes (empty without ridges).
  const std::vector<wavelet::RidgeTrack>& measured_ridges() const { return measured_ridges_; }
  /// Messages about adjustments made to the case (time step from the data...).
  const std::vector<std::string>& notes() const { return notes_; }

  /// The terms at `values` (dim parameter_count()). Thread-safe with one
  /// workspace per thread. Never throws: a numerical failure, a value the case
  /// rejects or any exception of the simulation, POD or wavelet stages (e.g.
  /// the CWT of an all-zero response, std::bad_alloc) marks the result failed
  /// with the reason, so that it may be called from NLopt's C callback and
  /// from OpenMP regions.
  TermValues Evaluate(const Eigen::VectorXd& values, const ObjectiveWeights& weights,
                      EvaluationWorkspace* workspace) const;
  TermValues Evaluate(const Eigen::VectorXd& values, const ObjectiveWeights& weights) const;

  /// The case at `values` (for reports and plots).
  CaseSpec SpecAt(const Eigen::VectorXd& values) const;
  /// The noise-free simulation at `values`.
  SimulationResult SimulateAt(const Eigen::VectorXd& values) const;

 private:
  TermValues EvaluateOrThrow(const Eigen::VectorXd& values, const ObjectiveWeights& weights,
                             EvaluationWorkspace* workspace) const;

  CaseDocument document_;
  TimeSeries measured_;
  ObjectiveOptions options_;
  std::vector<ParameterSpec> parameters_;
  PodResult measured_pod_;
  std::vector<wavelet::RidgeTrack> measured_ridges_;
  std::vector<std::string> notes_;
};

}  // namespace podid::ident
