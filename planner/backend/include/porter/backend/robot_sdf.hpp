#pragma once
// The per-link signed distance fields of a whole robot model: one LinkSdf per planning link
// (0 = base, 1..6 = arm links, 7 = gripper + payload), each in its own link frame Lj.
//
// Build once per model (and payload); a few hundred ms for the Scout Mini + Piper with a payload
// (links in parallel on two threads by default).
// Thread-safety: immutable after build(); share freely.

#include <array>
#include <cstdint>

#include "porter/backend/link_sdf.hpp"
#include "porter/core/robot_model.hpp"
#include "porter/core/types.hpp"

namespace porter::backend {

class RobotSdf {
 public:
  RobotSdf() = default;
  /// `threads` >= 1 build links in parallel (each link's field is independent; the result does
  /// not depend on the count).
  static RobotSdf build(const RobotModel& model, const SdfGridSettings& settings = {}, int threads = 2);

  /// build() calls in this process so far (a diagnostic: tests count builds). Thread-safe.
  static std::int64_t build_count();

  const LinkSdf& link(int j) const { return links_[static_cast<std::size_t>(j)]; }
  const SdfGridSettings& settings() const { return settings_; }

 private:
  std::array<LinkSdf, kNumLinks> links_;
  SdfGridSettings settings_;
};

}  // namespace porter::backend
