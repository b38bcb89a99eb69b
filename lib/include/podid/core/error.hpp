#pragma once
// Two kinds of error (what the CLI makes of them: docs/cli.md, "Exit status"):
//  * invalid user input throws std::invalid_argument whose message says where
//    (file:line, key, argument) and "expected X, got Y";
//  * a broken internal invariant is a bug: PODID_CHECK aborts with file:line,
//    in every build type.
// Numerical outcomes (a diverging Newton iteration, an optimiser stopping
// early) are neither: they are reported in a Summary's termination.

#include <cstddef>
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

/// A derived figure for a message (a tolerance, a share, a duration): 3
/// significant digits ("%.3g"); the values a user gave keep ToText's 10.
std::string ToShortText(double value);

/// Bytes of input text a message shows at most (Excerpt's default): enough to
/// recognise a token, too few to print a file's lines.
inline constexpr std::size_t kExcerptBytes = 40;

/// Length (2..4) of the well-formed UTF-8 sequence starting at byte i of s
/// (no overlong forms, no surrogates, at most U+10FFFF), or 0.
std::size_t Utf8SequenceLength(std::string_view s, std::size_t i);

/// `text` with every byte that could drive a terminal written as an escape:
/// \n, \r, \t, \xNN for the other C0 controls and DEL, C1 controls
/// (U+0080..U+009F) and bytes that are not valid UTF-8. Printable ASCII
/// (backslashes included) and valid UTF-8 pass unchanged, so escaping an
/// escaped text changes nothing. ThrowInvalid escapes every message with it.
std::string Escaped(std::string_view text);

/// Whether `text` holds a C0 control byte (NUL, a line break, an escape) or
/// DEL: what names read from files (channels, parameters, labels) may not
/// hold, since they reach messages, tables and output headers.
bool HasControlCharacter(std::string_view text);

/// A short, quoted, escaped excerpt of an input token for "got ...":
/// `"abc"`, or `"abcd..." (1234 bytes)` when longer than `max_bytes`.
std::string Excerpt(std::string_view text, std::size_t max_bytes = kExcerptBytes);

/// Throws std::invalid_argument("<where>: expected <expected>, got <got>"),
/// each part Escaped().
[[noreturn]] void ThrowInvalid(std::string_view where, std::string_view expected,
                               std::string_view got);

/// `text` with every occurrence of `from` (not empty) replaced by `to`, left to
/// right; a replacement is not searched again. The front-ends use it to put
/// their own names (--fmin, max_memory_MB) in the library's messages.
std::string ReplaceAll(std::string text, std::string_view from, std::string_view to);

/// Parses a whole string as a finite number (e.g. "2.5e9"); otherwise throws
/// ThrowInvalid(where, expected, Excerpt(text)).
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
