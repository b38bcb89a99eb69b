// POD speed: every method on the shapes (bench/README.md, "POD").
// Each benchmark reuses one PodSolver, as identification does across its
// objective evaluations. Data: Gaussian random (seeded) except the
// "measured" cases, which decompose tests/data/measured_knl50_T1.0.csv.
#include <benchmark/benchmark.h>

#include <Eigen/SVD>
#include <random>
#include <string>

#include "podid/core/io.hpp"
#include "podid/pod/pod.hpp"

namespace {

using podid::PodMethod;

Eigen::MatrixXd RandomMatrix(Eigen::Index rows, Eigen::Index cols) {
  std::mt19937 engine(42);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd a(rows, cols);
  for (Eigen::Index j = 0; j < cols; ++j) {
    for (Eigen::Index i = 0; i < rows; ++i) a(i, j) = normal(engine);
  }
  return a;
}

// tests/data/measured_knl50_T1.0.csv (5001 samples x 6 sensors).
podid::TimeSeries MeasuredSeries() {
  return podid::ReadCsv(std::string(PODID_TEST_DATA_DIR) + "/measured_knl50_T1.0.csv");
}

// The same as X (6 x 5001).
Eigen::MatrixXd MeasuredSnapshots() { return MeasuredSeries().values.transpose(); }

constexpr PodMethod kMethods[] = {PodMethod::kAuto, PodMethod::kSvd, PodMethod::kDirect,
                                  PodMethod::kSnapshot};

// Args: M, N, method index into kMethods, max_modes (0 = all).
void BM_Pod(benchmark::State& state) {
  const Eigen::Index m = state.range(0);
  const Eigen::Index n = state.range(1);
  podid::PodOptions options;
  options.method = kMethods[state.range(2)];
  options.max_modes = static_cast<int>(state.range(3));
  const Eigen::MatrixXd x = RandomMatrix(m, n);
  podid::PodSolver solver(options);
  const Eigen::Index gram = options.method == PodMethod::kSnapshot ? n : m;
  if (options.method != PodMethod::kSvd && options.method != PodMethod::kAuto &&
      gram > podid::kMaxGramDimension) {
    state.SkipWithError("Gram matrix larger than kMaxGramDimension");
    return;
  }
  for (auto _ : state) {
    const podid::PodResult& r = solver.Compute(x);
    benchmark::DoNotOptimize(r.poms.data());
  }
  state.SetLabel(std::string(podid::ToString(options.method)) + " ran " +
                 podid::ToString(solver.result().method));
}

// The identification's hot case on the reference data.
void BM_PodMeasured(benchmark::State& state) {
  podid::PodOptions options;
  options.method = kMethods[state.range(0)];
  options.max_modes = static_cast<int>(state.range(1));
  options.compute_time_modes = state.range(2) != 0;
  const Eigen::MatrixXd x = MeasuredSnapshots();
  podid::PodSolver solver(options);
  for (auto _ : state) {
    const podid::PodResult& r = solver.Compute(x);
    benchmark::DoNotOptimize(r.poms.data());
  }
  state.SetLabel(std::string(podid::ToString(options.method)) + " ran " +
                 podid::ToString(solver.result().method));
}

// The same data as the TimeSeries that identification decomposes on every
// evaluation (samples x sensors, contiguous sensor histories): all modes, V.
void BM_PodMeasuredSeries(benchmark::State& state) {
  podid::PodOptions options;
  options.method = kMethods[state.range(0)];
  const podid::TimeSeries series = MeasuredSeries();
  podid::PodSolver solver(options);
  for (auto _ : state) {
    const podid::PodResult& r = solver.Compute(series);
    benchmark::DoNotOptimize(r.poms.data());
  }
  state.SetLabel(std::string(podid::ToString(options.method)) + " ran " +
                 podid::ToString(solver.result().method));
}

// Eigen's two SVDs alone (thin U and V), for PodMethod::kSvd's choice.
template <typename Svd>
void BM_EigenSvd(benchmark::State& state) {
  const Eigen::MatrixXd x = RandomMatrix(state.range(0), state.range(1));
  Svd svd;
  for (auto _ : state) {
    svd.compute(x, Eigen::ComputeThinU | Eigen::ComputeThinV);
    benchmark::DoNotOptimize(svd.singularValues().data());
  }
}

struct Shape {
  int m, n;
};
// Every Gram method runs on every shape: the Gram on the long side (snapshot
// on 6 x 5001, direct on 2000 x 200) has rank <= the short side and is
// solved on its range (pod/src/range_eigen.hpp; the dense solver took ~250 s
// on 6 x 5001). The N x N snapshot problem of 12 x 50001 is refused (20 GB).
constexpr Shape kShapes[] = {{6, 501}, {6, 5001}, {12, 50001}, {200, 2000}, {2000, 200}};

void PodArguments(benchmark::internal::Benchmark* b) { b->ArgNames({"M", "N", "method", "modes"}); }

int RegisterAll() {
  for (const Shape& s : kShapes) {
    for (int method = 0; method < 4; ++method) {
      const std::string name = std::string("BM_Pod/") + podid::ToString(kMethods[method]);
      benchmark::RegisterBenchmark(name.c_str(), BM_Pod)
          ->Apply(PodArguments)
          ->Args({s.m, s.n, method, 0})
          ->Unit(benchmark::kMicrosecond);
    }
    for (auto* b :
         {benchmark::RegisterBenchmark(
              "BM_EigenSvd/jacobi",
              BM_EigenSvd<
                  Eigen::JacobiSVD<Eigen::MatrixXd, Eigen::ColPivHouseholderQRPreconditioner>>),
          benchmark::RegisterBenchmark("BM_EigenSvd/bdc",
                                       BM_EigenSvd<Eigen::BDCSVD<Eigen::MatrixXd>>)}) {
      b->ArgNames({"M", "N"})->Args({s.m, s.n})->Unit(benchmark::kMicrosecond);
    }
  }
  for (int method = 0; method < 4; ++method) {
    const std::string name = std::string("BM_PodMeasured/") + podid::ToString(kMethods[method]);
    for (auto [modes, with_v] : {std::pair{0, 1}, std::pair{1, 1}, std::pair{1, 0}}) {
      benchmark::RegisterBenchmark(name.c_str(), BM_PodMeasured)
          ->ArgNames({"method", "modes", "with_v"})
          ->Args({method, modes, with_v})
          ->Unit(benchmark::kMicrosecond);
    }
    const std::string series =
        std::string("BM_PodMeasuredSeries/") + podid::ToString(kMethods[method]);
    benchmark::RegisterBenchmark(series.c_str(), BM_PodMeasuredSeries)
        ->ArgNames({"method"})
        ->Args({method})
        ->Unit(benchmark::kMicrosecond);
  }
  return 0;
}

const int kRegistered = RegisterAll();

}  // namespace
