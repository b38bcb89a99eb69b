#pragma once
// Identification: minimise an objective over the parameters' box with NLopt
// (Ceres-style options and summary). Local derivative-free algorithms start
// from the parameters' start (and, with multistart > 1, from Latin-hypercube
// points in the bounds, run in parallel); global ones search the whole box.
// The best point seen is kept whatever NLopt returns.

#include <Eigen/Core>
#include <atomic>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "podid/ident/objective.hpp"
#include "podid/ident/progress.hpp"
#include "podid/ident/uncertainty.hpp"

namespace podid::ident {

enum class Algorithm {
  kLnBobyqa,      ///< LN_BOBYQA (default): quadratic trust-region models
  kLnNelderMead,  ///< LN_NELDERMEAD
  kLnSbplx,       ///< LN_SBPLX (subplex)
  kLnCobyla,      ///< LN_COBYLA
  kGnDirectL,     ///< GN_DIRECT_L (global, deterministic)
  kGnCrs2Lm,      ///< GN_CRS2_LM (global, random, seeded)
  kGnIsres,       ///< GN_ISRES (global, random, seeded)
  kGnMlslLds,     ///< GN_MLSL_LDS (NLopt's G_MLSL_LDS) with a local optimiser (local_algorithm)
};

/// NLopt's names: "LN_BOBYQA", ... (case-insensitive).
Algorithm ParseAlgorithm(std::string_view name);
const char* ToString(Algorithm algorithm);
bool IsLocal(Algorithm algorithm);

/// Upper bounds of the counts a user gives, checked before anything is
/// allocated: every evaluation keeps an IterationRecord (~100 bytes), so the
/// total budget multistart * max_evaluations is bounded too (~100 MB).
inline constexpr int kMaxMultistart = 10'000;
inline constexpr int kMaxEvaluations = 1'000'000;
inline constexpr long long kMaxTotalEvaluations = 1'000'000;

struct IdentifyOptions {
  Algorithm algorithm = Algorithm::kLnBobyqa;
  Algorithm local_algorithm = Algorithm::kLnBobyqa;  ///< for GN_MLSL_LDS; must be local
  /// The weighting minimised: an index into the objective's
  /// ObjectiveOptions::weightings (0: the first).
  int weighting = 0;
  /// Start (dim parameter_count); empty = the parameters' start values.
  Eigen::VectorXd start;
  double xtol_rel = 1e-6;   ///< stop when |dx| < xtol_rel |x| (> 0)
  double ftol_rel = 1e-10;  ///< stop when |df| < ftol_rel |f| (>= 0)
  int max_evaluations = 500;  ///< per start, in [1, kMaxEvaluations]
  double max_time_s = 0.0;    ///< per start, 0 = none
  int multistart = 1;          ///< local algorithms: number of starts, in [1, kMaxMultistart];
                              ///< multistart * max_evaluations <= kMaxTotalEvaluations
  std::uint64_t seed = 1;      ///< Latin hypercube and random global algorithms
  const std::atomic<bool>* cancel = nullptr;  ///< stops the run when it becomes true
  /// After each evaluation (see progress.hpp; total = starts * max_evaluations,
  /// an upper bound); empty = none.
  ProgressCallback progress;
  /// Starts run in parallel on this many threads, in [0, kMaxThreads]; 0 = OpenMP's
  /// default (OMP_NUM_THREADS, else one per core; at most kMaxThreads). Never more
  /// threads than this process's starts.
  int threads = 0;
  /// This process runs the starts s with s % share_count == share_index (the
  /// CLI's MPI ranks); merge the shares' start_results and histories, then
  /// call SummariseStarts().
  int share_index = 0;
  int share_count = 1;  ///< in [1, 65536]
  /// Standard errors, intervals and correlations at the best point
  /// (objective_uncertainty.hpp; 2 p + 2 simulations and noise_draws PODs).
  /// Not with share_count > 1: the caller computes them on the merged result.
  bool uncertainty = true;
  UncertaintyOptions uncertainty_options;
  bool IsValid(int parameter_count, std::string* why) const;
};

enum class Termination {
  kNotRun,
  kConverged,          ///< xtol or ftol reached
  kMaxEvaluations,     ///< budget exhausted; the best point seen is reported
  kMaxTime,            ///< time limit; the best point seen is reported
  kRoundoffLimited,    ///< NLopt stopped on round-off; the best point seen is reported
  kFailure,            ///< NLopt failed (generic failure, out of memory)
  kInvalidArguments,   ///< NLopt rejected the problem
  kInterrupted,        ///< cancelled by the caller
  kAllEvaluationsFailed,  ///< every simulation failed: no usable point
};

const char* ToString(Termination termination);

struct IterationRecord {
  int evaluation = 0;   ///< 1-based, within its start
  int start = 0;        ///< 0-based start index
  Eigen::VectorXd parameters;
  double objective = 0.0;
  double best_objective = 0.0;  ///< best so far within the start
  bool failed = false;
  std::string failure;  ///< why, when failed
};

/// What one start of a (multistart) identification found.
struct StartResult {
  bool computed = false;   ///< run (by this process, or merged)
  int evaluations = 0;
  int failed_evaluations = 0;
  double best_objective = std::numeric_limits<double>::infinity();
  Eigen::VectorXd best_parameters;  ///< empty when every evaluation failed
  TermValues best_terms;
  int nlopt_result = 0;             ///< NLopt's nlopt_result code
  std::string first_failure;        ///< the reason of its first failed evaluation
};

struct IdentifySummary {
  Termination termination = Termination::kNotRun;
  std::string message = "Identify was not called.";
  std::string algorithm;
  std::string objective;  ///< e.g. "dU + dS + dV"
  ObjectiveWeights weights{0.0, 0.0, 0.0, 0.0};  ///< the weighting minimised
  std::vector<std::string> parameter_names;
  Eigen::VectorXd initial_parameters;
  Eigen::VectorXd parameters;  ///< the best point seen
  double initial_objective = std::numeric_limits<double>::quiet_NaN();  ///< NaN if the start failed
  double final_objective = std::numeric_limits<double>::quiet_NaN();
  TermValues final_terms;
  /// The terms at the start as given (the first start), to see whether one
  /// term swamps the others (see TermContributions()).
  TermValues initial_terms;
  int evaluations = 0;
  int failed_evaluations = 0;
  int starts = 0;
  int best_start = 0;
  double wall_time_s = 0.0;
  std::vector<IterationRecord> history;  ///< every evaluation, by start
  std::vector<StartResult> start_results;  ///< per start (dim starts)
  /// At `parameters` (usable = false with the reason when not computed).
  ParameterUncertainty uncertainty;

  bool IsSolutionUsable() const;
  std::string BriefReport() const;
  std::string FullReport() const;
};

/// Each term's share of F = sum_t w_t d_t at `terms`: "dU 0.3 %, dS 0.01 %,
/// dIF 99.7 %" (the terms the weighting uses; empty when failed).
std::string TermContributions(const TermValues& terms, const ObjectiveWeights& weights);

/// Throws std::invalid_argument for invalid options. Numerical trouble goes
/// into the summary. Each start's point is evaluated first exactly as given
/// (global algorithms, which begin elsewhere, the box centre for DIRECT,
/// included), so the initial objective is the start's; the local algorithms'
/// first trust region or simplex is kept inside the bounds around it.
IdentifySummary Identify(const ObjectiveFunction& objective, const IdentifyOptions& options);

/// Sets the totals, the best point, the termination and the message of
/// `summary` from its start_results and history (Identify ends with it; call
/// it again after merging the shares of several processes). Without a usable
/// point the termination is kInterrupted when some start was not computed
/// (else kAllEvaluationsFailed); otherwise it is the best start's NLopt result.
void SummariseStarts(IdentifySummary* summary);

}  // namespace podid::ident
