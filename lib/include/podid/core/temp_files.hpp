#pragma once
// Temporary files that must not outlive the process, even when it is killed.
//
// WriteFileAtomically and the plots register each temporary file (and private
// folder) here while it exists. InstallTemporaryFileCleanup() installs a
// handler for the signals that end a process by default (SIGINT, SIGTERM,
// SIGHUP, SIGPIPE, SIGQUIT, SIGXFSZ) that removes every registered path (files
// first, then folders) and re-raises the signal with its default action, so
// the exit status still says which signal ended the process.
//
// The handler is async-signal-safe: the registry is a fixed array of
// kMaxTemporaryPaths slots of PATH_MAX bytes with lock-free atomic states, and
// the handler calls only unlink, rmdir, sigaction and raise. A path that does
// not fit (too many at once, or longer than PATH_MAX - 1) is not registered:
// it is still removed on every normal and error path, only not on a signal.

#include <signal.h>

#include <string>

namespace podid {

/// Paths registered at once (PODID writes at most a few files at a time).
inline constexpr int kMaxTemporaryPaths = 64;

/// Registers `path` for removal on those signals while the object
/// lives. The destructor (or Release()) unregisters it; it never removes it.
class TemporaryPath {
 public:
  enum class Kind { kFile, kFolder };
  TemporaryPath() = default;
  explicit TemporaryPath(const std::string& path, Kind kind = Kind::kFile);
  TemporaryPath(TemporaryPath&& other) noexcept;
  TemporaryPath& operator=(TemporaryPath&& other) noexcept;
  TemporaryPath(const TemporaryPath&) = delete;
  TemporaryPath& operator=(const TemporaryPath&) = delete;
  ~TemporaryPath();

  /// Unregisters now (the file was renamed away or removed).
  void Release();
  /// False when the registry was full or the path too long.
  bool registered() const { return slot_ >= 0; }

 private:
  int slot_ = -1;
};

/// Blocks those signals in the calling thread while it lives,
/// so that creating a file and registering it happen as one step.
class BlockCleanupSignals {
 public:
  BlockCleanupSignals();
  ~BlockCleanupSignals();
  BlockCleanupSignals(const BlockCleanupSignals&) = delete;
  BlockCleanupSignals& operator=(const BlockCleanupSignals&) = delete;

 private:
  sigset_t previous_;
};

/// Installs the cleanup handler for those signals, each only if its
/// disposition is still the default (an ignored SIGHUP under nohup, or an
/// ignored SIGPIPE or SIGXFSZ, stays ignored: write() then fails with an error
/// that is reported and cleaned up as usual). Idempotent. A program that later installs its own
/// handler for one of them should restore the previous one afterwards.
void InstallTemporaryFileCleanup();

/// Removes every registered path now (what the signal handler does).
/// Async-signal-safe.
void RemoveRegisteredTemporaries() noexcept;

}  // namespace podid
