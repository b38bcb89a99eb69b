// Readers: ReadMat of a level-5 file of many vector variables (one per
// channel, as some acquisition exports write them). Each variable is read
// from the position the listing recorded, so the time per variable should
// not grow with their number (a read by name passed over the headers before
// it again: 1000 vectors took 2.8 s, compressed 9 s).
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "mat5_file.hpp"
#include "podid/core/io.hpp"

namespace {

// One double row vector of `samples` values (channel k: sin(0.01 (k + 1) i)).
std::string VectorVariable(const std::string& name, int samples, int channel) {
  Eigen::MatrixXd values(1, samples);
  for (int i = 0; i < samples; ++i) values(0, i) = std::sin(0.01 * (channel + 1) * i);
  return podid::testing::Mat5DoubleVariable(name, values);
}

std::string WriteManyVectors(int variables, int samples) {
  std::string file = podid::testing::Mat5Header("MATLAB 5.0 MAT-file, podid io_benchmark");
  for (int k = 0; k < variables; ++k) {
    const std::string digits = std::to_string(k);  // k < 10^6: 8-character names
    file += VectorVariable("ch" + std::string(6 - digits.size(), '0') + digits, samples, k);
  }
  const std::string path = "/tmp/podid-io-benchmark-" + std::to_string(getpid()) + ".mat";
  std::ofstream(path, std::ios::binary | std::ios::trunc) << file;
  return path;
}

// Args: variables (1000 samples each). Counter: time per variable.
void BM_ReadMatManyVectors(benchmark::State& state) {
  const int variables = static_cast<int>(state.range(0));
  const std::string path = WriteManyVectors(variables, 1000);
  podid::MatReadOptions options;
  options.step_s = 1e-3;
  for (auto _ : state) {
    const podid::TimeSeries series = podid::ReadMat(path, options);
    benchmark::DoNotOptimize(series.values.data());
  }
  state.counters["per_variable"] = benchmark::Counter(
      static_cast<double>(variables),
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  std::remove(path.c_str());
}
BENCHMARK(BM_ReadMatManyVectors)->Arg(10)->Arg(100)->Arg(1000)->Unit(benchmark::kMillisecond);

}  // namespace
