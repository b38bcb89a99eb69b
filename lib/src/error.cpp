#include "podid/core/error.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace podid {
namespace internal {

void CheckFailed(const char* condition, const char* file, int line, std::string_view detail) {
  std::fprintf(stderr, "podid: internal error at %s:%d: check failed: %s%s%.*s\n", file, line,
               condition, detail.empty() ? "" : ": ", static_cast<int>(detail.size()),
               detail.data());
  std::abort();
}

}  // namespace internal

void ThrowInvalid(std::string_view where, std::string_view expected, std::string_view got) {
  std::string message;
  message.reserve(where.size() + expected.size() + got.size() + 24);
  message.append(where).append(": expected ").append(expected).append(", got ").append(got);
  throw std::invalid_argument(message);
}

double ParseNumber(std::string_view text, std::string_view where, std::string_view expected) {
  double value = 0.0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (text.empty() || ec != std::errc() || ptr != end || !std::isfinite(value)) {
    ThrowInvalid(where, expected, "\"" + std::string(text) + "\"");
  }
  return value;
}

}  // namespace podid
