// The wavelet module when the system refuses it threads (a process at its
// `ulimit -u`, a container at its pids.max): pthread_create fails with
// EAGAIN, std::thread throws std::system_error, and each threaded kernel must
// do the work on the threads it has - the same result as one thread, bit for
// bit - instead of leaving a joinable std::thread to std::terminate (the
// band-limited CWT did). This binary replaces pthread_create (symbol
// interposition: the executable's definition comes first) with one that
// fails on request and otherwise calls the next definition (libc's, or
// ASan's interceptor).
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <pthread.h>

#include <atomic>
#include <cerrno>
#include <cmath>
#include <string>
#include <system_error>
#include <thread>

#include "podid/wavelet/cwt.hpp"
#include "podid/wavelet/ridge.hpp"

namespace {
std::atomic<bool> refuse_threads{false};
std::atomic<int> allowed{0};  // threads still granted while refusing
std::atomic<int> refused{0};
}  // namespace

extern "C" int pthread_create(pthread_t* thread,
                              const pthread_attr_t* attributes,
                              void* (*start)(void*),
                              void* argument) {
  using Create = int (*)(pthread_t*, const pthread_attr_t*, void* (*)(void*), void*);
  static const auto next = reinterpret_cast<Create>(::dlsym(RTLD_NEXT, "pthread_create"));
  if (refuse_threads.load() && allowed-- <= 0) {
    ++refused;
    return EAGAIN;
  }
  return next(thread, attributes, start, argument);
}

namespace podid::wavelet {
namespace {

// A decaying tone whose frequency falls, 1 s at 1 kHz, plus a second tone.
Eigen::VectorXd Decay(Eigen::Index n, double step_s) {
  Eigen::VectorXd x(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) * step_s;
    x(i) = std::exp(-1.5 * t) * std::cos(2.0 * M_PI * (40.0 * t - 5.0 * t * t)) +
           0.3 * std::sin(2.0 * M_PI * 90.0 * t);
  }
  return x;
}

// Equal entries, NaN where the other has NaN (outside the cone).
bool SameValues(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  if (a.size() != b.size()) return false;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    if (!(a(i) == b(i) || (std::isnan(a(i)) && std::isnan(b(i))))) return false;
  }
  return true;
}

// From construction on, threads are refused after the first `allow`.
struct Refused {
  explicit Refused(int allow = 0) {
    refused = 0;
    allowed = allow;
    refuse_threads = true;
  }
  ~Refused() { refuse_threads = false; }
};

TEST(ThreadsRefused, TheInterposerIsInPlace) {
  Refused r;
  std::thread t;
  EXPECT_THROW(t = std::thread([] {}), std::system_error);
  EXPECT_EQ(refused.load(), 1);
}

TEST(ThreadsRefused, CwtComputesEveryScaleOnTheThreadsItHas) {
  const double step_s = 1e-3;
  const Eigen::VectorXd x = Decay(3001, step_s);
  // None granted, or one of the three asked for (a started thread beside a
  // refused one: the case that ended in std::terminate).
  for (int allow : {0, 1}) {
    for (bool band_limited : {false, true}) {
      SCOPED_TRACE(std::string(band_limited ? "band-limited" : "full rate") + ", " +
                   std::to_string(allow) + " thread(s) granted");
      CwtOptions o;
      o.band_limited = band_limited;
      const Scalogram serial = Cwt(x, step_s, o);
      o.threads = 4;
      Scalogram threaded;
      {
        Refused r(allow);
        ASSERT_NO_THROW(threaded = Cwt(x, step_s, o));
        EXPECT_GE(refused.load(), 1);  // the kernel did ask for more threads
      }
      EXPECT_TRUE(threaded.coefficients == serial.coefficients);
    }
  }
}

TEST(ThreadsRefused, RidgeFrequencyGivesTheOneThreadTrack) {
  const double step_s = 1e-3;
  const Eigen::VectorXd x = Decay(20001, step_s);
  RidgeFrequencyOptions options;
  options.block_cells = 4096.0;  // several blocks: the pipelined pass and pass 2's split
  RidgeFrequencyEstimator serial(options);
  const RidgeTrack a = serial.Estimate(x, step_s);
  options.cwt.threads = 2;
  RidgeFrequencyEstimator threaded(options);
  Refused r;
  const RidgeTrack& b = threaded.Estimate(x, step_s);
  EXPECT_GE(refused.load(), 1);
  EXPECT_TRUE((a.frequency_index.array() == b.frequency_index.array()).all());
  EXPECT_TRUE(SameValues(a.frequency_Hz, b.frequency_Hz));
  EXPECT_TRUE(SameValues(a.amplitude, b.amplitude));
}

}  // namespace
}  // namespace podid::wavelet
