// The registry of temporary paths removed on SIGINT/SIGTERM/SIGHUP.
#include "podid/core/temp_files.hpp"

#include <limits.h>
#include <pthread.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>

namespace podid {
namespace {

// Slot states. A registration claims a free slot (kFree -> kClaimed), copies
// the path, then publishes it (kClaimed -> kFile/kFolder); the handler only
// reads published slots.
enum : int { kFree = 0, kClaimed = 1, kFile = 2, kFolder = 3 };

struct Slot {
  std::atomic<int> state{kFree};
  char path[PATH_MAX];
};
static_assert(std::atomic<int>::is_always_lock_free, "the handler needs lock-free atomics");

Slot g_slots[kMaxTemporaryPaths];

// The termination signals: the three the user sends, a closed pipe
// (`podid ... -o /dev/stdout | head`), SIGQUIT and a file size limit.
constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGPIPE, SIGQUIT, SIGXFSZ};

extern "C" void RemoveAndReraise(int signal_number) {
  RemoveRegisteredTemporaries();
  struct sigaction default_action {};
  default_action.sa_handler = SIG_DFL;
  sigemptyset(&default_action.sa_mask);
  ::sigaction(signal_number, &default_action, nullptr);
  // Blocked while this handler runs: delivered, with the default action
  // (termination), as soon as it returns.
  ::raise(signal_number);
}

}  // namespace

TemporaryPath::TemporaryPath(const std::string& path, Kind kind) {
  if (path.empty() || path.size() >= PATH_MAX) return;
  for (int i = 0; i < kMaxTemporaryPaths; ++i) {
    int expected = kFree;
    if (!g_slots[i].state.compare_exchange_strong(expected, kClaimed)) continue;
    std::memcpy(g_slots[i].path, path.c_str(), path.size() + 1);
    g_slots[i].state.store(kind == Kind::kFolder ? kFolder : kFile);
    slot_ = i;
    return;
  }
}

TemporaryPath::TemporaryPath(TemporaryPath&& other) noexcept : slot_(other.slot_) {
  other.slot_ = -1;
}

TemporaryPath& TemporaryPath::operator=(TemporaryPath&& other) noexcept {
  if (this != &other) {
    Release();
    slot_ = other.slot_;
    other.slot_ = -1;
  }
  return *this;
}

TemporaryPath::~TemporaryPath() { Release(); }

void TemporaryPath::Release() {
  if (slot_ >= 0) g_slots[slot_].state.store(kFree);
  slot_ = -1;
}

BlockCleanupSignals::BlockCleanupSignals() {
  sigset_t block;
  sigemptyset(&block);
  for (const int signal_number : kSignals) sigaddset(&block, signal_number);
  ::pthread_sigmask(SIG_BLOCK, &block, &previous_);
}

BlockCleanupSignals::~BlockCleanupSignals() { ::pthread_sigmask(SIG_SETMASK, &previous_, nullptr); }

void RemoveRegisteredTemporaries() noexcept {
  const int saved_errno = errno;
  for (Slot& slot : g_slots) {
    if (slot.state.load() == kFile) ::unlink(slot.path);
  }
  for (Slot& slot : g_slots) {
    if (slot.state.load() == kFolder) ::rmdir(slot.path);
  }
  errno = saved_errno;
}

void InstallTemporaryFileCleanup() {
  for (const int signal_number : kSignals) {
    struct sigaction current {};
    if (::sigaction(signal_number, nullptr, &current) != 0) continue;
    if (current.sa_handler != SIG_DFL || (current.sa_flags & SA_SIGINFO) != 0) continue;
    struct sigaction action {};
    action.sa_handler = RemoveAndReraise;
    sigemptyset(&action.sa_mask);
    for (const int other : kSignals) sigaddset(&action.sa_mask, other);
    action.sa_flags = SA_RESTART;
    ::sigaction(signal_number, &action, nullptr);
  }
}

}  // namespace podid
