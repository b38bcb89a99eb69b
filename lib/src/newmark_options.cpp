// NewmarkOptions' checks and defaults from a case, and the summary's reports
// (newmark.hpp): kept apart from the time loop's file.
#include <limits>
#include <sstream>

#include "podid/core/error.hpp"
#include "podid/core/newmark.hpp"

namespace podid {

const char* ToString(SimulationTermination termination) {
  switch (termination) {
    case SimulationTermination::kNotRun: return "not run";
    case SimulationTermination::kCompleted: return "completed";
    case SimulationTermination::kStaticSolveFailed: return "static solve failed";
    case SimulationTermination::kNewtonFailed: return "Newton failed";
    case SimulationTermination::kNonFinite: return "non-finite state";
    case SimulationTermination::kDiverged: return "diverged";
  }
  return "unknown";
}

bool NewmarkOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (!(gamma >= 0.5 && gamma <= 1.0)) return fail("gamma: expected a value in [0.5, 1], got " + ToText(gamma));
  if (!(beta > 0.0 && beta <= 0.5)) return fail("beta: expected a value in (0, 0.5], got " + ToText(beta));
  if (!(step_s > 0.0 && std::isfinite(step_s))) return fail("step: expected a step > 0 s, got " + ToText(step_s));
  if (steps < 1) return fail("steps: expected at least 1 step, got " + ToText(steps));
  if (!(tolerance > 0.0 && tolerance < 1.0))
    return fail("tolerance: expected a value in (0, 1), got " + ToText(tolerance));
  if (max_iterations < 1) return fail("max_iterations: expected >= 1, got " + ToText(max_iterations));
  if (!(max_displacement > 0.0))
    return fail("max_displacement: expected > 0, got " + ToText(max_displacement));
  if (record_stride < 1 || steps % record_stride != 0)
    return fail("record_stride: expected >= 1 dividing steps (" + ToText(steps) + "), got " +
                ToText(record_stride));
  if (dense_dof_limit < 0) return fail("dense_dof_limit: expected >= 0, got " + ToText(dense_dof_limit));
  return true;
}

NewmarkOptions NewmarkOptions::FromCase(const CaseSpec& spec) {
  NewmarkOptions o;
  o.type = spec.integrator.type;
  o.gamma = spec.integrator.gamma;
  o.beta = spec.integrator.beta;
  o.tolerance = spec.integrator.tolerance;
  o.max_iterations = spec.integrator.max_iterations;
  const int k = spec.integrator.substeps;
  const long long fine_steps = static_cast<long long>(spec.time.samples() - 1) * k;
  if (k < 1 || fine_steps > std::numeric_limits<int>::max()) {
    ThrowInvalid("integrator.substeps",
                 "1.." + ToText(kMaxSubsteps) + " with (samples - 1) substeps <= " +
                     ToText(std::numeric_limits<int>::max()),
                 ToText(k) + " (" + ToText(fine_steps) + " steps)");
  }
  o.step_s = spec.time.step_s / k;
  o.steps = static_cast<int>(fine_steps);
  o.record_stride = k;
  return o;
}

std::string SimulationSummary::BriefReport() const {
  std::ostringstream os;
  os.precision(4);
  os << (integrator == IntegratorType::kModifiedNewmark ? "modified Newmark" : "Newmark (full Newton)")
     << ": " << ToString(termination) << ", " << steps_completed << "/" << steps_requested
     << " steps, " << newton_iterations << " Newton iterations (max " << max_step_iterations
     << " in a step), " << wall_time_s * 1e3 << " ms";
  return os.str();
}

std::string SimulationSummary::FullReport() const {
  std::ostringstream os;
  os.precision(6);
  os << "Simulation summary\n"
     << "  integrator:         "
     << (integrator == IntegratorType::kModifiedNewmark ? "modified Newmark (condensed, eq. 29)"
                                                        : "Newmark, Newton on all dofs")
     << "\n  dofs:               " << dofs << " (" << nonlinear_dofs << " nonlinear)"
     << "\n  steps:              " << steps_completed << " of " << steps_requested
     << "\n  Newton iterations:  " << newton_iterations << " total, worst step "
     << max_step_iterations << " at t = " << worst_step_time_s << " s"
     << "\n  step solve error:   " << step_error_estimate << " (estimated, relative, over all dofs"
     << (step_error_estimate > kMaxStepRelativeError ? "; above " + ToText(kMaxStepRelativeError)
                                                     : std::string())
     << ")"
     << "\n  wall time:          " << wall_time_s << " s"
     << "\n  termination:        " << ToString(termination) << "\n  message:            " << message
     << "\n";
  return os.str();
}

}  // namespace podid
