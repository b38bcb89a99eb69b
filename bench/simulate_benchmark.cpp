// Speed of the shared simulator (issue 2):
//  * 1 s of the reference case (5000 steps) with the condensed integrator;
//  * a 300-element beam (600 dofs, one nonlinear dof): condensed vs full
//    Newton per step, and the cost's growth with the number of steps.
#include <benchmark/benchmark.h>

#include <optional>
#include <string>
#include <vector>

#include "chain_model.hpp"
#include "silverbox_case.hpp"
#include "podid/core/case_file.hpp"
#include "podid/core/error.hpp"
#include "podid/core/newmark.hpp"
#include "podid/core/simulate.hpp"

namespace podid {
namespace {

CaseSpec Reference(const std::vector<std::string>& overrides) {
  CaseDocument document = CaseDocument::Load(std::string(PODID_EXAMPLES_DIR) + "/beam.toml");
  ApplySetArguments(document, overrides);
  return document.ToSpec();
}

// The time loop only: model, integrator and workspace are built once.
// per_step = CPU time per Newmark step (issue 11: <= 60 ns for the 12-dof case).
// The reference beam is Rayleigh-damped: it steps in modal coordinates by
// default when the modal loop runs in AVX2, else in the dense condensation.
enum class Path {
  kDefault,
  kDense,  ///< NewmarkOptions::modal = false
  kModal,  ///< NewmarkOptions::modal_portable = true: modal even on its portable loop
};

void RunLoop(benchmark::State& state,
             const CaseSpec& spec,
             bool cpu_dispatch = true,
             Path path = Path::kDefault) {
  const BeamModel model = BeamModel::Build(spec);
  NewmarkOptions options = NewmarkOptions::FromCase(spec);
  options.cpu_dispatch = cpu_dispatch;
  options.modal = path != Path::kDense;
  options.modal_portable = path == Path::kModal;
  const NewmarkIntegrator integrator(model, options);
  NewmarkWorkspace workspace(integrator);
  const State initial = InitialState(spec, model);
  const ExternalLoad load = BuildLoad(spec);
  Recording recording;
  recording.dofs = SensorDofs(spec);
  SimulationSummary summary;
  for (auto _ : state) {
    summary = integrator.Run(initial, load, &recording, &workspace);
    benchmark::DoNotOptimize(recording.displacement.data());
  }
  if (!summary.IsSolutionUsable()) state.SkipWithError(summary.message.c_str());
  if (integrator.sparse()) state.SetLabel(integrator.sparse_status());
  const double steps = integrator.options().steps;
  state.counters["steps"] = steps;
  state.counters["modal"] = integrator.modal() ? 1.0 : 0.0;
  state.counters["one_dof"] = integrator.one_dof() ? 1.0 : 0.0;
  state.counters["newton_per_step"] = static_cast<double>(summary.newton_iterations) / steps;
  state.counters["per_step"] = benchmark::Counter(steps, benchmark::Counter::kIsIterationInvariantRate |
                                                             benchmark::Counter::kInvert);
}

void BM_Reference1sCondensed(benchmark::State& state) {
  RunLoop(state, Reference({"time.duration=1.0"}));
}
BENCHMARK(BM_Reference1sCondensed)->Unit(benchmark::kMicrosecond);

// The same with the portable (SSE2) kernels, for the SIMD kernels' share:
// what a CPU without AVX2 runs (the dense condensation).
void BM_Reference1sCondensedPortable(benchmark::State& state) {
  RunLoop(state, Reference({"time.duration=1.0"}), false);
}
BENCHMARK(BM_Reference1sCondensedPortable)->Unit(benchmark::kMicrosecond);

// The dense condensation (NewmarkOptions::modal = false), AVX2 and portable.
void BM_Reference1sCondensedDense(benchmark::State& state) {
  RunLoop(state, Reference({"time.duration=1.0"}), true, Path::kDense);
}
BENCHMARK(BM_Reference1sCondensedDense)->Unit(benchmark::kMicrosecond);

void BM_Reference1sCondensedDensePortable(benchmark::State& state) {
  RunLoop(state, Reference({"time.duration=1.0"}), false, Path::kDense);
}
BENCHMARK(BM_Reference1sCondensedDensePortable)->Unit(benchmark::kMicrosecond);

// The modal path's portable loop (NewmarkOptions::modal_portable), the one
// the default chose without AVX2 before it fell back to the dense step.
void BM_Reference1sCondensedModalPortable(benchmark::State& state) {
  RunLoop(state, Reference({"time.duration=1.0"}), false, Path::kModal);
}
BENCHMARK(BM_Reference1sCondensedModalPortable)->Unit(benchmark::kMicrosecond);

// Two nonlinear dofs (the cubic tip and a gap at node 3), AVX2 dispatch:
// range(0) = 0 the default (the dense condensation: the modal loop has no
// AVX2 build for n_a != 1), 1 the modal path's generic loop (modal_portable).
void BM_TwoNonlinearDofs1s(benchmark::State& state) {
  RunLoop(state,
          Reference({"time.duration=1.0", "nonlinearity.1.type=\"gap\"", "nonlinearity.1.node=3",
                     "nonlinearity.1.gap=1e-5", "nonlinearity.1.stiffness=1e5"}),
          true, state.range(0) != 0 ? Path::kModal : Path::kDefault);
}
BENCHMARK(BM_TwoNonlinearDofs1s)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

// The Silverbox example's 1x1 Duffing model (examples/silverbox: m = 1, the
// stiffness a polynomial element, the measured V1 as its force) over the
// whole 131,072-sample record at its 16 sub-steps a sample: 2.1 million
// one-dof steps, the simulation inside BM_EvaluateWaveletSilverbox.
// range(0): 0 the default path (the one-dof loop, lib/src/newmark_one_dof.hpp),
// 1 the modal path's AVX2 loop that the default took before it
// (modal_portable = true).
void BM_SilverboxSteps(benchmark::State& state) {
  std::optional<CaseDocument> document = SilverboxCase(state);
  if (!document) return;
  // The whole record: 131,071 sampling steps from its first sample.
  document->Set("time.step", ToText(kSilverboxStep_s));
  document->Set("time.duration", ToText(131071 * kSilverboxStep_s));
  RunLoop(state, document->ToSpec(), true, state.range(0) != 0 ? Path::kModal : Path::kDefault);
}
BENCHMARK(BM_SilverboxSteps)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// No nonlinear dof: the reference beam's M, K, C imported without its
// element, released with a tip velocity, 1 s. range(0) as above; range(1) =
// cpu_dispatch.
void BM_Linear1s(benchmark::State& state) {
  const CaseSpec spec = Reference({"time.duration=1.0"});
  const BeamModel beam = BeamModel::Build(spec);
  const BeamModel model =
      BeamModel::FromMatrices(beam.DenseMass(), beam.DenseStiffness(), beam.DenseDamping(), {});
  NewmarkOptions options = NewmarkOptions::FromCase(spec);
  options.cpu_dispatch = state.range(1) != 0;
  options.modal_portable = state.range(0) != 0;
  const NewmarkIntegrator integrator(model, options);
  NewmarkWorkspace workspace(integrator);
  State initial{Eigen::VectorXd::Zero(model.dofs()), Eigen::VectorXd::Zero(model.dofs())};
  initial.velocity[model.dofs() - 2] = 0.5;
  Recording recording;
  recording.dofs = SensorDofs(spec);
  SimulationSummary summary;
  for (auto _ : state) {
    summary = integrator.Run(initial, ExternalLoad{}, &recording, &workspace);
    benchmark::DoNotOptimize(recording.displacement.data());
  }
  if (!summary.IsSolutionUsable()) state.SkipWithError(summary.message.c_str());
  state.counters["modal"] = integrator.modal() ? 1.0 : 0.0;
  state.counters["per_step"] = benchmark::Counter(
      options.steps, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_Linear1s)->ArgsProduct({{0, 1}, {0, 1}})->Unit(benchmark::kMicrosecond);

// Integrator set-up alone (first-call cost: dense condensation and, for the
// modal path, the generalised eigenproblem and the modal maps).
void BM_ReferenceIntegratorSetup(benchmark::State& state) {
  const CaseSpec spec = Reference({"time.duration=1.0"});
  const BeamModel model = BeamModel::Build(spec);
  NewmarkOptions options = NewmarkOptions::FromCase(spec);
  options.modal = state.range(0) != 0;
  for (auto _ : state) {
    NewmarkIntegrator integrator(model, options);
    benchmark::DoNotOptimize(&integrator);
  }
}
BENCHMARK(BM_ReferenceIntegratorSetup)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

void BM_Reference1sFullNewton(benchmark::State& state) {
  RunLoop(state, Reference({"time.duration=1.0", "integrator.type=\"newmark\""}));
}
BENCHMARK(BM_Reference1sFullNewton)->Unit(benchmark::kMicrosecond);

// Everything an identification evaluation pays: parse-free spec -> model
// (modal analysis for Rayleigh), static solve, integrator set-up, run.
void BM_Reference1sSimulateEndToEnd(benchmark::State& state) {
  const CaseSpec spec = Reference({"time.duration=1.0"});
  for (auto _ : state) {
    SimulationResult result = Simulate(spec);
    benchmark::DoNotOptimize(result.sensors.values.data());
  }
}
BENCHMARK(BM_Reference1sSimulateEndToEnd)->Unit(benchmark::kMicrosecond);

// 300 elements, steps = range(0); step 2e-5 s.
CaseSpec Long(int steps, bool full) {
  std::vector<std::string> sets = {"beam.elements=300", "time.step=2e-5",
                                   "time.duration=" + std::to_string(steps * 2e-5)};
  if (full) sets.push_back("integrator.type=\"newmark\"");
  return Reference(sets);
}

void BM_Beam300Condensed(benchmark::State& state) {
  RunLoop(state, Long(static_cast<int>(state.range(0)), false));
}
BENCHMARK(BM_Beam300Condensed)->Arg(100)->Arg(200)->Arg(400)->Unit(benchmark::kMillisecond);

void BM_Beam300FullNewton(benchmark::State& state) {
  RunLoop(state, Long(static_cast<int>(state.range(0)), true));
}
BENCHMARK(BM_Beam300FullNewton)->Arg(10)->Arg(20)->Arg(40)->Unit(benchmark::kMillisecond);

// Growth with the mesh (issue 11): 1 s at the reference step (5000 steps),
// released from the static tip deflection, elements = range(0). Above
// kDenseDofLimit dofs the condensed steps are sparse: cost per step linear in
// the dofs (300 elements within 15x of 30).
void BM_Beam1sElements(benchmark::State& state) {
  RunLoop(state, Reference({"time.duration=1.0", "beam.elements=" + std::to_string(state.range(0))}));
}
BENCHMARK(BM_Beam1sElements)->Arg(30)->Arg(300)->Unit(benchmark::kMillisecond);

// A 10^4-dof imported model (issue 11): a banded chain of masses and springs
// built with BeamModel::FromMatrices (sparse), two cubic springs, released
// from a static end force, 1 s at 5 kHz. Each iteration pays everything but
// the matrix assembly: static solve, integrator set-up (sparse LDL^T of S_b)
// and the 5000 steps. Target: <= 2 s and <= 200 MB (peak_rss_MB counter).
void BM_Imported10kDofs(benchmark::State& state) {
  const BeamModel model = testing::Chain(10000, testing::TwoCubics(10000));
  NewmarkOptions options;
  options.step_s = 2e-4;
  options.steps = 5000;
  Eigen::VectorXd force = Eigen::VectorXd::Zero(model.dofs());
  force[model.dofs() - 1] = 1.0;
  SimulationSummary summary;
  std::string label;
  for (auto _ : state) {
    StaticSolveSummary static_summary;
    const State initial{SolveStatic(model, force, StaticSolveOptions{}, &static_summary),
                        Eigen::VectorXd::Zero(model.dofs())};
    const NewmarkIntegrator integrator(model, options);
    Recording recording;
    recording.dofs = {model.dofs() / 2, model.dofs() - 1};
    summary = integrator.Run(initial, ExternalLoad{}, &recording);
    benchmark::DoNotOptimize(recording.displacement.data());
    label = integrator.sparse_status();
  }
  if (!summary.IsSolutionUsable()) state.SkipWithError(summary.message.c_str());
  state.SetLabel(label);
  state.counters["dofs"] = model.dofs();
  state.counters["newton_per_step"] = static_cast<double>(summary.newton_iterations) / options.steps;
  state.counters["peak_rss_MB"] = static_cast<double>(testing::PeakRssBytes()) / (1024.0 * 1024.0);
}
BENCHMARK(BM_Imported10kDofs)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
}  // namespace podid
