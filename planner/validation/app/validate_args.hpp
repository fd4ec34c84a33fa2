#pragma once
// Command line of porter-validate (usage text in kValidateUsage).

#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "porter/validation/validator.hpp"

namespace porter::validation {

inline constexpr const char* kValidateUsage =
    "usage: porter-validate --scene FILE [--seed N] [--set NAME=VALUE]... [--payload FILE]\n"
    "                       [--robot FILE] [--json FILE|-] [--trace FILE] [--max-step-m M]\n"
    "                       [--limit-tolerance R] [--pose-tolerance-m M] [--pose-tolerance-rad R]\n"
    "                       [--clearance-horizon-m M]\n"
    "                       [--no-ground] [--quiet] RESULT.json\n"
    "exit codes: 0 valid, 1 invalid, 2 bad arguments, 3 unreadable or invalid input,\n"
    "            4 the result holds no trajectory\n";

struct ValidateArgs {
  std::string scene_file;
  std::optional<std::uint64_t> seed;
  std::map<std::string, double> overrides;
  std::string payload_file;   ///< "" = the scene's payload
  std::string robot_file;     ///< "" = <scene dir>/../robots/scout_mini_piper/robot.yaml
  std::string result_file;
  std::string json_out;       ///< "" none, "-" stdout
  std::string trace_out;
  bool quiet = false;
  ValidationSettings settings;
};

/// Parses argv; on failure returns nullopt and sets *error.
std::optional<ValidateArgs> parse_validate_args(int argc, const char* const* argv, std::string* error);

}  // namespace porter::validation
