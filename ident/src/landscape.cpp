#include "podid/ident/landscape.hpp"

#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "podid/core/error.hpp"

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
  if (objectives.empty()) return fail("objectives: expected at least one, got none");
  for (const LandscapeAxis* axis : {&x, y ? &*y : nullptr}) {
    if (!axis) continue;
    if (axis->parameter < 0 || axis->parameter >= parameter_count)
      return fail("axis parameter: expected an index in 0.." + ToText(parameter_count - 1) +
                  ", got " + ToText(axis->parameter));
    if (!(axis->lower < axis->upper) || !std::isfinite(axis->lower) || !std::isfinite(axis->upper))
      return fail("range: expected lower < upper, got " + ToText(axis->lower) + ":" +
                  ToText(axis->upper));
    if (axis->points < 2) return fail("range: expected >= 2 points, got " + ToText(axis->points));
  }
  if (base.size() != 0 && base.size() != parameter_count)
    return fail("base: expected " + ToText(parameter_count) + " values, got " + ToText(base.size()));
  if (y && y->parameter == x.parameter)
    return fail("second parameter: expected a parameter other than the first, got the same");
  return true;
}

LandscapeMetrics ComputeMetrics(const Eigen::VectorXd& x, const Eigen::VectorXd& f) {
  PODID_CHECK(x.size() == f.size() && x.size() >= 2);
  const Eigen::Index n = f.size();
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
  m.basin_fraction = (x[hi] - x[lo]) / (x[n - 1] - x[0]);

  double variation = 0.0;
  for (Eigen::Index i = 1; i < n; ++i) variation += std::abs(f[i] - f[i - 1]);
  const double range = f.maxCoeff() - f.minCoeff();
  m.roughness = range > 0 ? variation / range : 0.0;
  return m;
}

std::string LandscapeResult::BriefReport() const {
  std::ostringstream os;
  os << "landscape: " << (termination == LandscapeTermination::kCompleted ? "completed" : "interrupted")
     << ", " << evaluations << " points (" << failed_evaluations << " failed), " << wall_time_s
     << " s";
  return os.str();
}

LandscapeResult ComputeLandscape(const ObjectiveFunction& objective, const LandscapeOptions& options) {
  std::string why;
  if (!options.IsValid(objective.parameter_count(), &why)) {
    throw std::invalid_argument("landscape options: " + why);
  }
  const auto start_time = std::chrono::steady_clock::now();
  LandscapeResult result;
  for (const NamedObjective& o : options.objectives) result.names.push_back(o.name);
  result.x = options.x.Values();
  result.parameter_names.push_back(objective.parameters()[options.x.parameter].name);
  if (options.y) {
    result.y = options.y->Values();
    result.parameter_names.push_back(objective.parameters()[options.y->parameter].name);
  }
  const Eigen::Index nx = result.x.size();
  const Eigen::Index ny = std::max<Eigen::Index>(result.y.size(), 1);
  const Eigen::Index total = nx * ny;

  // One simulation per point computes the union of the objectives' terms.
  ObjectiveWeights all{0.0, 0.0, 0.0, 0.0};
  for (const NamedObjective& o : options.objectives) {
    all.u = std::max(all.u, o.weights.u != 0 ? 1.0 : 0.0);
    all.s = std::max(all.s, o.weights.s != 0 ? 1.0 : 0.0);
    all.v = std::max(all.v, o.weights.v != 0 ? 1.0 : 0.0);
    all.f = std::max(all.f, o.weights.f != 0 ? 1.0 : 0.0);
  }
  result.terms.assign(total, TermValues{});
  std::vector<char> done(total, 0);
  const Eigen::VectorXd base = options.base.size() ? options.base : objective.StartValues();
  const bool progress = options.progress && isatty(STDERR_FILENO);
  int finished = 0;

#pragma omp parallel
  {
    EvaluationWorkspace workspace;
    Eigen::VectorXd values = base;
#pragma omp for schedule(dynamic)
    for (Eigen::Index p = 0; p < total; ++p) {
      if (options.cancel && options.cancel->load()) continue;
      const Eigen::Index i = p / ny, j = p % ny;
      values[options.x.parameter] = result.x[i];
      if (options.y) values[options.y->parameter] = result.y[j];
      result.terms[p] = objective.Evaluate(values, all, &workspace);
      done[p] = 1;
      if (progress) {
#pragma omp critical(podid_landscape_progress)
        {
          ++finished;
          std::fprintf(stderr, "\rlandscape: %d/%ld points", finished, static_cast<long>(total));
          std::fflush(stderr);
        }
      }
    }
  }
  if (progress) std::fprintf(stderr, "\n");

  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const NamedObjective& o : options.objectives) {
    Eigen::MatrixXd v(nx, ny);
    for (Eigen::Index p = 0; p < total; ++p) {
      v(p / ny, p % ny) = done[p] ? result.terms[p].Combine(o.weights, objective.options().failure_value) : nan;
    }
    result.values.push_back(v);
  }
  for (Eigen::Index p = 0; p < total; ++p) {
    if (!done[p]) continue;
    ++result.evaluations;
    if (result.terms[p].failed) ++result.failed_evaluations;
  }
  const bool complete = result.evaluations == total;
  result.termination = complete ? LandscapeTermination::kCompleted : LandscapeTermination::kInterrupted;
  result.message = complete ? "completed " + ToText(total) + " points"
                            : "interrupted after " + ToText(result.evaluations) + " of " +
                                  ToText(total) + " points";
  if (complete && !options.y) {
    for (const Eigen::MatrixXd& v : result.values) result.metrics.push_back(ComputeMetrics(result.x, v.col(0)));
  }
  result.wall_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
  return result;
}

}  // namespace podid::ident
