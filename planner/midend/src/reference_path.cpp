#include "porter/midend/reference_path.hpp"
#include "porter/planner/angle.hpp"

#include <algorithm>
#include <cmath>

#include "porter/midend/diff_drive.hpp"

namespace porter::midend {
namespace {

struct Node {
  RobotConfiguration config;
  double time_s = 0.0;
};
struct Segment {
  int eta = 1;
  bool still = false;
  std::vector<Node> nodes;
};

double base_distance(const Node& a, const Node& b) {
  return std::hypot(b.config.base.x_m - a.config.base.x_m, b.config.base.y_m - a.config.base.y_m);
}

bool coincident(const Node& a, const Node& b, double tol) {
  return base_distance(a, b) <= tol &&
         (b.config.q_rad - a.config.q_rad).cwiseAbs().maxCoeff() <= tol;
}

double base_length(const Segment& s) {
  double len = 0.0;
  for (std::size_t i = 1; i < s.nodes.size(); ++i) len += base_distance(s.nodes[i - 1], s.nodes[i]);
  return len;
}

void drop_coincident(Segment& s, double tol) {
  std::vector<Node> out;
  out.reserve(s.nodes.size());
  for (const Node& n : s.nodes) {
    if (out.empty() || !coincident(out.back(), n, tol)) out.push_back(n);
  }
  s.nodes = std::move(out);
}

bool finite_node(const planner::PathNode& n) {
  return std::isfinite(n.config.base.x_m) && std::isfinite(n.config.base.y_m) &&
         std::isfinite(n.config.base.yaw_rad) && n.config.q_rad.allFinite() &&
         std::isfinite(n.time_s);
}

Node interpolate(const Node& a, const Node& b, double s) {
  Node n;
  n.config.base.x_m = a.config.base.x_m + s * (b.config.base.x_m - a.config.base.x_m);
  n.config.base.y_m = a.config.base.y_m + s * (b.config.base.y_m - a.config.base.y_m);
  n.config.base.yaw_rad =
      a.config.base.yaw_rad + s * planner::angle_difference_rad(b.config.base.yaw_rad, a.config.base.yaw_rad);
  n.config.q_rad = a.config.q_rad + s * (b.config.q_rad - a.config.q_rad);
  n.time_s = a.time_s + s * (b.time_s - a.time_s);
  return n;
}

// Step 5b: the longest tail of `nodes` (edges e .. n-2, e >= 1 so that an edge stays moving)
// whose base path and heading change stay within the still bounds and which moves the arm by
// still_min_arm_rad; returns its first node e, or -1.
int still_tail_start(const std::vector<Node>& nodes, const MidendSettings& st) {
  double base = 0.0, yaw = 0.0, arm = 0.0;
  int best = -1;
  for (int e = static_cast<int>(nodes.size()) - 2; e >= 1; --e) {
    const Node& a = nodes[static_cast<std::size_t>(e)];
    const Node& b = nodes[static_cast<std::size_t>(e + 1)];
    base += base_distance(a, b);
    yaw += std::abs(planner::angle_difference_rad(b.config.base.yaw_rad, a.config.base.yaw_rad));
    arm += (b.config.q_rad - a.config.q_rad).norm();
    if (base > st.still_max_base_m || yaw > st.still_max_yaw_rad) break;
    if (arm >= st.still_min_arm_rad) best = e;
  }
  return best;
}

// Splits nodes[k..] (at_end) or nodes[..k] off `seg` as a still segment whose nodes all carry the
// end's base pose; the moving part's junction node gets it too. False (seg untouched) when the
// moving part would no longer move the base.
bool split_still(Segment& seg, int k, bool at_end, const MidendSettings& st, Segment* still) {
  std::vector<Node> nodes = seg.nodes;
  const std::size_t n = nodes.size();
  const BasePose end = at_end ? nodes.back().config.base : nodes.front().config.base;
  Segment moving;
  moving.eta = seg.eta;
  still->eta = seg.eta;
  still->still = true;
  const std::size_t j = static_cast<std::size_t>(k);
  if (at_end) {
    moving.nodes.assign(nodes.begin(), nodes.begin() + static_cast<std::ptrdiff_t>(j) + 1);
    still->nodes.assign(nodes.begin() + static_cast<std::ptrdiff_t>(j), nodes.end());
    moving.nodes.back().config.base = end;
  } else {
    const std::size_t h = n - 1 - j;  // head nodes 0..h
    still->nodes.assign(nodes.begin(), nodes.begin() + static_cast<std::ptrdiff_t>(h) + 1);
    moving.nodes.assign(nodes.begin() + static_cast<std::ptrdiff_t>(h), nodes.end());
    moving.nodes.front().config.base = end;
  }
  for (Node& node : still->nodes) node.config.base = end;
  drop_coincident(moving, st.coincident_tolerance);
  drop_coincident(*still, st.coincident_tolerance);
  if (still->nodes.size() < 2 || moving.nodes.size() < 2 ||
      base_length(moving) < std::max(st.min_segment_length_m, 1e-9)) {
    return false;
  }
  seg = std::move(moving);
  return true;
}

// Step 6 for one front-end edge whose length is len_b rho_b (base metric) and len_m rho_m
// (joints): the fractions in (0, 1] of its reference nodes, the last one 1: equal sub-edges of at
// most densify_factor rho.
std::vector<double> densify_fractions(double len_b, double len_m, const MidendSettings& st) {
  const double len = std::max(len_b, len_m);
  const int m = std::clamp(static_cast<int>(std::ceil(len / st.densify_factor - 1e-9)), 1, st.max_pieces_per_edge);
  std::vector<double> out;
  for (int k = 0; k < m; ++k) out.push_back((k + 1.0) / m);
  out.back() = 1.0;
  return out;
}

// Initial time allocation over all pieces of all segments (piece order): a speed profile along
// the base path limited by the wheel speed (v (1 + d_w |kappa| / 2) <= r omega_max, kappa from the
// edge's heading change per metre), the joint speeds, rest at the global start and goal, v_ns at
// gear switches and a wheel-acceleration bound (forward / backward passes), all at
// initial_speed_fraction of the limits. Edge durations are 2 L / (v_k + v_k+1) (exact for
// constant acceleration between nodes), at least the edge's heading / joint motion at the
// limited rates and min_initial_piece_duration_s.
// Time to cover d >= 0 from speed w0 to w1 (both <= cap, |w1^2 - w0^2| <= 2 a d) with
// acceleration a and speed cap: accelerate, cruise at the peak speed, brake.
double ramp_time(double d, double w0, double w1, double a, double cap) {
  if (d <= 0.0) return 0.0;
  const double peak = std::min(cap, std::sqrt(std::max(0.0, a * d + 0.5 * (w0 * w0 + w1 * w1))));
  if (peak <= 0.0) return 0.0;
  const double ramps_d = (2.0 * peak * peak - w0 * w0 - w1 * w1) / (2.0 * a);
  return (2.0 * peak - w0 - w1) / a + std::max(0.0, d - ramps_d) / peak;
}

// Per edge (all segments, in order): the time the arm needs when every joint follows its own
// speed profile along the path: at most f * qd_max, f * qdd_max between nodes, at rest at the
// global start and goal. allocate_times() uses it on still segments (the arm finishing at the
// goal or starting at the start while the base rests). Timed at constant joint speed instead,
// the nodes of such a motion sit at equal times while the trajectory must brake to rest: it runs
// ahead of its nodes and then creeps, and the residual to the node nearest in time exceeds rho_m
// (tunnel seed 13: 1.05 rho_m just before the last node-switch instant). On moving segments the
// constant-speed floor is kept: there the arm ramps stretched the edges where the base creeps
// during an arm reconfiguration and made several forest / tunnel solves stall (measured).
std::vector<double> arm_edge_times(const std::vector<ReferenceSegment>& segments,
                                   const MidendLimits& limits, double f, const StartDerivatives& start) {
  std::vector<JointVector> dq;
  for (const ReferenceSegment& seg : segments) {
    for (std::size_t i = 0; i + 1 < seg.nodes.size(); ++i) dq.push_back(seg.nodes[i + 1].q_rad - seg.nodes[i].q_rad);
  }
  const std::size_t n = dq.size();
  std::vector<double> out(n, 0.0);
  std::vector<double> w(n + 1);
  for (int j = 0; j < kNumArmJoints; ++j) {
    const double cap = f * limits.joint_velocity_max_radps[j];
    const double acc = f * limits.joint_acceleration_max_radps2[j];
    for (std::size_t k = 0; k <= n; ++k) w[k] = k > 0 && k < n ? cap : 0.0;
    w[0] = std::min(cap, std::abs(start.velocity[2 + j]));  // the start's joint speed (0 at rest)
    for (std::size_t k = 0; k < n; ++k) w[k + 1] = std::min(w[k + 1], std::sqrt(w[k] * w[k] + 2.0 * acc * std::abs(dq[k][j])));
    for (std::size_t k = n; k-- > 0;) w[k] = std::min(w[k], std::sqrt(w[k + 1] * w[k + 1] + 2.0 * acc * std::abs(dq[k][j])));
    for (std::size_t k = 0; k < n; ++k) out[k] = std::max(out[k], ramp_time(std::abs(dq[k][j]), w[k], w[k + 1], acc, cap));
  }
  return out;
}

void allocate_times(std::vector<ReferenceSegment>& segments, const MidendLimits& limits,
                    const MidendSettings& settings, const StartDerivatives& start) {
  const double f = settings.initial_speed_fraction;
  const std::vector<double> arm_s = arm_edge_times(segments, limits, f, start);
  const double v_max = f * limits.max_base_speed_mps();
  const double yaw_rate_max = f * limits.max_base_yaw_rate_radps();
  const double a_max = f * limits.wheel_radius_m * limits.wheel_alpha_max_radps2;
  const double v_ns = std::min(limits.nonsingular_speed_mps, v_max);
  struct Edge {
    double length_m, floor_s, cap_mps;
  };
  std::vector<Edge> edges;
  std::vector<double> v_node;  // speed bound at every node (segment joints shared)
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const auto& nodes = segments[s].nodes;
    if (s == 0) v_node.push_back(std::min(v_max, start.velocity.head<2>().norm()));  // 0 at rest
    for (std::size_t i = 0; i + 1 < nodes.size(); ++i) {
      const RobotConfiguration& a = nodes[i];
      const RobotConfiguration& b = nodes[i + 1];
      Edge e;
      e.length_m = std::hypot(b.base.x_m - a.base.x_m, b.base.y_m - a.base.y_m);
      const double dyaw = std::abs(planner::angle_difference_rad(b.base.yaw_rad, a.base.yaw_rad));
      e.floor_s = std::max(settings.min_initial_piece_duration_s, dyaw / yaw_rate_max);
      if (segments[s].base_still) {
        e.floor_s = std::max(e.floor_s, arm_s[edges.size()]);
      } else {
        for (int j = 0; j < kNumArmJoints; ++j) {
          e.floor_s = std::max(e.floor_s, std::abs(b.q_rad[j] - a.q_rad[j]) /
                                              (f * limits.joint_velocity_max_radps[j]));
        }
      }
      const double curvature = e.length_m > 0.0 ? dyaw / e.length_m : 0.0;
      e.cap_mps = v_max / (1.0 + 0.5 * limits.track_width_m * curvature);
      e.cap_mps = std::min(e.cap_mps, e.length_m / e.floor_s);
      edges.push_back(e);
      const bool junction = i + 2 == nodes.size() && s + 1 < segments.size();
      const bool rest = junction && (segments[s].base_still || segments[s + 1].base_still);
      const bool goal = i + 2 == nodes.size() && s + 1 == segments.size();
      v_node.push_back(goal || rest ? 0.0 : junction ? v_ns : v_max);
    }
  }
  const std::size_t n = edges.size();
  for (std::size_t i = 0; i < n; ++i) {
    v_node[i] = std::min(v_node[i], edges[i].cap_mps);
    v_node[i + 1] = std::min(v_node[i + 1], edges[i].cap_mps);
  }
  for (std::size_t i = 0; i < n; ++i) {
    v_node[i + 1] = std::min(v_node[i + 1], std::sqrt(v_node[i] * v_node[i] + 2.0 * a_max * edges[i].length_m));
  }
  for (std::size_t i = n; i-- > 0;) {
    v_node[i] = std::min(v_node[i], std::sqrt(v_node[i + 1] * v_node[i + 1] + 2.0 * a_max * edges[i].length_m));
  }
  std::size_t k = 0;
  for (ReferenceSegment& seg : segments) {
    seg.durations_s.clear();
    for (int i = 0; i + 1 < static_cast<int>(seg.nodes.size()); ++i, ++k) {
      const double v_sum = v_node[k] + v_node[k + 1];
      const double t = v_sum > 0.0 ? 2.0 * edges[k].length_m / v_sum : edges[k].floor_s;
      seg.durations_s.push_back(std::max(t, edges[k].floor_s));
    }
  }
}

// Step 8: groups the edges of every segment into pieces. On entry seg.durations_s holds one
// duration per edge (allocate_times); on exit one per piece, with knots and node fractions.
void group_pieces(std::vector<ReferenceSegment>& segments, const MidendSettings& settings) {
  const int num_segments = static_cast<int>(segments.size());
  for (int s = 0; s < num_segments; ++s) {
    ReferenceSegment& seg = segments[s];
    const std::vector<double> edge_s = std::move(seg.durations_s);
    const int num_edges = static_cast<int>(edge_s.size());
    // The edge next to a gear switch is a piece of its own (densely sampled, base at v_ns); a
    // junction with a still segment is a rest instant like the goal, not a gear switch.
    const bool gear_before = s > 0 && !seg.base_still && !segments[s - 1].base_still;
    const bool gear_after = s + 1 < num_segments && !seg.base_still && !segments[s + 1].base_still;
    const int first_free = gear_before ? 1 : 0;
    const int last_free = gear_after ? num_edges - 1 : num_edges;
    seg.knots.assign(1, 0);
    double length = 0.0, arm = 0.0, first_s = 0.0;
    int edges = 0;
    for (int e = 0; e < num_edges; ++e) {
      const RobotConfiguration& a = seg.nodes[e];
      const RobotConfiguration& b = seg.nodes[e + 1];
      const double de = std::hypot(b.base.x_m - a.base.x_m, b.base.y_m - a.base.y_m);
      const double dq = (b.q_rad - a.q_rad).norm();
      const bool forced = e == first_free || e == last_free;  // gear edges stay alone
      // Edges of very different durations (the speed profile accelerating or braking, an arm
      // motion starting) are not merged: inside a piece the node fractions are fixed, and where
      // the profile changes the waypoints carry it into the initial guess.
      const double ratio = edges > 0 ? std::max(edge_s[e] / first_s, first_s / edge_s[e]) : 1.0;
      if (edges > 0 && (forced || length + de > settings.piece_length_m ||
                        arm + dq > settings.piece_arm_motion_rad ||
                        edges + 1 > settings.max_edges_per_piece ||
                        ratio > settings.piece_duration_ratio)) {
        seg.knots.push_back(e);
        length = arm = 0.0;
        edges = 0;
      }
      if (edges == 0) first_s = edge_s[e];
      length += de;
      arm += dq;
      ++edges;
    }
    seg.knots.push_back(num_edges);
    const int num_pieces = static_cast<int>(seg.knots.size()) - 1;
    seg.durations_s.assign(num_pieces, 0.0);
    seg.intervals.assign(num_pieces, 0);
    seg.node_fraction.assign(seg.nodes.size(), 0.0);
    for (int p = 0; p < num_pieces; ++p) {
      const int m = seg.knots[p + 1] - seg.knots[p];
      double total = 0.0;
      for (int e = seg.knots[p]; e < seg.knots[p + 1]; ++e) total += edge_s[e];
      const int by_time = settings.max_sample_interval_s > 0.0
                              ? static_cast<int>(std::ceil(total / settings.max_sample_interval_s))
                              : 0;
      int kappa = std::max({settings.samples_per_piece, settings.samples_per_edge * m, 2 * m, by_time});
      const bool gear = (gear_before && p == 0) || (gear_after && p + 1 == num_pieces);
      if (gear) kappa *= settings.gear_sample_factor;
      kappa += kappa % 2;  // even: the instants midway between nodes are samples
      kappa = std::min(kappa, std::max(ReferenceSegment::kMaxSamplesPerPiece, 2 * m));
      seg.intervals[p] = kappa;
      seg.durations_s[p] = total;
      // Node fractions on the grid 2 / kappa (in grid units g, out of kappa / 2), strictly
      // increasing and leaving room for the nodes still to place.
      const int grid = kappa / 2;
      double t = 0.0;
      int prev = 0;
      for (int e = seg.knots[p]; e + 1 < seg.knots[p + 1]; ++e) {
        t += edge_s[e];
        const int left = seg.knots[p + 1] - (e + 1);  // nodes after this one, the end included
        const int g = std::clamp(static_cast<int>(std::lround(t / total * grid)), prev + 1, grid - left);
        seg.node_fraction[e + 1] = 2.0 * g / kappa;
        prev = g;
      }
    }
  }
}

}  // namespace

ReferenceBuild build_reference_path(const planner::WholeBodyPath& path, const MidendLimits& limits,
                                    const MidendSettings& settings, const StartDerivatives& start) {
  ReferenceBuild out;
  const double tol = settings.coincident_tolerance;

  // 1-2. validate and join.
  std::vector<Segment> segs;
  for (std::size_t si = 0; si < path.segments.size(); ++si) {
    const planner::PathSegment& in = path.segments[si];
    if (in.eta != 1 && in.eta != -1) {
      out.outcome = ReferenceOutcome::kMalformed;
      out.message = "segment " + std::to_string(si) + ": eta is " + std::to_string(in.eta) +
                    ", expected +1 or -1";
      return out;
    }
    Segment s;
    s.eta = in.eta;
    for (std::size_t ni = 0; ni < in.nodes.size(); ++ni) {
      if (!finite_node(in.nodes[ni])) {
        out.outcome = ReferenceOutcome::kMalformed;
        out.message = "segment " + std::to_string(si) + " node " + std::to_string(ni) +
                      ": non-finite configuration or time";
        return out;
      }
      s.nodes.push_back({in.nodes[ni].config, in.nodes[ni].time_s});
    }
    if (s.nodes.empty()) continue;
    if (!segs.empty() && !coincident(segs.back().nodes.back(), s.nodes.front(), tol)) {
      s.nodes.insert(s.nodes.begin(), segs.back().nodes.back());
    }
    segs.push_back(std::move(s));
  }
  if (segs.empty()) {
    out.outcome = ReferenceOutcome::kEmpty;
    out.message = "the path has no nodes";
    return out;
  }

  // 3. coincident nodes.
  for (Segment& s : segs) drop_coincident(s, tol);

  // 4. zero-length segments: keep their arm motion, drop their gear switches.
  {
    std::vector<Segment> kept;
    std::vector<Node> carry;  // arm-only nodes preceding the first moving segment
    for (Segment& s : segs) {
      if (base_length(s) >= settings.min_segment_length_m) {
        if (!carry.empty()) {
          std::vector<Node> nodes = carry;
          nodes.insert(nodes.end(), s.nodes.begin(), s.nodes.end());
          s.nodes = std::move(nodes);
          carry.clear();
        }
        kept.push_back(std::move(s));
      } else if (!kept.empty()) {
        kept.back().nodes.insert(kept.back().nodes.end(), s.nodes.begin(), s.nodes.end());
      } else {
        carry.insert(carry.end(), s.nodes.begin(), s.nodes.end());
      }
    }
    if (kept.empty()) {
      Segment s;
      s.eta = segs.front().eta;
      s.nodes = std::move(carry);
      kept.push_back(std::move(s));
    }
    segs = std::move(kept);
  }

  // 5. merge equal directions, then drop the duplicates the joins created.
  {
    std::vector<Segment> merged;
    for (Segment& s : segs) {
      if (!merged.empty() && merged.back().eta == s.eta) {
        merged.back().nodes.insert(merged.back().nodes.end(), s.nodes.begin(), s.nodes.end());
      } else {
        merged.push_back(std::move(s));
      }
    }
    segs = std::move(merged);
    for (Segment& s : segs) drop_coincident(s, tol);
  }

  if (segs.size() == 1 && segs.front().nodes.size() == 1) {
    out.outcome = ReferenceOutcome::kNoMotion;
    out.message = "every node of the path coincides";
    out.single = segs.front().nodes.front().config;
    return out;
  }

  // 5a. creeping ends without arm motion: a node next to the goal (start) within
  // 0.1 still_max_base_m (1 cm by default), still_max_yaw_rad and still_min_arm_rad of it is
  // dropped (longer edges, e.g. tunnel's 5 cm last edge with a 0.12 rad heading change, stay
  // reference edges: the back-end's frozen fixtures rely on that piece structure). Kept, a
  // millimetre edge into the rest state makes the interpolating quintic overshoot the goal and
  // come back (forest seed 17: 2 mm, base reversal and the rest-boundary heading term stuck at
  // its maximum, where its gradient vanishes).
  if (settings.still_max_base_m > 0.0) {
    auto close = [&](const Node& a, const Node& b) {
      return base_distance(a, b) <= 0.1 * settings.still_max_base_m &&
             std::abs(planner::angle_difference_rad(b.config.base.yaw_rad, a.config.base.yaw_rad)) <= settings.still_max_yaw_rad &&
             (b.config.q_rad - a.config.q_rad).norm() < settings.still_min_arm_rad;
    };
    std::vector<Node>& last = segs.back().nodes;
    if (last.size() >= 3 && close(last[last.size() - 2], last.back())) last.erase(last.end() - 2);
    std::vector<Node>& first = segs.front().nodes;
    if (first.size() >= 3 && close(first[1], first.front())) first.erase(first.begin() + 1);
  }

  // 5b. still ends: the base rests at the goal (start) while the arm finishes (starts).
  if (settings.still_max_base_m > 0.0) {
    Segment still;
    const int tail = still_tail_start(segs.back().nodes, settings);
    if (tail > 0 && split_still(segs.back(), tail, true, settings, &still)) segs.push_back(std::move(still));
    std::vector<Node> reversed(segs.front().nodes.rbegin(), segs.front().nodes.rend());
    // Not while the base moves at the start: it cannot rest there.
    const int head = segs.front().still || !start.base_at_rest() ? -1 : still_tail_start(reversed, settings);
    Segment still_head;
    if (head > 0 && split_still(segs.front(), head, false, settings, &still_head)) {
      segs.insert(segs.begin(), std::move(still_head));
    }
  }

  // 6-8. densify, allocate time, group edges into pieces.
  const std::size_t num_segs = segs.size();
  for (std::size_t si = 0; si < num_segs; ++si) {
    const Segment& s = segs[si];
    ReferenceSegment r;
    r.eta = s.eta;
    r.base_still = s.still;
    r.nodes.push_back(s.nodes.front().config);
    for (std::size_t i = 1; i < s.nodes.size(); ++i) {
      const Node& a = s.nodes[i - 1];
      const Node& b = s.nodes[i];
      const double dyaw = planner::angle_difference_rad(b.config.base.yaw_rad, a.config.base.yaw_rad);
      const double db = std::sqrt(base_distance(a, b) * base_distance(a, b) +
                                  settings.residual_yaw_weight_m2 * dyaw * dyaw);
      const double dq = (b.config.q_rad - a.config.q_rad).norm();
      const std::vector<double> fractions =
          densify_fractions(db / settings.residual_base_bound_m, dq / settings.residual_arm_bound_rad, settings);
      for (std::size_t k = 0; k < fractions.size(); ++k) {
        const Node n = k + 1 == fractions.size() ? b : interpolate(a, b, fractions[k]);
        r.nodes.push_back(n.config);
      }
    }
    out.path.segments.push_back(std::move(r));
  }
  out.path.start = start;
  allocate_times(out.path.segments, limits, settings, start);
  group_pieces(out.path.segments, settings);
  out.outcome = ReferenceOutcome::kOk;
  return out;
}

}  // namespace porter::midend
