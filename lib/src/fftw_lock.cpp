#include "podid/core/fftw_lock.hpp"

namespace podid::internal {

std::mutex& FftwPlannerMutex() {
  static std::mutex mutex;
  return mutex;
}

}  // namespace podid::internal
