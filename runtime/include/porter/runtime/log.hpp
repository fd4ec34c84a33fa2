#pragma once
// Process logging: one line per event on stderr, prefixed with the wall-clock time (UTC, ms),
// the process name and the level:
//
//   2026-12-02T08:01:02.345Z porter-base INFO command mode entered (base reported standby)
//
// Only processes log (libraries return statuses and never print). A launch script redirects
// stderr into the run folder; systemd sends it to the journal.
//
// Thread-safety: every function may be called from any thread; a line is written whole.

#include <string>
#include <string_view>

namespace porter::runtime {

enum class LogLevel { debug, info, warn, error };

/// Sets the name printed on every line (call once at the top of main) and the lowest level
/// written (default info; PORTER_LOG_LEVEL=debug|info|warn|error overrides it).
void init_log(std::string_view process_name, LogLevel min_level = LogLevel::info);

/// The name given to init_log ("porter" before it is called).
std::string process_name();

void log(LogLevel level, std::string_view message);
inline void log_debug(std::string_view m) { log(LogLevel::debug, m); }
inline void log_info(std::string_view m) { log(LogLevel::info, m); }
inline void log_warn(std::string_view m) { log(LogLevel::warn, m); }
inline void log_error(std::string_view m) { log(LogLevel::error, m); }

/// "12.3 ms"-style formatting helpers for log lines.
std::string format_ms(double seconds);

}  // namespace porter::runtime
