#include "plan_result_io.hpp"

#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "porter/core/load_error.hpp"
#include "porter/core/trajectory_json.hpp"

namespace porter::midend::testing {
namespace {

using nlohmann::json;

planner::WholeBodyPath parse_path(const std::string& file, const json& j) {
  planner::WholeBodyPath path;
  const json& segs = j.at("segments");
  for (std::size_t s = 0; s < segs.size(); ++s) {
    planner::PathSegment seg;
    seg.eta = segs[s].at("eta").get<int>();
    const json& nodes = segs[s].at("nodes");
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      const json& n = nodes[k];
      planner::PathNode node;
      node.time_s = n.at("t_s").get<double>();
      const std::vector<double> base = n.at("base").get<std::vector<double>>();
      const std::vector<double> q = n.at("q_rad").get<std::vector<double>>();
      if (base.size() != 3 || q.size() != static_cast<std::size_t>(kNumArmJoints)) {
        throw LoadError(file, "path.segments[" + std::to_string(s) + "].nodes[" + std::to_string(k) + "]",
                        "expected base [x, y, yaw] and 6 joint angles");
      }
      node.config.base = {base[0], base[1], base[2]};
      for (int d = 0; d < kNumArmJoints; ++d) node.config.q_rad[d] = q[static_cast<std::size_t>(d)];
      seg.nodes.push_back(node);
    }
    path.segments.push_back(std::move(seg));
  }
  return path;
}

}  // namespace

PlanResultFile read_plan_result(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw LoadError(file, "", "cannot open the file");
  std::stringstream text;
  text << in.rdbuf();
  json doc;
  try {
    doc = json::parse(text.str());
  } catch (const json::exception& e) {
    throw LoadError(file, "", std::string("not JSON: ") + e.what());
  }
  PlanResultFile out;
  out.file = file;
  try {
    out.scene_name = doc.at("scene").value("name", std::string());
    out.seed = doc.at("scene").value("seed", 0LL);
    if (!doc.at("path").is_null()) out.path = parse_path(file, doc.at("path"));
    if (!doc.at("midend").is_null()) {
      const json& m = doc.at("midend");
      out.has_midend = true;
      out.midend_status = m.at("status").get<std::string>();
      out.midend_optimize_ms = m.at("optimize_ms").get<double>();
      out.midend_time_ms = m.at("time_ms").get<double>();
      out.midend_arm_residual_bound_rad = m.value("residual_arm_bound_rad", 0.0);
    }
    if (!doc.at("trajectory").is_null()) {
      TrajectoryResult tr = trajectory_from_json(doc.at("trajectory").dump());
      if (!tr.ok()) throw LoadError(file, "trajectory", tr.error);
      out.trajectory = std::move(tr.trajectory);
    }
  } catch (const json::exception& e) {
    throw LoadError(file, "", std::string("unexpected layout: ") + e.what());
  }
  return out;
}

}  // namespace porter::midend::testing
