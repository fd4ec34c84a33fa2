#include "loop_io.hpp"

#include <cstdio>
#include <type_traits>
#include <utility>

namespace porter::tracker_app {

void apply_input(tracker::Tracker& tracker, InputEvent& event, std::vector<LogLine>& log) {
  using runtime::LogLevel;
  std::visit(
      [&](auto& e) {
        using E = std::decay_t<decltype(e)>;
        if constexpr (std::is_same_v<E, StateInput>) {
          tracker.on_state(e.state, e.receive_utime);
        } else if constexpr (std::is_same_v<E, TrajectoryInput>) {
          const std::int64_t plan_id = e.offer.plan_id;
          const double duration_s = e.offer.trajectory.total_duration_s();
          const int num_pieces = e.offer.trajectory.num_pieces();
          const double lead_s = static_cast<double>(e.offer.start_utime - e.receive_utime) * 1e-6;
          const auto r = tracker.on_trajectory(std::move(e.offer), e.receive_utime);
          if (!r.accepted) {
            log.push_back({LogLevel::warn, tracker.last_refusal()});
            return;
          }
          char b[160];
          std::snprintf(b, sizeof b, "plan %lld accepted: %d pieces, %.2f s, starts in %.3f s",
                        static_cast<long long>(plan_id), num_pieces, duration_s, lead_s);
          log.push_back({LogLevel::info, b});
        } else if constexpr (std::is_same_v<E, InvalidTrajectoryInput>) {
          tracker.on_invalid_trajectory(e.plan_id, e.error);
          log.push_back({LogLevel::warn, tracker.last_refusal()});
        } else if constexpr (std::is_same_v<E, EstopInput>) {
          const bool was = tracker.estop_latched();
          tracker.on_estop(e.active, e.source + ": " + e.reason, e.receive_utime);
          if (was != tracker.estop_latched()) {
            log.push_back({LogLevel::warn,
                           std::string(e.active ? "ESTOP engaged by " : "ESTOP released by ") +
                               e.source + (e.reason.empty() ? "" : " (" + e.reason + ")")});
          }
        }
      },
      event);
}

LogLine state_change_line(const tracker::TrackerOutput& out) {
  using tracker::TrackerState;
  std::string text = std::string("state ") + tracker::to_string(out.state) +
                     (out.message.empty() ? "" : ": " + out.message) + " (plan " +
                     std::to_string(out.plan_id) + ")";
  const bool normal = out.state == TrackerState::tracking || out.state == TrackerState::finished ||
                      out.state == TrackerState::idle;
  return {normal ? runtime::LogLevel::info : runtime::LogLevel::warn, std::move(text)};
}

}  // namespace porter::tracker_app
