#pragma once
// From a case to sensor time histories: builds the beam model, the initial
// state (static deflection or explicit), the external load, runs the chosen
// Newmark integrator and samples the sensors. Units are SI.

#include <Eigen/Core>

#include "podid/core/beam_model.hpp"
#include "podid/core/case_spec.hpp"
#include "podid/core/load.hpp"
#include "podid/core/newmark.hpp"
#include "podid/core/time_series.hpp"

namespace podid {

/// The initial state of the case: rest, explicit, or the static deflection
/// under [initial] static_tip_force solved with the nonlinear elements
/// (SolveStatic) and released with zero velocity. `static_summary` (optional)
/// receives the static solve's report.
State InitialState(const CaseSpec& spec, const BeamModel& model,
                   StaticSolveSummary* static_summary = nullptr);

/// The first `rows` recorded samples of the case's sensor quantity
/// (displacement, velocity or acceleration) into `sensors`, stamped
/// time.start + n time.step: what Simulate() and Simulator::Run() return.
void FillSensors(const CaseSpec& spec, const Recording& recording, int rows, TimeSeries* sensors);

/// Under [base], accelerometers (sensors.quantity "acceleration" with
/// reference "absolute") measure u_r'' + r a_g: adds r a_g (`load`'s base row
/// at the samples) to the first `rows` rows of recording->acceleration.
/// Nothing otherwise. Allocates nothing.
void AddBaseAcceleration(const CaseSpec& spec, const ExternalLoad& load, int rows, Recording* recording);

/// Free-dof indices of the case's sensors, in channel order.
std::vector<int> SensorDofs(const CaseSpec& spec);

struct SimulationResult {
  TimeSeries sensors;         ///< (samples x sensors), truncated to the completed steps;
                              ///< stamped time.start_s + n dt
  SimulationSummary summary;
  StaticSolveSummary static_solve;  ///< when the initial state is a static deflection
};

struct SimulateOptions {
  bool add_noise = true;  ///< apply the case's [noise] (std = relative * max |x(0)|)
};

/// Runs the case. Never throws for a numerical failure: a diverging
/// simulation is a summary termination with the partial history kept. Throws
/// std::invalid_argument for an inconsistent case.
SimulationResult Simulate(const CaseSpec& spec, const SimulateOptions& options = {});

}  // namespace podid
