#include "porter/backend/svsdf_safety_term.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>

namespace porter::backend {

namespace {
TimeHints no_hints() {
  TimeHints h;
  h.fill(std::numeric_limits<float>::quiet_NaN());
  return h;
}
}  // namespace

namespace {

/// Identifies a map: geometry and a hash of its bits (FNV-1a over the words). Never 0.
std::uint64_t map_key(const OccupancyGrid& map) {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&h](std::uint64_t v) {
    h ^= v;
    h *= 1099511628211ull;
  };
  auto mix_double = [&mix](double d) {
    std::uint64_t v = 0;
    std::memcpy(&v, &d, sizeof v);
    mix(v);
  };
  for (int a = 0; a < 3; ++a) {
    mix(static_cast<std::uint64_t>(map.dims()[a]));
    mix_double(map.origin_W()[a]);
  }
  mix_double(map.resolution_m());
  for (std::uint64_t w : map.words()) mix(w);
  return h == 0 ? 1 : h;
}

}  // namespace

SvsdfSafetyTerm::SvsdfSafetyTerm(const RobotModel& model, const RobotSdf& sdf,
                                 const SvsdfSafetySettings& settings)
    : sdf_(&sdf), settings_(settings), body_(model, settings.body) {
  certain_below_m_.fill(-std::numeric_limits<double>::infinity());
  for (int w = 0; w < std::max(1, settings_.threads); ++w) {
    workers_.push_back(std::make_unique<Worker>(sdf, body_, settings_.kc));
  }
  team_ = std::make_unique<TaskTeam>(static_cast<int>(workers_.size()));
  for (std::size_t j = 0; j < kNumLinks; ++j) {
    margin_[j] = settings_.link_margin_m[j] > 0.0 ? settings_.link_margin_m[j] : settings_.safety_margin_m;
    ground_margin_[j] =
        settings_.link_ground_margin_m[j] > 0.0 ? settings_.link_ground_margin_m[j] : settings_.ground_margin_m;
  }
}

void SvsdfSafetyTerm::prepare(const OccupancyGrid& map_W, const Trajectory& initial) {
  body_.reset(initial);
  const std::uint64_t key = map_key(map_W);
  if (settings_.selection_slack_m > 0.0) {
    // Once per map and warm start region (header comment "Selection").
    if (key != map_key_) {
      map_ = map_W;
      map_key_ = key;
      selection_ = CellMask();
      keys_.clear();
      points_.clear();
    }
    if (selection_.empty()) {
      Eigen::AlignedBox3d bounds = map_.bounds_W();
      bounds.min().z() -= map_.resolution_m();  // the ground layer lies half a voxel below the map
      selection_ = CellMask(bounds, kSelectCell_m);
      mark_boxes(selection_, settings_.selection_slack_m);
      collect_selected();
    } else if (!selection_covers_body()) {
      // Same map, another warm start (the warm-start choice prepares each): the selection grows.
      mark_boxes(selection_, settings_.selection_slack_m);
      collect_selected();
    }
  } else if (key != map_key_) {
    // Once per map: every surface voxel of the map (and the ground layer under it); the per-piece
    // prefilter visits only the index cells near the trajectory, so no cropping is needed.
    const auto t0 = std::chrono::steady_clock::now();
    points_ = collect_obstacle_points(map_W, map_W.bounds_W(), settings_.points);
    map_key_ = key;
    selection_ = CellMask();
    keys_.clear();
    index_points();
    ++collections_;
    collection_s_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  hints_.assign(points_.size(), no_hints());
  for (int j = 0; j < kNumLinks; ++j) {
    const LinkSdf& l = sdf_->link(j);
    certain_below_m_[static_cast<std::size_t>(j)] =
        l.empty() ? -std::numeric_limits<double>::infinity() : 0.5 * map_W.resolution_m() - l.fine().error_bound_m();
  }
  refresh_decisions();
}

double SvsdfSafetyTerm::level1_radius_m(int link) const {
  const auto j = static_cast<std::size_t>(link);
  return std::max(margin_[j], ground_margin_[j]) + sdf_->link(link).fine().error_bound_m();
}

void SvsdfSafetyTerm::mark_boxes(CellMask& mask, double grow_m) const {
  const int pieces = body_.trajectory().num_pieces();
  for (int j = 0; j < kNumLinks; ++j) {
    const Eigen::Vector3d grow = Eigen::Vector3d::Constant(level1_radius_m(j) + grow_m);
    for (int i = 0; i < pieces; ++i) {
      const Eigen::AlignedBox3d& box = body_.piece_box(j, i);
      if (!box.isEmpty()) mask.add(Eigen::AlignedBox3d(box.min() - grow, box.max() + grow));
    }
  }
}

bool SvsdfSafetyTerm::selection_covers_body() const {
  const int pieces = body_.trajectory().num_pieces();
  for (int j = 0; j < kNumLinks; ++j) {
    // Level 1 lets a point through for (j, i) only if it lies within r_j of the box (in every
    // axis, a fortiori), i.e. inside the box grown by r_j.
    const Eigen::Vector3d grow = Eigen::Vector3d::Constant(level1_radius_m(j));
    for (int i = 0; i < pieces; ++i) {
      const Eigen::AlignedBox3d& box = body_.piece_box(j, i);
      if (!box.isEmpty() && !selection_.covers(Eigen::AlignedBox3d(box.min() - grow, box.max() + grow))) return false;
    }
  }
  return true;
}

void SvsdfSafetyTerm::collect_selected() {
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::uint64_t> keys;
  std::vector<ObstaclePoint> points =
      collect_obstacle_points(map_, map_.bounds_W(), settings_.points, &selection_, &keys);
  // Carry every kept point's hints and frozen decisions over (both key lists increase).
  std::vector<TimeHints> hints(points.size(), no_hints());
  std::vector<std::unique_ptr<BallDecisions>> decisions(points.size());
  const bool have_hints = hints_.size() == points_.size() && keys_.size() == points_.size();
  const bool have_decisions = decisions_.size() == points_.size() && keys_.size() == points_.size();
  for (std::size_t a = 0, b = 0; a < keys_.size() && b < keys.size();) {
    if (keys_[a] < keys[b]) {
      ++a;
    } else if (keys[b] < keys_[a]) {
      ++b;
    } else {
      if (have_hints) hints[b] = hints_[a];
      if (have_decisions) decisions[b] = std::move(decisions_[a]);
      ++a;
      ++b;
    }
  }
  points_ = std::move(points);
  keys_ = std::move(keys);
  hints_ = std::move(hints);
  decisions_ = std::move(decisions);
  index_points();
  ++collections_;
  collection_s_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void SvsdfSafetyTerm::refresh_decisions() {
  decisions_.clear();
  decisions_.resize(points_.size());
  record_next_ = true;
}

void SvsdfSafetyTerm::index_points() {
  pair_lists_.clear();  // they hold indices into the old points
  // A uniform grid of point indices (CSR), so that each swept box visits only its own points.
  grid_box_.setEmpty();
  for (const ObstaclePoint& o : points_) grid_box_.extend(o.p_W);
  cell_start_.assign(1, 0);
  cell_points_.clear();
  if (grid_box_.isEmpty()) return;
  for (int a = 0; a < 3; ++a) {
    grid_dims_[a] = std::max(1, static_cast<int>(std::floor(grid_box_.sizes()[a] / kCell_m)) + 1);
  }
  const std::size_t cells = static_cast<std::size_t>(grid_dims_.prod());
  std::vector<int> count(cells + 1, 0);
  std::vector<std::size_t> cell_of(points_.size());
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const Eigen::Vector3i c = cell_index(points_[i].p_W);
    cell_of[i] = static_cast<std::size_t>(c.x()) + static_cast<std::size_t>(grid_dims_.x()) * (static_cast<std::size_t>(c.y()) + static_cast<std::size_t>(grid_dims_.y()) * c.z());
    ++count[cell_of[i] + 1];
  }
  cell_start_.resize(cells + 1);
  cell_start_[0] = 0;
  for (std::size_t c = 0; c < cells; ++c) cell_start_[c + 1] = cell_start_[c] + count[c + 1];
  cell_points_.resize(points_.size());
  std::vector<int> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t i = 0; i < points_.size(); ++i) cell_points_[static_cast<std::size_t>(fill[cell_of[i]]++)] = static_cast<int>(i);
}

Eigen::Vector3i SvsdfSafetyTerm::cell_index(const Eigen::Vector3d& p) const {
  Eigen::Vector3i c;
  for (int a = 0; a < 3; ++a) {
    c[a] = std::clamp(static_cast<int>(std::floor((p[a] - grid_box_.min()[a]) / kCell_m)), 0, grid_dims_[a] - 1);
  }
  return c;
}

void SvsdfSafetyTerm::find_candidates() {
  masks_.assign(points_.size(), 0u);
  tight_.assign(points_.size(), 0u);
  candidates_.clear();
  if (points_.empty()) return;
  const std::size_t pairs = static_cast<std::size_t>(kNumLinks) * static_cast<std::size_t>(body_.trajectory().num_pieces());
  if (pair_lists_.size() != pairs) pair_lists_.assign(pairs, PairList{});
  // The (link, piece) pairs are split over the workers, each with its own masks; the masks are
  // OR-ed in worker order (the result does not depend on timing).
  team_->run([this](int w) { mark_candidates(*workers_[static_cast<std::size_t>(w)], w); });
  for (const auto& w : workers_) {
    for (std::size_t idx = 0; idx < points_.size(); ++idx) {
      masks_[idx] |= w->masks[idx];
      tight_[idx] |= w->tight[idx];
    }
  }
  for (std::size_t idx = 0; idx < points_.size(); ++idx) {
    // A pair can pass the SDF level on one piece and the box levels only on another: evaluated
    // pairs are those passing both, somewhere.
    tight_[idx] &= masks_[idx];
    if (tight_[idx]) candidates_.push_back(static_cast<int>(idx));
  }
}

void SvsdfSafetyTerm::mark_candidates(Worker& worker, int index) {
  std::vector<std::uint32_t>& masks = worker.masks;
  std::vector<std::uint32_t>& tight = worker.tight;
  masks.assign(points_.size(), 0u);
  tight.assign(points_.size(), 0u);
  const int pieces = body_.trajectory().num_pieces();
  const int stride = static_cast<int>(workers_.size());
  const double reuse_slack = settings_.prefilter_slack_m;
  // Pairs numbered j * pieces + i: the payload's pieces (the most work) are spread over all workers.
  for (int pair = index; pair < kNumLinks * pieces; pair += stride) {
    const int j = pair / pieces;
    const int i = pair % pieces;
    const LinkSdf& sdf = sdf_->link(j);
    const double err = sdf.fine().error_bound_m();
    const double err_any = std::max(err, sdf.coarse().error_bound_m());
    const double widest = std::max(margin_[static_cast<std::size_t>(j)], ground_margin_[static_cast<std::size_t>(j)]);
    const Eigen::AlignedBox3d& local = sdf.body_bounds();
    const double step = body_.max_step_m(j);
    const std::uint32_t bit = 1u << j;
    // The base's bit stays the box levels' own: it decides the base search's options (kc_svsdf.cpp).
    const bool tighten = settings_.sdf_prefilter && j > 0 && !sdf.empty();
    const Eigen::AlignedBox3d& box = body_.piece_box(j, i);
    if (box.isEmpty()) continue;
    const int first = body_.piece_first_sample(i), last = body_.piece_first_sample(i + 1);
    // The three levels for one point of the pair (header comment "Prefilter").
    auto visit = [&](std::size_t idx) {
      const ObstaclePoint& o = points_[idx];
      bool box_hit = (masks[idx] & bit) != 0;
      bool sdf_hit = !tighten || (tight[idx] & bit) != 0;
      if (box_hit && sdf_hit) return;
      const double r = margin_of(o, j) + err;
      if (box.exteriorDistance(o.p_W) > r) return;
      const double r_sdf = margin_of(o, j) + err_any;
      // Level 2, in the link frame at the piece's samples: between samples every link
      // point moves at most `step`, so the link stays farther than (distance to its
      // local box at the nearest sample) - step from the point. The local box bounds the
      // link's signed distance from below, and that distance changes by at most `step`
      // per sample: a sample whose box distance exceeds r + (m + 1) step also proves the
      // link farther than r over the next m sample intervals, which are skipped (they
      // could only set the bit for a point the penalty would not see).
      // Level 3 (tighten): the same with the SDF's lower bound and r_sdf; looked up only
      // where the box does not already rule the sample out.
      for (int s = first; s <= last;) {
        const Eigen::Vector3d p_L = body_.sample_pose(s, j).apply(o.p_W);
        const double d = local.exteriorDistance(p_L);
        if (!box_hit && d <= r + step) box_hit = true;
        double lb = d;
        if (!sdf_hit && d <= r_sdf + step) {
          double sd_lower = d;
          sdf.distance_fast(p_L, &sd_lower);
          lb = std::max(d, sd_lower);
          // Between this sample and its neighbours the link moves at most the two
          // intervals' own bounds (each <= step).
          const double local_step =
              std::max(s > 0 ? body_.motion_bound_m(j, s - 1, s) : 0.0,
                       s + 1 < body_.num_samples() ? body_.motion_bound_m(j, s, s + 1) : 0.0);
          sdf_hit = lb <= r_sdf + local_step;
        }
        if (box_hit && sdf_hit) break;
        // Skip only samples that can decide neither open level: sample s + i is at least
        // (bound here) - motion(s, s + i) away, and a hit needs r + step (box) or
        // r_sdf + step (SDF) at most; the motion is summed over the actual intervals.
        double room = std::numeric_limits<double>::infinity();
        if (!box_hit) room = d - r - step;
        if (!sdf_hit) room = std::min(room, lb - r_sdf - step);
        s += 1 + body_.samples_within_motion(j, s, last, room);
      }
      if (box_hit) masks[idx] |= bit;
      // A piece may pass only the SDF level (the box levels passing on another piece):
      // the bits are AND-ed over all pieces in find_candidates().
      if (tighten ? sdf_hit : box_hit) tight[idx] |= bit;
    };
    // Level 1 lets a point through only within widest + err of the box, so inside the box grown by
    // that in every axis (header comment "Candidate lists").
    const Eigen::Vector3d reach = Eigen::Vector3d::Constant(widest + err);
    PairList* list = reuse_slack > 0.0 ? &pair_lists_[static_cast<std::size_t>(pair)] : nullptr;
    if (list && list->valid &&
        Eigen::AlignedBox3d(list->box.min() - Eigen::Vector3d::Constant(reuse_slack),
                            list->box.max() + Eigen::Vector3d::Constant(reuse_slack)).contains(box)) {
      ++worker.pairs_reused;
      for (int k : list->points) visit(static_cast<std::size_t>(k));
      continue;
    }
    ++worker.pairs_searched;
    // Level 1 from the point index, over the box grown by widest + err (+ the slack, recording
    // the pair's list: every point with the link's bit inside the box grown by reach + slack).
    const Eigen::Vector3d grow = reach + Eigen::Vector3d::Constant(list ? reuse_slack : 0.0);
    const Eigen::AlignedBox3d listed(box.min() - grow, box.max() + grow);
    if (list) {
      list->valid = true;
      list->box = box;
      list->points.clear();
    }
    const Eigen::Vector3i lo = cell_index(listed.min());
    const Eigen::Vector3i hi = cell_index(listed.max());
    for (int z = lo.z(); z <= hi.z(); ++z)
      for (int y = lo.y(); y <= hi.y(); ++y)
        for (int x = lo.x(); x <= hi.x(); ++x) {
          const std::size_t c = static_cast<std::size_t>(x) + static_cast<std::size_t>(grid_dims_.x()) * (static_cast<std::size_t>(y) + static_cast<std::size_t>(grid_dims_.y()) * z);
          for (int k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
            const auto idx = static_cast<std::size_t>(cell_points_[static_cast<std::size_t>(k)]);
            if (!(points_[idx].links & bit)) continue;
            if (list && listed.contains(points_[idx].p_W)) list->points.push_back(static_cast<int>(idx));
            visit(idx);
          }
        }
  }
}

void SvsdfSafetyTerm::run(Worker& w, int index, const Trajectory& trajectory) {
  const double weight = settings_.weight;
  const int stride = static_cast<int>(workers_.size());
  w.cost = 0.0;
  w.stats = SafetyStats{};
  w.grad.reset(trajectory.num_pieces());
  for (std::size_t c = static_cast<std::size_t>(index); c < candidates_.size(); c += static_cast<std::size_t>(stride)) {
    const auto i = static_cast<std::size_t>(candidates_[c]);
    const ObstaclePoint& o = points_[i];
    // The search cap and the base's options follow the box levels' mask (so every evaluated
    // pair's D_j is as without the SDF level); only the tight mask's links are evaluated.
    const std::uint32_t box_mask = masks_[i];
    const std::uint32_t mask = tight_[i];
    double cap = 0.0;  // D values above every needed link's margin are not used
    for (int j = 0; j < kNumLinks; ++j) {
      if (box_mask & (1u << j)) cap = std::max(cap, margin_of(o, j));
    }
    ++w.stats.candidate_points;
    TimeHints& hint = hints_[i];
    BallDecisions* decisions = nullptr;
    if (settings_.freeze_ball_decisions) {
      // Point i is run by one worker per evaluate(): its slot is not shared.
      std::unique_ptr<BallDecisions>& slot = decisions_[i];
      if (!slot) slot = std::make_unique<BallDecisions>();
      decisions = slot.get();
    }
    w.kc.evaluate(o.p_W, mask, w.result, cap, &hint, decisions, record_next_);
    hint[0] = static_cast<float>(w.result.t0_star_s);
    for (int j = 0; j < kNumLinks; ++j) {
      const LinkDistance& l = w.result.links[static_cast<std::size_t>(j)];
      if (j > 0 && l.computed) hint[static_cast<std::size_t>(j)] = static_cast<float>(l.t_star_s);
      if (!(mask & (1u << j))) continue;
      const double d = l.d;
      ++w.stats.link_queries;
      if (l.g < certain_below_m_[static_cast<std::size_t>(j)]) w.stats.certain_collision = true;
      w.stats.min_distance_m = std::min(w.stats.min_distance_m, d);
      w.stats.inside += d < 0.0;
      const double x = margin_of(o, j) - d;
      if (x <= 0.0) continue;
      ++w.stats.violations;
      w.cost += weight * x * x * x;
      w.result.add_gradient(trajectory, j, -3.0 * weight * x * x, w.grad);
    }
  }
}

double SvsdfSafetyTerm::evaluate(const Trajectory& trajectory, TrajectoryGradient& grad, SafetyStats* stats) {
  const auto start = std::chrono::steady_clock::now();
  body_.reset(trajectory);
  if (selecting() && !selection_covers_body()) {
    // A link left the selected region: grow it around the current trajectory.
    mark_boxes(selection_, settings_.selection_slack_m);
    collect_selected();
  }
  if (cell_start_.size() < 2) index_points();  // points set by set_points()
  if (hints_.size() != points_.size()) hints_.assign(points_.size(), no_hints());
  if (decisions_.size() != points_.size()) refresh_decisions();
  const auto t_prefilter = std::chrono::steady_clock::now();
  find_candidates();
  const double prefilter_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_prefilter).count();
  team_->run([this, &trajectory](int w) { run(*workers_[static_cast<std::size_t>(w)], w, trajectory); });
  record_next_ = false;
  SafetyStats total;
  total.obstacle_points = static_cast<int>(points_.size());
  double cost = 0.0;
  for (const auto& w : workers_) {
    cost += w->cost;
    grad.add(w->grad);
    total.candidate_points += w->stats.candidate_points;
    total.link_queries += w->stats.link_queries;
    total.violations += w->stats.violations;
    total.inside += w->stats.inside;
    total.certain_collision = total.certain_collision || w->stats.certain_collision;
    total.min_distance_m = std::min(total.min_distance_m, w->stats.min_distance_m);
  }
  total.cost = cost;
  total.prefilter_s = prefilter_s;
  total.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (stats) *stats = total;
  return cost;
}

std::int64_t SvsdfSafetyTerm::pairs_reused() const {
  std::int64_t n = 0;
  for (const auto& w : workers_) n += w->pairs_reused;
  return n;
}

std::int64_t SvsdfSafetyTerm::pairs_searched() const {
  std::int64_t n = 0;
  for (const auto& w : workers_) n += w->pairs_searched;
  return n;
}

KcSvsdfStats SvsdfSafetyTerm::kc_stats() const {
  KcSvsdfStats s;
  for (const auto& w : workers_) s.add(w->kc.stats());
  return s;
}

SvsdfStats SvsdfSafetyTerm::svsdf_stats() const {
  SvsdfStats s;
  for (const auto& w : workers_) s.add(w->kc.svsdf().stats());
  return s;
}

void SvsdfSafetyTerm::reset_stats() {
  for (auto& w : workers_) {
    w->kc.stats() = KcSvsdfStats{};
    w->kc.svsdf().stats() = SvsdfStats{};
  }
}

}  // namespace porter::backend
