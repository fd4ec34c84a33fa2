#include "porter/pipeline/exact_acceptance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

#include "porter/validation/flat_trajectory.hpp"
#include "porter/validation/validator.hpp"

namespace porter::pipeline {

namespace {

/// The link index (0..kNumLinks-1) of a validator body name, -1 when it is none of the robot's
/// planning links (the payload counts as the last link).
int link_of(const RobotModel& robot, const std::string& body) {
  if (body.rfind("payload", 0) == 0) return kNumLinks - 1;
  for (int j = 0; j < kNumLinks; ++j)
    if (robot.links[static_cast<std::size_t>(j)].name == body) return j;
  return -1;
}

/// Pieces of `t` covering [t0_s, t1_s]: the first cut at t0 (its polynomial re-expanded about
/// the cut, c'_k = sum_{i >= k} C(i, k) a^(i-k) c_i), the last shortened to end at t1.
std::vector<validation::PolyPiece> slice(const Trajectory& t, double t0_s, double t1_s) {
  std::vector<validation::PolyPiece> out;
  for (int i = 0; i < t.num_pieces(); ++i) {
    const double s0 = t.piece_start_time_s(i), s1 = t.piece_start_time_s(i + 1);
    if (s1 <= t0_s || s0 >= t1_s) continue;
    const TrajectoryPiece& p = t.piece(i);
    const double a = std::max(0.0, t0_s - s0);
    const double b = std::min(p.duration_s, t1_s - s0);
    if (!(b - a > 1e-9)) continue;
    validation::PolyPiece v;
    v.duration_s = b - a;
    v.eta = p.eta;
    for (int k = 0; k < kTrajNumCoeffs; ++k) {
      double binom = 1.0;  // C(i, k) for i = k, k+1, ...
      double power = 1.0;  // a^(i-k)
      for (int j = k; j < kTrajNumCoeffs; ++j) {
        v.coeffs.row(k) += binom * power * p.coeffs.row(j);
        binom = binom * static_cast<double>(j + 1) / static_cast<double>(j + 1 - k);
        power *= a;
      }
    }
    out.push_back(v);
  }
  return out;
}

/// A largest-displacement bound of any robot point between two configurations: base translation,
/// the reach times the heading change, each joint's swept radius times its change.
double displacement_bound_m(const planner::ChainRadii& r, const RobotConfiguration& a, const RobotConfiguration& b) {
  double d = std::hypot(b.base.x_m - a.base.x_m, b.base.y_m - a.base.y_m);
  d += r.reach_m * std::abs(std::remainder(b.base.yaw_rad - a.base.yaw_rad, 2.0 * M_PI));
  for (int j = 0; j < kNumArmJoints; ++j)
    d += r.sweep_radius_m[static_cast<std::size_t>(j)] * std::abs(b.q_rad[j] - a.q_rad[j]);
  return d;
}

RobotConfiguration config_at(const Trajectory& t, double t_s) {
  const TrajVector z = t.position(t_s);
  RobotConfiguration c;
  c.base = {z[0], z[1], t.yaw_rad(t_s)};
  c.q_rad = z.tail<kNumArmJoints>();
  return c;
}

}  // namespace

ExactClearanceAcceptance::ExactClearanceAcceptance(RobotModel robot, Payload payload, Scene scene,
                                                   ExactAcceptanceSettings settings,
                                                   std::shared_ptr<const planner::KernelRobot> kernel_robot,
                                                   const OccupancyGrid& map_W)
    : ExactClearanceAcceptance(std::move(robot), std::move(payload), std::move(scene), settings) {
  if (!(settings_.filter_step_m > 0.0) || !std::isfinite(settings_.filter_step_m))
    throw std::invalid_argument("exact acceptance: filter_step_m must be finite and > 0");
  planner::MapKernelSettings dilated;
  dilated.safety_margin_m = settings_.margin_m + 0.5 * settings_.filter_step_m;
  filter_ = std::make_unique<planner::KernelCollisionChecker>(std::move(kernel_robot), dilated);
  filter_->set_map(map_W);
}

ExactClearanceAcceptance::ExactClearanceAcceptance(RobotModel robot, Payload payload, Scene scene,
                                                   ExactAcceptanceSettings settings)
    : robot_(std::move(robot)), payload_(std::move(payload)), scene_(std::move(scene)), settings_(settings) {
  if (!(settings_.margin_m >= 0.0) || !std::isfinite(settings_.margin_m))
    throw std::invalid_argument("exact acceptance: margin_m must be finite and >= 0");
  if (!(settings_.max_step_m > 0.0) || !std::isfinite(settings_.max_step_m))
    throw std::invalid_argument("exact acceptance: max_step_m must be finite and > 0");
}

planner::AcceptanceResult ExactClearanceAcceptance::check(const Trajectory& trajectory) const {
  return check(trajectory, nullptr);
}

planner::AcceptanceResult ExactClearanceAcceptance::check(const Trajectory& trajectory, ExactClearance* out) const {
  ExactClearance c;
  c.min_m = std::numeric_limits<double>::infinity();
  // Windows [t0, t1] to check exactly: the whole trajectory, or around the filter's flags.
  std::vector<std::pair<double, double>> windows;
  const double total = trajectory.total_duration_s();
  if (!filter_) {
    windows.emplace_back(0.0, total);
  } else {
    // Samples: every 20 ms (the deviation of a polynomial motion from the chord over 20 ms is
    // below a tenth of a millimetre at the robot's accelerations), bisected until neighbours are
    // within filter_step_m.
    const planner::ChainRadii& radii = filter_->kernels().radii();
    constexpr double kBaseInterval_s = 0.02;
    const int n = std::max(1, static_cast<int>(std::ceil(total / kBaseInterval_s)));
    auto flagged = [&](double t) {
      ++c.filter_samples;
      return filter_->check(config_at(trajectory, t)).in_collision;
    };
    double t_prev = 0.0;
    RobotConfiguration prev = config_at(trajectory, 0.0);
    bool prev_flag = flagged(0.0);
    auto add = [&](double t0, double t1) {
      if (!windows.empty() && windows.back().second >= t0 - 1e-12) windows.back().second = std::max(windows.back().second, t1);
      else windows.emplace_back(t0, t1);
    };
    if (prev_flag) add(0.0, 0.0);
    for (int k = 1; k <= n; ++k) {
      const double t_next = std::min(total, total * static_cast<double>(k) / static_cast<double>(n));
      // Walk from t_prev to t_next in steps that keep the displacement within filter_step_m.
      double t = t_prev;
      while (t < t_next) {
        double h = t_next - t;
        RobotConfiguration next = config_at(trajectory, t + h);
        for (int halvings = 0; displacement_bound_m(radii, prev, next) > settings_.filter_step_m && halvings < 20;
             ++halvings) {
          h *= 0.5;
          next = config_at(trajectory, t + h);
        }
        const bool f = flagged(t + h);
        if (f || prev_flag) add(t, t + h);  // the interval next to a flagged sample
        t += h;
        prev = next;
        prev_flag = f;
      }
      t_prev = t_next;
    }
  }
  c.windows = static_cast<int>(windows.size());

  planner::AcceptanceResult r;
  r.accepted = true;
  validation::ValidationSettings vs;
  vs.max_step_m = settings_.max_step_m;
  // Exact distances only where a bounding box comes within the margin: farther pairs clear it
  // by their box gap, a lower bound of their distance.
  vs.clearance_horizon_m = settings_.margin_m + 1e-3;
  for (const auto& [t0, t1] : windows) {
    std::vector<validation::PolyPiece> pieces;
    if (t1 - t0 > 1e-9) {
      pieces = slice(trajectory, t0, t1);
    } else {  // a flag at one instant (an end of the trajectory): the robot held there
      validation::PolyPiece v;
      v.duration_s = 1e-3;
      v.coeffs.row(0) = trajectory.position(t0).transpose();
      pieces.push_back(v);
    }
    if (pieces.empty()) continue;
    for (const auto& p : pieces) c.exact_duration_s += p.duration_s;
    const validation::FlatTrajectory flat(std::move(pieces), trajectory.yaw_rad(t0));
    const validation::ValidationReport rep = validation::validate_trajectory(robot_, payload_, scene_, flat, vs);
    double window_min = std::numeric_limits<double>::infinity();
    std::string obstacle, body;
    for (const validation::ObstacleClearance& o : rep.clearances) {
      if (o.min_m < window_min) {
        window_min = o.min_m;
        obstacle = o.obstacle;
        body = o.body;
      }
    }
    if (window_min < c.min_m) {
      c.min_m = window_min;
      c.obstacle = obstacle;
      c.body = body;
    }
    c.self_collision = c.self_collision || rep.self_collision.found;
    if (rep.collision.found) {
      r.link = link_of(robot_, rep.collision.body);
    } else if (rep.self_collision.found) {
      r.link = link_of(robot_, rep.self_collision.body_a);
      r.other_link = link_of(robot_, rep.self_collision.body_b);
    } else if (window_min < settings_.margin_m) {
      r.link = link_of(robot_, body);
    }
    if (rep.collision.found || rep.self_collision.found || window_min < settings_.margin_m) {
      r.accepted = false;
      break;  // the first window that fails decides
    }
  }
  if (out) *out = c;
  return r;
}

}  // namespace porter::pipeline
