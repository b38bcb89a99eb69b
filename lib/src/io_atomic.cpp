// WriteFileAtomically: temporary file in the destination folder, fsync, rename.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <ostream>
#include <stdexcept>
#include <streambuf>
#include <string>
#include <vector>

#include "podid/core/error.hpp"
#include "podid/core/io.hpp"

namespace podid {
namespace {

/// A std::streambuf writing to a file descriptor; remembers the first errno.
class FdStreamBuf : public std::streambuf {
 public:
  explicit FdStreamBuf(int fd) : fd_(fd), buffer_(kBufferBytes) {
    setp(buffer_.data(), buffer_.data() + buffer_.size());
  }
  int error() const { return error_; }

 protected:
  int_type overflow(int_type ch) override {
    if (!Drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(ch, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(ch);
      pbump(1);
    }
    return traits_type::not_eof(ch);
  }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    if (n <= epptr() - pptr()) {
      std::memcpy(pptr(), s, static_cast<std::size_t>(n));
      pbump(static_cast<int>(n));
      return n;
    }
    if (!Drain() || !WriteAll(s, static_cast<std::size_t>(n))) return 0;
    return n;
  }
  int sync() override { return Drain() ? 0 : -1; }

 private:
  static constexpr std::size_t kBufferBytes = std::size_t{1} << 16;

  bool Drain() {
    const bool ok = WriteAll(pbase(), static_cast<std::size_t>(pptr() - pbase()));
    setp(buffer_.data(), buffer_.data() + buffer_.size());
    return ok;
  }
  bool WriteAll(const char* data, std::size_t size) {
    if (error_ != 0) return false;
    while (size > 0) {
      const ssize_t written = ::write(fd_, data, size);
      if (written < 0) {
        if (errno == EINTR) continue;
        error_ = errno;
        return false;
      }
      data += written;
      size -= static_cast<std::size_t>(written);
    }
    return true;
  }

  int fd_;
  std::vector<char> buffer_;
  int error_ = 0;
};

[[noreturn]] void Fail(const std::string& path, const std::string& why) {
  throw std::runtime_error("cannot write " + path + ": " + why);
}

std::atomic<unsigned> temp_counter{0};

/// Runs `write` on a stream over `fd` and flushes it. On any failure calls
/// `discard` and throws: std::invalid_argument from the callback stays one,
/// anything else becomes std::runtime_error naming `path`.
void WriteThrough(int fd,
                  const std::string& path,
                  const std::function<void(std::ostream&)>& write,
                  const std::function<void()>& discard) {
  FdStreamBuf buffer(fd);
  std::ostream stream(&buffer);
  try {
    write(stream);
  } catch (const std::invalid_argument& e) {
    discard();
    throw std::invalid_argument("writing " + path + ": " + e.what());
  } catch (const std::exception& e) {
    discard();
    Fail(path, e.what());
  } catch (...) {
    discard();
    throw;
  }
  stream.flush();
  if (buffer.error() != 0) {
    const int error = buffer.error();
    discard();
    Fail(path, std::strerror(error));
  }
  if (!stream) {
    discard();
    Fail(path, "the output stream reported a failure");
  }
}

/// An existing device, FIFO or socket (/dev/null, /dev/full, a pipe) is
/// written in place: renaming a temporary onto it would replace the device
/// node with a regular file (as root, /dev/null itself for everyone).
void WriteInPlace(const std::string& path, const std::function<void(std::ostream&)>& write) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0) Fail(path, std::strerror(errno));
  WriteThrough(fd, path, write, [fd] { ::close(fd); });
  if (::close(fd) != 0) Fail(path, std::string("close failed: ") + std::strerror(errno));
}

}  // namespace

void WriteFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  if (path.empty() || !target.has_filename()) {
    ThrowInvalid("output file", "a file name", "\"" + path + "\"");
  }
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  struct stat status {};
  if (::stat(path.c_str(), &status) == 0 && !S_ISREG(status.st_mode) &&
      !S_ISDIR(status.st_mode)) {
    WriteInPlace(path, write);
    return;
  }

  // Create the temporary: same folder, so that rename() is atomic.
  std::string temp;
  int fd = -1;
  for (int attempt = 0; attempt < 100 && fd < 0; ++attempt) {
    temp = (folder / ("." + target.filename().string() + ".tmp-" + std::to_string(::getpid()) +
                      "-" + std::to_string(temp_counter.fetch_add(1))))
               .string();
    fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 && errno != EEXIST) {
      Fail(path,
           "cannot create a temporary file in " + folder.string() + ": " + std::strerror(errno));
    }
  }
  if (fd < 0) Fail(path, "cannot create a temporary file in " + folder.string());

  auto discard = [&]() {
    if (fd >= 0) ::close(fd);
    fd = -1;
    ::unlink(temp.c_str());
  };

  WriteThrough(fd, path, write, discard);
  if (::fsync(fd) != 0) {
    const int error = errno;
    discard();
    Fail(path, std::string("fsync failed: ") + std::strerror(error));
  }
  const int close_result = ::close(fd);
  fd = -1;
  if (close_result != 0) {
    const int error = errno;
    discard();
    Fail(path, std::string("close failed: ") + std::strerror(error));
  }
  if (::rename(temp.c_str(), path.c_str()) != 0) {
    const int error = errno;
    discard();
    Fail(path, std::string("rename failed: ") + std::strerror(error));
  }
  // Make the rename itself durable (best effort: not every file system allows it).
  const int dir = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    (void)::fsync(dir);
    ::close(dir);
  }
}

}  // namespace podid
