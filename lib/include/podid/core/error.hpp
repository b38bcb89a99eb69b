#pragma once
// Two kinds of error (see docs/method.md, "Errors"):
//  * invalid user input throws std::invalid_argument whose message says where
//    (file:line, key, argument) and "expected X, got Y";
//  * a broken internal invariant is a bug: PODID_CHECK aborts with file:line,
//    in every build type.
// Numerical outcomes (a diverging Newton iteration, an optimiser stopping
// early) are neither: they are reported in a Summary's termination.

#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>

namespace podid {

namespace internal {
[[noreturn]] void CheckFailed(const char* condition, const char* file, int line,
                              std::string_view detail = {});
}  // namespace internal

/// Formats a value for an "expected X, got Y" message.
template <typename T>
std::string ToText(const T& value) {
  std::ostringstream os;
  os.precision(10);
  os << value;
  return os.str();
}

/// Throws std::invalid_argument("<where>: expected <expected>, got <got>").
[[noreturn]] void ThrowInvalid(std::string_view where, std::string_view expected,
                               std::string_view got);

/// Parses a whole string as a finite number (e.g. "2.5e9"); otherwise throws
/// ThrowInvalid(where, expected, "\"text\"").
double ParseNumber(std::string_view text, std::string_view where,
                   std::string_view expected = "a number");

}  // namespace podid

/// Always-on invariant check (not compiled out by NDEBUG).
#define PODID_CHECK(condition)                                           \
  do {                                                                   \
    if (!(condition)) ::podid::internal::CheckFailed(#condition, __FILE__, __LINE__); \
  } while (false)

#define PODID_CHECK_MSG(condition, detail)                                         \
  do {                                                                             \
    if (!(condition)) ::podid::internal::CheckFailed(#condition, __FILE__, __LINE__, (detail)); \
  } while (false)
