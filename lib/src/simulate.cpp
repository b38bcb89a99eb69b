#include "podid/core/simulate.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include "podid/core/error.hpp"
#include "podid/core/interpolate.hpp"
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

ExternalLoad BuildLoad(const CaseSpec& spec) {
  ExternalLoad load;
  const ForceSpec& f = spec.force;
  if (f.type == ForceType::kNone) return load;
  load.dof = ResolveDof(spec, f.node, f.dof, SensorDof::kW, f.dof > 0 ? "force.dof" : "force.node");
  const int samples = spec.time.samples();
  const double dt = spec.time.step_s;
  const double duration = (samples - 1) * dt;
  // Sub-stepping: analytic forces at the fine times; a sampled force on the
  // data's grid here, interpolated band-limited below.
  const bool sampled = f.type == ForceType::kFile || f.type == ForceType::kChannel;
  const int k = sampled ? 1 : spec.integrator.substeps;
  const int count = (samples - 1) * k + 1;
  load.values_N.resize(count);
  constexpr double kTwoPi = 2 * std::numbers::pi;
  for (int i = 0; i < count; ++i) {
    const double t = i * dt / k;                   // from the simulation's start
    const double t_abs = spec.time.start_s + t;    // on the record's time axis
    double value = 0.0;
    switch (f.type) {
      case ForceType::kHarmonic:
        value = f.amplitude_N * std::sin(kTwoPi * f.frequency_Hz * t);
        break;
      case ForceType::kSweep:  // linear sweep: phase = 2 pi (f0 t + (f1 - f0) t^2 / (2 T))
        value = f.amplitude_N *
                std::sin(kTwoPi * (f.start_frequency_Hz * t +
                                   (f.end_frequency_Hz - f.start_frequency_Hz) * t * t / (2 * duration)));
        break;
      case ForceType::kFile:
      case ForceType::kChannel: {
        const Eigen::VectorXd& ft = f.file_time_s;
        const Eigen::VectorXd& fv = f.file_values;
        PODID_CHECK(ft.size() == fv.size());
        if (ft.size() >= 2 && t_abs >= ft[0] && t_abs <= ft[ft.size() - 1]) {
          // Linear interpolation on the (uniform, increasing) file time grid.
          const double h = (ft[ft.size() - 1] - ft[0]) / static_cast<double>(ft.size() - 1);
          Eigen::Index k =
              std::min<Eigen::Index>(static_cast<Eigen::Index>((t_abs - ft[0]) / h), ft.size() - 2);
          const double s = (t_abs - ft[k]) / (ft[k + 1] - ft[k]);
          value = f.gain * ((1 - s) * fv[k] + s * fv[k + 1]) + f.offset_N;
        }
        break;
      }
      case ForceType::kNone:
        break;
    }
    load.values_N[i] = value;
  }
  if (sampled && spec.integrator.substeps > 1)
    load.values_N = InterpolateBandLimited(load.values_N, spec.integrator.substeps);
  return load;
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
  result.summary = integrator.Run(initial, BuildLoad(spec), &recording);
  FillSensors(spec, recording, result.summary.rows_recorded, &result.sensors);
  if (options.add_noise && spec.noise.relative > 0.0) {
    AddNoise(result.sensors, spec.noise.relative, spec.noise.seed);
  }
  return result;
}

}  // namespace podid
