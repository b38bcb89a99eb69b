#pragma once
// A cached simulation of one case whose parameters change between runs (an
// identification's evaluations). It holds the CaseSpec, the BeamModel, the
// NewmarkIntegrator with its workspace, the initial state, the load and the
// sensor dofs, and after a change rebuilds only what the changed parameters
// invalidate (ModelParameter::effect(), model_parameter.hpp):
//   kNonlinear     the elements' coefficients in the model and the integrator
//                  (nothing refactored; the static initial state re-solved)
//   kLoad          the load
//   kInitialState  the initial state
//   kDamping, kModel  the model, the integrator and the initial state
// Run() gives the same result as Simulate(spec(), {add_noise = false}) (to
// round-off: tests/core/simulator_test.cpp). One Simulator per thread.

#include <string>

#include "podid/core/beam_model.hpp"
#include "podid/core/case_spec.hpp"
#include "podid/core/load.hpp"
#include "podid/core/model_parameter.hpp"
#include "podid/core/newmark.hpp"
#include "podid/core/simulate.hpp"

#include <memory>
#include <vector>

namespace podid {

class Simulator {
 public:
  /// Builds everything for `spec`. Throws std::invalid_argument for an
  /// inconsistent case (as Simulate does).
  explicit Simulator(CaseSpec spec);

  const CaseSpec& spec() const { return spec_; }

  /// Writes `value` through the typed parameter `parameter` (resolved against
  /// a case of the same structure) and marks what it invalidates. Returns
  /// false with the reason for a value out of the key's range (the case is
  /// then unchanged). Never throws.
  bool Set(const ModelParameter& parameter, double value, std::string* why);

  /// Replaces the whole case (a kDocument parameter changed): everything is
  /// rebuilt on the next Run().
  void Reset(CaseSpec spec);

  /// Rebuilds what is invalidated, then runs the noise-free simulation. A
  /// numerical failure is the summary's termination; an inconsistent case
  /// (e.g. a modal-ratio damping whose modes coincide) throws
  /// std::invalid_argument, as Simulate does.
  SimulationResult Run();
  /// Run() without copying the record out (an objective's evaluations): the
  /// summary, and the sensors' samples in sensor_values() until the next run.
  const SimulationSummary& RunInPlace();
  /// The sensors' samples of the last RunInPlace() (its summary's rows_recorded x
  /// sensors, the layout of TimeSeries::values, the case's sensor quantity).
  Eigen::Block<const Eigen::MatrixXd> sensor_values() const;
  /// The interpolated file and channel forces kept between runs.
  const LoadCache& load_cache() const { return load_cache_; }

 private:
  void Rebuild();

  CaseSpec spec_;
  bool model_dirty_ = true, nonlinear_dirty_ = false, load_dirty_ = true, initial_dirty_ = true;
  std::unique_ptr<BeamModel> model_;
  std::unique_ptr<NewmarkIntegrator> integrator_;
  std::unique_ptr<NewmarkWorkspace> workspace_;
  NewmarkOptions options_;
  State initial_;
  StaticSolveSummary static_solve_;
  ExternalLoad load_;
  LoadCache load_cache_;  // interpolated file and channel forces (a gain change rescales them)
  Recording recording_;
  SimulationSummary summary_;
  std::vector<std::string> channel_names_;
};

}  // namespace podid
