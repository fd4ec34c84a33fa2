#pragma once
// Piece windows: the back-end re-optimizes only the pieces around the places where the
// acceptance test finds the trajectory in collision, with every other piece held exactly as it is
// (BackendSettings::window_grow_pieces).
//
// Localisation: each piece of the trajectory is checked on its own (a one-piece trajectory with
// the piece's coefficients, which are in the piece's own time) by the acceptance test; a piece it
// rejects is flagged. Every check covers the piece's whole time span, so a trajectory whose pieces
// all pass would pass as a whole.
// Windows: each maximal run of flagged pieces grown by `grow` pieces on each side, runs that then
// touch or overlap merged, each cut at gear-segment boundaries (a window lies inside one moving
// segment; a still segment, where only the arm moves, is not windowed: a window never contains
// one of its pieces). Why the neighbours: the window's end states are held (position, velocity and
// acceleration of every coordinate, the full trajectory's at the cut), so a flagged piece at a
// window end could not move its end at all; with one piece of room on each side the detour can
// leave and rejoin the path.
// The window's problem (window_reference): the mid-end's problem over the window's reference
// nodes, with the held trajectory's state at both cuts as its start and end
// (ReferencePath::start / end), the full reference's initial durations (so the min-speed and
// sample settings of each piece are the full problem's) and the window's own time scale. Its
// trajectory starts at the held trajectory's heading at the first cut. Spliced back (splice()),
// the window's pieces replace the originals; the whole trajectory stays C^2 at the cuts (the end
// states are the held ones); jerk and higher may jump there.
// The fixed pieces' penalties are constants of the window's problem: they are not evaluated.
// Cuts: a window's pieces are quintics that hold position, velocity and acceleration at each cut,
// not the jerk, so the base's jerk may jump there and with it the yaw acceleration and the wheel
// accelerations (measured before the term below: wheel accelerations 7-27 % over their limit at
// cuts on forest). With a weight > 0 the window's problem pulls the base's jerk at each cut towards
// the held side's (ReferencePath::cut_jerk_weight; zero at a window's first evaluation, since the
// whole trajectory is C^4 there).
//
// Pure functions; thread-safe.

#include <optional>
#include <vector>

#include "porter/core/trajectory.hpp"
#include "porter/midend/reference_path.hpp"
#include "porter/planner/trajectory_acceptance.hpp"

namespace porter::backend {

/// Pieces [first, last) of a trajectory (global piece indices, segment after segment).
struct PieceWindow {
  int first = 0;
  int last = 0;
  int size() const { return last - first; }
  bool operator==(const PieceWindow& o) const { return first == o.first && last == o.last; }
};

/// Per piece of `trajectory`: whether `acceptance` rejects the piece checked on its own.
std::vector<bool> flag_pieces(const Trajectory& trajectory, const planner::TrajectoryAcceptance& acceptance);

/// The windows around the flagged pieces of a trajectory of `reference` (header comment), in
/// order. Empty when nothing is flagged or a flagged piece lies on a still segment (there is no
/// moving segment to window).
std::vector<PieceWindow> windows_around(const std::vector<bool>& flagged, const midend::ReferencePath& reference,
                                        int grow);

/// `w` grown by `grow` pieces on each side, within its segment (unchanged at the segment's ends).
PieceWindow grow_window(const PieceWindow& w, const midend::ReferencePath& reference, int grow);

/// The mid-end reference of window `w` of `current` (a trajectory of `reference`; header comment),
/// nullopt when w is empty, crosses a segment boundary or lies on a still segment.
/// `cut_jerk_weight`: ReferencePath::cut_jerk_weight (header comment "Cuts").
std::optional<midend::ReferencePath> window_reference(const midend::ReferencePath& reference,
                                                      const Trajectory& current, const PieceWindow& w,
                                                      double cut_jerk_weight = 0.0);

/// Pieces [w.first, w.last) of `t` as a trajectory of their own, starting at t's heading there.
std::optional<Trajectory> cut_window(const Trajectory& t, const PieceWindow& w);

/// `full` with pieces [w.first, w.last) replaced by `window`'s (w.size() pieces).
std::optional<Trajectory> splice(const Trajectory& full, const PieceWindow& w, const Trajectory& window);

}  // namespace porter::backend
