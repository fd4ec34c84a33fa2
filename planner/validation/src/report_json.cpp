#include "porter/validation/report_json.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

namespace porter::validation {
namespace {

using nlohmann::json;

json number_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json pose_json(const PoseCheck& p) {
  return {{"ok", p.ok}, {"position_error_m", p.position_error_m}, {"yaw_error_rad", p.yaw_error_rad},
          {"joint_error_rad", p.joint_error_rad}};
}

std::string fixed(double v, int precision) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(precision);
  s << v;
  return s.str();
}

}  // namespace

std::string report_to_json(const PlanFile& plan, const ValidationReport* r, int indent) {
  json doc;
  doc["format"] = "porter-validate/1";
  doc["valid"] = r != nullptr && r->valid;
  json failures = json::array();
  if (!r) failures.push_back("no trajectory in the plan result");
  json p = {{"file", plan.label}, {"has_trajectory", plan.has_trajectory},
            {"exit_code", plan.verdict.exit_code}, {"status", plan.verdict.status},
            {"answer_stage", plan.verdict.answer_stage}};
  p["collision_free"] = plan.verdict.collision_free ? json(*plan.verdict.collision_free) : json(nullptr);
  doc["plan"] = p;
  if (!r) {
    doc["failures"] = failures;
    return doc.dump(indent);
  }
  for (const auto& f : r->failures) failures.push_back(f);
  doc["failures"] = failures;
  doc["samples"] = r->samples;
  doc["duration_s"] = r->duration_s;
  doc["max_step_m"] = r->max_step_m;
  doc["time_ms"] = r->time_ms;
  const auto& c = r->collision;
  doc["collision"] = {{"found", c.found}, {"t_s", c.t_s}, {"body", c.body}, {"shape", c.shape},
                      {"obstacle", c.obstacle}, {"depth_m", c.depth_m}, {"samples", c.samples}};
  const auto& s = r->self_collision;
  doc["self_collision"] = {{"found", s.found}, {"t_s", s.t_s}, {"body_a", s.body_a}, {"body_b", s.body_b},
                           {"depth_m", s.depth_m}, {"samples", s.samples}};
  json cl = json::array();
  double least = std::numeric_limits<double>::infinity();
  for (const auto& o : r->clearances) {
    cl.push_back({{"obstacle", o.obstacle}, {"min_m", number_or_null(o.min_m)}, {"t_s", o.t_s}, {"body", o.body},
               {"exact", o.exact}});
    if (o.obstacle != "ground") least = std::min(least, o.min_m);
  }
  doc["clearance"] = cl;
  doc["min_clearance_m"] = number_or_null(least);
  json lim = json::array();
  for (const auto& l : r->limits)
    lim.push_back({{"quantity", l.quantity}, {"worst_ratio", number_or_null(l.worst_ratio)}, {"t_s", l.t_s},
                   {"where", l.where}, {"value", number_or_null(l.value)}, {"limit", l.limit}, {"kept", l.kept}});
  doc["limits"] = lim;
  doc["start"] = pose_json(r->start);
  doc["goal"] = pose_json(r->goal);
  return doc.dump(indent);
}

std::string report_line(const PlanFile& plan, const ValidationReport* r) {
  if (!r) return "INVALID: no trajectory in " + plan.label + " (planner status: " + plan.verdict.status + ")";
  std::string line = r->valid ? "valid" : "INVALID: ";
  for (size_t i = 0; i < r->failures.size(); ++i) line += (i ? "; " : "") + r->failures[i];
  // The closest obstacle and the worst limit ratio.
  const ObstacleClearance* closest = nullptr;
  for (const auto& o : r->clearances)
    if (o.obstacle != "ground" && (!closest || o.min_m < closest->min_m)) closest = &o;
  line += " | " + std::to_string(r->samples) + " samples over " + fixed(r->duration_s, 2) + " s";
  if (closest && std::isfinite(closest->min_m))
    line += ", min clearance " + fixed(closest->min_m * 1000.0, 1) + " mm (" + closest->obstacle + ", " +
            closest->body + ", t=" + fixed(closest->t_s, 2) + " s)";
  const LimitCheck* worst = nullptr;
  for (const auto& l : r->limits)
    if (!worst || l.worst_ratio > worst->worst_ratio) worst = &l;
  if (worst) line += ", worst limit ratio " + fixed(worst->worst_ratio, 3) + " (" + worst->quantity + ", " + worst->where + ")";
  line += ", goal error " + fixed(r->goal.position_error_m * 1000.0, 1) + " mm, " + fixed(r->time_ms, 0) + " ms";
  return line;
}

}  // namespace porter::validation
