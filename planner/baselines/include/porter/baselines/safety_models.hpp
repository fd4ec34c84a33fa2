#pragma once
// One switch for the paper's comparisons (porter-plan --safety / --collision and the benchmarks):
//   --safety kc_svsdf | svsdf_per_link | spheres     the back-end collision term
//   --collision kernels | spheres                     the front-end / re-check collision model
// "kernels" is planner/collision's KernelCollisionChecker; "spheres" the sphere-ESDF baseline
// (sphere_collision_checker.hpp, sphere_safety_term.hpp). With --collision spheres, the back-end
// term is the sphere one as well (REMANI / TOPAY use one model throughout).

#include <memory>
#include <optional>
#include <string>

#include "porter/backend/robot_sdf.hpp"
#include "porter/backend/safety_term.hpp"
#include "porter/backend/svsdf_safety_term.hpp"
#include "porter/baselines/sphere_safety_term.hpp"
#include "porter/core/robot_model.hpp"

namespace porter::baselines {

enum class SafetyModel { kKcSvsdf, kSvsdfPerLink, kSpheres };
enum class CollisionModel { kKernels, kSpheres };

const char* to_string(SafetyModel m);
const char* to_string(CollisionModel m);
/// "kc_svsdf", "svsdf_per_link", "spheres"; nullopt for anything else.
std::optional<SafetyModel> parse_safety_model(const std::string& name);
/// "kernels", "spheres"; nullopt for anything else.
std::optional<CollisionModel> parse_collision_model(const std::string& name);

struct SafetyTermSettings {
  backend::SvsdfSafetySettings svsdf;   ///< kc_svsdf and svsdf_per_link (filter set by the model)
  SphereSafetySettings spheres;         ///< spheres
};

/// The back-end term for `model`. The SVSDF terms need `sdf` (RobotSdf::build(robot)); it must
/// outlive the term (as must `robot`).
std::unique_ptr<backend::SafetyTerm> make_safety_term(SafetyModel model, const RobotModel& robot,
                                                      const backend::RobotSdf* sdf,
                                                      const SafetyTermSettings& settings = {});

}  // namespace porter::baselines
