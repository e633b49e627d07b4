#include "rove/core/interrupt.h"

#include <atomic>
#include <csignal>

namespace rove {
namespace {

std::atomic<bool> g_interrupted{false};
std::atomic<bool> g_installed{false};

extern "C" void on_signal(int sig) {
  if (g_interrupted.exchange(true)) {
    // Second signal: the user insists; end now with the default action.
    std::signal(sig, SIG_DFL);
    std::raise(sig);
  }
}

}  // namespace

Interrupted::Interrupted() : Error("interrupted by Ctrl-C (SIGINT); stopped cleanly") {}

void install_interrupt_handler() {
  if (g_installed.exchange(true)) return;
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;
  sigaction(SIGINT, &sa, nullptr);
}

bool interrupted() noexcept { return g_interrupted.load(std::memory_order_relaxed); }

void throw_if_interrupted() {
  if (interrupted()) throw Interrupted();
}

void reset_interrupted() noexcept { g_interrupted.store(false); }

}  // namespace rove
