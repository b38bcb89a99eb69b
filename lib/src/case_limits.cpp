#include "case_limits.hpp"

#include <cstring>
#include <utility>

#include "podid/core/bounded_read.hpp"
#include "podid/core/error.hpp"

namespace podid::case_detail {
namespace {

const std::string kSizeExpected =
    "a case file of at most " + std::to_string(kMaxCaseFileBytes) + " bytes (1 MiB)";

}  // namespace

std::string ReadCaseText(const std::string& path) {
  using Status = internal::BoundedRead::Status;
  // FIFOs and devices are read too (a case piped in by process substitution),
  // up to the bound.
  internal::BoundedRead file = internal::ReadFileBounded(path, kMaxCaseFileBytes, false);
  const std::string readable = "a readable case file";
  switch (file.status) {
    case Status::kOk:
      break;
    case Status::kCannotOpen:
      ThrowInvalid(path, readable,
                   std::string("a file that cannot be opened (") + std::strerror(file.error) + ")");
    case Status::kFolder:
      ThrowInvalid(path, readable, "a folder");
    case Status::kTooLarge:
      ThrowInvalid(path, kSizeExpected, std::to_string(file.size) + " bytes");
    case Status::kMoreThanMax:
      ThrowInvalid(path, kSizeExpected, "more (a device or a pipe?)");
    case Status::kCannotStat:
    case Status::kReadError:
    case Status::kNotRegular:  // not asked for
      ThrowInvalid(path, readable, std::string("a read error (") + std::strerror(file.error) + ")");
  }
  return std::move(file.text);
}

void CheckCaseText(std::string_view text, std::string_view source) {
  if (text.size() > kMaxCaseFileBytes) {
    ThrowInvalid(source, kSizeExpected, std::to_string(text.size()) + " bytes");
  }
  // Depth = open arrays / inline tables / header brackets + the dots of the
  // dotted key being read since the last delimiter. A value has at most one
  // dot outside strings (1.5), so counting every dot only over-counts by one.
  const std::string expected =
      "TOML nested at most " + std::to_string(kMaxTomlNesting) +
      " levels deep (dotted keys, tables, arrays and inline tables together)";
  int brackets = 0, dots = 0;
  long long line = 1;
  const std::size_t n = text.size();
  auto fail = [&] {
    ThrowInvalid(std::string(source) + ":" + std::to_string(line), expected, "deeper nesting");
  };
  for (std::size_t i = 0; i < n; ++i) {
    const char c = text[i];
    switch (c) {
      case '\n':
        ++line;
        dots = 0;
        break;
      case '#':  // a comment to the end of the line
        while (i + 1 < n && text[i + 1] != '\n') ++i;
        break;
      case '"':
      case '\'': {
        const bool multi = i + 2 < n && text[i + 1] == c && text[i + 2] == c;
        if (multi) {
          const std::string_view close = c == '"' ? "\"\"\"" : "'''";
          std::size_t k = i + 3;
          while (k < n && text.substr(k, 3) != close) {
            if (c == '"' && text[k] == '\\') ++k;
            if (k < n && text[k] == '\n') ++line;
            ++k;
          }
          i = k + 2 < n ? k + 2 : n;  // toml++ reports an unterminated string
        } else {
          std::size_t k = i + 1;
          while (k < n && text[k] != c && text[k] != '\n') {
            if (c == '"' && text[k] == '\\') ++k;
            ++k;
          }
          if (k < n && text[k] == '\n') ++line;
          i = k;
        }
        break;
      }
      case '[':
      case '{':
        ++brackets;
        dots = 0;
        if (brackets > kMaxTomlNesting) fail();
        break;
      case ']':
      case '}':
        if (brackets > 0) --brackets;
        dots = 0;
        break;
      case '=':
      case ',':
        dots = 0;
        break;
      case '.':
        ++dots;
        if (brackets + dots > kMaxTomlNesting) fail();
        break;
      default:
        break;
    }
  }
}

}  // namespace podid::case_detail
