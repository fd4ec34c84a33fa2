#include "porter/pipeline/plan_request.hpp"

#include <algorithm>

namespace porter::pipeline {

StartState StartState::on_trajectory(const Trajectory& trajectory, double t_s) {
  const double t = std::clamp(t_s, 0.0, trajectory.total_duration_s());
  StartState s;
  const TrajVector z = trajectory.position(t);
  s.config.base = {z[0], z[1], trajectory.yaw_rad(t)};
  s.config.q_rad = z.tail<kNumArmJoints>();
  s.velocity = trajectory.velocity(t);
  s.acceleration = trajectory.acceleration(t);
  return s;
}

}  // namespace porter::pipeline
