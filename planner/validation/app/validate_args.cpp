#include "validate_args.hpp"

#include <cmath>
#include <cstdlib>

namespace porter::validation {
namespace {

bool parse_double(const std::string& text, double* out) {
  if (text.empty()) return false;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (*end != '\0' || !std::isfinite(v)) return false;
  *out = v;
  return true;
}

}  // namespace

std::optional<ValidateArgs> parse_validate_args(int argc, const char* const* argv, std::string* error) {
  ValidateArgs a;
  auto positive = [&](const std::string& flag, const std::string& v, double* out) {
    if (!parse_double(v, out) || !(*out > 0.0)) {
      *error = flag + ": expected a number > 0, got '" + v + "'";
      return false;
    }
    return true;
  };
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    auto value = [&]() { return std::string(argv[++i]); };
    if (arg == "--quiet") {
      a.quiet = true;
    } else if (arg == "--no-ground") {
      a.settings.check_ground = false;
    } else if (arg.rfind("--", 0) == 0 && !has_value) {
      *error = arg + ": missing value";
      return std::nullopt;
    } else if (arg == "--scene") {
      a.scene_file = value();
    } else if (arg == "--seed") {
      const std::string v = value();
      char* end = nullptr;
      const unsigned long long s = std::strtoull(v.c_str(), &end, 10);
      if (v.empty() || *end != '\0' || v[0] == '-') {
        *error = "--seed: expected a non-negative integer, got '" + v + "'";
        return std::nullopt;
      }
      a.seed = static_cast<std::uint64_t>(s);
    } else if (arg == "--set") {
      const std::string v = value();
      const auto eq = v.find('=');
      double x = 0.0;
      if (eq == std::string::npos || eq == 0 || !parse_double(v.substr(eq + 1), &x)) {
        *error = "--set: expected NAME=NUMBER, got '" + v + "'";
        return std::nullopt;
      }
      a.overrides[v.substr(0, eq)] = x;
    } else if (arg == "--payload") {
      a.payload_file = value();
    } else if (arg == "--robot") {
      a.robot_file = value();
    } else if (arg == "--json") {
      a.json_out = value();
    } else if (arg == "--trace") {
      a.trace_out = value();
    } else if (arg == "--max-step-m") {
      if (!positive(arg, value(), &a.settings.max_step_m)) return std::nullopt;
    } else if (arg == "--limit-tolerance") {
      const std::string v = value();
      if (!parse_double(v, &a.settings.limit_tolerance) || a.settings.limit_tolerance < 0.0) {
        *error = "--limit-tolerance: expected a number >= 0, got '" + v + "'";
        return std::nullopt;
      }
    } else if (arg == "--clearance-horizon-m") {
      if (!positive(arg, value(), &a.settings.clearance_horizon_m)) return std::nullopt;
    } else if (arg == "--pose-tolerance-m") {
      if (!positive(arg, value(), &a.settings.pose_tolerance_m)) return std::nullopt;
    } else if (arg == "--pose-tolerance-rad") {
      if (!positive(arg, value(), &a.settings.pose_tolerance_rad)) return std::nullopt;
    } else if (arg.rfind("--", 0) == 0) {
      *error = "unknown option " + arg;
      return std::nullopt;
    } else if (a.result_file.empty()) {
      a.result_file = arg;
    } else {
      *error = "more than one result file: " + arg;
      return std::nullopt;
    }
  }
  if (a.scene_file.empty()) *error = "--scene is required";
  else if (a.result_file.empty()) *error = "a result file is required";
  else return a;
  return std::nullopt;
}

}  // namespace porter::validation
