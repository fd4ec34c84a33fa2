#include "porter/baselines/safety_models.hpp"

#include "porter/baselines/svsdf_per_link.hpp"

namespace porter::baselines {

const char* to_string(SafetyModel m) {
  switch (m) {
    case SafetyModel::kKcSvsdf: return "kc_svsdf";
    case SafetyModel::kSvsdfPerLink: return "svsdf_per_link";
    case SafetyModel::kSpheres: return "spheres";
  }
  return "unknown";
}

const char* to_string(CollisionModel m) {
  return m == CollisionModel::kKernels ? "kernels" : "spheres";
}

std::optional<SafetyModel> parse_safety_model(const std::string& name) {
  if (name == "kc_svsdf") return SafetyModel::kKcSvsdf;
  if (name == "svsdf_per_link") return SafetyModel::kSvsdfPerLink;
  if (name == "spheres") return SafetyModel::kSpheres;
  return std::nullopt;
}

std::optional<CollisionModel> parse_collision_model(const std::string& name) {
  if (name == "kernels") return CollisionModel::kKernels;
  if (name == "spheres") return CollisionModel::kSpheres;
  return std::nullopt;
}

std::unique_ptr<backend::SafetyTerm> make_safety_term(SafetyModel model, const RobotModel& robot,
                                                      const backend::RobotSdf* sdf,
                                                      const SafetyTermSettings& settings) {
  switch (model) {
    case SafetyModel::kKcSvsdf: {
      if (!sdf) return nullptr;
      backend::SvsdfSafetySettings s = settings.svsdf;
      s.kc.kinematic_filter = true;
      return std::make_unique<backend::SvsdfSafetyTerm>(robot, *sdf, s);
    }
    case SafetyModel::kSvsdfPerLink:
      if (!sdf) return nullptr;
      return make_svsdf_per_link(robot, *sdf, settings.svsdf);
    case SafetyModel::kSpheres:
      return std::make_unique<SphereSafetyTerm>(robot, settings.spheres);
  }
  return nullptr;
}

}  // namespace porter::baselines
