#include "podid/core/bounded_read.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

namespace podid::internal {
namespace {

struct FileDescriptor {
  int fd = -1;
  ~FileDescriptor() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

BoundedRead ReadFileBounded(const std::string& path, std::size_t max_bytes, bool regular_only) {
  using Status = BoundedRead::Status;
  BoundedRead out;
  // max_bytes + 1 below must not wrap (SIZE_MAX would read nothing and say kOk).
  max_bytes = std::min(max_bytes, out.text.max_size() - 1);
  FileDescriptor file;
  file.fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (file.fd < 0) {
    out.status = Status::kCannotOpen;
    out.error = errno;
    return out;
  }
  struct ::stat info {};
  if (::fstat(file.fd, &info) != 0) {
    out.status = Status::kCannotStat;
    out.error = errno;
    return out;
  }
  if (S_ISDIR(info.st_mode)) {
    out.status = Status::kFolder;
    return out;
  }
  const bool regular = S_ISREG(info.st_mode);
  if (!regular && regular_only) {
    out.status = Status::kNotRegular;
    return out;
  }
  if (regular && static_cast<std::uint64_t>(info.st_size) > max_bytes) {
    out.status = Status::kTooLarge;
    out.size = static_cast<std::uint64_t>(info.st_size);
    return out;
  }
  const int flags = ::fcntl(file.fd, F_GETFL);
  if (flags >= 0) ::fcntl(file.fd, F_SETFL, flags & ~O_NONBLOCK);
  // One byte beyond the expected end, to see a file that grew; a stream
  // starts at 4 KiB. Grows by doubling up to max_bytes + 1.
  const std::size_t limit = max_bytes + 1;
  std::size_t capacity =
      std::min(limit, regular ? static_cast<std::size_t>(info.st_size) + 1 : std::size_t{4096});
  out.text.resize(capacity);
  std::size_t got = 0;
  while (got < limit) {
    if (got == out.text.size()) out.text.resize(std::min(limit, 2 * got + 4096));
    const ::ssize_t n = ::read(file.fd, out.text.data() + got, out.text.size() - got);
    if (n == 0) break;
    if (n < 0) {
      if (errno == EINTR) continue;
      out.status = Status::kReadError;
      out.error = errno;
      out.text.clear();
      return out;
    }
    got += static_cast<std::size_t>(n);
  }
  if (got > max_bytes) {
    out.status = Status::kMoreThanMax;
    out.text.clear();
    return out;
  }
  out.text.resize(got);
  return out;
}

}  // namespace podid::internal
