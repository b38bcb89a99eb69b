#pragma once
// FFTW for the model module's one-off transforms (band-limited interpolation,
// the measured-quantity check): estimated plans made and destroyed
// under the process-wide planner lock (podid/core/fftw_lock.hpp). FFTW rather
// than Eigen's kissfft: kissfft costs O(n p) for a prime factor p of n, and a
// measured record's length is whatever it is (the Silverbox window's 86,917 =
// 23 x 3779 samples took ~1 s per spectrum).

#include <fftw3.h>

#include <Eigen/Core>
#include <mutex>

#include "podid/core/error.hpp"
#include "podid/core/fftw_buffer.hpp"
#include "podid/core/fftw_lock.hpp"

namespace podid::internal {

/// A plan of length n <= kMaxLength, real -> half spectrum (forward) or half
/// spectrum -> real (inverse, unnormalised, overwrites its input), estimated.
class FftwRealPlan {
 public:
  /// FFTW's lengths are ints.
  static constexpr Eigen::Index kMaxLength = (Eigen::Index{1} << 31) - 1;
  static FftwRealPlan Forward(Eigen::Index n, double* in, fftw_complex* out) {
    std::lock_guard<std::mutex> lock(FftwPlannerMutex());
    return FftwRealPlan(fftw_plan_dft_r2c_1d(Checked(n), in, out, FFTW_ESTIMATE));
  }
  static FftwRealPlan Inverse(Eigen::Index n, fftw_complex* in, double* out) {
    std::lock_guard<std::mutex> lock(FftwPlannerMutex());
    return FftwRealPlan(fftw_plan_dft_c2r_1d(Checked(n), in, out, FFTW_ESTIMATE));
  }
  FftwRealPlan(FftwRealPlan&& other) noexcept : plan_(other.plan_) { other.plan_ = nullptr; }
  FftwRealPlan(const FftwRealPlan&) = delete;
  FftwRealPlan& operator=(const FftwRealPlan&) = delete;
  FftwRealPlan& operator=(FftwRealPlan&&) = delete;
  ~FftwRealPlan() {
    if (plan_ == nullptr) return;
    std::lock_guard<std::mutex> lock(FftwPlannerMutex());
    fftw_destroy_plan(plan_);
  }
  void Execute() const { fftw_execute(plan_); }

 private:
  explicit FftwRealPlan(fftw_plan plan) : plan_(plan) {
    PODID_CHECK_MSG(plan_ != nullptr, "FFTW could not make a plan");
  }
  static int Checked(Eigen::Index n) {
    if (n < 1 || n > kMaxLength) {  // callers check first; an error, never an abort
      ThrowInvalid("FFT length", "1.." + ToText(kMaxLength), ToText(n));
    }
    return static_cast<int>(n);
  }
  fftw_plan plan_ = nullptr;
};

}  // namespace podid::internal
