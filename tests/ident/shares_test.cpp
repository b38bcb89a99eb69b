// Splitting a landscape's points or an identification's starts into shares
// (the CLI's MPI ranks), merging them and summarising again gives exactly the
// one-process result; threads and the progress callback.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <stdexcept>

#include "podid/core/case_file.hpp"
#include "podid/core/io.hpp"
#include "podid/ident/identify.hpp"
#include "podid/ident/landscape.hpp"
#include "test_support.hpp"

namespace podid::ident {
namespace {

using testing::DataPath;
using testing::ExamplePath;

ObjectiveFunction TimeFreeAndFull() {
  ObjectiveOptions options;
  options.weightings = {{"time-free", ObjectiveWeights::Preset("time-free")},
                        {"full", ObjectiveWeights::Preset("full")}};
  return ObjectiveFunction(CaseDocument::Load(ExamplePath("beam.toml")),
                           ReadCsv(DataPath("measured_knl50_T0.1.csv")), options);
}

TEST(SharesTest, LandscapeSharesMergeToTheWholeGrid) {
  const ObjectiveFunction objective = TimeFreeAndFull();
  LandscapeOptions options;
  options.x = {0, 0.0, 200.0, 23};
  options.threads = 2;
  long long calls = 0, last_done = 0;
  options.progress = [&](const Progress& p) {
    ++calls;
    EXPECT_GT(p.done, last_done);  // serial calls, counting up
    last_done = p.done;
    EXPECT_EQ(p.total, 23);
  };
  const LandscapeResult whole = ComputeLandscape(objective, options);
  ASSERT_EQ(whole.termination, LandscapeTermination::kCompleted) << whole.message;
  EXPECT_EQ(calls, 23);

  // Three shares, merged as the CLI does: each point from its owner.
  options.progress = nullptr;
  options.threads = 1;
  LandscapeResult merged;
  for (int share = 0; share < 3; ++share) {
    options.share_index = share;
    options.share_count = 3;
    LandscapeResult part = ComputeLandscape(objective, options);
    EXPECT_EQ(part.termination, LandscapeTermination::kInterrupted);  // a share is not the grid
    EXPECT_EQ(part.evaluations, share < 2 ? 8 : 7);
    if (share == 0) {
      merged = part;
      continue;
    }
    for (std::size_t p = 0; p < part.terms.size(); ++p) {
      if (!part.computed[p]) continue;
      EXPECT_FALSE(merged.computed[p]) << "point " << p << " computed twice";
      merged.terms[p] = part.terms[p];
      merged.computed[p] = 1;
    }
  }
  SummariseLandscape(objective.options().weightings, &merged);
  ASSERT_EQ(merged.termination, LandscapeTermination::kCompleted) << merged.message;
  for (std::size_t k = 0; k < whole.values.size(); ++k) {
    EXPECT_TRUE(merged.values[k].cwiseEqual(whole.values[k]).all()) << "weighting " << k;
    EXPECT_EQ(merged.metrics[k].local_minima, whole.metrics[k].local_minima);
    EXPECT_EQ(merged.metrics[k].global_minimiser, whole.metrics[k].global_minimiser);
  }
}

// Threads beyond the work only hold workspaces: a landscape of 3 points asked
// for 64 threads (or for OpenMP's count) runs on at most 3, an
// identification of 2 starts on at most 2 (the team sizes seen inside).
TEST(SharesTest, NoMoreThreadsThanPointsOrStarts) {
  const ObjectiveFunction objective = TimeFreeAndFull();
  for (int threads : {64, 0}) {
    LandscapeOptions options;
    options.x = {0, 40.0, 60.0, 3};
    options.threads = threads;
    int team = 0;
    options.progress = [&](const Progress&) { team = std::max(team, omp_get_num_threads()); };
    ASSERT_EQ(ComputeLandscape(objective, options).termination, LandscapeTermination::kCompleted);
    EXPECT_GE(team, 1);
    EXPECT_LE(team, 3) << "threads " << threads;
  }
  IdentifyOptions options;
  options.multistart = 2;
  options.threads = 64;
  std::atomic<int> team{0};
  options.progress = [&](const Progress&) {  // from the starts' threads at once
    const int now = omp_get_num_threads();
    int seen = team.load();
    while (now > seen && !team.compare_exchange_weak(seen, now)) {
    }
  };
  ASSERT_TRUE(Identify(objective, options).IsSolutionUsable());
  EXPECT_GE(team.load(), 1);
  EXPECT_LE(team.load(), 2);
}

// An exception from the progress callback (Python's Ctrl-C) stops every
// start, not only the one whose evaluation called it, and the callback is not
// called again: before, the other starts ran to their end.
TEST(SharesTest, AProgressCallbackThatThrowsStopsEveryStart) {
  const ObjectiveFunction objective = TimeFreeAndFull();
  for (int threads : {1, 2}) {
    IdentifyOptions options;
    options.multistart = 4;
    options.threads = threads;
    std::atomic<int> calls{0};
    options.progress = [&](const Progress&) {
      if (++calls == 3) throw std::runtime_error("stop");
    };
    EXPECT_THROW(Identify(objective, options), std::runtime_error);
    EXPECT_EQ(calls.load(), 3) << threads << " threads";
    LandscapeOptions landscape;
    landscape.x = {0, 0.0, 200.0, 40};
    landscape.threads = threads;
    calls = 0;
    landscape.progress = options.progress;
    EXPECT_THROW(ComputeLandscape(objective, landscape), std::runtime_error);
    EXPECT_EQ(calls.load(), 3) << threads << " threads, landscape";
  }
}

TEST(SharesTest, MultistartSharesMergeToTheSameBestPoint) {
  const ObjectiveFunction objective = TimeFreeAndFull();
  IdentifyOptions options;
  options.multistart = 4;
  options.threads = 2;
  std::atomic<long long> calls{0};
  options.progress = [&](const Progress& p) {
    ++calls;
    EXPECT_EQ(p.total, 4 * options.max_evaluations);
  };
  const IdentifySummary whole = Identify(objective, options);
  ASSERT_TRUE(whole.IsSolutionUsable()) << whole.message;
  EXPECT_EQ(calls.load(), whole.evaluations);

  options.progress = nullptr;
  options.share_count = 2;
  IdentifySummary merged;
  for (int share = 0; share < 2; ++share) {
    options.share_index = share;
    IdentifySummary part = Identify(objective, options);
    if (share == 0) {
      merged = part;
      continue;
    }
    for (std::size_t s = 0; s < part.start_results.size(); ++s) {
      if (part.start_results[s].computed) merged.start_results[s] = part.start_results[s];
    }
    merged.history.insert(merged.history.end(), part.history.begin(), part.history.end());
  }
  // The history in start order, as one process keeps it.
  std::stable_sort(merged.history.begin(), merged.history.end(),
                   [](const IterationRecord& a, const IterationRecord& b) { return a.start < b.start; });
  SummariseStarts(&merged);
  EXPECT_EQ(merged.termination, whole.termination);
  EXPECT_EQ(merged.parameters, whole.parameters);
  EXPECT_EQ(merged.final_objective, whole.final_objective);
  EXPECT_EQ(merged.best_start, whole.best_start);
  EXPECT_EQ(merged.evaluations, whole.evaluations);
  EXPECT_EQ(merged.initial_objective, whole.initial_objective);
  ASSERT_EQ(merged.history.size(), whole.history.size());
  for (std::size_t i = 0; i < whole.history.size(); ++i) {
    EXPECT_EQ(merged.history[i].objective, whole.history[i].objective) << i;
  }
}

TEST(SharesTest, InvalidSharesAndThreads) {
  const ObjectiveFunction objective = TimeFreeAndFull();
  LandscapeOptions landscape;
  landscape.x = {0, 0.0, 1.0, 3};
  landscape.share_index = 2;
  landscape.share_count = 2;
  EXPECT_THROW(ComputeLandscape(objective, landscape), std::invalid_argument);
  landscape.share_index = 0;
  landscape.threads = kMaxThreads + 1;
  EXPECT_THROW(ComputeLandscape(objective, landscape), std::invalid_argument);
  IdentifyOptions identify;
  identify.threads = -1;
  EXPECT_THROW(Identify(objective, identify), std::invalid_argument);
}

}  // namespace
}  // namespace podid::ident
