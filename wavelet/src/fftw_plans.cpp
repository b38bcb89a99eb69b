#include "fftw_plans.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <map>
#include <mutex>
#include <new>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "podid/core/error.hpp"
#include "podid/core/fftw_lock.hpp"
#include "podid/wavelet/plans.hpp"
#include "wisdom_file.hpp"

namespace podid::wavelet {
namespace internal {
namespace {

enum class Kind { kRealForward, kComplexBackward, kBatchedBackward, kComplexForward };

// Planner effort, in increasing rigour: 0 FFTW_ESTIMATE, then the
// PlanEffort values + 1 (1 FFTW_MEASURE, 2 FFTW_PATIENT).
constexpr unsigned kEffortFlags[] = {FFTW_ESTIMATE, FFTW_MEASURE, FFTW_PATIENT};
constexpr int kMostRigorous = 2;

struct Entry {
  fftw_plan plan = nullptr;
  int effort = 0;  // of kEffortFlags
};

// Plans live for the whole process and are destroyed at exit. A measured plan
// replacing an estimated one keeps the old one alive (another thread's
// transform may still hold it).
struct State {
  std::mutex& mutex = podid::internal::FftwPlannerMutex();  // shared with the model module
  std::map<std::tuple<Kind, int, int>, Entry> plans;  // (kind, length, howmany)
  std::vector<fftw_plan> retired;
  std::set<std::string> loaded;  // cache files already imported
  std::string ignored;           // why the cache file was last ignored ("" if read or missing)
  ~State() {
    for (auto& entry : plans) fftw_destroy_plan(entry.second.plan);
    for (fftw_plan p : retired) fftw_destroy_plan(p);
  }
};

State& GlobalState() {
  static State state;
  return state;
}

// Imports the cache file once per path (callers hold the mutex). A missing,
// foreign or malformed file is ignored (wisdom_file.hpp): the plans are then estimated.
void LoadWisdomLocked(State& state) {
  const std::string path = FftWisdomPath();
  if (path.empty() || !state.loaded.insert(path).second) return;
  state.ignored = ImportWisdomFile(path);
}

// Writes all wisdom (this process's merged with the file's) to the cache:
// unique temporary file in the same folder, then rename. Returns "" or why not.
// A file that cannot be merged is replaced (state.ignored says why).
std::string SaveWisdomLocked(State& state) {
  const std::string path = FftWisdomPath();
  if (path.empty()) return "no cache folder (neither XDG_CACHE_HOME nor HOME is set)";
  const std::filesystem::path file(path);
  const std::filesystem::path folder = file.parent_path();
  std::error_code ec;
  std::filesystem::create_directories(folder.parent_path(), ec);
  if (::mkdir(folder.c_str(), 0700) != 0 && errno != EEXIST) {
    return "cannot create " + folder.string();
  }
  if (std::string why = ImportWisdomFile(path); !why.empty()) state.ignored = std::move(why);
  std::string temp = path + ".tmp-" + std::to_string(::getpid()) + "-XXXXXX";
  const int fd = ::mkstemp(temp.data());
  if (fd < 0) return "cannot write in " + folder.string();
  FILE* out = ::fdopen(fd, "w");
  if (out == nullptr) {
    ::close(fd);
    ::unlink(temp.c_str());
    return "cannot write " + temp;
  }
  fftw_export_wisdom_to_file(out);
  const bool written = std::fflush(out) == 0 && ::fsync(fd) == 0;
  const bool closed = std::fclose(out) == 0;
  if (!written || !closed || std::rename(temp.c_str(), path.c_str()) != 0) {
    ::unlink(temp.c_str());
    return "cannot write " + path;
  }
  return "";
}

fftw_plan MakePlan(Kind kind, int n, int howmany, unsigned flags) {
  // Planning with FFTW_MEASURE overwrites the arrays: plan on scratch arrays.
  if (kind == Kind::kBatchedBackward) {
    const auto size = static_cast<std::size_t>(n) * static_cast<std::size_t>(howmany);
    ComplexBuffer in = AllocateComplex(size);
    ComplexBuffer out = AllocateComplex(size);
    // Input preserved: the pruned inverse twiddles block r from block r - 1
    // after its transform (pruned_inverse.cpp), at no cost measured.
    return fftw_plan_many_dft(1, &n, howmany, AsFftw(in.get()), nullptr, 1, n, AsFftw(out.get()),
                              nullptr, 1, n, FFTW_BACKWARD, flags | FFTW_PRESERVE_INPUT);
  }
  if (kind == Kind::kRealForward) {
    RealBuffer in = AllocateReal(static_cast<std::size_t>(n));
    ComplexBuffer out = AllocateComplex(static_cast<std::size_t>(n / 2 + 1));
    return fftw_plan_dft_r2c_1d(n, in.get(), AsFftw(out.get()), flags);
  }
  ComplexBuffer data = AllocateComplex(static_cast<std::size_t>(n));
  return fftw_plan_dft_1d(n, AsFftw(data.get()), AsFftw(data.get()),
                          kind == Kind::kComplexForward ? FFTW_FORWARD : FFTW_BACKWARD, flags);
}

// Returns the plan of at least effort `wanted` (0: whatever is known, else
// estimated), measuring it when wisdom of that effort is missing; a more
// rigorous plan from the wisdom is taken when there is one (FFTW_WISDOM_ONLY
// returns no plan unless wisdom at least as rigorous as its flags exists).
// *measured_now says whether this call measured it.
fftw_plan GetPlanLocked(
    State& state, Kind kind, int n, int howmany, int wanted, bool* measured_now) {
  PODID_CHECK(n >= 1 && howmany >= 1 && static_cast<long long>(n) * howmany <= kMaxPlanLength);
  PODID_CHECK(wanted >= 0 && wanted <= kMostRigorous);
  *measured_now = false;
  LoadWisdomLocked(state);
  Entry& entry = state.plans[{kind, n, howmany}];
  if (entry.plan != nullptr && (wanted == 0 || entry.effort >= wanted)) return entry.plan;
  fftw_plan plan = nullptr;
  int effort = 0;
  for (int e = kMostRigorous; e >= std::max(wanted, 1) && plan == nullptr; --e) {
    plan = MakePlan(kind, n, howmany, kEffortFlags[e] | FFTW_WISDOM_ONLY);
    effort = e;
  }
  if (plan == nullptr && wanted > 0) {
    plan = MakePlan(kind, n, howmany, kEffortFlags[wanted]);
    effort = wanted;
    *measured_now = true;
  } else if (plan == nullptr) {
    plan = MakePlan(kind, n, howmany, FFTW_ESTIMATE);
    effort = 0;
  }
  PODID_CHECK_MSG(plan != nullptr, "FFTW could not make a plan");
  if (entry.plan != nullptr) state.retired.push_back(entry.plan);
  entry.plan = plan;
  entry.effort = effort;
  return plan;
}

fftw_plan GetPlan(Kind kind, int n, int howmany, bool measure, bool* measured = nullptr) {
  State& state = GlobalState();
  std::lock_guard<std::mutex> lock(state.mutex);
  bool measured_now = false;
  fftw_plan plan = GetPlanLocked(state, kind, n, howmany, measure ? 1 : 0, &measured_now);
  if (measured_now) SaveWisdomLocked(state);  // best effort: an unwritable cache only costs time
  if (measured != nullptr) *measured = state.plans[{kind, n, howmany}].effort >= 1;
  return plan;
}

}  // namespace

fftw_plan RealForwardPlan(int n, bool measure) {
  return GetPlan(Kind::kRealForward, n, 1, measure);
}
fftw_plan ComplexForwardPlan(int n, bool measure) {
  return GetPlan(Kind::kComplexForward, n, 1, measure);
}
fftw_plan ComplexBackwardPlan(int n, bool measure) {
  return GetPlan(Kind::kComplexBackward, n, 1, measure);
}
fftw_plan BatchedBackwardPlan(int m, int d, bool measure, bool* measured) {
  return GetPlan(Kind::kBatchedBackward, m, d, measure, measured);
}

double FftCostModel(long long n) {
  // Per-point cost of one radix-p pass in units of a radix-2 pass: log2(p)
  // times an efficiency factor. Measured (FFTW 3.3.10, complex double,
  // 6561..131072 points): 0.47-0.60 ns per n log2 n for powers of 2,
  // 0.79-0.84 for powers of 3, 5 and 7, hence 1.6.
  constexpr std::pair<int, double> kRadix[] = {
      {2, 1.0}, {3, 1.6 * 1.585}, {5, 1.6 * 2.322}, {7, 1.6 * 2.807}};
  if (n < 1) return std::numeric_limits<double>::infinity();
  double cost = 0.0;
  for (const auto& [p, w] : kRadix) {
    while (n % p == 0) {
      n /= p;
      cost += w;
    }
  }
  return n == 1 ? std::max(cost, 1.0) : std::numeric_limits<double>::infinity();
}

namespace {

// The m in [n, max(n + 8, 1.25 n)] with factors 2, 3, 5, 7 only and the
// lowest cost(m) (ties: the shortest).
template <class Cost>
long long CheapestSmoothLength(long long n, const Cost& cost) {
  n = std::max<long long>(n, 1);
  const long long limit = std::max<long long>(n + 8, (5 * n + 3) / 4);  // 8 is smooth
  long long best = -1;
  double best_cost = std::numeric_limits<double>::infinity();
  // Every 2^a 3^b 5^c 7^d in [n, limit].
  for (long long p7 = 1; p7 <= limit; p7 *= 7) {
    for (long long p5 = p7; p5 <= limit; p5 *= 5) {
      for (long long p3 = p5; p3 <= limit; p3 *= 3) {
        for (long long m = p3; m <= limit; m *= 2) {
          if (m < n) continue;
          const double c = cost(m);
          if (c < best_cost || (c == best_cost && m < best)) {
            best_cost = c;
            best = m;
          }
        }
      }
    }
  }
  return best;
}

}  // namespace

long long FastFftLength(long long n) {
  return CheapestSmoothLength(n,
                              [](long long m) { return FftCostModel(m) * static_cast<double>(m); });
}

long long FastBlockLength(long long n, long long overlap) {
  PODID_CHECK(overlap >= 0 && overlap < std::max<long long>(n, 1));
  // Beyond 2048 points the model misleads with FFTW_ESTIMATE's plans, which
  // take 128-point codelets for 4096 points: 3.3 ns a point against 2.3 with
  // a measured plan (estimated, 1792: 2.25, 2048: 1.76, 3584: 3.0), and
  // 4096-point blocks made the 10-300 Hz Silverbox ridge 5 % slower than
  // 3584-point ones (docs/benchmark-log.md, "Ridge blocks by cost per kept time").
  constexpr long long kModelledBlock = 2048;
  if (n > kModelledBlock) return FastFftLength(n);
  return CheapestSmoothLength(n, [overlap](long long m) {
    return m > kModelledBlock
               ? std::numeric_limits<double>::infinity()
               : FftCostModel(m) * static_cast<double>(m) / static_cast<double>(m - overlap);
  });
}

}  // namespace internal

std::string FftWisdomPath() {
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  if (xdg != nullptr && xdg[0] == '/') return std::string(xdg) + "/podid/fftw3-wisdom";
  const char* home = std::getenv("HOME");
  if (home != nullptr && home[0] != '\0') return std::string(home) + "/.cache/podid/fftw3-wisdom";
  return "";
}

void MergeFftLengths(const FftLengths& more, FftLengths* lengths) {
  if (lengths == nullptr) {
    throw std::invalid_argument("MergeFftLengths: expected lengths to merge into, got null");
  }
  const auto merge = [](const auto& add, auto* into) {
    into->insert(into->end(), add.begin(), add.end());
    std::sort(into->begin(), into->end());
    into->erase(std::unique(into->begin(), into->end()), into->end());
  };
  merge(more.real_forward, &lengths->real_forward);
  merge(more.complex_backward, &lengths->complex_backward);
  merge(more.interleaved_backward, &lengths->interleaved_backward);
  merge(more.complex_forward, &lengths->complex_forward);
}

PlanSummary MeasureFftPlans(const FftLengths& lengths, PlanEffort effort) {
  if (effort != PlanEffort::kMeasure && effort != PlanEffort::kPatient) {
    ThrowInvalid("MeasureFftPlans: effort", "kMeasure or kPatient",
                 ToText(static_cast<int>(effort)));
  }
  const int wanted = effort == PlanEffort::kPatient ? 2 : 1;
  for (const std::vector<int>* list :
       {&lengths.real_forward, &lengths.complex_backward, &lengths.complex_forward}) {
    for (int n : *list) {
      if (n < 1 || n > internal::kMaxPlanLength) {
        ThrowInvalid("FFT length", "1.." + ToText(internal::kMaxPlanLength), ToText(n));
      }
    }
  }
  for (const auto& [m, d] : lengths.interleaved_backward) {
    if (m < 1 || d < 1 || static_cast<long long>(m) * d > internal::kMaxPlanLength) {
      ThrowInvalid("FFT length x decimation",
                   "m, d >= 1 with m d <= " + ToText(internal::kMaxPlanLength),
                   ToText(m) + " x " + ToText(d));
    }
  }
  PlanSummary summary;
  summary.wisdom_path = FftWisdomPath();
  const auto start = std::chrono::steady_clock::now();
  internal::State& state = internal::GlobalState();
  std::lock_guard<std::mutex> lock(state.mutex);
  const auto plan = [&](internal::Kind kind, int n, int howmany) {
    bool measured_now = false;
    internal::GetPlanLocked(state, kind, n, howmany, wanted, &measured_now);
    (measured_now ? summary.measured : summary.known) += 1;
  };
  for (int n : lengths.real_forward) plan(internal::Kind::kRealForward, n, 1);
  for (int n : lengths.complex_backward) plan(internal::Kind::kComplexBackward, n, 1);
  for (int n : lengths.complex_forward) plan(internal::Kind::kComplexForward, n, 1);
  for (const auto& [m, d] : lengths.interleaved_backward) {
    plan(internal::Kind::kBatchedBackward, m, d);
  }
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (summary.measured > 0) {
    summary.message = internal::SaveWisdomLocked(state);
    summary.saved = summary.message.empty();
  }
  summary.ignored = state.ignored;
  return summary;
}

}  // namespace podid::wavelet
