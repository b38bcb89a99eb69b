#include "case_limits.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "podid/core/error.hpp"

namespace podid::case_detail {
namespace {

const std::string kSizeExpected =
    "a case file of at most " + std::to_string(kMaxCaseFileBytes) + " bytes (1 MiB)";

struct FileDescriptor {
  int fd = -1;
  ~FileDescriptor() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

std::string ReadCaseText(const std::string& path) {
  FileDescriptor file;
  // O_NONBLOCK: opening a FIFO with no writer must not hang; cleared below so
  // that reads wait for data as usual.
  file.fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (file.fd < 0) {
    ThrowInvalid(path, "a readable case file",
                 std::string("a file that cannot be opened (") + std::strerror(errno) + ")");
  }
  struct stat info {};
  if (::fstat(file.fd, &info) != 0 || S_ISDIR(info.st_mode)) {
    ThrowInvalid(path, "a readable case file", "a folder");
  }
  if (S_ISREG(info.st_mode) && static_cast<unsigned long long>(info.st_size) > kMaxCaseFileBytes) {
    ThrowInvalid(path, kSizeExpected, std::to_string(info.st_size) + " bytes");
  }
  const int flags = ::fcntl(file.fd, F_GETFL);
  if (flags >= 0) ::fcntl(file.fd, F_SETFL, flags & ~O_NONBLOCK);
  std::string text(kMaxCaseFileBytes + 1, '\0');
  std::size_t size = 0;
  while (size < text.size()) {
    const ssize_t got = ::read(file.fd, text.data() + size, text.size() - size);
    if (got == 0) break;
    if (got < 0) {
      if (errno == EINTR) continue;
      ThrowInvalid(path, "a readable case file",
                   std::string("a read error (") + std::strerror(errno) + ")");
    }
    size += static_cast<std::size_t>(got);
  }
  if (size > kMaxCaseFileBytes) ThrowInvalid(path, kSizeExpected, "more (a device or a pipe?)");
  text.resize(size);
  return text;
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
