#include "podid/core/simulate.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include "podid/core/error.hpp"
#include "podid/core/noise.hpp"

namespace podid {

State InitialState(const CaseSpec& spec, const BeamModel& model, StaticSolveSummary* static_summary) {
  const int n = model.dofs();
  State state{Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n)};
  switch (spec.initial.type) {
    case InitialType::kRest:
      break;
    case InitialType::kExplicit:
      if (spec.initial.displacement.size() != n || spec.initial.velocity.size() != n) {
        ThrowInvalid("initial.displacement/velocity", ToText(n) + " values each (one per model dof)",
                     ToText(spec.initial.displacement.size()) + " and " +
                         ToText(spec.initial.velocity.size()));
      }
      state.displacement = spec.initial.displacement;
      state.velocity = spec.initial.velocity;
      break;
    case InitialType::kStaticForce: {
      const int dof = ResolveDof(spec, spec.initial.static_force_node, spec.initial.static_force_dof,
                                 SensorDof::kW,
                                 spec.initial.static_force_dof > 0 ? "initial.dof" : "initial.node");
      Eigen::VectorXd force = Eigen::VectorXd::Zero(n);
      force[dof] = spec.initial.static_force_N;
      StaticSolveSummary local;
      state.displacement = SolveStatic(model, force, StaticSolveOptions{}, &local);
      if (static_summary) *static_summary = local;
      break;
    }
  }
  return state;
}

std::vector<int> SensorDofs(const CaseSpec& spec) {
  std::vector<int> dofs;
  if (!spec.sensors.dofs.empty()) {
    for (int dof : spec.sensors.dofs) {
      if (dof < 1) ThrowInvalid("sensors.dofs", "model dofs in 1.." + ToText(spec.dofs()), ToText(dof));
      dofs.push_back(ResolveDof(spec, 0, dof, spec.sensors.dof, "sensors.dofs"));
    }
    return dofs;
  }
  for (int node : spec.sensors.nodes) {
    dofs.push_back(ResolveDof(spec, node, 0, spec.sensors.dof, "sensors.nodes"));
  }
  return dofs;
}

void AddBaseAcceleration(const CaseSpec& spec, const ExternalLoad& load, int rows, Recording* recording) {
  // Accelerometers under base excitation: u'' = u_r'' + r a_g at the samples.
  if (load.base_row < 0 || spec.sensors.quantity != SensorQuantity::kAcceleration ||
      spec.sensors.reference != SensorReference::kAbsolute)
    return;
  const int stride = spec.integrator.substeps;
  for (std::size_t k = 0; k < recording->dofs.size(); ++k) {
    const double r = load.base_influence[recording->dofs[k]];
    if (r == 0.0) continue;
    for (int i = 0; i < rows; ++i)
      recording->acceleration(i, static_cast<Eigen::Index>(k)) += r * load.history(load.base_row, i * stride);
  }
}

void FillSensors(const CaseSpec& spec, const Recording& recording, int rows, TimeSeries* sensors) {
  const Eigen::MatrixXd& recorded =
      spec.sensors.quantity == SensorQuantity::kVelocity       ? recording.velocity
      : spec.sensors.quantity == SensorQuantity::kAcceleration ? recording.acceleration
                                                               : recording.displacement;
  sensors->values = recorded.topRows(rows);
  sensors->time_s.resize(rows);
  for (int i = 0; i < rows; ++i) sensors->time_s[i] = spec.time.start_s + i * spec.time.step_s;
}

SimulationResult Simulate(const CaseSpec& spec, const SimulateOptions& options) {
  SimulationResult result;
  const BeamModel model = BeamModel::Build(spec);
  const State initial = InitialState(spec, model, &result.static_solve);
  const NewmarkOptions newmark = NewmarkOptions::FromCase(spec);
  const NewmarkIntegrator integrator(model, newmark);
  Recording recording;
  recording.dofs = SensorDofs(spec);
  recording.record_velocity = spec.sensors.quantity == SensorQuantity::kVelocity;
  recording.record_acceleration = spec.sensors.quantity == SensorQuantity::kAcceleration;
  result.sensors.channel_names = spec.sensors.ChannelNames();
  if (spec.initial.type == InitialType::kStaticForce && !result.static_solve.converged) {
    result.summary.termination = SimulationTermination::kStaticSolveFailed;
    result.summary.message = result.static_solve.message;
    result.summary.steps_requested = newmark.steps;
    result.sensors.time_s.resize(0);
    result.sensors.values.resize(0, static_cast<Eigen::Index>(recording.dofs.size()));
    return result;
  }
  const ExternalLoad load = BuildLoad(spec, model);
  result.summary = integrator.Run(initial, load, &recording);
  AddBaseAcceleration(spec, load, result.summary.rows_recorded, &recording);
  FillSensors(spec, recording, result.summary.rows_recorded, &result.sensors);
  if (options.add_noise && spec.noise.relative > 0.0) {
    AddNoise(result.sensors, spec.noise.relative, spec.noise.seed);
  }
  return result;
}

}  // namespace podid
