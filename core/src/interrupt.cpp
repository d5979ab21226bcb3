// The table of pending temporary files and the SIGINT/SIGTERM handlers that remove them (interrupt.hpp).
#include "millnet/core/interrupt.hpp"

#include <atomic>
#include <csignal>
#include <cstring>
#include <mutex>
#include <unistd.h>

namespace millnet {

namespace {

// 1024 slots of 1 KiB: a command's OutputSet holds its temporaries until it commits them all.
constexpr int kSlots = 1024;
constexpr std::size_t kPathMax = 1024;

// state: 0 free, 1 being filled or emptied (the handler skips it), 2 holds a path to unlink.
struct Slot {
  std::atomic<int> state{0};
  char path[kPathMax];
};
Slot g_slots[kSlots];
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler reads the slot states");

// DeferInterrupts: how many are alive, and the signal held back (0: none). The handler notes the
// signal before it looks at the depth, and the last DeferInterrupts clears the depth before it
// takes the note, so a signal is never lost between them (at worst both act on it).
std::atomic<int> g_defer_depth{0};
std::atomic<int> g_deferred{0};
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler reads the deferral state");

void remove_temporaries_and_raise(int sig) {
  for (Slot& s : g_slots)
    if (s.state.load(std::memory_order_acquire) == 2) ::unlink(s.path);
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

extern "C" void on_interrupt(int sig) {
  g_deferred.store(sig);
  if (g_defer_depth.load() > 0) return;
  remove_temporaries_and_raise(sig);
}

void install_handlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    struct sigaction sa {};
    sa.sa_handler = on_interrupt;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = 0;
    for (int sig : {SIGINT, SIGTERM}) {
      struct sigaction old {};
      // A signal the parent set to be ignored (nohup, a background job) stays ignored.
      if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
      ::sigaction(sig, &sa, nullptr);
    }
    // A file-size limit: the write fails with EFBIG and the writer reports it (see interrupt.hpp).
    std::signal(SIGXFSZ, SIG_IGN);
  });
}

}  // namespace

int register_temp_file(const std::filesystem::path& tmp) {
  install_handlers();
  const std::string& p = tmp.native();
  if (p.size() + 1 > kPathMax) return -1;
  for (int pass = 0; pass < 2; ++pass) {
    for (int i = 0; i < kSlots; ++i) {
      int expected = 0;
      if (g_slots[i].state.compare_exchange_strong(expected, 1, std::memory_order_acq_rel)) {
        std::memcpy(g_slots[i].path, p.c_str(), p.size() + 1);
        g_slots[i].state.store(2, std::memory_order_release);
        return i;
      }
    }
    // Full: reclaim the slots whose temporary is gone (renamed into place by an OutputSet, which
    // does not hold the slot), then try once more.
    for (Slot& s : g_slots) {
      int expected = 2;
      if (s.state.compare_exchange_strong(expected, 1, std::memory_order_acq_rel))
        s.state.store(::access(s.path, F_OK) == 0 ? 2 : 0, std::memory_order_release);
    }
  }
  return -1;
}

void unregister_temp_file(int slot) {
  if (slot < 0 || slot >= kSlots) return;
  g_slots[slot].state.store(0, std::memory_order_release);
}

DeferInterrupts::DeferInterrupts() {
  install_handlers();
  g_defer_depth.fetch_add(1);
}

DeferInterrupts::~DeferInterrupts() {
  if (g_defer_depth.fetch_sub(1) != 1) return;
  if (const int sig = g_deferred.exchange(0); sig != 0) remove_temporaries_and_raise(sig);
}

}  // namespace millnet
