#pragma once
/// \file
/// Stopping cleanly on Ctrl-C. The command line installs the handler once;
/// long-running loops (SLAM over a log, graph iterations, rawlog copies) call
/// `throw_if_interrupted()` between steps, so a first SIGINT unwinds normally:
/// temporary outputs are removed, complete outputs are kept, and the command
/// says what was written. A second SIGINT ends the process at once.
/// A library user who installs no handler is never interrupted. SIGTERM keeps
/// its default action: a process told to terminate ends at once.

#include "rove/core/error.h"

namespace rove {

/// Thrown by throw_if_interrupted() after SIGINT.
class Interrupted : public Error {
 public:
  Interrupted();
};

/// Installs the SIGINT handler (idempotent). The first signal sets the flag
/// read by interrupted(); the second restores the default action and re-raises
/// it.
void install_interrupt_handler();

/// True once SIGINT has been received after install_interrupt_handler().
bool interrupted() noexcept;

/// Throws rove::Interrupted when interrupted().
void throw_if_interrupted();

/// Clears the flag (tests).
void reset_interrupted() noexcept;

}  // namespace rove
