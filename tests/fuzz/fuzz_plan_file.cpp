// Fuzz target: porter-plan result files as porter-validate reads them. Any bytes either parse
// into pieces with positive durations, eta +-1 and finite coefficients, or throw LoadError.
#include <cmath>
#include <cstdint>
#include <string>

#include "porter/core/load_error.hpp"
#include "porter/validation/flat_trajectory.hpp"
#include "porter/validation/plan_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const porter::validation::PlanFile p = porter::validation::parse_plan_file(text, "fuzz.json");
    if (!p.has_trajectory) return 0;
    for (const auto& piece : p.pieces)
      if (!(piece.duration_s > 0.0) || (piece.eta != 1 && piece.eta != -1) || !piece.coeffs.allFinite())
        __builtin_trap();
    const porter::validation::FlatTrajectory t(p.pieces, p.start_yaw_rad);
    const double yaw = t.yaw_rad(0.5 * t.duration_s());
    if (!(std::abs(yaw) <= M_PI + 1e-12)) __builtin_trap();
  } catch (const porter::LoadError&) {
  }
  return 0;
}
