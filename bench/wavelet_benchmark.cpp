// Wavelet benchmarks (issue 4). One core; sizes of the identification's call:
// a 5001-sample record at 5 kHz. Run: bench/README.md, "Wavelet".
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "podid/core/io.hpp"
#include "podid/wavelet/cwt.hpp"
#include "podid/wavelet/denoise.hpp"
#include "podid/wavelet/ridge.hpp"
#include "podid/wavelet/synthesis.hpp"
#include "silverbox_case.hpp"

namespace {

using namespace podid::wavelet;
constexpr double kStep = 1.0 / 5000.0;

// A decaying, slightly hardening 33 Hz mode plus a weak 207 Hz one.
Eigen::VectorXd Signal(Eigen::Index n) {
  Eigen::VectorXd x(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) * kStep;
    const double phase = 2 * std::numbers::pi * (33.0 * t + 0.5 * std::exp(-2.0 * t));
    x(i) = std::exp(-2.0 * t) * std::cos(phase) + 0.1 * std::sin(2 * std::numbers::pi * 207.0 * t);
  }
  return x;
}

// Full time resolution, `scales` linear frequencies over 10-120 Hz.
void BM_CwtFull(benchmark::State& state) {
  const Eigen::VectorXd x = Signal(state.range(0));
  CwtOptions o;
  o.frequencies.spacing = FrequencySpacing::kLinear;
  o.frequencies.bins = static_cast<int>(state.range(1));
  CwtTransform transform(o);
  Scalogram out;
  transform.Compute(x, kStep, &out);  // plans and filters
  for (auto _ : state) {
    transform.Compute(x, kStep, &out);
    benchmark::DoNotOptimize(out.coefficients.data());
  }
  state.counters["padded"] = static_cast<double>(transform.padded_length());
}
BENCHMARK(BM_CwtFull)->Args({5001, 64})->Unit(benchmark::kMillisecond);

// The identification's call: main ridge + phase IF over 10-120 Hz, 32 voices
// per octave (115 frequencies), band-limited (M = 640, every 16th sample).
// Second argument: 1 = keep_scalogram (the whole-scalogram path: CwtTransform,
// FindRidges, TrackRidge, what Estimate ran before the streamed ridge), 0 =
// streamed (one block here), 2 = streamed transforming every scale
// (screen_scales off). Compare them in one run.
void BM_RidgeFrequencyBandLimited(benchmark::State& state) {
  const Eigen::VectorXd x = Signal(state.range(0));
  RidgeFrequencyOptions o;
  o.keep_scalogram = state.range(1) == 1;
  o.screen_scales = state.range(1) != 2;
  RidgeFrequencyEstimator estimator(o);
  estimator.Estimate(x, kStep);
  for (auto _ : state) {
    const RidgeTrack& track = estimator.Estimate(x, kStep);
    benchmark::DoNotOptimize(track.frequency_Hz.data());
  }
  state.counters["transformed_scales"] = static_cast<double>(estimator.transformed_scales());
}
BENCHMARK(BM_RidgeFrequencyBandLimited)
    ->Args({5001, 1})
    ->Args({5001, 0})
    ->Args({5001, 2})
    ->Unit(benchmark::kMillisecond);

// Peak resident memory of this process (VmHWM), in MB.
double PeakRssMB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

// Issue 13 item 3: the ridge and IF of a long record (10^6 samples = 200 s at
// 5 kHz) in one band-limited call, CwtOptions defaults (zero padding), the
// first call included (plans, filters, every buffer): what a one-shot user
// pays. Second argument as above (1: whole scalogram, 0: streamed).
// peak_RSS_MB is the process's peak resident set after the run (VmHWM),
// which includes the signal, Google Benchmark and the runs before it: run
// each variant alone (--benchmark_filter) for its own peak.
void BM_LongRecordRidgeFirstCall(benchmark::State& state) {
  const Eigen::VectorXd x = Signal(state.range(0));
  RidgeFrequencyOptions o;
  o.cwt.padding = Padding::kZero;
  o.cwt.coi_factor = 2.0;
  o.keep_scalogram = state.range(1) != 0;
  for (auto _ : state) {
    RidgeFrequencyEstimator estimator(o);
    const RidgeTrack& track = estimator.Estimate(x, kStep);
    benchmark::DoNotOptimize(track.frequency_Hz.data());
  }
  state.counters["peak_RSS_MB"] = PeakRssMB();
}
BENCHMARK(BM_LongRecordRidgeFirstCall)
    ->Args({1000000, 1})
    ->Args({1000000, 0})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(2);

// Issue 13 item 3: the wavelet objective's ridge on the Silverbox record
// (../shared/realdata/silverbox/SNLS80mV.mat, V2: 131,072 samples at
// 10^7 / 2^14 Hz = 610.35 Hz), 10-300 Hz at 32 voices (158 frequencies),
// the objective's reflect padding and coi 1. The band reaches Nyquist: no
// decimation, 20.6 M output cells. Steady state (the estimator reused, as
// the objective reuses it per evaluation). Arguments: keep_scalogram (1: the
// whole scalogram, 0: streamed), cwt.threads (2: the streamed pass 1 as a
// two-thread pipeline). Wall time (real_time): the pipeline's point.
void BM_SilverboxRidge(benchmark::State& state) {
  if (!podid::HaveSilverbox(state)) return;
  podid::MatReadOptions read;
  read.variable = "V2";
  read.step_s = podid::kSilverboxStep_s;
  const Eigen::VectorXd x = podid::ReadMat(podid::SilverboxMat(), read).values.col(0);
  RidgeFrequencyOptions o;
  o.cwt.frequencies.max_frequency_Hz = 300.0;
  o.keep_scalogram = state.range(0) != 0;
  o.cwt.threads = static_cast<int>(state.range(1));
  RidgeFrequencyEstimator estimator(o);
  estimator.Estimate(x, read.step_s);
  for (auto _ : state) {
    const RidgeTrack& track = estimator.Estimate(x, read.step_s);
    benchmark::DoNotOptimize(track.frequency_Hz.data());
  }
  state.counters["blocks"] = static_cast<double>(estimator.blocks());
  state.counters["peak_RSS_MB"] = PeakRssMB();
}
BENCHMARK(BM_SilverboxRidge)
    ->Args({1, 1})
    ->Args({0, 1})
    ->Args({0, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The same at full time resolution, for comparison.
void BM_RidgeFrequencyFull(benchmark::State& state) {
  const Eigen::VectorXd x = Signal(state.range(0));
  RidgeFrequencyOptions o;
  o.cwt.band_limited = false;
  RidgeFrequencyEstimator estimator(o);
  estimator.Estimate(x, kStep);
  for (auto _ : state) {
    const RidgeTrack& track = estimator.Estimate(x, kStep);
    benchmark::DoNotOptimize(track.frequency_Hz.data());
  }
}
BENCHMARK(BM_RidgeFrequencyFull)->Arg(5001)->Unit(benchmark::kMillisecond);

// The PyWavelets comparison's case (bench/compare_pywt.py): w6 of the
// reference record, 64 linear frequencies 10-120 Hz, zero padding, full rate.
Eigen::VectorXd ReferenceW6() {
  std::ifstream in(std::string(PODID_TEST_DATA_DIR) + "/measured_knl50_T1.0.csv");
  std::string line;
  std::getline(in, line);
  std::vector<double> values;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string cell;
    for (int c = 0; c <= 6; ++c) std::getline(row, cell, ',');
    values.push_back(std::stod(cell));
  }
  return Eigen::Map<Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
}

void BM_CwtPywtCase(benchmark::State& state) {
  const Eigen::VectorXd x = ReferenceW6();
  CwtOptions o;
  o.padding = Padding::kZero;
  o.frequencies.spacing = FrequencySpacing::kLinear;
  o.frequencies.bins = 64;
  CwtTransform transform(o);
  Scalogram out;
  transform.Compute(x, kStep, &out);
  for (auto _ : state) {
    transform.Compute(x, kStep, &out);
    benchmark::DoNotOptimize(out.coefficients.data());
  }
  state.counters["samples"] = static_cast<double>(x.size());
}
BENCHMARK(BM_CwtPywtCase)->Unit(benchmark::kMillisecond);

// The same as a one-shot call: transform object, plans (estimated unless the
// wisdom cache has them), filters, twiddles and a new output.
void BM_CwtPywtCaseFirstCall(benchmark::State& state) {
  const Eigen::VectorXd x = ReferenceW6();
  CwtOptions o;
  o.padding = Padding::kZero;
  o.frequencies.spacing = FrequencySpacing::kLinear;
  o.frequencies.bins = 64;
  for (auto _ : state) {
    Scalogram out = Cwt(x, kStep, o);
    benchmark::DoNotOptimize(out.coefficients.data());
  }
}
BENCHMARK(BM_CwtPywtCaseFirstCall)->Unit(benchmark::kMillisecond);

// fCWT's own benchmark setup (bench/compare_fcwt.sh): fs 64 Hz, 300
// log-spaced frequencies 1-31.6 Hz (60 voices per octave), a 1-8 Hz chirp;
// full-rate complex double output. Args: samples, threads, planning (0
// estimate as fCWT's cwt() does, 1 measured wisdom). Plans and filters are
// made before the timed loop; BM_CwtFcwtCaseFirstCall times a whole
// one-shot call instead.
Eigen::VectorXd FcwtSignal(Eigen::Index n) {
  Eigen::VectorXd x(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / 64.0;
    x(i) = std::cos(2.0 * std::numbers::pi * (1.0 + 7.0 * static_cast<double>(i) / n) * t);
  }
  return x;
}

CwtOptions FcwtOptions(int threads, bool measure) {
  CwtOptions o;
  o.frequencies.min_frequency_Hz = 1.0;
  o.frequencies.max_frequency_Hz = std::exp2(299.0 / 60.0);
  o.frequencies.voices_per_octave = 60;
  o.threads = threads;
  o.planning = measure ? FftPlanning::kMeasure : FftPlanning::kEstimate;
  return o;
}

// The timed loop of the fCWT-case benchmarks: state.range(0) samples, output
// `output`, threads and planning as given.
void RunFcwtCase(benchmark::State& state, int threads, bool measure, CwtOutput output) {
  const Eigen::VectorXd x = FcwtSignal(state.range(0));
  CwtOptions o = FcwtOptions(threads, measure);
  o.output = output;
  CwtTransform transform(o);
  Scalogram out;
  transform.Compute(x, 1.0 / 64.0, &out);
  for (auto _ : state) {
    transform.Compute(x, 1.0 / 64.0, &out);
    benchmark::DoNotOptimize(out.coefficients.data());
    benchmark::DoNotOptimize(out.coefficients_float.data());
    benchmark::DoNotOptimize(out.magnitude.data());
  }
  state.counters["frequencies"] = static_cast<double>(out.frequencies());
  state.counters["padded"] = static_cast<double>(transform.padded_length());
}

void BM_CwtFcwtCase(benchmark::State& state) {
  RunFcwtCase(state, static_cast<int>(state.range(1)), state.range(2) != 0, CwtOutput::kComplex);
}
BENCHMARK(BM_CwtFcwtCase)
    ->ArgsProduct({{10000, 100000}, {1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The same with W computed in double and stored as complex float
// (CwtOutput::kComplexFloat): the bytes fCWT writes (8 a coefficient). Args
// as BM_CwtFcwtCase's (bench/compare_fcwt.sh times both).
void BM_CwtFcwtCaseComplexFloat(benchmark::State& state) {
  RunFcwtCase(state, static_cast<int>(state.range(1)), state.range(2) != 0,
              CwtOutput::kComplexFloat);
}
BENCHMARK(BM_CwtFcwtCaseComplexFloat)
    ->ArgsProduct({{10000, 100000}, {1}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The same with single-precision |W| output (CwtOutput::kMagnitudeFloat).
void BM_CwtFcwtCaseMagnitude(benchmark::State& state) {
  RunFcwtCase(state, 1, false, CwtOutput::kMagnitudeFloat);
}
BENCHMARK(BM_CwtFcwtCaseMagnitude)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);

// A whole one-shot call (transform object, estimated plans, filters,
// output allocation), as a `podid cwt` process pays it.
void BM_CwtFcwtCaseFirstCall(benchmark::State& state) {
  const Eigen::VectorXd x = FcwtSignal(state.range(0));
  for (auto _ : state) {
    Scalogram out = Cwt(x, 1.0 / 64.0, FcwtOptions(1, false));
    benchmark::DoNotOptimize(out.coefficients.data());
  }
}
BENCHMARK(BM_CwtFcwtCaseFirstCall)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);

// `podid cwt --channel w6` on the whole transform: 10-120 Hz, 32 voices per
// octave (115 frequencies), full rate; argument 0 = the CWT ridge (FindRidges,
// TrackRidge), 1 = the synchrosqueezed one (--synchrosqueeze: Synchrosqueeze,
// one more inverse FFT per scale for dW/dt, then SynchrosqueezedRidges).
// Both include the transform; compare them in one run.
void BM_RidgeOfTransform(benchmark::State& state) {
  const Eigen::VectorXd x = Signal(5001);
  const bool squeeze = state.range(0) == 1;
  CwtTransform transform(CwtOptions{});
  const RidgeOptions ridge;
  Scalogram sg;
  SynchrosqueezedTransform sst;
  const auto run = [&] {
    transform.Compute(x, kStep, &sg);
    if (squeeze) {
      Synchrosqueeze(sg, transform, {}, &sst);
      return SynchrosqueezedRidges(sst, ridge).front();
    }
    return TrackRidge(sg, FindRidges(sg, ridge).front(), ridge, &transform);
  };
  run();  // plans and filters
  for (auto _ : state) {
    const RidgeTrack track = run();
    benchmark::DoNotOptimize(track.frequency_Hz.data());
  }
}
BENCHMARK(BM_RidgeOfTransform)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// The inverse CWT of the same transform (the signal's in-band part).
void BM_InverseCwt(benchmark::State& state) {
  const Eigen::VectorXd x = Signal(5001);
  CwtTransform transform(CwtOptions{});
  Scalogram sg;
  transform.Compute(x, kStep, &sg);
  for (auto _ : state) {
    const Eigen::VectorXd y = InverseCwt(sg);
    benchmark::DoNotOptimize(y.data());
  }
}
BENCHMARK(BM_InverseCwt)->Unit(benchmark::kMillisecond);

void BM_Denoise(benchmark::State& state) {
  const Eigen::VectorXd x = Signal(state.range(0));
  for (auto _ : state) {
    Eigen::VectorXd y = Denoise(x);
    benchmark::DoNotOptimize(y.data());
  }
}
BENCHMARK(BM_Denoise)->Arg(5001)->Unit(benchmark::kMillisecond);

}  // namespace
