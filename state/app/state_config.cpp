#include "state_config.hpp"

#include <cmath>
#include <stdexcept>

#include "porter/core/load_error.hpp"
#include "porter/core/yaml_reader.hpp"

namespace porter::state_app {

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

StateConfig load_state_config(const std::string& path) {
  const auto cfg = yaml::Reader::load_file(path);
  cfg.expect_keys({"frame_id", "rate_hz", "start_pose", "base", "lio", "arm"});
  StateConfig out;
  out.file = path;
  out.frame_id = cfg.get("frame_id").as_string();
  if (out.frame_id.empty()) cfg.get("frame_id").fail("must not be empty");
  out.rate_hz = cfg.get("rate_hz").as_positive();
  if (out.rate_hz < 1.0 || out.rate_hz > 1000.0) cfg.get("rate_hz").fail("must be in [1, 1000]");

  state::FusionParams& f = out.fusion;
  const auto start = cfg.get("start_pose");
  start.expect_keys({"x_m", "y_m", "yaw_rad"});
  // Within the scenes' bounds (10 km); the yaw within one turn either way, wrapped.
  const double yaw = start.get("yaw_rad").as_in(-2.0 * kPi, 2.0 * kPi, "rad");
  f.start_pose = {start.get("x_m").as_in(-1e4, 1e4, "m"), start.get("y_m").as_in(-1e4, 1e4, "m"),
                  std::remainder(yaw, 2.0 * kPi)};

  const auto base = cfg.get("base");
  base.expect_keys({"timeout_s", "history_s", "reset_m", "reset_rad", "max_extrapolation_s"});
  // Timeouts up to 10 s (a state that old moving the robot is no state); histories up to a
  // minute (kept at the input's rate); a jump up to 100 m or half a turn.
  f.base_timeout_s = base.get("timeout_s").as_in(0.0, 10.0, "s", true);
  f.odom_history_s = base.get("history_s").as_in(0.0, 60.0, "s", true);
  f.odom_reset_m = base.get("reset_m").as_in(0.0, 100.0, "m", true);
  f.odom_reset_rad = base.get("reset_rad").as_in(0.0, kPi, "rad", true);
  f.max_extrapolation_s = base.get("max_extrapolation_s").as_in(0.0, 10.0, "s");
  if (f.max_extrapolation_s > f.base_timeout_s) {
    base.get("max_extrapolation_s").fail("must not exceed base.timeout_s");
  }

  const auto lio = cfg.get("lio");
  lio.expect_keys({"use", "child_frame_id", "timeout_s", "jump_m", "jump_rad"});
  f.use_lio = lio.get("use").as_bool();
  out.lio_child_frame_id = lio.get("child_frame_id").as_string();
  if (out.lio_child_frame_id.empty()) lio.get("child_frame_id").fail("must not be empty");
  f.lio_timeout_s = lio.get("timeout_s").as_in(0.0, 10.0, "s", true);
  f.lio_jump_m = lio.get("jump_m").as_in(0.0, 100.0, "m", true);
  f.lio_jump_rad = lio.get("jump_rad").as_in(0.0, kPi, "rad", true);

  const auto arm = cfg.get("arm");
  arm.expect_keys({"timeout_s"});
  f.arm_timeout_s = arm.get("timeout_s").as_in(0.0, 10.0, "s", true);
  try {
    f.validate();
  } catch (const std::invalid_argument& e) {
    throw LoadError(path, "", e.what());
  }
  return out;
}

}  // namespace porter::state_app
