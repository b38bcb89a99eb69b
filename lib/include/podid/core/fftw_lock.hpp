#pragma once
// FFTW's planner (making and destroying plans, wisdom) is global to the
// process and not thread-safe; executing a plan is. Every podid module that
// plans (the wavelet module's plan cache, the model's band-limited
// interpolation) holds this one lock while it does, so that threads of a
// landscape or an identification may plan at the same time.

#include <mutex>

namespace podid::internal {

std::mutex& FftwPlannerMutex();

}  // namespace podid::internal
