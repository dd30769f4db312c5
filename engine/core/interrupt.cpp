#include "core/interrupt.h"

#include <unistd.h>

#include <atomic>
#include <csignal>

#include "core/error.h"

namespace caustica {
namespace {

std::atomic<int> g_signal{0};
std::atomic<int> g_polling{0};

void on_interrupt(int signal) {
  // Nobody to see it, or asked twice (whatever is stuck): end now.
  if (g_polling.load() == 0 || g_signal.exchange(signal) != 0) _exit(128 + signal);
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

InterruptPolling::InterruptPolling() {
  ++g_polling;
}
InterruptPolling::~InterruptPolling() {
  --g_polling;
}

}  // namespace caustica
