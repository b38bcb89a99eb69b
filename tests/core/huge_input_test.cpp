// Huge inputs (issue 7): a 10^6-sample, 64-channel CSV (about 1.3 GB) is read
// in memory bounded by the result plus one block, and in reasonable time.
// Writing the file takes a while and 1.3 GB of $TMPDIR, so the test runs only
// with PODID_HUGE_TESTS=1; the overlong-line rejection is in io_test.cpp
// (ReadCsvRejects.OverlongLineWithoutReadingIt, a 10 MB line) and always runs.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "podid/core/io.hpp"
#include "temp_dir.hpp"

namespace podid {
namespace {

using testing::TempDir;

constexpr long kSamples = 1000000;
constexpr int kChannels = 64;

/// Writes t,c1..c64 with %.12e numbers, one row at a time (no big buffer).
void WriteHugeCsv(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  std::string header = "t";
  for (int j = 1; j <= kChannels; ++j) header += ",c" + std::to_string(j);
  std::fprintf(f, "%s\n", header.c_str());
  char row[(kChannels + 1) * 32];
  for (long i = 0; i < kSamples; ++i) {
    char* p = row;
    p = std::to_chars(p, row + sizeof row, i * 1e-4, std::chars_format::scientific, 12).ptr;
    for (int j = 1; j <= kChannels; ++j) {
      *p++ = ',';
      const double v = 1e-3 * static_cast<double>((i * 31 + j * 17) % 1000) - 0.5;
      p = std::to_chars(p, row + sizeof row, v, std::chars_format::scientific, 12).ptr;
    }
    *p++ = '\n';
    ASSERT_EQ(std::fwrite(row, 1, p - row, f), static_cast<std::size_t>(p - row));
  }
  ASSERT_EQ(std::fclose(f), 0);
}

long PeakRssKiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;  // KiB on Linux
}

TEST(HugeInput, MillionSamplesBy64ChannelsInBoundedMemory) {
  const char* enabled = std::getenv("PODID_HUGE_TESTS");
  if (enabled == nullptr || std::string(enabled) != "1") {
    GTEST_SKIP() << "set PODID_HUGE_TESTS=1 to write and read a 1.3 GB CSV";
  }
  const TempDir dir;
  const std::string path = dir.File("huge.csv");
  WriteHugeCsv(path);
  if (HasFatalFailure()) return;

  // Read in a child so that its peak RSS is the reader's alone.
  int pipe_fds[2];
  ASSERT_EQ(::pipe(pipe_fds), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::close(pipe_fds[0]);
    const long before_kib = PeakRssKiB();
    const auto start = std::chrono::steady_clock::now();
    long samples = 0, channels = 0;
    try {
      const TimeSeries series = ReadCsv(path);
      samples = series.samples();
      channels = series.channels();
    } catch (...) {
      std::_Exit(3);
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    char message[128];
    const int n = std::snprintf(message, sizeof message, "%ld %ld %ld %ld %.3f", samples, channels,
                                before_kib, PeakRssKiB(), seconds);
    if (::write(pipe_fds[1], message, n) != n) std::_Exit(4);
    std::_Exit(0);
  }
  ::close(pipe_fds[1]);
  char buffer[128] = {};
  const ssize_t got = ::read(pipe_fds[0], buffer, sizeof buffer - 1);
  ::close(pipe_fds[0]);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "child status " << status;
  ASSERT_GT(got, 0);
  long samples = 0, channels = 0, before_kib = 0, peak_kib = 0;
  double seconds = 0.0;
  ASSERT_EQ(std::sscanf(buffer, "%ld %ld %ld %ld %lf", &samples, &channels, &before_kib, &peak_kib,
                        &seconds),
            5);
  EXPECT_EQ(samples, kSamples);
  EXPECT_EQ(channels, kChannels);
  const double result_mib = (kSamples * (kChannels + 1) * 8.0) / (1 << 20);
  const double peak_mib = peak_kib / 1024.0;
  std::printf("ReadCsv %ld x %d (%.0f MB file): %.2f s, peak RSS %.0f MiB (result %.0f MiB, "
              "%.0f MiB before reading)\n",
              kSamples, kChannels, std::filesystem::file_size(path) / 1e6, seconds, peak_mib,
              result_mib, before_kib / 1024.0);
  // Bounded: the result, one block of rows (1 MiB), the 1 MiB line buffer and
  // what the process held before; 64 MiB of slack for the allocator.
  constexpr double kSlackMiB = 64.0;
  EXPECT_LT(peak_mib, result_mib + before_kib / 1024.0 + kSlackMiB);
}

}  // namespace
}  // namespace podid
