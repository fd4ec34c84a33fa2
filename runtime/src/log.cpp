#include "porter/runtime/log.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <mutex>
#include <string>

#include "porter/runtime/clock.hpp"

namespace porter::runtime {
namespace {

std::mutex& log_mutex() {
  static std::mutex m;
  return m;
}

struct LogState {
  std::string name = "porter";
  LogLevel min_level = LogLevel::info;
};

LogState& state() {
  static LogState s;
  return s;
}

const char* level_name(LogLevel level) {
  switch (level) {
    case LogLevel::debug: return "DEBUG";
    case LogLevel::info: return "INFO";
    case LogLevel::warn: return "WARN";
    case LogLevel::error: return "ERROR";
  }
  return "?";
}

bool parse_level(const char* text, LogLevel& out) {
  if (text == nullptr) return false;
  if (std::strcmp(text, "debug") == 0) out = LogLevel::debug;
  else if (std::strcmp(text, "info") == 0) out = LogLevel::info;
  else if (std::strcmp(text, "warn") == 0) out = LogLevel::warn;
  else if (std::strcmp(text, "error") == 0) out = LogLevel::error;
  else return false;
  return true;
}

}  // namespace

void init_log(std::string_view process_name, LogLevel min_level) {
  std::lock_guard<std::mutex> lock(log_mutex());
  state().name = std::string(process_name);
  LogLevel from_env;
  state().min_level = parse_level(std::getenv("PORTER_LOG_LEVEL"), from_env) ? from_env : min_level;
}

std::string process_name() {
  std::lock_guard<std::mutex> lock(log_mutex());
  return state().name;
}

void log(LogLevel level, std::string_view message) {
  const std::int64_t utime = wall_utime();
  std::lock_guard<std::mutex> lock(log_mutex());
  if (static_cast<int>(level) < static_cast<int>(state().min_level)) return;
  const std::time_t seconds = static_cast<std::time_t>(utime / 1000000);
  std::tm tm{};
  gmtime_r(&seconds, &tm);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%S", &tm);
  std::fprintf(stderr, "%s.%03dZ %s %s %.*s\n", stamp, static_cast<int>((utime / 1000) % 1000),
               state().name.c_str(), level_name(level), static_cast<int>(message.size()),
               message.data());
  std::fflush(stderr);
}

std::string format_ms(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f ms", seconds * 1e3);
  return text;
}

}  // namespace porter::runtime
