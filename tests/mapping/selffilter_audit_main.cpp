// porter-selffilter-audit: how the mapper's self-filter did on a recorded run of the simulated
// stack on a scene without obstacles (every return above the ground is then a hit on the robot
// or its payload).
//
//   porter-selffilter-audit --log RUN.lcmlog [--payload FILE|none] [--config porter_mapper.yaml]
//                           [--ground-z M]
//
// Reads LIDAR_POINTS, ROBOT_STATE and SIM_TRUTH (porter-sim's ground truth) with their receive
// times, and prints:
//   - time bases: ROBOT_STATE's base pose and joint angles against SIM_TRUTH, with the time
//     shift that fits them best (the joints once by utime, once by arm_utime), the states
//     without joints, and the clouds' stamps against their arrival;
//   - the self-filter, run three ways over every cloud: "utime, held" (the state buffer as
//     porter-mapper kept it before: the joints on ROBOT_STATE.utime, a state without joints as
//     q = 0, a cloud waiting 0.05 s for its state and then filtered with what was there),
//     "arm_utime, covered" (as porter-mapper does now: joints on arm_utime, a cloud integrated
//     only when the states up to state.wait_s (state time) after its last point cover it, else
//     dropped) and "truth"
//     (SIM_TRUTH; then SIM_TRUTH shifted to the best fit): self hits (returns more than
//     --ground-z above the ground), removed, kept, and the occupied voxels left in a map built
//     from the filtered clouds (each is a phantom: the scene holds nothing).
// Exit codes: 0 done, 2 bad arguments or config, 3 unreadable log or nothing to audit.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>
#include <octomap/OcTree.h>

#include <sstream>

#include "mapper_conversions.hpp"
#include "mapper_params.hpp"
#include "porter/channels.hpp"
#include "porter/core/load_error.hpp"
#include "porter/core/payload.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/mapping/mapper.hpp"
#include "porter/octomap_t.hpp"
#include "porter/point_cloud_t.hpp"
#include "porter/robot_state_t.hpp"

namespace pm = porter::mapping;

namespace {

struct Received {
  std::int64_t rx_us = 0;  // logger's receive time
  porter::robot_state_t msg;
};
struct Cloud {
  std::int64_t rx_us = 0;
  std::int64_t start_us = 0, end_us = 0;
  pm::SensorCloud cloud;
};
struct Truth {
  std::int64_t t_us;
  porter::RobotConfiguration c;
  double qd_max;  // largest joint speed, rad/s
};

porter::RobotConfiguration truth_at(const std::vector<Truth>& truth, std::int64_t t_us) {
  const auto it = std::lower_bound(truth.begin(), truth.end(), t_us, [](const Truth& s, std::int64_t t) { return s.t_us < t; });
  if (it == truth.begin()) return truth.front().c;
  if (it == truth.end()) return truth.back().c;
  const Truth& a = *(it - 1);
  const Truth& b = *it;
  return pm::interpolate_configuration(a.c, b.c, static_cast<double>(t_us - a.t_us) / static_cast<double>(b.t_us - a.t_us));
}

template <class Msg>
bool decode(const lcm::LogEvent& e, Msg& m) {
  return m.decode(e.data, 0, static_cast<int>(e.datalen)) >= 0;
}

// Fit of a stamped series against the truth: RMS of the largest joint error (or position error)
// over the samples, with the stamps shifted by d (truth at stamp + d).
template <class Err>
void fit(const char* what, Err err, std::size_t n) {
  if (n == 0) {
    std::printf("  %s: no samples while moving\n", what);
    return;
  }
  auto rms = [&](std::int64_t d_us) {
    double s = 0.0, mx = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double e = err(i, d_us);
      s += e * e;
      mx = std::max(mx, e);
    }
    return std::make_pair(std::sqrt(s / static_cast<double>(n)), mx);
  };
  const auto at0 = rms(0);
  std::int64_t best = 0;
  double best_rms = at0.first;
  for (std::int64_t d = -300'000; d <= 100'000; d += 1000) {
    const double r = rms(d).first;
    if (r < best_rms) best_rms = r, best = d;
  }
  const auto at_best = rms(best);
  std::printf("  %s over %zu samples: RMS %.4f, max %.4f as stamped; best fit with the truth %+.0f ms later "
              "than the stamp: RMS %.4f, max %.4f\n",
              what, n, at0.first, at0.second, best * 1e-3, at_best.first, at_best.second);
}

struct Result {
  std::uint64_t clouds = 0, dropped = 0, self_hits = 0, removed = 0, clouds_with_kept = 0, kept_max = 0;
  std::int64_t occupied_max = 0, occupied_final = 0, clouds_with_phantoms = 0;
};

}  // namespace

int main(int argc, char** argv) {
  std::string log_path, payload_path, config_path = PORTER_SOURCE_DIR "/config/mapping/porter_mapper.yaml";
  bool payload_given = false;
  double ground_z = 0.03;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--log" && i + 1 < argc) {
      log_path = argv[++i];
    } else if (a == "--payload" && i + 1 < argc) {
      payload_path = argv[++i];
      payload_given = true;
    } else if (a == "--config" && i + 1 < argc) {
      config_path = argv[++i];
    } else if (a == "--ground-z" && i + 1 < argc) {
      ground_z = std::atof(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: porter-selffilter-audit --log LOG [--payload FILE|none] [--config FILE] [--ground-z M]\n");
      return 2;
    }
  }
  if (log_path.empty()) {
    std::fprintf(stderr, "porter-selffilter-audit: --log is required\n");
    return 2;
  }
  pm::app::MapperConfig cfg;
  porter::RobotModel robot;
  try {
    cfg = pm::app::load_mapper_config(config_path);
    if (payload_given) cfg.payload_yaml = payload_path == "none" ? "" : payload_path;
    robot = porter::load_robot_model(cfg.robot_yaml);
    if (!cfg.payload_yaml.empty()) robot = porter::attach_payload(robot, porter::load_payload(cfg.payload_yaml));
  } catch (const porter::LoadError& e) {
    std::fprintf(stderr, "porter-selffilter-audit: %s\n", e.what());
    return 2;
  }

  lcm::LogFile log(log_path, "r");
  if (!log.good()) {
    std::fprintf(stderr, "porter-selffilter-audit: cannot read %s\n", log_path.c_str());
    return 3;
  }
  std::vector<Truth> truth;
  std::vector<double> truth_delay_ms;  // receive time - stamp of SIM_TRUTH
  std::vector<Received> states;
  std::vector<Cloud> clouds;
  std::vector<std::int64_t> map_phantoms;  // occupied voxels of each recorded MAP_OCTOMAP
  for (const lcm::LogEvent* e = log.readNextEvent(); e != nullptr; e = log.readNextEvent()) {
    if (e->channel == porter::channels::kSimTruth.name()) {
      porter::robot_state_t m;
      if (!decode(*e, m) || m.num_joints != porter::kNumArmJoints) continue;
      Truth t{m.utime, {}, 0.0};
      t.c.base = {m.x_m, m.y_m, m.yaw_rad};
      for (int j = 0; j < porter::kNumArmJoints; ++j) {
        t.c.q_rad[j] = m.q_rad[static_cast<std::size_t>(j)];
        t.qd_max = std::max(t.qd_max, std::abs(m.qd_radps[static_cast<std::size_t>(j)]));
      }
      if (truth.empty() || t.t_us > truth.back().t_us) truth.push_back(t);
      truth_delay_ms.push_back((e->timestamp - m.utime) * 1e-3);
    } else if (e->channel == porter::channels::kRobotState.name()) {
      Received r;
      r.rx_us = e->timestamp;
      if (decode(*e, r.msg)) states.push_back(std::move(r));
    } else if (e->channel == porter::channels::kMapOctomap.name()) {
      porter::octomap_t m;
      if (!decode(*e, m) || !m.binary) continue;
      octomap::OcTree tree(m.resolution_m);
      std::istringstream in(std::string(m.data.begin(), m.data.end()));
      if (!tree.readBinaryData(in)) continue;
      std::int64_t occupied = 0;
      for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
        if (!tree.isNodeOccupied(*it)) continue;
        const std::int64_t side = std::int64_t{1} << (tree.getTreeDepth() - it.getDepth());
        occupied += side * side * side;
      }
      map_phantoms.push_back(occupied);
    } else if (e->channel == porter::channels::kLidarPoints.name()) {
      porter::point_cloud_t m;
      Cloud c;
      std::string why;
      if (!decode(*e, m) || !pm::app::to_sensor_cloud(m, c.cloud, why) || c.cloud.size() == 0) continue;
      c.rx_us = e->timestamp;
      const auto [lo, hi] = std::minmax_element(c.cloud.time_offset_ns.begin(), c.cloud.time_offset_ns.end());
      c.start_us = c.cloud.utime + *lo / 1000;
      c.end_us = c.cloud.utime + *hi / 1000;
      clouds.push_back(std::move(c));
    }
  }
  if (truth.size() < 2 || states.empty() || clouds.empty()) {
    std::fprintf(stderr, "porter-selffilter-audit: %s holds %zu SIM_TRUTH, %zu ROBOT_STATE, %zu LIDAR_POINTS\n",
                 log_path.c_str(), truth.size(), states.size(), clouds.size());
    return 3;
  }
  std::printf("log %s: %zu SIM_TRUTH, %zu ROBOT_STATE, %zu clouds; robot %s%s\n", log_path.c_str(), truth.size(),
              states.size(), clouds.size(), robot.name.c_str(),
              robot.payload_name.empty() ? "" : (" with " + robot.payload_name).c_str());

  // Time bases.
  std::printf("time bases (SIM_TRUTH is the simulator's own clock):\n");
  {
    std::size_t no_joints = 0;
    std::int64_t last_no_joints_rx = 0;
    std::vector<std::size_t> moving;  // states with joints while the arm moves (> 0.05 rad/s)
    std::vector<std::size_t> base_moving;
    for (std::size_t i = 0; i < states.size(); ++i) {
      const porter::robot_state_t& m = states[i].msg;
      if (m.num_joints != porter::kNumArmJoints) {
        ++no_joints;
        last_no_joints_rx = states[i].rx_us;
        continue;
      }
      const auto it = std::lower_bound(truth.begin(), truth.end(), m.utime, [](const Truth& s, std::int64_t t) { return s.t_us < t; });
      if (it != truth.end() && it->qd_max > 0.05) moving.push_back(i);
      if (std::abs(m.v_mps) > 0.05 || std::abs(m.omega_radps) > 0.05) base_moving.push_back(i);
    }
    std::printf("  ROBOT_STATE without joints (num_joints 0, the arm unknown): %zu", no_joints);
    if (no_joints > 0) std::printf(", the last %.3f s after the first cloud arrived", (last_no_joints_rx - clouds.front().rx_us) * 1e-6);
    std::printf("\n");
    auto q_err = [&](bool by_arm_utime) {
      return [&, by_arm_utime](std::size_t k, std::int64_t d) {
        const porter::robot_state_t& m = states[moving[k]].msg;
        const std::int64_t t = (by_arm_utime && m.arm_utime != 0 ? m.arm_utime : m.utime) + d;
        const porter::RobotConfiguration c = truth_at(truth, t);
        double e = 0.0;
        for (int j = 0; j < porter::kNumArmJoints; ++j) e = std::max(e, std::abs(m.q_rad[static_cast<std::size_t>(j)] - c.q_rad[j]));
        return e;
      };
    };
    fit("joint angles (rad, largest joint) on utime", q_err(false), moving.size());
    fit("joint angles (rad, largest joint) on arm_utime", q_err(true), moving.size());
    fit("base position (m) on utime", [&](std::size_t k, std::int64_t d) {
      const porter::robot_state_t& m = states[base_moving[k]].msg;
      const porter::RobotConfiguration c = truth_at(truth, m.utime + d);
      return std::hypot(m.x_m - c.base.x_m, m.y_m - c.base.y_m);
    }, base_moving.size());
    auto stats = [](const char* what, std::vector<double> v) {
      if (v.empty()) return;
      std::sort(v.begin(), v.end());
      std::printf("  %s: min %.1f, median %.1f, p95 %.1f, max %.1f ms\n", what, v.front(), v[v.size() / 2],
                  v[v.size() * 95 / 100], v.back());
    };
    std::vector<double> lag, state_delay, uncovered;
    for (const Received& s : states) state_delay.push_back((s.rx_us - s.msg.utime) * 1e-3);
    std::size_t k = 0;
    std::int64_t newest = 0;
    for (const Cloud& c : clouds) {
      lag.push_back((c.rx_us - c.end_us) * 1e-3);
      for (; k < states.size() && states[k].rx_us <= c.rx_us; ++k) newest = std::max(newest, states[k].msg.utime);
      uncovered.push_back((c.end_us - newest) * 1e-3);
    }
    stats("SIM_TRUTH receive time - stamp (the simulator behind the wall clock)", truth_delay_ms);
    stats("ROBOT_STATE receive time - utime", state_delay);
    stats("LIDAR_POINTS receive time - last point's time", lag);
    stats("cloud's last point - newest ROBOT_STATE utime at the cloud's arrival", uncovered);
  }

  if (!map_phantoms.empty()) {
    std::int64_t mx = 0, with = 0;
    for (std::int64_t n : map_phantoms) mx = std::max(mx, n), with += n > 0;
    std::printf("recorded MAP_OCTOMAP (porter-mapper of the run): %zu maps, %lld with occupied voxels (phantoms), "
                "at most %lld, in the last %lld\n", map_phantoms.size(), static_cast<long long>(with),
                static_cast<long long>(mx), static_cast<long long>(map_phantoms.back()));
  }

  // The self-filter three (four) ways.
  pm::MapperParams params = cfg.mapper;
  auto run = [&](const char* name, auto make_states, bool integrate = true) {
    pm::Mapper mapper(robot, params);
    Result r;
    for (const Cloud& c : clouds) {
      pm::StateBuffer buf(cfg.state_history_s);
      if (!make_states(c, buf)) {
        ++r.dropped;
        continue;
      }
      ++r.clouds;
      pm::FilteredCloud f;
      std::vector<std::uint8_t> removed;
      mapper.filter(c.cloud, buf, f, &removed);
      std::uint64_t kept = 0;
      const Eigen::Isometry3d& T = params.T_B_S;
      for (std::size_t i = 0; i < c.cloud.size(); ++i) {
        const Eigen::Vector3d p_B = T * Eigen::Vector3d(c.cloud.x_m[i], c.cloud.y_m[i], c.cloud.z_m[i]);
        if (p_B.z() <= ground_z || (p_B - T.translation()).norm() < params.min_range_m) continue;
        ++r.self_hits;
        r.removed += removed[i];
        kept += !removed[i];
      }
      r.clouds_with_kept += kept > 0;
      r.kept_max = std::max(r.kept_max, kept);
      if (!integrate) continue;
      mapper.integrate(f);
      const std::int64_t occ = mapper.map().count(pm::VoxelState::occupied);
      r.occupied_max = std::max(r.occupied_max, occ);
      r.occupied_final = occ;
      r.clouds_with_phantoms += occ > 0;
    }
    if (!integrate) return r;
    std::printf("  %-34s clouds %4llu (dropped %3llu): self hits %8llu, removed %8llu (%.4f %%), kept %6llu in %llu clouds "
                "(at most %llu in one); occupied voxels (phantoms) max %lld, at the end %lld, after %lld clouds\n",
                name, static_cast<unsigned long long>(r.clouds), static_cast<unsigned long long>(r.dropped),
                static_cast<unsigned long long>(r.self_hits), static_cast<unsigned long long>(r.removed),
                r.self_hits ? 100.0 * static_cast<double>(r.removed) / static_cast<double>(r.self_hits) : 100.0,
                static_cast<unsigned long long>(r.self_hits - r.removed), static_cast<unsigned long long>(r.clouds_with_kept),
                static_cast<unsigned long long>(r.kept_max), static_cast<long long>(r.occupied_max),
                static_cast<long long>(r.occupied_final), static_cast<long long>(r.clouds_with_phantoms));
    return r;
  };
  std::printf("self-filter (margin %.3f m) over every cloud; self hit = a return more than %.3f m above the ground:\n",
              params.self.margin_m, ground_z);
  // Before: one track on utime, q = 0 when a state has no joints, 0.05 s wait then held.
  run("utime, held (before)", [&](const Cloud& c, pm::StateBuffer& buf) {
    for (const Received& s : states) {
      if (s.rx_us > c.rx_us + 50'000) break;
      porter::RobotConfiguration k;
      k.base = {s.msg.x_m, s.msg.y_m, s.msg.yaw_rad};
      for (int j = 0; j < s.msg.num_joints && j < porter::kNumArmJoints; ++j) k.q_rad[j] = s.msg.q_rad[static_cast<std::size_t>(j)];
      buf.add(s.msg.utime, k);
    }
    return true;
  });
  // Now: porter-mapper's own conversion and rule.
  run("arm_utime, covered (now)", [&](const Cloud& c, pm::StateBuffer& buf) {
    const std::int64_t deadline_us = c.end_us + static_cast<std::int64_t>(cfg.state_wait_s * 1e6);
    for (const Received& s : states) {
      pm::app::StateSample k;
      std::string why;
      if (!pm::app::to_state_sample(s.msg, k, why)) continue;
      buf.add_base(k.utime, k.base);
      if (k.has_arm) buf.add_arm(k.arm_utime, k.q_rad, k.utime);
      if (k.utime > deadline_us) break;  // the states have passed the cloud by state.wait_s
    }
    return buf.covers_by(c.start_us, c.end_us, deadline_us) == pm::StateBuffer::Cover::yes;
  });
  auto truth_run = [&](const char* name, std::int64_t shift_us, bool integrate = true) {
    return run(name, [&, shift_us](const Cloud& c, pm::StateBuffer& buf) {
      const auto from = std::lower_bound(truth.begin(), truth.end(), c.start_us + shift_us - 20'000,
                                         [](const Truth& s, std::int64_t t) { return s.t_us < t; });
      for (auto it = from == truth.begin() ? from : from - 1; it != truth.end() && it->t_us <= c.end_us + shift_us + 20'000; ++it)
        buf.add(it->t_us - shift_us, it->c);
      return true;
    }, integrate);
  };
  const Result at_truth = truth_run("truth", 0);
  // The clouds' clock against the simulator's: the shift of SIM_TRUTH that keeps the fewest
  // (shown when it keeps fewer than the truth as stamped; a still arm cannot tell).
  std::int64_t best = 0;
  std::uint64_t best_kept = at_truth.self_hits - at_truth.removed;
  for (std::int64_t d = -60'000; d <= 60'000; d += 5'000) {
    const Result r = truth_run("", d, false);
    if (r.self_hits - r.removed < best_kept) best_kept = r.self_hits - r.removed, best = d;
  }
  const std::string name = "truth " + std::to_string(best / 1000) + " ms later (best)";
  if (best != 0) truth_run(name.c_str(), best);
  return 0;
}
