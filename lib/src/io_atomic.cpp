// WriteFileAtomically: symlinks followed to the real target; a temporary file in
// the target's folder, fsync, rename; devices and descriptors written in place.
#include <fcntl.h>
#include <limits.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <ostream>
#include <stdexcept>
#include <streambuf>
#include <string>
#include <vector>

#include "podid/core/error.hpp"
#include "podid/core/io.hpp"
#include "podid/core/temp_files.hpp"

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

/// Symlinks followed before giving up (Linux's own limit is 40).
constexpr int kMaxSymlinkHops = 40;
/// Bytes of the target's name kept in a temporary's name (NAME_MAX is 255).
constexpr std::size_t kTempNameBytes = 100;
/// Names tried for a temporary or a second name before giving up.
constexpr int kNameAttempts = 100;

/// A fresh hidden name beside `target`: .<name>.<tag>-<pid>-<n>.
std::string HiddenSibling(const std::filesystem::path& target, const char* tag) {
  const std::string name = target.filename().string().substr(0, kTempNameBytes);
  return (target.parent_path() / ("." + name + "." + tag + "-" + std::to_string(::getpid()) + "-" +
                                  std::to_string(temp_counter.fetch_add(1))))
      .string();
}

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

/// Writes to an open descriptor that is closed afterwards.
void WriteToDescriptor(int fd,
                       const std::string& path,
                       const std::function<void(std::ostream&)>& write) {
  WriteThrough(fd, path, write, [fd] { ::close(fd); });
  if (::close(fd) != 0) Fail(path, std::string("close failed: ") + std::strerror(errno));
}

/// realpath(3), or "" with errno set.
std::string RealPath(const std::string& path) {
  char buffer[PATH_MAX];
  return ::realpath(path.c_str(), buffer) != nullptr ? std::string(buffer) : std::string();
}

bool IsDescriptorNumber(const std::string& name) {
  if (name.empty() || name.size() > 9) return false;
  for (const char c : name) {
    if (c < '0' || c > '9') return false;
  }
  return true;
}

/// No write bit for anyone: someone made it read-only. access() alone does not
/// see it for root (CAP_DAC_OVERRIDE writes through any mode), who would
/// otherwise replace a 0444 file or write into a 0555 folder.
bool NoWriteBit(mode_t mode) { return (mode & (S_IWUSR | S_IWGRP | S_IWOTH)) == 0; }

std::string ModeText(mode_t mode) {
  char text[8];
  std::snprintf(text, sizeof text, "%04o", static_cast<unsigned>(mode & 07777));
  return text;
}

/// Fails unless `folder` (the resolved folder of `path`) takes new files.
void CheckFolderWritable(const std::string& path, const std::string& folder) {
  const std::string why = FolderNotWritable(folder);
  if (!why.empty()) Fail(path, "cannot create a temporary file in " + folder + ": " + why);
}

}  // namespace

std::string FolderNotWritable(const std::string& folder) {
  if (::faccessat(AT_FDCWD, folder.c_str(), W_OK | X_OK, AT_EACCESS) != 0) {
    return std::strerror(errno);
  }
  struct stat status {};
  if (::stat(folder.c_str(), &status) == 0 && NoWriteBit(status.st_mode)) {
    return "the folder is read-only (mode " + ModeText(status.st_mode) + ")";
  }
  return "";
}

OutputTarget ResolveOutput(const std::string& path) {
  namespace fs = std::filesystem;
  if (path.empty() || !fs::path(path).has_filename()) {
    ThrowInvalid("output file", "a file name", "\"" + path + "\"");
  }
  // Our own descriptors: /dev/stdout -> /proc/self/fd/1 -> /proc/<pid>/fd/1.
  const std::string own_descriptors = RealPath("/proc/self/fd");
  OutputTarget target;
  std::string current = path;
  for (int hop = 0; hop <= kMaxSymlinkHops; ++hop) {
    const fs::path spelled(current);
    const std::string folder_spelled =
        spelled.has_parent_path() ? spelled.parent_path().string() : std::string(".");
    const std::string folder = RealPath(folder_spelled);
    if (folder.empty()) {
      Fail(path,
           "cannot create a temporary file in " + folder_spelled + ": " + std::strerror(errno));
    }
    struct stat status {};
    if (::stat(folder.c_str(), &status) != 0 || !S_ISDIR(status.st_mode)) {
      Fail(path,
           "cannot create a temporary file in " + folder_spelled + ": " + std::strerror(ENOTDIR));
    }
    const std::string name = spelled.filename().string();
    if (name.empty() || name == "." || name == "..") Fail(path, "it is a folder");
    const std::string joined = folder == "/" ? "/" + name : folder + "/" + name;

    if (!own_descriptors.empty() && folder == own_descriptors && IsDescriptorNumber(name)) {
      target.kind = OutputTarget::Kind::kDescriptor;
      target.path = joined;
      target.descriptor = std::stoi(name);
      if (::fstat(target.descriptor, &status) != 0) Fail(path, std::strerror(errno));
      target.exists = true;
      target.device = status.st_dev;
      target.inode = status.st_ino;
      return target;
    }
    if (::lstat(joined.c_str(), &status) != 0) {
      if (errno != ENOENT) Fail(path, std::strerror(errno));
      target.path = joined;  // a new file (perhaps at the end of a dangling link)
      CheckFolderWritable(path, folder);
      return target;
    }
    if (S_ISLNK(status.st_mode)) {
      std::vector<char> link(static_cast<std::size_t>(PATH_MAX) + 1);
      const ssize_t size = ::readlink(joined.c_str(), link.data(), link.size() - 1);
      if (size < 0) Fail(path, std::string("readlink failed: ") + std::strerror(errno));
      const std::string destination(link.data(), static_cast<std::size_t>(size));
      if (destination.empty()) Fail(path, "an empty symbolic link");
      current = destination.front() == '/' ? destination : folder + "/" + destination;
      continue;
    }
    if (S_ISDIR(status.st_mode)) Fail(path, "it is a folder");
    target.path = joined;
    target.exists = true;
    target.device = status.st_dev;
    target.inode = status.st_ino;
    if (S_ISREG(status.st_mode)) {
      // The file before its folder: "read-only file" says more than the folder's error.
      if (::faccessat(AT_FDCWD, joined.c_str(), W_OK, AT_EACCESS) != 0) {
        Fail(path, "the file is read-only (" + std::string(std::strerror(errno)) + ")");
      }
      if (NoWriteBit(status.st_mode)) {
        Fail(path, "the file is read-only (mode " + ModeText(status.st_mode) + ")");
      }
      CheckFolderWritable(path, folder);
    } else {
      target.kind = OutputTarget::Kind::kSpecial;
      if (::faccessat(AT_FDCWD, joined.c_str(), W_OK, AT_EACCESS) != 0) {
        Fail(path, std::strerror(errno));
      }
    }
    return target;
  }
  Fail(path, std::strerror(ELOOP));
}

struct OutputBatch::Staged {
  std::string path;    // as the caller spelled it (messages)
  std::string target;  // the resolved file the temporary replaces
  std::string temp;
  TemporaryPath registration;
};

namespace {

/// Makes the renames in `folder` durable (best effort: not every file system
/// allows it).
void SyncFolder(const std::string& folder) {
  const int dir = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    (void)::fsync(dir);
    ::close(dir);
  }
}

std::string FolderOf(const std::string& file) {
  return std::filesystem::path(file).parent_path().string();
}

/// Renames a complete temporary onto its target and syncs the folder; on
/// failure the temporary is removed and the error names the file.
void Publish(OutputBatch::Staged& staged) {
  if (::rename(staged.temp.c_str(), staged.target.c_str()) != 0) {
    const int error = errno;
    ::unlink(staged.temp.c_str());
    staged.registration.Release();
    Fail(staged.path, std::string("rename failed: ") + std::strerror(error));
  }
  staged.registration.Release();
  SyncFolder(FolderOf(staged.target));
}

/// How Commit puts a published file back when a later rename fails: the
/// replaced file under a second name (a hard link made before the rename),
/// or nothing to restore for a target that did not exist.
struct Undo {
  enum class Kind { kNew, kLinked, kUnrecoverable };
  Kind kind = Kind::kNew;
  std::string backup;
  TemporaryPath registration;  // a kill leaves no stray second name
};

/// A hard link to `target` beside it, or why there is none. A link, not a
/// copy: instant and atomic whatever the file's size, and renaming it back
/// restores the very file (mode, owner, other names) the rename replaced.
Undo LinkBeside(const std::string& target) {
  Undo undo;
  for (int attempt = 0; attempt < kNameAttempts; ++attempt) {
    const std::string backup = HiddenSibling(target, "old");
    const BlockCleanupSignals blocked;  // link and register as one step
    if (::link(target.c_str(), backup.c_str()) == 0) {
      undo.kind = Undo::Kind::kLinked;
      undo.backup = backup;
      undo.registration = TemporaryPath(backup);
      return undo;
    }
    if (errno == ENOENT) return undo;  // nothing there to replace
    if (errno != EEXIST) break;
  }
  // A file system without hard links (EPERM), a file at its link limit: this
  // file alone cannot be put back, as with a single rename.
  undo.kind = Undo::Kind::kUnrecoverable;
  return undo;
}

/// Drops the second name of a replaced file that stays replaced.
void Forget(Undo& undo) {
  if (!undo.backup.empty()) ::unlink(undo.backup.c_str());
  undo.backup.clear();
  undo.registration.Release();
}

}  // namespace

void WriteFileAtomically(const std::string& path,
                         const std::function<void(std::ostream&)>& write,
                         OutputBatch* batch) {
  namespace fs = std::filesystem;
  if (batch != nullptr && batch->committed_) {
    throw std::logic_error("WriteFileAtomically(" + path + "): the batch was already committed");
  }
  const OutputTarget target = ResolveOutput(path);
  if (target.kind == OutputTarget::Kind::kDescriptor) {
    // Keep the order of what was printed before on the same stream.
    std::fflush(nullptr);
    const int fd = ::fcntl(target.descriptor, F_DUPFD_CLOEXEC, 0);
    if (fd < 0) Fail(path, std::strerror(errno));
    WriteToDescriptor(fd, path, write);
    return;
  }
  if (target.kind == OutputTarget::Kind::kSpecial) {
    // Renaming a temporary onto a device would replace the node with a
    // regular file (as root, /dev/null itself for everyone).
    const int fd = ::open(target.path.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0) Fail(path, std::strerror(errno));
    WriteToDescriptor(fd, path, write);
    return;
  }

  // The temporary: in the target's own folder, so that rename() is atomic.
  auto staged = std::make_unique<OutputBatch::Staged>();
  staged->path = path;
  staged->target = target.path;
  const fs::path final_path(target.path);
  const std::string folder = final_path.parent_path().string();
  int fd = -1;
  for (int attempt = 0; attempt < kNameAttempts && fd < 0; ++attempt) {
    staged->temp = HiddenSibling(final_path, "tmp");
    const BlockCleanupSignals blocked;  // create and register as one step
    fd = ::open(staged->temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd < 0 && errno != EEXIST) {
      Fail(path, "cannot create a temporary file in " + folder + ": " + std::strerror(errno));
    }
    if (fd >= 0) staged->registration = TemporaryPath(staged->temp);
  }
  if (fd < 0) Fail(path, "cannot create a temporary file in " + folder);

  auto discard = [&]() {
    if (fd >= 0) ::close(fd);
    fd = -1;
    ::unlink(staged->temp.c_str());
    staged->registration.Release();
  };

  if (target.exists) {
    // Keep the replaced file's mode (and owner, which only root can give).
    struct stat old {};
    if (::stat(target.path.c_str(), &old) == 0) {
      if (::geteuid() == 0 && (old.st_uid != ::geteuid() || old.st_gid != ::getegid())) {
        (void)::fchown(fd, old.st_uid, old.st_gid);
      }
      if (::fchmod(fd, old.st_mode & 0777) != 0) {
        const int error = errno;
        discard();
        Fail(path, std::string("cannot keep the file's mode: ") + std::strerror(error));
      }
    }
  }

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
  if (batch != nullptr) {
    batch->files_.push_back(std::move(staged));
  } else {
    Publish(*staged);
  }
}

OutputBatch::OutputBatch() = default;

OutputBatch::~OutputBatch() {
  if (committed_) return;
  for (const std::unique_ptr<Staged>& file : files_) {
    if (file) ::unlink(file->temp.c_str());  // the registration goes with it
  }
  // Deepest first; rmdir leaves a folder that holds anything else.
  for (auto folder = created_folders_.rbegin(); folder != created_folders_.rend(); ++folder) {
    ::rmdir(folder->c_str());
  }
}

void OutputBatch::CreateFolders(const std::string& folder) {
  namespace fs = std::filesystem;
  // The missing ancestors, nearest the root first, then create_directories.
  std::vector<std::string> missing;
  std::error_code error;
  fs::path start = fs::absolute(folder, error).lexically_normal();
  if (!start.has_filename()) start = start.parent_path();  // "figs/"
  for (fs::path p = start; !error && !p.empty(); p = p.parent_path()) {
    // libstdc++ reports "not found" both as the type and as the error.
    if (fs::symlink_status(p, error).type() != fs::file_type::not_found) break;
    error.clear();
    missing.push_back(p.string());
    if (p == p.parent_path()) break;
  }
  fs::create_directories(folder);  // throws filesystem_error naming the folder
  created_folders_.insert(created_folders_.end(), missing.rbegin(), missing.rend());
}

void OutputBatch::AdoptFolder(const std::string& folder) { created_folders_.push_back(folder); }

void OutputBatch::Commit() {
  if (committed_) throw std::logic_error("OutputBatch::Commit: already committed");
  // A second name for each file about to be replaced, so that a rename failing
  // midway can put the files before it back: all or nothing, not only up to
  // the last rename.
  std::vector<Undo> undo;
  undo.reserve(files_.size());
  for (const std::unique_ptr<Staged>& file : files_) {
    undo.push_back(file ? LinkBeside(file->target) : Undo{});
  }
  std::size_t done = 0;
  try {
    for (; done < files_.size(); ++done) {
      if (files_[done]) Publish(*files_[done]);  // on failure its temporary is gone
    }
  } catch (const std::runtime_error& e) {
    std::string lost;
    for (std::size_t i = 0; i < done; ++i) {  // the published ones, back as they were
      if (!files_[i]) continue;
      const Staged& file = *files_[i];
      const bool back =
          undo[i].kind == Undo::Kind::kLinked
              ? ::rename(undo[i].backup.c_str(), file.target.c_str()) == 0
              : undo[i].kind == Undo::Kind::kNew && ::unlink(file.target.c_str()) == 0;
      if (back) {
        undo[i].backup.clear();  // renamed back: that name is gone
        SyncFolder(FolderOf(file.target));
      } else {
        lost += (lost.empty() ? "" : ", ") + file.path;
      }
    }
    for (Undo& u : undo) Forget(u);
    // The published ones and the failed one have no temporary left; the rest
    // stay staged, and the destructor removes them.
    for (std::size_t i = 0; i <= done; ++i) files_[i].reset();
    throw std::runtime_error(std::string(e.what()) +
                             (lost.empty()
                                  ? "; the batch's other files were left as they were"
                                  : "; these were replaced and could not be put back: " + lost));
  }
  for (Undo& u : undo) Forget(u);
  files_.clear();
  committed_ = true;
}

std::size_t OutputBatch::staged() const {
  std::size_t count = 0;
  for (const std::unique_ptr<Staged>& file : files_) count += file ? 1 : 0;
  return count;
}

}  // namespace podid
