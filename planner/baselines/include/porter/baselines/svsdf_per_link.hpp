#pragma once
// The paper's ablation baseline (§VII-A-2): the back-end safety term on each link's SVSDF
// independently [Zhang et al., SVSDF], i.e. Algorithm 1 without the KinematicFilter: outside,
// D[j] = g_j; inside, the same ball search over every sample direction. Everything else (t*
// search, windows, AABB prefilter, penalty, gradients) is the back-end's, so the comparison
// isolates the coupling.

#include <memory>

#include "porter/backend/svsdf_safety_term.hpp"

namespace porter::baselines {

/// An SvsdfSafetyTerm named "svsdf_per_link": `settings` with the KinematicFilter switched off.
std::unique_ptr<backend::SvsdfSafetyTerm> make_svsdf_per_link(const RobotModel& model,
                                                              const backend::RobotSdf& sdf,
                                                              backend::SvsdfSafetySettings settings = {});

}  // namespace porter::baselines
