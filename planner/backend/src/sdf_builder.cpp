#include "sdf_builder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace porter::backend::detail {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Triangle {
  Eigen::Vector3d a, b, c;
};

/// One group of elements whose pointwise minimum is a distance: either primitives (signed) or the
/// triangles of one mesh (unsigned, signed afterwards by containment in `mesh`).
struct Group {
  std::vector<const CollisionShape*> primitives;
  std::vector<Triangle> triangles;
  const CollisionShape* mesh = nullptr;  ///< set for a triangle group
  bool signed_mesh = false;              ///< closed mesh: sign by containment

  bool is_mesh() const { return mesh != nullptr; }
  int size() const {
    return is_mesh() ? static_cast<int>(triangles.size()) : static_cast<int>(primitives.size());
  }
  double element_distance(int e, const Eigen::Vector3d& p) const {
    if (is_mesh()) {
      const Triangle& t = triangles[static_cast<std::size_t>(e)];
      return (p - closest_point_on_triangle(p, t.a, t.b, t.c)).norm();
    }
    return shape_signed_distance(*primitives[static_cast<std::size_t>(e)], p);
  }
};

class Filler {
 public:
  Filler(const Group& group, SdfGrid& grid) : group_(group), grid_(grid) {}

  void run() {
    std::vector<int> all(static_cast<std::size_t>(group_.size()));
    for (int e = 0; e < group_.size(); ++e) all[static_cast<std::size_t>(e)] = e;
    const Eigen::Vector3i hi = grid_.dims() - Eigen::Vector3i::Ones();
    recurse(Eigen::Vector3i::Zero(), hi, all, 0);
  }

 private:
  /// Node index box [lo, hi] (inclusive), elements that may be nearest, and the mesh sign when
  /// known for the whole box (0: unknown).
  void recurse(const Eigen::Vector3i& lo, const Eigen::Vector3i& hi, const std::vector<int>& cand,
               int sign) {
    const Eigen::Vector3i n = hi - lo + Eigen::Vector3i::Ones();
    if (n.prod() <= 1 || cand.size() <= 1) {
      leaf(lo, hi, cand, sign);
      return;
    }
    const double h = grid_.resolution_m();
    const Eigen::Vector3d p_lo = grid_.node_position(lo.x(), lo.y(), lo.z());
    const Eigen::Vector3d p_hi = grid_.node_position(hi.x(), hi.y(), hi.z());
    const Eigen::Vector3d c = 0.5 * (p_lo + p_hi);
    const double rho = 0.5 * (p_hi - p_lo).norm() + 1e-9 * h;
    std::vector<double> d(cand.size());
    double dmin = kInf;
    for (std::size_t k = 0; k < cand.size(); ++k) {
      d[k] = group_.element_distance(cand[k], c);
      dmin = std::min(dmin, d[k]);
    }
    std::vector<int> kept;
    kept.reserve(cand.size());
    for (std::size_t k = 0; k < cand.size(); ++k) {
      if (d[k] <= dmin + 2.0 * rho) kept.push_back(cand[k]);
    }
    if (group_.is_mesh() && sign == 0 && dmin > rho) sign = mesh_sign(c);
    // Split every axis with more than one node at its middle.
    const Eigen::Vector3i mid = lo + (n - Eigen::Vector3i::Ones()) / 2;
    for (int cz = 0; cz < (n.z() > 1 ? 2 : 1); ++cz) {
      for (int cy = 0; cy < (n.y() > 1 ? 2 : 1); ++cy) {
        for (int cx = 0; cx < (n.x() > 1 ? 2 : 1); ++cx) {
          Eigen::Vector3i a, b;
          const int choice[3] = {cx, cy, cz};
          for (int ax = 0; ax < 3; ++ax) {
            if (n[ax] == 1) {
              a[ax] = lo[ax];
              b[ax] = hi[ax];
            } else if (choice[ax] == 0) {
              a[ax] = lo[ax];
              b[ax] = mid[ax];
            } else {
              a[ax] = mid[ax] + 1;
              b[ax] = hi[ax];
            }
          }
          recurse(a, b, kept, sign);
        }
      }
    }
  }

  void leaf(const Eigen::Vector3i& lo, const Eigen::Vector3i& hi, const std::vector<int>& cand,
            int sign) {
    for (int k = lo.z(); k <= hi.z(); ++k) {
      for (int j = lo.y(); j <= hi.y(); ++j) {
        for (int i = lo.x(); i <= hi.x(); ++i) {
          const Eigen::Vector3d p = grid_.node_position(i, j, k);
          double d = kInf;
          for (int e : cand) d = std::min(d, group_.element_distance(e, p));
          if (group_.is_mesh()) d *= sign != 0 ? sign : mesh_sign(p);
          grid_.set(i, j, k, static_cast<float>(d));
        }
      }
    }
  }

  int mesh_sign(const Eigen::Vector3d& p) const {
    if (!group_.signed_mesh) return 1;
    return shape_contains(*group_.mesh, p) ? -1 : 1;
  }

  const Group& group_;
  SdfGrid& grid_;
};

}  // namespace

void fill_exact_sdf(const std::vector<CollisionShape>& shapes, SdfGrid& grid) {
  std::vector<Group> groups;
  Group primitives;
  for (const CollisionShape& shape : shapes) {
    if (const auto* m = std::get_if<MeshShape>(&shape.geometry)) {
      if (!m->mesh || m->mesh->triangles.empty()) continue;
      Group g;
      g.mesh = &shape;
      g.signed_mesh = m->mesh->closed;
      const auto& v = m->mesh->vertices_m;
      for (const Eigen::Vector3i& t : m->mesh->triangles) {
        g.triangles.push_back({shape.T_parent_shape * v[static_cast<std::size_t>(t[0])],
                               shape.T_parent_shape * v[static_cast<std::size_t>(t[1])],
                               shape.T_parent_shape * v[static_cast<std::size_t>(t[2])]});
      }
      groups.push_back(std::move(g));
    } else {
      primitives.primitives.push_back(&shape);
    }
  }
  if (!primitives.primitives.empty()) groups.push_back(std::move(primitives));

  std::fill(grid.values().begin(), grid.values().end(), std::numeric_limits<float>::max());
  SdfGrid scratch(grid.origin(), grid.resolution_m(), grid.dims());
  for (const Group& g : groups) {
    Filler(g, scratch).run();
    auto& out = grid.values();
    const auto& in = scratch.values();
    for (std::size_t k = 0; k < out.size(); ++k) out[k] = std::min(out[k], in[k]);
  }
}

}  // namespace porter::backend::detail
