#include "porter/backend/piece_window.hpp"

#include <algorithm>
#include <utility>

namespace porter::backend {
namespace {

/// Per global piece: its segment.
std::vector<int> segment_of_pieces(const midend::ReferencePath& reference) {
  std::vector<int> out;
  for (std::size_t s = 0; s < reference.segments.size(); ++s) {
    out.insert(out.end(), static_cast<std::size_t>(reference.segments[s].num_pieces()), static_cast<int>(s));
  }
  return out;
}

/// The first global piece of segment s.
int first_piece_of(const midend::ReferencePath& reference, int s) {
  int n = 0;
  for (int k = 0; k < s; ++k) n += reference.segments[static_cast<std::size_t>(k)].num_pieces();
  return n;
}

}  // namespace

std::vector<bool> flag_pieces(const Trajectory& trajectory, const planner::TrajectoryAcceptance& acceptance) {
  std::vector<bool> flagged(static_cast<std::size_t>(trajectory.num_pieces()), false);
  for (int i = 0; i < trajectory.num_pieces(); ++i) {
    const std::optional<Trajectory> one = cut_window(trajectory, PieceWindow{i, i + 1});
    flagged[static_cast<std::size_t>(i)] = !one || !acceptance.check(*one).accepted;
  }
  return flagged;
}

PieceWindow grow_window(const PieceWindow& w, const midend::ReferencePath& reference, int grow) {
  const std::vector<int> seg = segment_of_pieces(reference);
  if (w.size() <= 0 || w.first < 0 || w.last > static_cast<int>(seg.size())) return w;
  const int s = seg[static_cast<std::size_t>(w.first)];
  const int lo = first_piece_of(reference, s);
  const int hi = lo + reference.segments[static_cast<std::size_t>(s)].num_pieces();
  return PieceWindow{std::max(lo, w.first - grow), std::min(hi, w.last + grow)};
}

std::vector<PieceWindow> windows_around(const std::vector<bool>& flagged, const midend::ReferencePath& reference,
                                        int grow) {
  const std::vector<int> seg = segment_of_pieces(reference);
  std::vector<PieceWindow> out;
  if (flagged.size() != seg.size()) return out;
  const int n = static_cast<int>(flagged.size());
  for (int i = 0; i < n;) {
    if (!flagged[static_cast<std::size_t>(i)]) {
      ++i;
      continue;
    }
    const int s = seg[static_cast<std::size_t>(i)];
    if (reference.segments[static_cast<std::size_t>(s)].base_still) return {};
    int j = i;  // the run of flagged pieces within segment s
    while (j < n && flagged[static_cast<std::size_t>(j)] && seg[static_cast<std::size_t>(j)] == s) ++j;
    PieceWindow w = grow_window(PieceWindow{i, j}, reference, grow);
    if (!out.empty() && seg[static_cast<std::size_t>(out.back().first)] == s && out.back().last >= w.first) {
      out.back().last = std::max(out.back().last, w.last);  // touching or overlapping: merged
    } else {
      out.push_back(w);
    }
    i = j;
  }
  return out;
}

std::optional<midend::ReferencePath> window_reference(const midend::ReferencePath& reference,
                                                      const Trajectory& current, const PieceWindow& w,
                                                      double cut_jerk_weight) {
  const std::vector<int> seg = segment_of_pieces(reference);
  if (w.size() <= 0 || w.first < 0 || w.last > static_cast<int>(seg.size()) ||
      current.num_pieces() != static_cast<int>(seg.size()))
    return std::nullopt;
  const int s = seg[static_cast<std::size_t>(w.first)];
  if (seg[static_cast<std::size_t>(w.last - 1)] != s) return std::nullopt;
  const midend::ReferenceSegment& full = reference.segments[static_cast<std::size_t>(s)];
  if (full.base_still) return std::nullopt;
  const int a = w.first - first_piece_of(reference, s);  // the window's pieces in the segment
  const int b = a + w.size();
  const int n0 = full.knots[static_cast<std::size_t>(a)];
  const int n1 = full.knots[static_cast<std::size_t>(b)];

  midend::ReferenceSegment out;
  out.eta = full.eta;
  out.base_still = false;
  out.nodes.assign(full.nodes.begin() + n0, full.nodes.begin() + n1 + 1);
  out.node_fraction.assign(full.node_fraction.begin() + n0, full.node_fraction.begin() + n1 + 1);
  out.node_fraction.back() = 0.0;  // a knot
  for (int p = a; p <= b; ++p) out.knots.push_back(full.knots[static_cast<std::size_t>(p)] - n0);
  out.durations_s.assign(full.durations_s.begin() + a, full.durations_s.begin() + b);
  out.intervals.assign(full.intervals.begin() + a, full.intervals.begin() + b);

  // The cuts: the held trajectory's state there is the window's start and end; the nodes stay
  // the reference's (the pose residuals' targets, as in the whole problem).
  const TrajectoryPiece& first = current.piece(w.first);
  const TrajectoryPiece& last = current.piece(w.last - 1);

  midend::ReferencePath path;
  path.cut_start_position = piece_derivative(first.coeffs, 0.0, 0);
  path.cut_start_yaw_rad = current.yaw_rad(current.piece_start_time_s(w.first));
  path.start.velocity = piece_derivative(first.coeffs, 0.0, 1);
  path.start.acceleration = piece_derivative(first.coeffs, 0.0, 2);
  path.cut_end_position = piece_derivative(last.coeffs, last.duration_s, 0);
  path.end.velocity = piece_derivative(last.coeffs, last.duration_s, 1);
  path.end.acceleration = piece_derivative(last.coeffs, last.duration_s, 2);
  // Where the whole problem pins the state, the window takes the pinned values, not the
  // trajectory's (equal up to the MINCO solve's rounding, but a base "at rest" to 1e-17 is not at
  // rest to the problem): the plan's start and goal are no cuts at all, and at a rest junction
  // the base's velocity and acceleration are exactly zero.
  const int segment_first = w.first - a;
  const int segment_last = segment_first + full.num_pieces();
  if (w.first == segment_first) {
    if (s == 0) {
      path.cut_start_position.reset();
      path.start = reference.start;
    } else if (reference.segments[static_cast<std::size_t>(s - 1)].base_still) {
      path.start.velocity.head<2>().setZero();
      path.start.acceleration.head<2>().setZero();
    }
  }
  if (w.last == segment_last) {
    if (s + 1 == static_cast<int>(reference.segments.size())) {
      path.cut_end_position.reset();
      path.end = reference.end;
    } else if (reference.segments[static_cast<std::size_t>(s + 1)].base_still) {
      path.end.velocity.head<2>().setZero();
      path.end.acceleration.head<2>().setZero();
    }
  }
  // The held side's base jerk at each cut (header comment "Cuts").
  path.cut_jerk_weight = cut_jerk_weight;
  if (path.cut_start_position && w.first > 0) {
    const TrajectoryPiece& held = current.piece(w.first - 1);
    path.cut_start_base_jerk = piece_derivative(held.coeffs, held.duration_s, 3).head<2>();
  }
  if (path.cut_end_position && w.last < current.num_pieces()) {
    path.cut_end_base_jerk = piece_derivative(current.piece(w.last).coeffs, 0.0, 3).head<2>();
  }
  path.segments.push_back(std::move(out));
  return path;
}

std::optional<Trajectory> cut_window(const Trajectory& t, const PieceWindow& w) {
  if (w.size() <= 0 || w.first < 0 || w.last > t.num_pieces()) return std::nullopt;
  std::vector<TrajectoryPiece> pieces(t.pieces().begin() + w.first, t.pieces().begin() + w.last);
  TrajectoryResult r = Trajectory::create(std::move(pieces), t.yaw_rad(t.piece_start_time_s(w.first)));
  return std::move(r.trajectory);
}

std::optional<Trajectory> splice(const Trajectory& full, const PieceWindow& w, const Trajectory& window) {
  if (w.size() <= 0 || w.first < 0 || w.last > full.num_pieces() || window.num_pieces() != w.size())
    return std::nullopt;
  std::vector<TrajectoryPiece> pieces = full.pieces();
  std::copy(window.pieces().begin(), window.pieces().end(), pieces.begin() + w.first);
  TrajectoryResult r = Trajectory::create(std::move(pieces), full.start_yaw_rad());
  return std::move(r.trajectory);
}

}  // namespace porter::backend
