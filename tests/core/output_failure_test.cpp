// Output failure paths and special targets not covered by io_test.cpp (which
// has the missing folder, RLIMIT_FSIZE as a full disk, a read-only folder and
// a throwing callback): devices, FIFOs, /dev/stdout, symlinks, hard links,
// modes, and ResolveOutput's identification of the file really written.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <ostream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "podid/core/io.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

namespace podid {
namespace {

using testing::ReadText;
using testing::TempDir;

bool IsCharacterDevice(const char* path) {
  struct stat status {};
  return ::stat(path, &status) == 0 && S_ISCHR(status.st_mode);
}

bool IsSymlink(const std::string& path) {
  struct stat status {};
  return ::lstat(path.c_str(), &status) == 0 && S_ISLNK(status.st_mode);
}

mode_t Mode(const std::string& path) {
  struct stat status {};
  EXPECT_EQ(::stat(path.c_str(), &status), 0) << path;
  return status.st_mode & 07777;
}

std::vector<std::string> Sorted(std::vector<std::string> names) {
  std::sort(names.begin(), names.end());
  return names;
}

void Write(const std::string& path, const std::string& text) {
  WriteFileAtomically(path, [&](std::ostream& os) { os << text; });
}

TEST(OutputFailure, DevFullIsAClearErrorAndStaysADevice) {
  // Writing through a temporary and renaming it onto /dev/full used to
  // replace the device node with a regular file (when /dev is writable, as for
  // root). A device is now written in place: /dev/full says ENOSPC.
  if (!IsCharacterDevice("/dev/full")) GTEST_SKIP() << "no /dev/full here";
  PODID_EXPECT_THROW_WITH(
      WriteFileAtomically("/dev/full", [](std::ostream& os) { os << std::string(1 << 20, 'x'); }),
      std::runtime_error, "cannot write /dev/full: No space left on device");
  EXPECT_TRUE(IsCharacterDevice("/dev/full"));
}

TEST(OutputFailure, DevNullAcceptsOutputAndStaysADevice) {
  if (!IsCharacterDevice("/dev/null")) GTEST_SKIP() << "no /dev/null here";
  EXPECT_NO_THROW(WriteFileAtomically("/dev/null", [](std::ostream& os) { os << "t,w1\n"; }));
  EXPECT_TRUE(IsCharacterDevice("/dev/null"));
}

TEST(OutputFailure, CallbackErrorOnADeviceKeepsItsKind) {
  if (!IsCharacterDevice("/dev/null")) GTEST_SKIP() << "no /dev/null here";
  PODID_EXPECT_THROW_WITH(
      WriteFileAtomically("/dev/null",
                          [](std::ostream&) { throw std::invalid_argument("bad series"); }),
      std::invalid_argument, "writing /dev/null: bad series");
}

// --- Symlinks, hard links, modes (issue 10 item 4) -------------------------

TEST(SpecialTargets, SymlinkIsWrittenThroughAndKept) {
  // Renaming onto the link used to replace the link itself with a regular
  // file, leaving the file it pointed to stale.
  const TempDir dir;
  std::filesystem::create_directory(dir.File("real"));
  const std::string target = dir.Write("real/data.csv", "old\n");
  std::filesystem::create_symlink("real/data.csv", dir.File("link.csv"));        // relative
  std::filesystem::create_symlink(dir.File("link.csv"), dir.File("link2.csv"));  // chained
  Write(dir.File("link2.csv"), "new\n");
  EXPECT_TRUE(IsSymlink(dir.File("link.csv")));
  EXPECT_TRUE(IsSymlink(dir.File("link2.csv")));
  EXPECT_EQ(ReadText(target), "new\n");
  // The temporary lived (and was renamed) next to the real file.
  EXPECT_EQ(Sorted(dir.Entries()), (std::vector<std::string>{"link.csv", "link2.csv", "real"}));
  std::vector<std::string> real;
  for (const auto& entry : std::filesystem::directory_iterator(dir.File("real"))) {
    real.push_back(entry.path().filename().string());
  }
  EXPECT_EQ(real, std::vector<std::string>{"data.csv"});
}

TEST(SpecialTargets, DanglingSymlinkCreatesItsTarget) {
  const TempDir dir;
  std::filesystem::create_symlink("made.csv", dir.File("link.csv"));
  Write(dir.File("link.csv"), "x\n");
  EXPECT_TRUE(IsSymlink(dir.File("link.csv")));
  EXPECT_EQ(ReadText(dir.File("made.csv")), "x\n");
}

TEST(SpecialTargets, SymlinkLoopIsAClearError) {
  const TempDir dir;
  std::filesystem::create_symlink("b", dir.File("a"));
  std::filesystem::create_symlink("a", dir.File("b"));
  PODID_EXPECT_THROW_WITH(Write(dir.File("a"), "x"), std::runtime_error,
                          "cannot write " + dir.File("a") + ": Too many levels of symbolic links");
}

TEST(SpecialTargets, ExistingFileKeepsItsMode) {
  // The temporary (0666 minus the umask) used to replace a 0600 file as 0644.
  const TempDir dir;
  for (const mode_t mode : {mode_t{0600}, mode_t{0640}, mode_t{0755}}) {
    const std::string path = dir.Write("secret.csv", "old\n");
    ASSERT_EQ(::chmod(path.c_str(), mode), 0);
    Write(path, "new\n");
    EXPECT_EQ(ReadText(path), "new\n");
    EXPECT_EQ(Mode(path), mode);
  }
}

TEST(SpecialTargets, HardLinkedFileIsReplacedAtThisNameOnly) {
  // The documented choice (io.hpp): the write is atomic, so the name written
  // gets a new file; another hard link keeps the previous content.
  const TempDir dir;
  const std::string path = dir.Write("a.csv", "old\n");
  ASSERT_EQ(::link(path.c_str(), dir.File("b.csv").c_str()), 0);
  Write(path, "new\n");
  EXPECT_EQ(ReadText(path), "new\n");
  EXPECT_EQ(ReadText(dir.File("b.csv")), "old\n");
}

TEST(SpecialTargets, ReadOnlyFileIsRefused) {
  // A file its owner made read-only is not replaced (the folder being
  // writable would let a rename do it). Root writes through permission bits,
  // so as root the write runs in a child process as nobody.
  const TempDir dir;
  const std::string path = dir.Write("locked.csv", "precious\n");
  ASSERT_EQ(::chmod(path.c_str(), 0444), 0);
  ASSERT_EQ(::chmod(dir.path().c_str(), 0777), 0);
  auto child = [&] {
    if (::geteuid() == 0 && (::setgid(65534) != 0 || ::setuid(65534) != 0)) std::_Exit(3);
    try {
      Write(path, "new\n");
    } catch (const std::runtime_error& e) {
      const std::string message = e.what();
      std::_Exit(message.find("cannot write " + path + ": the file is read-only") !=
                         std::string::npos
                     ? 0
                     : 2);
    }
    std::_Exit(1);
  };
  const testing::DeathTestTempRoot child_folders;
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(child(), ::testing::ExitedWithCode(0), "");
  EXPECT_EQ(ReadText(path), "precious\n");
  EXPECT_EQ(dir.Entries(), std::vector<std::string>{"locked.csv"});
}

TEST(SpecialTargets, NoWriteBitIsRefusedWhoeverWrites) {
  // Root passes access(W_OK) whatever the mode and replaced a 0444 file, also
  // through a symlink and in a 0555 folder: the mode bits refuse it now, for
  // every user (CI runs this as root).
  const TempDir dir;
  const std::string folder = dir.File("locked");
  ASSERT_TRUE(std::filesystem::create_directory(folder));
  const std::string path = folder + "/precious.csv";
  Write(path, "precious\n");
  ASSERT_EQ(::chmod(path.c_str(), 0444), 0);
  const std::string link = dir.File("link.csv");
  std::filesystem::create_symlink(path, link);
  for (const std::string& target : {path, link}) {
    PODID_EXPECT_THROW_WITH(Write(target, "new\n"), std::runtime_error,
                            "cannot write " + target + ": the file is read-only");
  }
  ASSERT_EQ(::chmod(folder.c_str(), 0555), 0);
  PODID_EXPECT_THROW_WITH(Write(link, "new\n"), std::runtime_error,
                          "cannot write " + link + ": the file is read-only");
  PODID_EXPECT_THROW_WITH(Write(folder + "/new.csv", "new\n"), std::runtime_error,
                          "cannot write " + folder + "/new.csv: cannot create a temporary file in");
  PODID_EXPECT_THROW_WITH(ResolveOutput(folder + "/new.csv"), std::runtime_error,
                          "cannot create a temporary file in");
  ASSERT_EQ(::chmod(folder.c_str(), 0755), 0);  // for TempDir's removal
  EXPECT_EQ(ReadText(path), "precious\n");
  EXPECT_EQ(Sorted(dir.Entries()), (std::vector<std::string>{"link.csv", "locked"}));
  std::vector<std::string> inside;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    inside.push_back(entry.path().filename().string());
  }
  EXPECT_EQ(inside, std::vector<std::string>{"precious.csv"});
}

TEST(SpecialTargets, FifoIsWrittenInPlace) {
  const TempDir dir;
  const std::string fifo = dir.File("pipe");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string received;
  std::thread reader([&] { received = ReadText(fifo); });
  const std::string text(200000, 'z');  // more than a pipe's buffer
  Write(fifo, text);
  reader.join();
  EXPECT_EQ(received, text);
  struct stat status {};
  ASSERT_EQ(::lstat(fifo.c_str(), &status), 0);
  EXPECT_TRUE(S_ISFIFO(status.st_mode));
  EXPECT_EQ(dir.Entries(), std::vector<std::string>{"pipe"});
}

// Runs `body` with descriptor 1 redirected to `file`.
template <typename Body>
void WithStdoutIn(const std::string& file, Body body) {
  std::fflush(stdout);
  const int saved = ::dup(1);
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ASSERT_GE(fd, 0);
  ::dup2(fd, 1);
  ::close(fd);
  body();
  std::fflush(stdout);
  ::dup2(saved, 1);
  ::close(saved);
}

TEST(SpecialTargets, DevStdoutIsWrittenToDescriptorOne) {
  // /dev/stdout -> /proc/self/fd/1 -> (here) a regular file: as root, the
  // rename used to replace the system's /dev/stdout link with a regular file.
  if (!IsSymlink("/dev/stdout") || !std::filesystem::is_directory("/proc/self/fd")) {
    GTEST_SKIP() << "no /dev/stdout link or /proc here";
  }
  const TempDir dir;
  const std::string file = dir.File("captured");
  for (const char* name : {"/dev/stdout", "/dev/fd/1", "/proc/self/fd/1"}) {
    WithStdoutIn(file, [&] {
      std::printf("before,");  // printed earlier on the same stream: stays first
      Write(name, "t,w1\n");
    });
    EXPECT_EQ(ReadText(file), "before,t,w1\n") << name;
    EXPECT_TRUE(IsSymlink("/dev/stdout")) << name;
    EXPECT_EQ(dir.Entries(), std::vector<std::string>{"captured"}) << name;
  }
  const OutputTarget target = ResolveOutput("/dev/stdout");
  EXPECT_EQ(target.kind, OutputTarget::Kind::kDescriptor);
  EXPECT_EQ(target.descriptor, 1);
}

TEST(SpecialTargets, ClosedDescriptorIsAClearError) {
  if (!std::filesystem::is_directory("/proc/self/fd")) GTEST_SKIP() << "no /proc here";
  const int fd = ::open("/dev/null", O_RDONLY);
  ASSERT_GE(fd, 0);
  ::close(fd);  // now a closed descriptor number
  const std::string path = "/dev/fd/" + std::to_string(fd);
  PODID_EXPECT_THROW_WITH(Write(path, "x"), std::runtime_error,
                          "cannot write " + path + ": Bad file descriptor");
}

TEST(SpecialTargets, ResolveOutputIdentifiesTheFileWritten) {
  // What the CLI compares with its inputs: the same device and inode through a
  // symlink, a hard link and a "./" spelling; a new file does not exist yet.
  const TempDir dir;
  const std::string input = dir.Write("in.csv", "t,w1\n");
  struct stat in {};
  ASSERT_EQ(::stat(input.c_str(), &in), 0);
  std::filesystem::create_symlink("in.csv", dir.File("sym.csv"));
  ASSERT_EQ(::link(input.c_str(), dir.File("hard.csv").c_str()), 0);
  for (const std::string& path :
       {input, dir.File("sym.csv"), dir.File("hard.csv"), dir.path() + "/./in.csv",
        dir.path() + "/../" + std::filesystem::path(dir.path()).filename().string() + "/in.csv"}) {
    const OutputTarget target = ResolveOutput(path);
    EXPECT_TRUE(target.exists) << path;
    EXPECT_EQ(target.kind, OutputTarget::Kind::kFile) << path;
    EXPECT_EQ(target.device, static_cast<std::uint64_t>(in.st_dev)) << path;
    EXPECT_EQ(target.inode, static_cast<std::uint64_t>(in.st_ino)) << path;
  }
  const OutputTarget fresh = ResolveOutput(dir.File("new.csv"));
  EXPECT_FALSE(fresh.exists);
  EXPECT_EQ(fresh.path, std::filesystem::canonical(dir.path()).string() + "/new.csv");
  // Nothing was written by resolving.
  EXPECT_EQ(Sorted(dir.Entries()), (std::vector<std::string>{"hard.csv", "in.csv", "sym.csv"}));
}

TEST(SpecialTargets, ResolveOutputChecksTheFolderFirst) {
  const TempDir dir;
  PODID_EXPECT_THROW_WITH(ResolveOutput(dir.File("missing/x.csv")), std::runtime_error,
                          "cannot create a temporary file in " + dir.File("missing"));
  const std::string file = dir.Write("plain", "x");
  PODID_EXPECT_THROW_WITH(ResolveOutput(file + "/x.csv"), std::runtime_error,
                          "cannot write " + file + "/x.csv");
  PODID_EXPECT_THROW_WITH(ResolveOutput(dir.path()), std::runtime_error, "it is a folder");
}

}  // namespace
}  // namespace podid
