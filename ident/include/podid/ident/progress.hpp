#pragma once
// Progress of a long computation (a landscape's points, an identification's
// evaluations), reported through a callback instead of printing from library
// code: the CLI draws its progress line with it, the Python module a bar.

#include <functional>

namespace podid::ident {

struct Progress {
  long long done = 0;    ///< units finished (points, evaluations)
  long long total = 0;   ///< units planned (0 when not known in advance)
  long long failed = 0;  ///< of `done`, those that failed
  double elapsed_s = 0.0;
};

/// Called serially (never two calls at once), from whichever worker thread
/// finished a unit. It should return quickly. An exception thrown by it stops
/// the computation (every start of an identification, every point of a
/// landscape), it is not called again, and the exception is rethrown to the
/// caller once the workers have stopped.
using ProgressCallback = std::function<void(const Progress&)>;

/// The most worker threads a long computation (Identify's starts,
/// ComputeLandscape's points) may be asked for.
inline constexpr int kMaxThreads = 1024;

}  // namespace podid::ident
