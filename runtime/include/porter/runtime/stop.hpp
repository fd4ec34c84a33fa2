#pragma once
// Clean shutdown on SIGINT and SIGTERM.
//
//   porter::runtime::install_stop_handlers();
//   while (!porter::runtime::stop_requested()) { ... poll({bus_fd, stop_fd()}, ...) ... }
//
// The handler only sets a flag and writes to a pipe, so it is async-signal-safe; stop_fd()
// becomes readable when a stop was requested, so a loop blocked in poll() wakes at once.
// A second signal while stopping restores the default action (a stuck process can still be
// killed with a second Ctrl-C).
//
// Thread-safety: stop_requested() and stop_fd() may be called from any thread.

namespace porter::runtime {

/// Installs the handlers (idempotent). Returns false when the pipe or sigaction failed.
bool install_stop_handlers();

/// True once SIGINT/SIGTERM arrived or request_stop() was called.
bool stop_requested();

/// Requests a stop from inside the process (e.g. a fatal error in a worker thread).
void request_stop();

/// Read end of the wake-up pipe; readable once a stop was requested. -1 before
/// install_stop_handlers().
int stop_fd();

}  // namespace porter::runtime
