#pragma once
// Ctrl-C and termination requests for every command. Where something checks for them (an
// InterruptPolling lives: the executor's wait for a frame, the viewer's loop), the first SIGINT or
// SIGTERM sets a flag it sees, so it ends promptly and cleanly even while the device runs a shader
// that never ends; where nothing checks (a CPU reference, recording a frame), and on a second
// signal, the process ends at once with 128 + the signal (outputs are written to a temporary name
// and renamed, so none is left half-written).
namespace caustica {

void install_interrupt_handlers();
// The signal that arrived, or 0.
int interrupt_signal();
// Throws Interrupted (core/error.h) if a signal arrived.
void throw_if_interrupted();

// While one lives, a signal is left to the code that polls interrupt_signal().
class InterruptPolling {
 public:
  InterruptPolling();
  ~InterruptPolling();
  InterruptPolling(const InterruptPolling&) = delete;
  InterruptPolling& operator=(const InterruptPolling&) = delete;
};

}  // namespace caustica
