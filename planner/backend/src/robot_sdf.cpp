#include "porter/backend/robot_sdf.hpp"

namespace porter::backend {

RobotSdf RobotSdf::build(const RobotModel& model, const SdfGridSettings& settings) {
  RobotSdf sdf;
  sdf.settings_ = settings;
  for (int j = 0; j < kNumLinks; ++j) {
    sdf.links_[static_cast<std::size_t>(j)] = LinkSdf::build(model.links[static_cast<std::size_t>(j)].shapes, settings);
  }
  return sdf;
}

}  // namespace porter::backend
