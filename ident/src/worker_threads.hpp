#pragma once
// The worker-thread count of a landscape's points or an identification's
// starts, one rule for both (landscape.hpp, LandscapeOptions::threads).

#include <omp.h>

#include <algorithm>
#include <cstddef>

#include "podid/ident/landscape.hpp"  // kMaxThreads

namespace podid::ident::internal {

/// `requested` > 0 as given; 0: OpenMP's count (OMP_NUM_THREADS, else the
/// cores), bounded by kMaxThreads as the option is. Never more than `items`
/// (each thread holds a workspace: a simulation's buffers), at least 1.
inline int WorkerThreads(int requested, std::size_t items) {
  const int wanted = requested > 0 ? requested : std::min(omp_get_max_threads(), kMaxThreads);
  return static_cast<int>(std::clamp<std::size_t>(static_cast<std::size_t>(std::max(wanted, 1)), 1,
                                                  std::max<std::size_t>(items, 1)));
}

}  // namespace podid::ident::internal
