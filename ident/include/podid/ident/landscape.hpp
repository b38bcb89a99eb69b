#pragma once
// Objective landscapes (the paper's figs. 3-6): objective vs one parameter on
// a grid, or two parameters on a 2-D grid, for every weighting of the
// objective (ObjectiveOptions::weightings) at once: one simulation per grid
// point feeds every weighting (ObjectiveFunction::Evaluate). Points run in parallel
// (OpenMP), one EvaluationWorkspace per thread. Other parameters stay at
// LandscapeOptions::base (default: their start values).

#include <Eigen/Core>
#include <atomic>
#include <optional>
#include <string>
#include <vector>

#include "podid/ident/objective.hpp"
#include "podid/ident/progress.hpp"

namespace podid::ident {

/// The most grid points of a landscape (per axis and in total, nx * ny):
/// about 100 MB of results, and hours of simulations at ~10 ms a point.
inline constexpr long long kMaxLandscapePoints = 1'000'000;

/// A uniform grid lower..upper with `points` values of parameter `parameter`.
struct LandscapeAxis {
  int parameter = 0;  ///< index into ObjectiveFunction::parameters()
  double lower = 0.0;
  double upper = 1.0;
  int points = 101;   ///< in [2, kMaxLandscapePoints]
  Eigen::VectorXd Values() const;
};

struct LandscapeOptions {
  LandscapeAxis x;
  std::optional<LandscapeAxis> y;          ///< second axis for a 2-D landscape
  /// Values of the parameters not on an axis (dim parameter_count); empty =
  /// their start values.
  Eigen::VectorXd base;
  /// After each point (see progress.hpp); empty = none.
  ProgressCallback progress;
  /// Checked between points: when it becomes true the run stops early and the
  /// summary says kInterrupted (values not computed are NaN).
  const std::atomic<bool>* cancel = nullptr;
  /// Worker threads, in [0, kMaxThreads]; 0 = OpenMP's default (OMP_NUM_THREADS,
  /// else one per core; at most kMaxThreads). Each thread has its own workspace
  /// (a simulation's buffers), so there are never more threads than this share's points.
  int threads = 0;
  /// This process computes the points p (row-major, p = i ny + j) with
  /// p % share_count == share_index; the others are left not computed, for
  /// another process to compute (the CLI's MPI ranks). Merge the shares'
  /// terms and `computed` flags, then call SummariseLandscape().
  int share_index = 0;
  int share_count = 1;  ///< in [1, 65536]
  bool IsValid(int parameter_count, std::string* why) const;
};

/// Metrics of a 1-D landscape f(x) on its grid, for comparing objectives.
/// Failed points (NaN, or any non-finite value) are left out: the metrics are
/// those of the curve through the points that succeeded. Throws
/// std::invalid_argument when no value is finite.
struct LandscapeMetrics {
  /// Grid local minima, the ends included: after merging runs of equal values,
  /// a point lower than each of its neighbours.
  int local_minima = 0;
  double global_minimiser = 0.0;  ///< x of the lowest value (first if tied)
  double global_minimum = 0.0;
  /// The basin of attraction of the global minimiser: the interval of grid
  /// points from which a descent to the lower neighbour reaches it, i.e. f is
  /// non-increasing towards it on [basin_lower, basin_upper].
  double basin_lower = 0.0;
  double basin_upper = 0.0;
  double basin_fraction = 0.0;  ///< (basin_upper - basin_lower) / (x_max - x_min)
  /// Total variation / (max - min): 1 for a monotone curve, 2 for a clean valley
  /// with equal ends, larger the more the curve ripples.
  double roughness = 0.0;
};

LandscapeMetrics ComputeMetrics(const Eigen::VectorXd& x, const Eigen::VectorXd& f);

/// kCompleted: every point evaluated and at least one succeeded (failed points
/// are NaN); kNoneSucceeded: every point evaluated and every one failed (no
/// metrics, no minimiser); kInterrupted: the cancel flag stopped it.
enum class LandscapeTermination { kNotRun, kCompleted, kNoneSucceeded, kInterrupted };

struct LandscapeResult {
  std::vector<std::string> names;      ///< the objective's weighting names
  std::vector<std::string> parameter_names;  ///< x (and y) parameter names
  Eigen::VectorXd x;                   ///< (dim nx) grid
  Eigen::VectorXd y;                   ///< (dim ny) grid, empty for 1-D
  /// per weighting, (nx x max(ny, 1)); NaN where the point failed or was not
  /// computed (never the objective's failure_value)
  std::vector<Eigen::MatrixXd> values;
  std::vector<TermValues> terms;       ///< per point, row-major (i * ny + j)
  std::vector<char> computed;          ///< per point: 1 when evaluated (by this process or merged)
  std::vector<LandscapeMetrics> metrics;  ///< per weighting (1-D landscapes only)
  LandscapeTermination termination = LandscapeTermination::kNotRun;
  std::string message = "Landscape was not computed.";
  int evaluations = 0;
  int failed_evaluations = 0;
  double wall_time_s = 0.0;
  std::string BriefReport() const;
};

/// Throws std::invalid_argument for invalid options.
LandscapeResult ComputeLandscape(const ObjectiveFunction& objective, const LandscapeOptions& options);

/// Fills `values`, the counts, the termination, the message and the metrics
/// of `result` from its `terms` and `computed` flags (ComputeLandscape ends
/// with it; call it again after merging the shares of several processes).
/// A point not computed makes the result kInterrupted.
void SummariseLandscape(const std::vector<NamedObjective>& weightings, LandscapeResult* result);

}  // namespace podid::ident
