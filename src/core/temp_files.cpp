#include "core/temp_files.h"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <system_error>
#include <utility>

namespace nsf {

namespace {

// A fixed table the signal handler can read without allocating or locking: a slot's path is
// only read while its state is kLive, and only written while the registering thread holds it
// in kBusy. A path longer than kMaxPath, or a 65th file at once, goes untracked.
constexpr int kSlots = 64;
constexpr size_t kMaxPath = 4096;
enum : int { kFree = 0, kBusy = 1, kLive = 2 };

struct Slot {
  std::atomic<int> state{kFree};
  char path[kMaxPath];
};
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler needs lock-free atomics");

Slot g_slots[kSlots];

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};

extern "C" void remove_temp_files_and_die(int sig) {
  const int saved = errno;
  for (Slot& s : g_slots)
    if (s.state.load() == kLive) ::unlink(s.path);
  // SA_RESETHAND already restored the default action; the signal is blocked until this handler
  // returns, then delivered again and ends the process as it would have.
  ::raise(sig);
  errno = saved;
}

void install_handlers() {
  for (int sig : kSignals) {
    struct sigaction old {};
    if (::sigaction(sig, nullptr, &old) != 0 || (old.sa_flags & SA_SIGINFO) != 0 ||
        old.sa_handler != SIG_DFL)
      continue;
    struct sigaction sa {};
    sa.sa_handler = remove_temp_files_and_die;
    sigemptyset(&sa.sa_mask);
    for (int other : kSignals) sigaddset(&sa.sa_mask, other);
    sa.sa_flags = SA_RESETHAND;
    ::sigaction(sig, &sa, nullptr);
  }
}

}  // namespace

TempFileRegistration::TempFileRegistration(const std::string& path) {
  static std::once_flag installed;
  std::call_once(installed, install_handlers);
  std::error_code ec;
  const std::string full = std::filesystem::absolute(path, ec).string();
  if (ec || full.size() >= kMaxPath) return;
  for (int i = 0; i < kSlots; ++i) {
    int expected = kFree;
    if (!g_slots[i].state.compare_exchange_strong(expected, kBusy)) continue;
    std::memcpy(g_slots[i].path, full.c_str(), full.size() + 1);
    g_slots[i].state.store(kLive);
    slot_ = i;
    return;
  }
}

TempFileRegistration::TempFileRegistration(TempFileRegistration&& o) noexcept
    : slot_(std::exchange(o.slot_, -1)) {}

TempFileRegistration& TempFileRegistration::operator=(TempFileRegistration&& o) noexcept {
  if (this != &o) {
    release();
    slot_ = std::exchange(o.slot_, -1);
  }
  return *this;
}

void TempFileRegistration::release() {
  if (slot_ < 0) return;
  g_slots[slot_].state.store(kFree);
  slot_ = -1;
}

int registered_temp_files() {
  int n = 0;
  for (const Slot& s : g_slots) n += s.state.load() == kLive;
  return n;
}

}  // namespace nsf
