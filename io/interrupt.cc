#include "io/interrupt.h"

#include <unistd.h>

#include <atomic>
#include <cstring>

namespace surfreg {
namespace {

volatile std::sig_atomic_t g_signal = 0;

// The registry is a fixed array so that the handler can read it: no
// allocation, no lock; a slot's state is a lock-free atomic (free, being
// filled, live), and its path is complete before it turns live.
constexpr int kSlots = 64;
constexpr std::size_t kPathBytes = 4096;
enum SlotState : int { kFree = 0, kFilling = 1, kLive = 2 };
struct Slot {
  std::atomic<int> state{kFree};
  char path[kPathBytes];
};
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler reads slot states");
Slot g_slots[kSlots];

void UnlinkLive() {  // async-signal-safe: atomics and unlink(2) only
  for (Slot& slot : g_slots) {
    if (slot.state.load() == kLive) ::unlink(slot.path);
  }
}

extern "C" void OnSignal(int signal) {
  if (g_signal == 0) {
    g_signal = signal;
    return;
  }
  // The user insists: a stage that does not check would keep them waiting.
  UnlinkLive();
  static const char kMessage[] = "surfreg: interrupted\n";
  const ssize_t ignored = ::write(2, kMessage, sizeof(kMessage) - 1);
  (void)ignored;
  ::_exit(128 + signal);
}

}  // namespace

void InstallInterruptHandlers() {
  struct sigaction action;
  std::memset(&action, 0, sizeof(action));
  action.sa_handler = OnSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;  // reads and writes go on; the loops check the flag
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  // Past a file-size limit (ulimit -f) a write then fails with EFBIG, which
  // the writers report naming the file, instead of the process being killed
  // with its temporary file left behind.
  std::signal(SIGXFSZ, SIG_IGN);
}

void ThrowIfInterrupted() {
  const int signal = g_signal;
  if (signal != 0) throw Interrupted(signal);
}

int InterruptExitCode(int signal) { return 128 + signal; }

int RegisterTemporary(const std::string& path) {
  if (path.size() >= kPathBytes) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = kFree;
    if (!g_slots[i].state.compare_exchange_strong(expected, kFilling)) continue;
    std::memcpy(g_slots[i].path, path.c_str(), path.size() + 1);
    g_slots[i].state.store(kLive);
    return i;
  }
  return -1;
}

void UnregisterTemporary(int slot) {
  if (slot >= 0 && slot < kSlots) g_slots[slot].state.store(kFree);
}

void RemoveTemporaries() {
  UnlinkLive();
  for (Slot& slot : g_slots) {
    int expected = kLive;
    slot.state.compare_exchange_strong(expected, kFree);
  }
}

}  // namespace surfreg
