#include "core/interrupt.h"

#include <unistd.h>

#include <atomic>
#include <csignal>

#include "core/error.h"

namespace caustica {
namespace {

std::atomic<int> g_signal{0};

void on_interrupt(int signal) {
  if (g_signal.exchange(signal) != 0) _exit(128 + signal);  // asked twice: whatever is stuck, end now
}

}  // namespace

void install_interrupt_handlers() {
  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
}

int interrupt_signal() {
  return g_signal.load();
}

void throw_if_interrupted() {
  if (const int signal = g_signal.load(); signal != 0) throw Interrupted(signal);
}

}  // namespace caustica
