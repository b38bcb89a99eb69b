// Speed of the identification (issue 5):
//  * one objective evaluation on the 1 s reference record (tests/data/
//    measured_knl50_T1.0.csv, 5001 samples): simulate + POD (+ ridge of the
//    simulated side for `wavelet`). The measured side (its POD and ridges) is
//    built once, outside the timed loop; the workspace is reused as in an
//    optimiser's thread. Targets: `wavelet` <= 3 ms median on one core.
//  * a landscape of 1000 points of knl, 1 s record, `wavelet` objective, on
//    all cores OpenMP gives it (both cores of the reference machine): <= 2 s.
#include <benchmark/benchmark.h>

#include <cmath>
#include <ctime>
#include <fstream>
#include <limits>
#include <optional>
#include <string>

#include "podid/core/case_file.hpp"
#include "podid/core/error.hpp"
#include "podid/core/io.hpp"
#include "podid/ident/landscape.hpp"
#include "podid/ident/objective.hpp"
#include "silverbox_case.hpp"

namespace podid {
namespace {

const CaseDocument& ReferenceCase() {
  static const CaseDocument document =
      CaseDocument::Load(std::string(PODID_EXAMPLES_DIR) + "/beam.toml");
  return document;
}

const TimeSeries& MeasuredRecord() {
  static const TimeSeries record =
      ReadCsv(std::string(PODID_TEST_DATA_DIR) + "/measured_knl50_T1.0.csv");
  return record;
}

// One evaluation at knl = 50 (the record's true value, so the ridge is the
// ordinary one, not a failure path) with the named preset's terms.
void Evaluation(benchmark::State& state,
                const char* preset,
                int ridge_threads = 1,
                bool screen_scales = true) {
  const ident::ObjectiveWeights weights = ident::ObjectiveWeights::Preset(preset);
  ident::ObjectiveOptions options;
  options.SetWeights(weights);
  options.ridge.cwt.threads = ridge_threads;
  options.ridge.screen_scales = screen_scales;
  const ident::ObjectiveFunction objective(ReferenceCase(), MeasuredRecord(), options);
  ident::EvaluationWorkspace workspace;
  Eigen::VectorXd values = objective.StartValues();
  values[0] = 50.0;
  ident::TermValues terms;
  for (auto _ : state) {
    terms = objective.Evaluate(values, &workspace).terms;
    // Not DoNotOptimize(terms.u): with GCC its "+m,r" asm on a double can
    // corrupt the value (google/benchmark#903); the counters below need it.
    benchmark::ClobberMemory();
  }
  if (terms.failed) {
    state.SkipWithError(terms.failure.c_str());
    return;
  }
  state.counters["samples"] = static_cast<double>(MeasuredRecord().samples());
  state.counters["objective"] = terms.Combine(weights, objective.options().failure_value);
  // The terms, for bench/compare_python_ident.py's agreement check.
  if (weights.u != 0) state.counters["dU"] = terms.u;
  if (weights.s != 0) state.counters["dS"] = terms.s;
  if (weights.v != 0) state.counters["dV"] = terms.v;
  if (weights.f != 0) state.counters["dIF"] = terms.f;
}

void BM_EvaluateWavelet1s(benchmark::State& state) { Evaluation(state, "wavelet"); }
BENCHMARK(BM_EvaluateWavelet1s)->Unit(benchmark::kMillisecond);

// The same transforming every scale (RidgeFrequencyOptions::screen_scales
// off; the same dIF): the screening's gain, side by side in one run.
void BM_EvaluateWavelet1sUnscreened(benchmark::State& state) {
  Evaluation(state, "wavelet", 1, false);
}
BENCHMARK(BM_EvaluateWavelet1sUnscreened)->Unit(benchmark::kMillisecond);

// The same with the ridge on two threads (one block: its scales shared);
// wall time, the point of the second thread.
void BM_EvaluateWavelet1sTwoThreads(benchmark::State& state) { Evaluation(state, "wavelet", 2); }
BENCHMARK(BM_EvaluateWavelet1sTwoThreads)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_EvaluateFull1s(benchmark::State& state) { Evaluation(state, "full"); }
BENCHMARK(BM_EvaluateFull1s)->Unit(benchmark::kMillisecond);

void BM_EvaluateTimeFree1s(benchmark::State& state) { Evaluation(state, "time-free"); }
BENCHMARK(BM_EvaluateTimeFree1s)->Unit(benchmark::kMillisecond);

// The cached path as an optimiser uses it: knl changes at every evaluation
// (here alternating 49.9 and 50.1), so the static initial deflection is
// solved again each time; the model and the integrator stay.
void BM_EvaluateWaveletChanging1s(benchmark::State& state) {
  ident::ObjectiveOptions options;
  options.SetWeights(ident::ObjectiveWeights::Preset("wavelet"));
  const ident::ObjectiveFunction objective(ReferenceCase(), MeasuredRecord(), options);
  ident::EvaluationWorkspace workspace;
  Eigen::VectorXd values = objective.StartValues();
  bool failed = false;
  int i = 0;
  for (auto _ : state) {
    values[0] = (i++ % 2) ? 50.1 : 49.9;
    failed = failed || objective.Evaluate(values, &workspace).failed();
    benchmark::ClobberMemory();
  }
  if (failed) state.SkipWithError("an evaluation failed");
}
BENCHMARK(BM_EvaluateWaveletChanging1s)->Unit(benchmark::kMillisecond);

// A /proc/self/status field in kB ("VmRSS:", "VmHWM:"), as MB; NaN if absent.
double StatusMB(const std::string& field) {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind(field, 0) == 0) return std::stod(line.substr(field.size())) / 1024.0;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

// Issue 13 item 3: one evaluation of the objective `preset` (BM_EvaluateWaveletSilverbox:
// `wavelet`, dU + dS + dIF) on the whole Silverbox record
// (../shared/realdata/silverbox/SNLS80mV.mat: V2 measured, V1 the force; 131,072 samples at 610.35
// Hz), examples/silverbox's 1x1 Duffing model at its start values with data.window widened to the
// whole record. BM_EvaluateWaveletSilverbox's arguments: Newmark sub-steps per sample (16 as the
// example, 1); the ridge's top frequency, 300 Hz (10-300 Hz, 158 frequencies, as BM_SilverboxRidge:
// no decimation) or 120 Hz (the objective's default 10-120 Hz, 115 frequencies, every 2nd sample);
// the ridge's cwt.threads (2: its streamed pass 1 as a two-thread pipeline). Wall time (real_time).
// Steady state: the measured ridge and the workspace are built before the loop.
// evaluation_peak_MB: run each argument alone (--benchmark_filter), since a
// later run reuses the memory an earlier one freed.
void EvaluateSilverbox(
    benchmark::State& state, const char* preset, int substeps, int max_frequency_Hz, int threads) {
  std::optional<CaseDocument> loaded = SilverboxCase(state);
  if (!loaded) return;
  CaseDocument& document = *loaded;
  const std::string mat = SilverboxMat();
  const double step_s = kSilverboxStep_s;
  document.Set("integrator.substeps", ToText(substeps));
  MatReadOptions read;
  read.variable = "V2";
  read.step_s = step_s;
  TimeSeries measured = ReadMat(mat, read);
  measured.channel_names = {"y"};  // the sensor [data] channels = ["V2"] names
  const double last_s = measured.time_s[measured.samples() - 1];
  document.Set("data.window", "[" + ToText(-0.5 * step_s) + ", " + ToText(last_s + 0.5 * step_s) + "]");
  const ident::ObjectiveWeights weights = ident::ObjectiveWeights::Preset(preset);
  ident::ObjectiveOptions options;
  options.SetWeights(weights);
  options.ridge.cwt.frequencies.max_frequency_Hz = max_frequency_Hz;
  options.ridge.cwt.threads = threads;
  const ident::ObjectiveFunction objective(document, measured, options);
  ident::EvaluationWorkspace workspace;
  const Eigen::VectorXd values = objective.StartValues();
  // The evaluations' own memory (workspace, simulation, ridge buffers):
  // VmHWM reset to the current RSS (Linux clear_refs 5) once the objective
  // is built, so the peak after the loop less the RSS then is what
  // evaluating adds to the objective (measured ridge, record, model).
  std::ofstream("/proc/self/clear_refs") << "5";
  const double before_MB = StatusMB("VmRSS:");
  ident::Evaluation e = objective.Evaluate(values, &workspace);  // buffers, plans
  for (auto _ : state) {
    e = objective.Evaluate(values, &workspace);
    benchmark::ClobberMemory();
  }
  if (e.failed()) {
    state.SkipWithError(e.terms.failure.c_str());
    return;
  }
  state.counters["samples"] = static_cast<double>(measured.samples());
  state.counters["objective"] = e.terms.Combine(weights, objective.options().failure_value);
  state.counters["RSS_before_MB"] = before_MB;
  state.counters["evaluation_peak_MB"] = StatusMB("VmHWM:") - before_MB;
}
void BM_EvaluateWaveletSilverbox(benchmark::State& state) {
  EvaluateSilverbox(state, "wavelet", static_cast<int>(state.range(0)),
                    static_cast<int>(state.range(1)), static_cast<int>(state.range(2)));
}
BENCHMARK(BM_EvaluateWaveletSilverbox)
    ->Args({16, 300, 1})
    ->Args({1, 300, 1})
    ->Args({16, 120, 1})
    ->Args({16, 300, 2})
    ->Args({16, 120, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The same evaluation with the `time-free` objective (dU + dS): the
// simulation (2.1 million steps of the 1-dof model at 16 sub-steps) and the
// POD of its one channel, no ridge.
void BM_EvaluateTimeFreeSilverbox(benchmark::State& state) {
  EvaluateSilverbox(state, "time-free", static_cast<int>(state.range(0)), 120, 1);
}
BENCHMARK(BM_EvaluateTimeFreeSilverbox)->Arg(16)->Unit(benchmark::kMillisecond)->UseRealTime();

// How often the simulated POD falls back from the Gram (direct) method to
// the SVD (issue 11 item 5): over 201 values of knl in [0, 200], the case's
// bounds, on the 1 s record. Counter svd_fraction.
void BM_PodFallbackRate1s(benchmark::State& state) {
  ident::ObjectiveOptions options;
  options.SetWeights(ident::ObjectiveWeights::Preset("time-free"));
  const ident::ObjectiveFunction objective(ReferenceCase(), MeasuredRecord(), options);
  ident::EvaluationWorkspace workspace;
  Eigen::VectorXd values = objective.StartValues();
  int svd = 0, total = 0;
  for (auto _ : state) {
    svd = total = 0;
    for (int i = 0; i <= 200; ++i) {
      values[0] = i;
      const ident::Evaluation e = objective.Evaluate(values, &workspace);
      svd += e.pod_method == PodMethod::kSvd ? 1 : 0;
      ++total;
    }
  }
  state.counters["svd_fraction"] = static_cast<double>(svd) / total;
}
BENCHMARK(BM_PodFallbackRate1s)->Unit(benchmark::kMillisecond)->Iterations(1);

// 1000 points of knl over the case's bounds [0, 200], `wavelet` objective;
// OpenMP threads as the environment gives them (OMP_NUM_THREADS, default all
// cores). Wall time is what the target means: UseRealTime. The process CPU
// time of all threads is the counter process_cpu_ms (the CPU column is the
// main thread's only): on a loaded machine process_cpu_ms / cores is what the
// wall time would be with the cores to itself.
double ProcessCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

void BM_LandscapeWavelet1s(benchmark::State& state) {
  const ident::ObjectiveWeights weights = ident::ObjectiveWeights::Preset("wavelet");
  ident::ObjectiveOptions objective_options;
  objective_options.SetWeights(weights);
  const ident::ObjectiveFunction objective(ReferenceCase(), MeasuredRecord(), objective_options);
  ident::LandscapeOptions options;
  options.x.parameter = 0;
  options.x.lower = objective.parameters()[0].lower;
  options.x.upper = objective.parameters()[0].upper;
  options.x.points = static_cast<int>(state.range(0));
  ident::LandscapeResult result;
  double cpu_s = 0.0;
  for (auto _ : state) {
    const double cpu0 = ProcessCpuSeconds();
    result = ident::ComputeLandscape(objective, options);
    cpu_s += ProcessCpuSeconds() - cpu0;
    benchmark::DoNotOptimize(result.values.data());
  }
  if (result.termination != ident::LandscapeTermination::kCompleted) {
    state.SkipWithError(result.message.c_str());
    return;
  }
  state.counters["points"] = static_cast<double>(result.evaluations);
  state.counters["failed"] = static_cast<double>(result.failed_evaluations);
  state.counters["minimiser"] = result.metrics.at(0).global_minimiser;
  state.counters["process_cpu_ms"] = 1e3 * cpu_s / static_cast<double>(state.iterations());
}
BENCHMARK(BM_LandscapeWavelet1s)->Arg(1000)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace
}  // namespace podid
