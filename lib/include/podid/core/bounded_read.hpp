#pragma once
// Reading a small file whole, with a bound on the bytes read: the case file
// (case_limits.cpp) and the FFTW wisdom cache (wavelet/src/wisdom_file.cpp)
// both come from paths a user controls, which may name a FIFO with no writer
// (an ordinary open() would wait for ever), /dev/zero (no end) or a file far
// larger than any real one. POSIX read() by hand because std::ifstream can do
// neither the non-blocking open nor tell a device from a file.

#include <cstddef>
#include <cstdint>
#include <string>

namespace podid::internal {

struct BoundedRead {
  enum class Status {
    kOk,
    kCannotOpen,   ///< open() failed; `error` holds errno.
    kCannotStat,   ///< fstat() failed; `error` holds errno.
    kFolder,       ///< a directory.
    kNotRegular,   ///< a FIFO, socket or device, and only regular files were asked for.
    kTooLarge,     ///< a regular file of `size` > max_bytes bytes (nothing read).
    kReadError,    ///< read() failed; `error` holds errno.
    kMoreThanMax,  ///< more than max_bytes came (a file that grew, a device, a pipe).
  };
  Status status = Status::kOk;
  int error = 0;           ///< errno of kCannotOpen, kCannotStat, kReadError.
  std::uint64_t size = 0;  ///< the file's size for kTooLarge.
  std::string text;        ///< the whole file for kOk.
};

/// Reads the file at `path` whole, at most `max_bytes` + 1 bytes. Opens with
/// O_NONBLOCK (a FIFO with no writer does not block the open; reads then wait
/// as usual) and O_NOCTTY. A regular file larger than `max_bytes` is refused
/// from its size before any read. With `regular_only`, FIFOs, sockets and
/// devices are refused before any read; else they are read until their end
/// or max_bytes + 1 bytes. A `max_bytes` beyond std::string's max_size() - 1
/// (SIZE_MAX: no bound) is taken as that. Never throws for the file's sake (std::bad_alloc
/// aside); each caller words its own messages from the status.
BoundedRead ReadFileBounded(const std::string& path, std::size_t max_bytes, bool regular_only);

}  // namespace podid::internal
