#include "podid/core/error.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace podid {

std::string ToShortText(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

namespace internal {

void CheckFailed(const char* condition, const char* file, int line, std::string_view detail) {
  std::fprintf(stderr, "podid: internal error at %s:%d: check failed: %s%s%.*s\n", file, line,
               condition, detail.empty() ? "" : ": ", static_cast<int>(detail.size()),
               detail.data());
  std::abort();
}

}  // namespace internal

namespace {

// Length of the valid UTF-8 sequence at s[i] (1-4), or 0 when it is not one
// (overlong forms, surrogates and code points above U+10FFFF are invalid).

void AppendHex(std::string& out, unsigned char c) {
  constexpr char kDigits[] = "0123456789abcdef";
  out.append("\\x").push_back(kDigits[c >> 4]);
  out.push_back(kDigits[c & 15]);
}

}  // namespace

std::size_t Utf8SequenceLength(std::string_view s, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char b0 = byte(i);
  std::size_t n = 0;
  unsigned lo = 0x80, hi = 0xBF;  // range of the second byte
  if (b0 >= 0xC2 && b0 <= 0xDF) {
    n = 2;
  } else if (b0 >= 0xE0 && b0 <= 0xEF) {
    n = 3;
    if (b0 == 0xE0) lo = 0xA0;
    if (b0 == 0xED) hi = 0x9F;
  } else if (b0 >= 0xF0 && b0 <= 0xF4) {
    n = 4;
    if (b0 == 0xF0) lo = 0x90;
    if (b0 == 0xF4) hi = 0x8F;
  } else {
    return 0;
  }
  if (i + n > s.size()) return 0;
  if (byte(i + 1) < lo || byte(i + 1) > hi) return 0;
  for (std::size_t k = 2; k < n; ++k) {
    if (byte(i + k) < 0x80 || byte(i + k) > 0xBF) return 0;
  }
  return n;
}

bool HasControlCharacter(std::string_view text) {
  for (const char c : text) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return true;
  }
  return false;
}

std::string Escaped(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c < 0x7F) {
      out.push_back(static_cast<char>(c));
      ++i;
    } else if (c == '\n') {
      out.append("\\n");
      ++i;
    } else if (c == '\r') {
      out.append("\\r");
      ++i;
    } else if (c == '\t') {
      out.append("\\t");
      ++i;
    } else if (c < 0x80) {  // other C0 controls, DEL
      AppendHex(out, c);
      ++i;
    } else if (const std::size_t n = Utf8SequenceLength(text, i);
               n == 0 || (n == 2 && c == 0xC2 && static_cast<unsigned char>(text[i + 1]) < 0xA0)) {
      AppendHex(out, c);  // not UTF-8, or a C1 control (U+0080..U+009F): byte by byte
      ++i;
    } else {
      out.append(text.substr(i, n));
      i += n;
    }
  }
  return out;
}

std::string Excerpt(std::string_view text, std::size_t max_bytes) {
  if (text.size() <= max_bytes) return "\"" + Escaped(text) + "\"";
  std::size_t cut = max_bytes;  // not inside a UTF-8 sequence
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;
  return "\"" + Escaped(text.substr(0, cut)) + "...\" (" + std::to_string(text.size()) +
         " bytes)";
}

std::string ReplaceAll(std::string text, std::string_view from, std::string_view to) {
  PODID_CHECK(!from.empty());
  for (std::size_t at = text.find(from); at != std::string::npos;
       at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
  }
  return text;
}

void ThrowInvalid(std::string_view where, std::string_view expected, std::string_view got) {
  std::string message;
  message.reserve(where.size() + expected.size() + got.size() + 24);
  message.append(Escaped(where))
      .append(": expected ")
      .append(Escaped(expected))
      .append(", got ")
      .append(Escaped(got));
  throw std::invalid_argument(message);
}

double ParseNumber(std::string_view text, std::string_view where, std::string_view expected) {
  double value = 0.0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (text.empty() || ec != std::errc() || ptr != end || !std::isfinite(value)) {
    ThrowInvalid(where, expected, Excerpt(text));
  }
  return value;
}

}  // namespace podid
