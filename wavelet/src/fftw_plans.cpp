#include "fftw_plans.hpp"

#include <map>
#include <mutex>
#include <new>
#include <utility>

#include "podid/core/error.hpp"

namespace podid::wavelet::internal {
namespace {

enum class Kind { kRealForward, kComplexBackward };

std::mutex& PlannerMutex() {
  static std::mutex mutex;
  return mutex;
}

// Plans live for the whole process and are destroyed at exit.
struct PlanCache {
  std::map<std::pair<Kind, int>, fftw_plan> plans;
  ~PlanCache() {
    for (auto& entry : plans) fftw_destroy_plan(entry.second);
  }
};

std::map<std::pair<Kind, int>, fftw_plan>& Plans() {
  static PlanCache cache;
  return cache.plans;
}

fftw_plan GetPlan(Kind kind, int n) {
  PODID_CHECK(n >= 1);
  std::lock_guard<std::mutex> lock(PlannerMutex());
  auto& plans = Plans();
  const auto key = std::make_pair(kind, n);
  if (auto it = plans.find(key); it != plans.end()) return it->second;
  // FFTW_MEASURE overwrites the arrays while planning: plan on scratch arrays.
  // Planning happens once per length (about 0.1 s for n = 10000).
  fftw_plan plan = nullptr;
  if (kind == Kind::kRealForward) {
    RealBuffer in = AllocateReal(static_cast<std::size_t>(n));
    ComplexBuffer out = AllocateComplex(static_cast<std::size_t>(n / 2 + 1));
    plan = fftw_plan_dft_r2c_1d(n, in.get(), AsFftw(out.get()), FFTW_MEASURE);
  } else {
    ComplexBuffer data = AllocateComplex(static_cast<std::size_t>(n));
    plan = fftw_plan_dft_1d(n, AsFftw(data.get()), AsFftw(data.get()), FFTW_BACKWARD, FFTW_MEASURE);
  }
  PODID_CHECK_MSG(plan != nullptr, "FFTW could not make a plan");
  plans.emplace(key, plan);
  return plan;
}

}  // namespace

RealBuffer AllocateReal(std::size_t n) {
  auto* p = static_cast<double*>(fftw_malloc(sizeof(double) * (n == 0 ? 1 : n)));
  if (p == nullptr) throw std::bad_alloc();
  return RealBuffer(p);
}

ComplexBuffer AllocateComplex(std::size_t n) {
  auto* p = static_cast<std::complex<double>*>(
      fftw_malloc(sizeof(std::complex<double>) * (n == 0 ? 1 : n)));
  if (p == nullptr) throw std::bad_alloc();
  return ComplexBuffer(p);
}

fftw_plan RealForwardPlan(int n) { return GetPlan(Kind::kRealForward, n); }
fftw_plan ComplexBackwardPlan(int n) { return GetPlan(Kind::kComplexBackward, n); }

}  // namespace podid::wavelet::internal
