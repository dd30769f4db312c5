#pragma once
// Ctrl-C and termination requests for every command. The first SIGINT or SIGTERM sets a flag that
// every wait on the device checks (the executor's frame wait), so a command ends promptly even
// while the device runs a shader that never ends; a second one ends the process at once.
namespace caustica {

void install_interrupt_handlers();
// The signal that arrived, or 0.
int interrupt_signal();
// Throws Interrupted (core/error.h) if a signal arrived.
void throw_if_interrupted();

}  // namespace caustica
