// ReadFileBounded (podid/core/bounded_read.hpp), the one reader of the case
// file and of the FFTW wisdom cache: every status, the bound on what is read
// from files, FIFOs and devices, and that no open or read waits for ever.
#include "podid/core/bounded_read.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <string>
#include <thread>

#include "temp_dir.hpp"

namespace podid::internal {
namespace {

using Status = BoundedRead::Status;
using testing::TempDir;

TEST(ReadFileBounded, ReadsRegularFilesUpToTheBoundAndRefusesLargerOnesFromTheirSize) {
  const TempDir dir;
  constexpr std::size_t kMax = 10'000;  // a regular file is read into size + 1 bytes at once
  const std::string exact(kMax, 'x');
  for (const bool regular_only : {false, true}) {
    BoundedRead read = ReadFileBounded(dir.Write("exact", exact), kMax, regular_only);
    EXPECT_EQ(read.status, Status::kOk);
    EXPECT_EQ(read.text, exact);
    read = ReadFileBounded(dir.Write("empty", ""), kMax, regular_only);
    EXPECT_EQ(read.status, Status::kOk);
    EXPECT_EQ(read.text, "");
    read = ReadFileBounded(dir.Write("big", exact + "y"), kMax, regular_only);
    EXPECT_EQ(read.status, Status::kTooLarge);
    EXPECT_EQ(read.size, kMax + 1);
    EXPECT_EQ(read.text, "");
  }
  // No bound at all: the bound plus the byte past it must not wrap to 0.
  const BoundedRead unbounded = ReadFileBounded(dir.Write("any", exact), SIZE_MAX, true);
  EXPECT_EQ(unbounded.status, Status::kOk);
  EXPECT_EQ(unbounded.text, exact);
}

TEST(ReadFileBounded, NamesWhatIsNotAFileItCanRead) {
  const TempDir dir;
  BoundedRead read = ReadFileBounded(dir.File("missing"), 100, false);
  EXPECT_EQ(read.status, Status::kCannotOpen);
  EXPECT_EQ(read.error, ENOENT);
  read = ReadFileBounded(dir.Write("file", "a") + "/below", 100, false);
  EXPECT_EQ(read.status, Status::kCannotOpen);
  EXPECT_EQ(read.error, ENOTDIR);
  for (const bool regular_only : {false, true}) {
    EXPECT_EQ(ReadFileBounded(dir.path(), 100, regular_only).status, Status::kFolder);
  }
  EXPECT_EQ(ReadFileBounded("/dev/zero", 100, true).status, Status::kNotRegular);
}

// /dev/zero has no end: the read stops one byte past the bound.
TEST(ReadFileBounded, ADeviceIsReadAtMostOneBytePastTheBound) {
  const BoundedRead read = ReadFileBounded("/dev/zero", std::size_t{1} << 20, false);
  EXPECT_EQ(read.status, Status::kMoreThanMax);
  EXPECT_EQ(read.text, "");
  const BoundedRead null = ReadFileBounded("/dev/null", 100, false);
  EXPECT_EQ(null.status, Status::kOk);
  EXPECT_EQ(null.text, "");
}

// A FIFO with no writer: open() without O_NONBLOCK waits for one for ever.
// Refused unopened-for-reading when only regular files are asked for; else
// read as an empty stream.
TEST(ReadFileBounded, AFifoWithoutAWriterDoesNotWait) {
  const TempDir dir;
  const std::string fifo = dir.File("fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(ReadFileBounded(fifo, 100, true).status, Status::kNotRegular);
  const BoundedRead read = ReadFileBounded(fifo, 100, false);
  EXPECT_EQ(read.status, Status::kOk);
  EXPECT_EQ(read.text, "");
}

// A FIFO fed in pieces: the reads wait for the data (the non-blocking flag
// is cleared after open; left set, a read would fail with EAGAIN) and gather
// it whole, or stop one byte past the bound.
TEST(ReadFileBounded, AFifoFedInPiecesIsReadWholeOrBounded) {
  const TempDir dir;
  const std::string fifo = dir.File("fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // Within Linux's 64 KiB pipe buffer, so the writer never blocks.
  const std::string text(50'000, 'z');
  for (const std::size_t max : {text.size(), text.size() - 1}) {
    // O_RDWR opens a FIFO at once on Linux; this end, the only writer, is
    // also a reader, so the writer never gets SIGPIPE.
    const int fd = ::open(fifo.c_str(), O_RDWR | O_CLOEXEC);
    ASSERT_GE(fd, 0);
    std::thread writer([&] {
      constexpr std::size_t kPiece = 1000;
      for (std::size_t at = 0; at < text.size(); at += kPiece) {
        if (::write(fd, text.data() + at, kPiece) != static_cast<::ssize_t>(kPiece)) break;
        std::this_thread::sleep_for(std::chrono::microseconds(200));
      }
      ::close(fd);  // the end of the stream
    });
    const BoundedRead read = ReadFileBounded(fifo, max, false);
    writer.join();
    if (max == text.size()) {
      EXPECT_EQ(read.status, Status::kOk);
      EXPECT_EQ(read.text, text);
    } else {
      EXPECT_EQ(read.status, Status::kMoreThanMax);
      EXPECT_EQ(read.text, "");
    }
  }
}

}  // namespace
}  // namespace podid::internal
