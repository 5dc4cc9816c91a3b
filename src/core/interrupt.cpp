#include "core/interrupt.hpp"

#include <atomic>
#include <csignal>
#include <initializer_list>

#include <unistd.h>

namespace rbpart {

namespace {

// Fixed slots of plain pointers: a signal handler may neither lock nor allocate, only load atomics
// and call async-signal-safe functions such as unlink(2).
constexpr int kSlots = 64;
std::atomic<const char*> temp_files[kSlots];
std::atomic<bool> deferred{false};
volatile std::sig_atomic_t noted = 0;

void on_signal(int signal) {
  if (deferred.load() && noted == 0) {
    noted = signal;
    return;
  }
  for (auto& slot : temp_files)
    if (const char* path = slot.load()) ::unlink(path);
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

}  // namespace

void install_interrupt_handlers() {
  struct sigaction action {};
  action.sa_handler = on_signal;
  sigemptyset(&action.sa_mask);
  for (int signal : {SIGINT, SIGTERM}) ::sigaction(signal, &action, nullptr);
}

void defer_interrupts(bool defer) { deferred.store(defer); }

int interrupt_signal() { return noted; }

const char* signal_name(int signal) { return signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "a signal"; }

int register_temp_file(const char* path) {
  for (int i = 0; i < kSlots; ++i) {
    const char* empty = nullptr;
    if (temp_files[i].compare_exchange_strong(empty, path)) return i;
  }
  return -1;
}

void unregister_temp_file(int slot) {
  if (slot >= 0) temp_files[slot].store(nullptr);
}

}  // namespace rbpart
