#include "podid/core/simulator.hpp"

#include <algorithm>
#include <utility>

#include "podid/core/error.hpp"

namespace podid {

Simulator::Simulator(CaseSpec spec) : spec_(std::move(spec)) { Rebuild(); }

bool Simulator::Set(const ModelParameter& parameter, double value, std::string* why) {
  if (parameter.Get(spec_) == value) return true;
  if (!parameter.Set(value, &spec_, why)) return false;
  switch (parameter.effect()) {
    case ParameterEffect::kNonlinear:
      nonlinear_dirty_ = true;
      // The static deflection is solved with the nonlinear elements.
      if (spec_.initial.type == InitialType::kStaticForce) initial_dirty_ = true;
      break;
    case ParameterEffect::kLoad: load_dirty_ = true; break;
    case ParameterEffect::kInitialState: initial_dirty_ = true; break;
    case ParameterEffect::kDamping:
    case ParameterEffect::kModel:
    case ParameterEffect::kDocument:
      model_dirty_ = initial_dirty_ = true;
      break;
  }
  return true;
}

void Simulator::Reset(CaseSpec spec) {
  spec_ = std::move(spec);
  model_dirty_ = load_dirty_ = initial_dirty_ = true;
}

void Simulator::Rebuild() {
  if (model_dirty_) {
    // A failed build leaves the flags set: the next Run() tries again.
    options_ = NewmarkOptions::FromCase(spec_);
    workspace_.reset();
    integrator_.reset();
    model_ = std::make_unique<BeamModel>(BeamModel::Build(spec_));
    integrator_ = std::make_unique<NewmarkIntegrator>(*model_, options_);
    workspace_ = std::make_unique<NewmarkWorkspace>(*integrator_);
    recording_.dofs = SensorDofs(spec_);
    recording_.record_velocity = spec_.sensors.quantity == SensorQuantity::kVelocity;
    recording_.record_acceleration = spec_.sensors.quantity == SensorQuantity::kAcceleration;
    channel_names_ = spec_.sensors.ChannelNames();
    model_dirty_ = nonlinear_dirty_ = false;
    initial_dirty_ = true;
    if (spec_.base.history_m_per_s2.type != ForceType::kNone)
      load_dirty_ = true;  // -M r a_g depends on M
  }
  if (nonlinear_dirty_) {
    model_->SetNonlinearCoefficients(spec_.nonlinearities);
    integrator_->SetNonlinearCoefficients(spec_.nonlinearities);
    nonlinear_dirty_ = false;
  }
  if (load_dirty_) {
    load_ = BuildLoad(spec_, *model_, &load_cache_);
    load_dirty_ = false;
  }
  if (initial_dirty_) {
    static_solve_ = StaticSolveSummary{};
    initial_ = InitialState(spec_, *model_, &static_solve_);
    initial_dirty_ = false;
  }
}

const SimulationSummary& Simulator::RunInPlace() {
  Rebuild();
  if (spec_.initial.type == InitialType::kStaticForce && !static_solve_.converged) {
    summary_ = SimulationSummary{};
    summary_.termination = SimulationTermination::kStaticSolveFailed;
    summary_.message = static_solve_.message;
    summary_.steps_requested = options_.steps;
    return summary_;
  }
  summary_ = integrator_->Run(initial_, load_, &recording_, workspace_.get());
  AddBaseAcceleration(spec_, load_, summary_.rows_recorded, &recording_);
  return summary_;
}

Eigen::Block<const Eigen::MatrixXd> Simulator::sensor_values() const {
  const Eigen::MatrixXd& recorded =
      spec_.sensors.quantity == SensorQuantity::kVelocity       ? recording_.velocity
      : spec_.sensors.quantity == SensorQuantity::kAcceleration ? recording_.acceleration
                                                                : recording_.displacement;
  return recorded.topRows(std::min<Eigen::Index>(summary_.rows_recorded, recorded.rows()));
}

SimulationResult Simulator::Run() {
  // As Simulate() (simulate.cpp), with the cached parts.
  const SimulationSummary& summary = RunInPlace();
  SimulationResult result;
  result.static_solve = static_solve_;
  result.summary = summary;
  result.sensors.channel_names = channel_names_;
  if (summary.termination == SimulationTermination::kStaticSolveFailed) {
    result.sensors.time_s.resize(0);
    result.sensors.values.resize(0, static_cast<Eigen::Index>(recording_.dofs.size()));
    return result;
  }
  FillSensors(spec_, recording_, summary.rows_recorded, &result.sensors);
  return result;
}

}  // namespace podid
