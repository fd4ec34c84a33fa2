#include "porter/baselines/svsdf_per_link.hpp"

namespace porter::baselines {

std::unique_ptr<backend::SvsdfSafetyTerm> make_svsdf_per_link(const RobotModel& model, const backend::RobotSdf& sdf,
                                                              backend::SvsdfSafetySettings settings) {
  settings.kc.kinematic_filter = false;
  return std::make_unique<backend::SvsdfSafetyTerm>(model, sdf, settings);
}

}  // namespace porter::baselines
