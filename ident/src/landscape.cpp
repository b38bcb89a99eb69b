#include "podid/ident/landscape.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <sstream>

#include "podid/core/error.hpp"
#include "worker_threads.hpp"

namespace podid::ident {

Eigen::VectorXd LandscapeAxis::Values() const {
  Eigen::VectorXd v(points);
  for (int i = 0; i < points; ++i) v[i] = lower + (upper - lower) * i / (points - 1);
  return v;
}

bool LandscapeOptions::IsValid(int parameter_count, std::string* why) const {
  auto fail = [why](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  for (const LandscapeAxis* axis : {&x, y ? &*y : nullptr}) {
    if (!axis) continue;
    if (axis->parameter < 0 || axis->parameter >= parameter_count)
      return fail("axis parameter: expected an index in 0.." + ToText(parameter_count - 1) +
                  ", got " + ToText(axis->parameter));
    if (!(axis->lower < axis->upper) || !std::isfinite(axis->lower) || !std::isfinite(axis->upper))
      return fail("range: expected lower < upper, got " + ToText(axis->lower) + ":" +
                  ToText(axis->upper));
    if (axis->points < 2 || axis->points > kMaxLandscapePoints)
      return fail("range: expected 2 to " + ToText(kMaxLandscapePoints) + " points, got " +
                  ToText(axis->points));
    // Every grid value finite: lower + (upper - lower) i / (n - 1) overflows
    // for bounds like -1.7e308:1.7e308.
    if (!std::isfinite(axis->upper - axis->lower))
      return fail("range: expected a finite width upper - lower, got " + ToText(axis->lower) +
                  ":" + ToText(axis->upper));
  }
  if (y && static_cast<long long>(x.points) * y->points > kMaxLandscapePoints)
    return fail("range: expected at most " + ToText(kMaxLandscapePoints) +
                " points in all, got " + ToText(x.points) + " x " + ToText(y->points));
  if (base.size() != 0 && base.size() != parameter_count)
    return fail("base: expected " + ToText(parameter_count) + " values, got " + ToText(base.size()));
  if (y && y->parameter == x.parameter)
    return fail("second parameter: expected a parameter other than the first, got the same");
  if (threads < 0 || threads > kMaxThreads)
    return fail("threads: expected 0 to " + ToText(kMaxThreads) + ", got " + ToText(threads));
  if (share_count < 1 || share_count > 65536 || share_index < 0 || share_index >= share_count)
    return fail("share: expected 0 <= index < count <= 65536, got " + ToText(share_index) + " of " +
                ToText(share_count));
  return true;
}

LandscapeMetrics ComputeMetrics(const Eigen::VectorXd& x_all, const Eigen::VectorXd& f_all) {
  if (x_all.size() != f_all.size()) {
    ThrowInvalid("ComputeMetrics", "x and f of one size " + ToText(x_all.size()),
                 ToText(f_all.size()));
  }
  // The curve through the points that succeeded.
  Eigen::Index n = 0;
  for (Eigen::Index i = 0; i < f_all.size(); ++i) n += std::isfinite(f_all[i]) ? 1 : 0;
  if (n == 0) ThrowInvalid("ComputeMetrics", "at least one finite value", "none");
  Eigen::VectorXd x(n), f(n);
  for (Eigen::Index i = 0, k = 0; i < f_all.size(); ++i) {
    if (!std::isfinite(f_all[i])) continue;
    x[k] = x_all[i];
    f[k++] = f_all[i];
  }
  LandscapeMetrics m;
  Eigen::Index best = 0;
  for (Eigen::Index i = 1; i < n; ++i)
    if (f[i] < f[best]) best = i;
  m.global_minimiser = x[best];
  m.global_minimum = f[best];

  // Local minima on the sequence with runs of equal values merged.
  std::vector<double> merged;
  for (Eigen::Index i = 0; i < n; ++i)
    if (merged.empty() || f[i] != merged.back()) merged.push_back(f[i]);
  const std::size_t k = merged.size();
  if (k == 1) {
    m.local_minima = 1;
  } else {
    for (std::size_t i = 0; i < k; ++i) {
      const bool left_ok = i == 0 || merged[i] < merged[i - 1];
      const bool right_ok = i + 1 == k || merged[i] < merged[i + 1];
      if (left_ok && right_ok) ++m.local_minima;
    }
  }

  // Basin: f non-increasing towards the global minimiser.
  Eigen::Index lo = best, hi = best;
  while (lo > 0 && f[lo - 1] >= f[lo]) --lo;
  while (hi + 1 < n && f[hi + 1] >= f[hi]) ++hi;
  m.basin_lower = x[lo];
  m.basin_upper = x[hi];
  const double width = x_all[x_all.size() - 1] - x_all[0];
  m.basin_fraction = width > 0 ? (x[hi] - x[lo]) / width : 1.0;

  double variation = 0.0;
  for (Eigen::Index i = 1; i < n; ++i) variation += std::abs(f[i] - f[i - 1]);
  const double range = f.maxCoeff() - f.minCoeff();
  m.roughness = range > 0 ? variation / range : 0.0;
  return m;
}

std::string LandscapeResult::BriefReport() const {
  std::ostringstream os;
  const char* state = "not run";
  switch (termination) {
    case LandscapeTermination::kNotRun: break;
    case LandscapeTermination::kCompleted: state = "completed"; break;
    case LandscapeTermination::kNoneSucceeded: state = "no point succeeded"; break;
    case LandscapeTermination::kInterrupted: state = "interrupted"; break;
  }
  os << "landscape: " << state << ", " << evaluations << " points (" << failed_evaluations
     << " failed), " << wall_time_s << " s";
  return os.str();
}

LandscapeResult ComputeLandscape(const ObjectiveFunction& objective, const LandscapeOptions& options) {
  std::string why;
  if (!options.IsValid(objective.parameter_count(), &why)) {
    throw std::invalid_argument("landscape options: " + why);
  }
  const auto start_time = std::chrono::steady_clock::now();
  LandscapeResult result;
  const std::vector<NamedObjective>& weightings = objective.options().weightings;
  for (const NamedObjective& o : weightings) result.names.push_back(o.name);
  result.x = options.x.Values();
  result.parameter_names.push_back(objective.parameters()[options.x.parameter].name);
  if (options.y) {
    result.y = options.y->Values();
    result.parameter_names.push_back(objective.parameters()[options.y->parameter].name);
  }
  const Eigen::Index nx = result.x.size();
  const Eigen::Index ny = std::max<Eigen::Index>(result.y.size(), 1);
  const Eigen::Index total = nx * ny;

  // One simulation per point gives every weighting's value (Evaluate).
  result.terms.assign(total, TermValues{});
  result.computed.assign(total, 0);
  const Eigen::VectorXd base = options.base.size() ? options.base : objective.StartValues();
  long long finished = 0, failed = 0;
  long long mine = 0;  // the points of this share
  for (Eigen::Index p = options.share_index; p < total; p += options.share_count) ++mine;
  // No exception may leave the parallel region: the first one stops the
  // remaining points and is rethrown after it. (Evaluate itself never throws;
  // this covers the buffers, e.g. std::bad_alloc, and the progress callback.)
  std::exception_ptr error, progress_error;
  std::atomic<bool> stop{false};
  const int threads = internal::WorkerThreads(options.threads, static_cast<std::size_t>(mine));

#pragma omp parallel num_threads(threads)
  {
    try {
      EvaluationWorkspace workspace;
      Eigen::VectorXd values = base;
#pragma omp for schedule(dynamic)
      for (Eigen::Index q = 0; q < mine; ++q) {
        if (stop.load(std::memory_order_relaxed) || (options.cancel && options.cancel->load()))
          continue;
        const Eigen::Index p = options.share_index + q * options.share_count;
        try {
          const Eigen::Index i = p / ny, j = p % ny;
          values[options.x.parameter] = result.x[i];
          if (options.y) values[options.y->parameter] = result.y[j];
          Evaluation e = objective.Evaluate(values, &workspace);
          result.terms[p] = std::move(e.terms);
          result.computed[p] = 1;
          if (options.progress) {
#pragma omp critical(podid_landscape_progress)
            {
              ++finished;
              failed += result.terms[p].failed ? 1 : 0;
              Progress progress;
              progress.done = finished;
              progress.total = mine;
              progress.failed = failed;
              progress.elapsed_s =
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
              // No exception may leave a critical region either; once one
              // has stopped the run, the callback is not called again.
              if (!stop.load()) {
                try {
                  options.progress(progress);
                } catch (...) {
                  progress_error = std::current_exception();
                  stop.store(true);
                }
              }
            }
          }
        } catch (...) {
#pragma omp critical(podid_landscape_error)
          if (!error) error = std::current_exception();
          stop.store(true);
        }
      }
    } catch (...) {  // the workspace or the parameter vector
#pragma omp critical(podid_landscape_error)
      if (!error) error = std::current_exception();
      stop.store(true);
    }
  }
  if (error) std::rethrow_exception(error);
  if (progress_error) std::rethrow_exception(progress_error);
  SummariseLandscape(objective.options().weightings, &result);
  result.wall_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
  return result;
}

void SummariseLandscape(const std::vector<NamedObjective>& weightings, LandscapeResult* r) {
  LandscapeResult& result = *r;
  const Eigen::Index nx = result.x.size();
  const Eigen::Index ny = std::max<Eigen::Index>(result.y.size(), 1);
  const Eigen::Index total = nx * ny;
  PODID_CHECK(static_cast<Eigen::Index>(result.terms.size()) == total &&
              static_cast<Eigen::Index>(result.computed.size()) == total);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  result.values.clear();
  for (const NamedObjective& weighting : weightings) {
    Eigen::MatrixXd v(nx, ny);
    for (Eigen::Index p = 0; p < total; ++p) {
      // A failed point is NaN, never the failure value (which is not an
      // objective); so is a non-finite combination.
      const bool usable = result.computed[p] && !result.terms[p].failed;
      v(p / ny, p % ny) = usable ? result.terms[p].Combine(weighting.weights, nan) : nan;
    }
    result.values.push_back(v);
  }
  result.evaluations = result.failed_evaluations = 0;
  for (Eigen::Index p = 0; p < total; ++p) {
    if (!result.computed[p]) continue;
    ++result.evaluations;
    if (result.terms[p].failed) ++result.failed_evaluations;
  }
  const bool complete = result.evaluations == total;
  const bool none_succeeded = complete && result.failed_evaluations == total;
  result.metrics.clear();
  if (!complete) {
    result.termination = LandscapeTermination::kInterrupted;
    result.message = "interrupted after " + ToText(result.evaluations) + " of " + ToText(total) +
                     " points";
  } else if (none_succeeded) {
    result.termination = LandscapeTermination::kNoneSucceeded;
    result.message = "none of the " + ToText(total) + " points succeeded; e.g. at " +
                     result.parameter_names[0] + " = " + ToText(result.x[0]) +
                     (result.y.size() ? ", " + result.parameter_names[1] + " = " + ToText(result.y[0])
                                      : std::string()) +
                     ": " + result.terms[0].failure;
  } else {
    result.termination = LandscapeTermination::kCompleted;
    result.message = "completed " + ToText(total) + " points";
    if (result.failed_evaluations > 0) {
      result.message += " (" + ToText(result.failed_evaluations) + " failed, NaN)";
    }
  }
  if (result.termination == LandscapeTermination::kCompleted && result.y.size() == 0) {
    for (const Eigen::MatrixXd& v : result.values) {
      if (v.col(0).array().isFinite().any()) {
        result.metrics.push_back(ComputeMetrics(result.x, v.col(0)));
      } else {  // every successful point gave a non-finite value of this objective
        LandscapeMetrics none;
        none.global_minimiser = none.global_minimum = nan;
        none.basin_lower = none.basin_upper = none.basin_fraction = none.roughness = nan;
        result.metrics.push_back(none);
      }
    }
  }
}

}  // namespace podid::ident
