// The registry of temporary paths and the signal cleanup (issue 10 item 10):
// SIGINT/SIGTERM/SIGHUP during a write used to leave ".<name>.tmp-<pid>-<n>"
// files of up to 68 MB behind.
#include "podid/core/temp_files.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "podid/core/io.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

namespace podid {
namespace {

using testing::ReadText;
using testing::TempDir;

bool Exists(const std::string& path) { return std::filesystem::exists(path); }

TEST(TemporaryPath, RegisteredPathsAreRemovedFilesFirst) {
  const TempDir dir;
  std::filesystem::create_directory(dir.File("private"));
  const std::string inside = dir.Write("private/data0", "1 2\n");
  const std::string loose = dir.Write("loose.tmp", "x");
  const std::string kept = dir.Write("released.tmp", "x");
  // The folder is registered before its file: removal still empties it first.
  TemporaryPath folder(dir.File("private"), TemporaryPath::Kind::kFolder);
  TemporaryPath file(inside), other(loose), released(kept);
  ASSERT_TRUE(folder.registered() && file.registered() && other.registered());
  released.Release();
  RemoveRegisteredTemporaries();
  EXPECT_FALSE(Exists(inside));
  EXPECT_FALSE(Exists(dir.File("private")));
  EXPECT_FALSE(Exists(loose));
  EXPECT_TRUE(Exists(kept));  // unregistered: never removed
}

TEST(TemporaryPath, FullRegistryOrLongPathIsNotRegistered) {
  std::vector<TemporaryPath> paths;
  for (int i = 0; i < kMaxTemporaryPaths; ++i) {
    paths.emplace_back("/nonexistent/podid-slot-" + std::to_string(i));
    ASSERT_TRUE(paths.back().registered()) << i;
  }
  EXPECT_FALSE(TemporaryPath("/nonexistent/one-too-many").registered());
  paths.pop_back();  // a slot is free again
  EXPECT_TRUE(TemporaryPath("/nonexistent/fits-now").registered());
  EXPECT_FALSE(TemporaryPath(std::string(PATH_MAX, 'a')).registered());
}

// A write interrupted by `signal_number` after 1 MiB has reached the
// temporary (more than the 64 KiB stream buffer): in a child process, which
// the signal kills; the parent then finds the earlier file intact and no
// temporary left.
void ExpectSignalRemovesTheTemporary(int signal_number) {
  const TempDir dir;
  const std::string path = dir.Write("out.csv", "precious\n");
  auto child = [&] {
    std::signal(signal_number, SIG_DFL);  // e.g. SIGINT is ignored in background jobs
    InstallTemporaryFileCleanup();
    WriteFileAtomically(path, [&](std::ostream& os) {
      os << std::string(1 << 20, 'x');
      os.flush();
      // The temporary exists and holds the data: the signal arrives now.
      bool temporary_present = false;
      for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
        temporary_present |= entry.path().filename().string().find(".tmp-") != std::string::npos;
      }
      if (!temporary_present) std::_Exit(3);
      ::raise(signal_number);
      std::_Exit(4);  // not reached: the default action ends the process
    });
  };
  const testing::DeathTestTempRoot child_folders;
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(child(), ::testing::KilledBySignal(signal_number), "");
  EXPECT_EQ(ReadText(path), "precious\n");
  EXPECT_EQ(dir.Entries(), std::vector<std::string>{"out.csv"});
}

TEST(TemporaryFileCleanup, SigtermDuringAWrite) { ExpectSignalRemovesTheTemporary(SIGTERM); }
TEST(TemporaryFileCleanup, SigintDuringAWrite) { ExpectSignalRemovesTheTemporary(SIGINT); }
TEST(TemporaryFileCleanup, SighupDuringAWrite) { ExpectSignalRemovesTheTemporary(SIGHUP); }

TEST(TemporaryFileCleanup, AnIgnoredSignalStaysIgnored) {
  // nohup: SIGHUP ignored before podid starts must not start ending it.
  auto child = [] {
    std::signal(SIGHUP, SIG_IGN);
    InstallTemporaryFileCleanup();
    ::raise(SIGHUP);
    std::_Exit(0);
  };
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(child(), ::testing::ExitedWithCode(0), "");
}

}  // namespace
}  // namespace podid
