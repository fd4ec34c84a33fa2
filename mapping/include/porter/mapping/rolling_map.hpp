#pragma once
// A bounded, robot-centred occupancy map at the planner's resolution: a dense grid of log-odds
// over a window of OctoMap keys that slides with the robot (ring-buffer indexing: a voxel's
// slot is its key modulo the window size per axis, so a shift clears the slabs that leave and
// moves nothing). OctoMap is only the published format (octomap_binary.hpp).
//
// Voxels are OctoMap's: key k = floor(coord / resolution) + 32768 per axis, voxel k covers
// [(k - 32768) res, (k - 32767) res). The window spans keys [window_min, window_min + dims).
//
// Update (integrate): the same occupancy model as octomap::OccupancyOcTreeBase::insertPointCloud
// with one sensor origin per cloud: every voxel a ray passes through (origin voxel included,
// endpoint voxel excluded, 3D-DDA) gets one "miss", every endpoint voxel one "hit", at most one
// update per voxel per cloud, and a voxel that is an endpoint is never also a miss (hits win).
// Log-odds are clamped to [logodds(clamp_min), logodds(clamp_max)]; a voxel is occupied when
// its log-odds >= logodds(occupancy_threshold). Unknown voxels (never updated) are distinct
// from free ones.
// What makes it fast: rays are deduplicated per endpoint voxel (one ray per occupied voxel per
// cloud, cast to the first point that fell in it), per-cloud dedup of traversed voxels uses a
// dense mark array instead of a hash set, and rays stop where they leave the window.
//
// Shadow of a new surface (new_surface_shadow_m > 0). A voxel that misses had left at the
// clamp (seen free again and again) and that then turns occupied by hits alone is a new surface:
// something stands where rays passed before. The free space seen behind and below it before it
// appeared is stale - the surface now hides it - so the free voxels right behind it along the
// ray that saw it (up to new_surface_shadow_m), and the free voxels below it and below each of
// those (new obstacles stand on the floor), are set to shadow_log_odds(): occupied, and free
// again after one miss. Each run of them ends at the first voxel that is unknown or occupied
// (behind a surface lies the object's unseen inside); voxels a ray of this cloud crossed are
// seen free and keep their state. Without this the far side and the lower part of a box that
// appears in seen-free space stay free in the map (docs/mapping.md, "Shadow of a new surface").
// A surface seen for the first time, or a voxel whose hits alternate with misses (a surface
// grazed by rays), casts no shadow.
//
// Kinds of points (integrate's options): a point farther than max_range_m from the origin gives
// a free ray to the range limit (as OctoMap's maxrange); a point below ground_height_m (world z)
// gives a free ray to the point but no hit (the ground is not an obstacle, yet rays to it clear
// the space above it); every other point is a hit. Endpoints outside the window give only the
// free part of their ray inside the window.
//
// Change tracking (for readers that re-encode only what changed, octomap_binary.hpp): slots are
// grouped in blocks of 8 x 8 x 8 (slot / 8 per axis; the last block of an axis may be partial).
// Every mutating call (integrate, a center_on that moves, clear) raises revision(), and stamps
// with it every block in which a voxel's state (unknown / free / occupied) may have changed.
// A block whose stamp is <= a revision r held no state change since r. The states themselves
// are also kept packed, 2 bits a voxel, block by block (block_states()), so a reader of a block
// touches 128 bytes instead of 512 scattered floats.
//
// Frames and units: world frame W, metres. Memory: 4.5 bytes per voxel of the window.
// Thread-safety: none (one thread integrates; const queries may run while nothing writes).

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>

namespace porter::mapping {

struct RollingMapParams {
  double resolution_m = 0.05;           ///< voxel edge, m (> 0)
  Eigen::Vector3i dims{400, 400, 64};   ///< window size in voxels per axis (each >= 2)
  double z_min_m = 0.0;                 ///< bottom of the window (snapped down to a voxel face)
  double prob_hit = 0.7;                ///< OctoMap defaults
  double prob_miss = 0.4;
  double clamp_min = 0.1192;
  double clamp_max = 0.971;
  double occupancy_threshold = 0.5;
  /// Depth behind a new surface whose free voxels are set occupied (see the header
  /// comment), m; 0 = off (OctoMap's model).
  double new_surface_shadow_m = 0.0;
};

struct IntegrateOptions {
  double max_range_m = -1.0;   ///< < 0: no limit
  double ground_height_m = -std::numeric_limits<double>::infinity();  ///< z below: ground
};

struct IntegrateStats {
  std::uint64_t points = 0;
  std::uint64_t hits = 0;            ///< points that are hits
  std::uint64_t ground = 0;          ///< points below the ground height
  std::uint64_t beyond_range = 0;    ///< points past max_range_m
  std::uint64_t outside_window = 0;  ///< hits whose voxel lies outside the window
  std::uint64_t invalid = 0;         ///< non-finite, or beyond OctoMap's key range: ignored
  std::uint64_t rays = 0;            ///< rays cast after deduplication
  std::uint64_t occupied_updates = 0;
  std::uint64_t free_updates = 0;
  std::uint64_t voxels_traversed = 0;
  std::uint64_t new_surfaces = 0;  ///< voxels turned occupied from settled free (shadow casters)
  std::uint64_t shadowed = 0;      ///< free voxels behind and below them set occupied (shadow)
  bool origin_outside = false;       ///< the origin was outside the window: nothing integrated
};

enum class VoxelState : std::uint8_t { unknown = 0, free = 1, occupied = 2 };

class RollingMap {
 public:
  static constexpr int kKeyOffset = 32768;  ///< OctoMap's tree_max_val (depth 16)

  explicit RollingMap(const RollingMapParams& params);

  const RollingMapParams& params() const { return params_; }
  double resolution_m() const { return params_.resolution_m; }
  const Eigen::Vector3i& dims() const { return params_.dims; }
  const Eigen::Vector3i& window_min_key() const { return window_min_; }

  /// OctoMap key of a coordinate.
  int key_of(double coord_m) const {
    return static_cast<int>(std::floor(inv_res_ * coord_m)) + kKeyOffset;
  }
  Eigen::Vector3i key_of(const Eigen::Vector3d& p_W) const {
    return {key_of(p_W.x()), key_of(p_W.y()), key_of(p_W.z())};
  }
  /// Centre of a key's voxel.
  double key_to_coord(int key) const { return (static_cast<double>(key - kKeyOffset) + 0.5) * params_.resolution_m; }
  bool in_window(const Eigen::Vector3i& key) const {
    return (key.array() >= window_min_.array()).all() &&
           (key.array() < (window_min_ + params_.dims).array()).all();
  }

  /// Moves the window so that (x, y) lies at its centre in x and y (z stays); voxels leaving
  /// the window are forgotten. A position past half the key range (or not finite) is ignored.
  /// Returns true when the window moved.
  bool center_on(double x_m, double y_m);
  /// True when (x, y) is farther than distance_m (per axis) from the window's centre.
  bool needs_recenter(double x_m, double y_m, double distance_m) const;

  /// Integrates one cloud taken from `origin_W` (see the header comment).
  IntegrateStats integrate(const Eigen::Vector3f& origin_W, const std::vector<Eigen::Vector3f>& points_W,
                           const IntegrateOptions& options);

  VoxelState state(const Eigen::Vector3i& key) const;
  /// Log-odds of a voxel; NaN when unknown or outside the window.
  float log_odds(const Eigen::Vector3i& key) const;
  bool occupied(float log_odds) const { return log_odds >= occupancy_log_; }
  /// Calls fn(key, log_odds) for every known voxel of the window.
  template <class Fn>
  void for_each_known(Fn&& fn) const;
  std::int64_t count(VoxelState s) const;
  /// Forgets everything (the window stays).
  void clear();

  /// Log-odds constants as OctoMap stores them (float).
  float hit_log() const { return hit_log_; }
  float miss_log() const { return miss_log_; }
  float clamp_min_log() const { return clamp_min_log_; }
  float clamp_max_log() const { return clamp_max_log_; }
  float occupancy_log() const { return occupancy_log_; }
  /// Log-odds of a shadow voxel: halfway between the threshold and one miss above it, so that
  /// it is occupied and one miss makes it free.
  float shadow_log_odds() const { return occupancy_log_ - 0.5f * miss_log_; }

  /// Slot of a key inside the window (precondition: in_window).
  std::int64_t slot(const Eigen::Vector3i& key) const {
    const int sx = key.x() % params_.dims.x(), sy = key.y() % params_.dims.y(),
              sz = key.z() % params_.dims.z();
    return sx + stride_y_ * sy + stride_z_ * sz;
  }
  const float* raw_log_odds() const { return log_odds_.data(); }

  /// Change tracking (see the header comment).
  static constexpr int kBlockShift = 3;
  std::uint64_t revision() const { return revision_; }
  const Eigen::Vector3i& block_dims() const { return block_dims_; }
  /// Revision of the last possible state change in block (bx, by, bz) (slot >> kBlockShift).
  std::uint64_t block_revision(int bx, int by, int bz) const { return block_rev_[block_index(bx, by, bz)]; }
  /// The states of block (bx, by, bz): kBlockWords words, voxel (x, y, z) of the block (slot
  /// & 7 per axis) at bits 2 i, 2 i + 1 with i = x + 8 y + 64 z; 0 unknown, 1 free, 2 occupied
  /// (VoxelState). Slots past the window's end in a partial block read unknown.
  static constexpr int kBlockWords = 16;
  const std::uint64_t* block_states(int bx, int by, int bz) const {
    return &states_[block_index(bx, by, bz) * kBlockWords];
  }

 private:
  /// Forgets slots [first, first + count) along x (axis 0) or y (axis 1).
  void clear_slots(int axis, int first, int count);
  /// The packed states and stamps of one such plane of slots.
  void clear_plane_states(int axis, int slot_index);
  std::size_t block_index(int bx, int by, int bz) const {
    return static_cast<std::size_t>(bx + block_dims_.x() * (by + static_cast<std::int64_t>(block_dims_.y()) * bz));
  }
  /// Records a slot's new state (packed) and stamps its block with the current revision.
  void set_state(std::int64_t slot, int state);
  /// Marks the voxels of the ray origin -> end (end voxel excluded) as free in this cloud.
  void cast(const Eigen::Vector3f& origin, const Eigen::Vector3i& key_origin, const Eigen::Vector3f& end,
            IntegrateStats& stats);
  /// Sets the shadow behind (and below) the new surface at `end` (seen from `origin`); runs while
  /// the touched marks of this cloud's free voxels are still set.
  void shadow_behind(const Eigen::Vector3f& origin, const Eigen::Vector3f& end, IntegrateStats& stats);
  /// Sets the free voxels below `key` as shadows, down to the first unknown or occupied one.
  void shadow_below(const Eigen::Vector3i& key, IntegrateStats& stats);
  /// One voxel of a shadow run: crossed by this cloud (kept, the run goes on), set, or the end
  /// of the run (unknown or occupied).
  enum class Shade { seen, set, end };
  Shade shade(std::int64_t slot, IntegrateStats& stats);

  RollingMapParams params_;
  double inv_res_;
  Eigen::Vector3i window_min_;
  std::int64_t stride_y_, stride_z_;
  std::vector<float> log_odds_;        ///< NaN = unknown
  std::vector<std::uint64_t> touched_;  ///< per-cloud: hit or free in this cloud (zero between)
  std::vector<std::uint64_t> ray_end_;  ///< per-cloud: a free-only ray ends here (zero between)
  /// Set when a miss leaves a voxel at clamp_min (seen free until the clamp), cleared by a miss
  /// that leaves it above; hits keep it. A voxel that turns occupied with it set is a new surface.
  /// Stale bits of forgotten voxels are harmless: a voxel needs a miss to be free again.
  std::vector<std::uint64_t> settled_free_;
  std::vector<std::int64_t> occupied_list_, end_list_;
  std::vector<Eigen::Vector3f> ray_ends_;
  std::vector<Eigen::Vector3f> occupied_ends_;  ///< the ray end of each occupied_list_ entry
  std::vector<std::size_t> new_surfaces_;     ///< indices into occupied_list_
  float hit_log_, miss_log_, clamp_min_log_, clamp_max_log_, occupancy_log_;
  std::uint64_t revision_ = 0;
  Eigen::Vector3i block_dims_;
  std::vector<std::uint64_t> block_rev_;
  std::vector<std::uint64_t> states_;  ///< packed states, block by block
};

template <class Fn>
void RollingMap::for_each_known(Fn&& fn) const {
  const Eigen::Vector3i& n = params_.dims;
  for (int z = 0; z < n.z(); ++z)
    for (int y = 0; y < n.y(); ++y)
      for (int x = 0; x < n.x(); ++x) {
        const Eigen::Vector3i key = window_min_ + Eigen::Vector3i(x, y, z);
        const float v = log_odds_[static_cast<std::size_t>(slot(key))];
        if (v == v) fn(key, v);
      }
}

}  // namespace porter::mapping
