#include "porter/core/scene_random.hpp"

#include <algorithm>
#include <string>

#include "porter/core/scene.hpp"

namespace porter {

ColumnFieldResult place_columns(const ColumnFieldSpec& spec, const std::vector<CollisionShape>& existing_W,
                                const std::vector<Eigen::Vector2d>& keep_clear_xy_W, PortableRandom& rng) {
  ColumnFieldResult result;
  result.columns.reserve(static_cast<std::size_t>(std::max(0, spec.count)));
  // The columns placed so far as discs (centre, radius). A column is an upright cylinder, so
  // footprint_distance to it is max(0, |c - centre| - r): tested here directly, without its
  // per-call shape dispatch and rotation (the identity) of the offset, with the same result.
  // In a crowded field most tests are against placed columns.
  struct Disc {
    Eigen::Vector2d centre;
    double radius;
  };
  std::vector<Disc> discs;
  discs.reserve(result.columns.capacity());
  // Tests counted as distance evaluations: a tilted or mesh obstacle costs its triangles.
  std::vector<std::int64_t> cost(existing_W.size());
  std::int64_t existing_cost = 0;
  for (std::size_t i = 0; i < existing_W.size(); ++i) {
    cost[i] = static_cast<std::int64_t>(footprint_cost(existing_W[i]));
    existing_cost += cost[i];
  }
  for (int k = 0; k < spec.count; ++k) {
    bool placed = false;
    for (int attempt = 0; attempt < spec.max_attempts && !placed; ++attempt) {
      const std::int64_t most =
          static_cast<std::int64_t>(keep_clear_xy_W.size() + discs.size()) + existing_cost;
      if (result.footprint_tests > spec.max_footprint_tests - most) {
        result.out_of_tests = true;
        return result;
      }
      const double r = rng.uniform(spec.radius_min_m, spec.radius_max_m);
      const double x = rng.uniform(spec.region_min_W.x() + r, spec.region_max_W.x() - r);
      const double y = rng.uniform(spec.region_min_W.y() + r, spec.region_max_W.y() - r);
      if (spec.region_max_W.x() - spec.region_min_W.x() < 2.0 * r ||
          spec.region_max_W.y() - spec.region_min_W.y() < 2.0 * r)
        continue;  // the disc does not fit in the region at this radius
      const Eigen::Vector2d c(x, y);
      const double need = r + spec.min_clearance_m;
      bool ok = true;
      for (std::size_t i = 0; ok && i < keep_clear_xy_W.size(); ++i, ++result.footprint_tests)
        ok = (keep_clear_xy_W[i] - c).norm() >= need;
      for (std::size_t i = 0; ok && i < existing_W.size(); result.footprint_tests += cost[i], ++i)
        ok = footprint_distance(existing_W[i], c) >= need;
      for (std::size_t i = 0; ok && i < discs.size(); ++i, ++result.footprint_tests)
        ok = std::max(0.0, (c - discs[i].centre).norm() - discs[i].radius) >= need;
      if (!ok) continue;
      CollisionShape col;
      col.geometry = Cylinder{r, spec.height_m};
      col.T_parent_shape.translation() = Eigen::Vector3d(x, y, 0.5 * spec.height_m);
      col.name = spec.name_prefix + "[" + std::to_string(k) + "]";
      result.columns.push_back(std::move(col));
      discs.push_back({c, r});
      placed = true;
    }
    if (!placed) return result;
  }
  result.complete = true;
  return result;
}

}  // namespace porter
