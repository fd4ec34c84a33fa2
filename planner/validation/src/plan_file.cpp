#include "porter/validation/plan_file.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "porter/core/load_error.hpp"

namespace porter::validation {
namespace {

using nlohmann::json;

[[noreturn]] void fail(const std::string& label, const std::string& key, const std::string& why) {
  throw LoadError(label, key.empty() ? std::string() : "key '" + key + "'", why);
}

double finite_number(const json& v, const std::string& label, const std::string& key) {
  if (!v.is_number()) fail(label, key, "expected a number");
  const double x = v.get<double>();
  if (!std::isfinite(x)) fail(label, key, "expected a finite number");
  return x;
}

PolyPiece parse_piece(const json& p, const std::string& label, const std::string& key) {
  if (!p.is_object()) fail(label, key, "expected an object");
  PolyPiece piece;
  for (const char* k : {"duration_s", "eta", "coeffs"})
    if (!p.contains(k)) fail(label, key + "." + k, "missing");
  piece.duration_s = finite_number(p["duration_s"], label, key + ".duration_s");
  if (!(piece.duration_s > 0.0)) fail(label, key + ".duration_s", "expected a duration > 0");
  const json& eta = p["eta"];
  if (!eta.is_number_integer() || (eta.get<long long>() != 1 && eta.get<long long>() != -1))
    fail(label, key + ".eta", "expected the integer 1 or -1");
  piece.eta = static_cast<int>(eta.get<long long>());
  const json& c = p["coeffs"];
  if (!c.is_array() || c.size() != kPolyCoeffs)
    fail(label, key + ".coeffs", "expected an array of " + std::to_string(kPolyCoeffs) + " rows");
  for (int k = 0; k < kPolyCoeffs; ++k) {
    const json& row = c[static_cast<size_t>(k)];
    const std::string rk = key + ".coeffs[" + std::to_string(k) + "]";
    if (!row.is_array() || row.size() != kFlatDim)
      fail(label, rk, "expected an array of " + std::to_string(kFlatDim) + " numbers");
    for (int d = 0; d < kFlatDim; ++d)
      piece.coeffs(k, d) = finite_number(row[static_cast<size_t>(d)], label, rk);
  }
  return piece;
}

void parse_trajectory(const json& t, const std::string& label, PlanFile& out) {
  const std::string key = "trajectory";
  if (!t.is_object()) fail(label, key, "expected an object or null");
  for (const char* k : {"dimension", "degree", "start_yaw_rad", "pieces"})
    if (!t.contains(k)) fail(label, key + "." + k, "missing");
  if (!t["dimension"].is_number_integer() || t["dimension"].get<long long>() != kFlatDim)
    fail(label, key + ".dimension", "expected " + std::to_string(kFlatDim));
  if (!t["degree"].is_number_integer() || t["degree"].get<long long>() != kPolyCoeffs - 1)
    fail(label, key + ".degree", "expected " + std::to_string(kPolyCoeffs - 1));
  out.start_yaw_rad = finite_number(t["start_yaw_rad"], label, key + ".start_yaw_rad");
  const json& pieces = t["pieces"];
  if (!pieces.is_array() || pieces.empty()) fail(label, key + ".pieces", "expected a non-empty array");
  double total_s = 0.0;
  for (size_t i = 0; i < pieces.size(); ++i) {
    out.pieces.push_back(parse_piece(pieces[i], label, key + ".pieces[" + std::to_string(i) + "]"));
    total_s += out.pieces.back().duration_s;
  }
  if (!std::isfinite(total_s)) fail(label, key + ".pieces", "total duration overflows");
  out.has_trajectory = true;
}

}  // namespace

PlanFile parse_plan_file(const std::string& json_text, const std::string& label) {
  json doc = json::parse(json_text, nullptr, /*allow_exceptions=*/false);
  if (doc.is_discarded()) fail(label, "", "not valid JSON");
  if (!doc.is_object()) fail(label, "", "expected a JSON object");
  PlanFile out;
  out.label = label;
  if (doc.contains("exit_code")) {
    if (!doc["exit_code"].is_number_integer()) fail(label, "exit_code", "expected an integer");
    out.verdict.exit_code = static_cast<int>(doc["exit_code"].get<long long>());
  }
  if (doc.contains("status")) {
    if (!doc["status"].is_string()) fail(label, "status", "expected a string");
    out.verdict.status = doc["status"].get<std::string>();
  }
  if (doc.contains("final_check") && !doc["final_check"].is_null()) {
    const json& fc = doc["final_check"];
    if (!fc.is_object()) fail(label, "final_check", "expected an object or null");
    if (fc.contains("collision_free")) {
      if (!fc["collision_free"].is_boolean()) fail(label, "final_check.collision_free", "expected a boolean");
      out.verdict.collision_free = fc["collision_free"].get<bool>();
    }
    if (fc.contains("stage")) {
      if (!fc["stage"].is_string()) fail(label, "final_check.stage", "expected a string");
      out.verdict.answer_stage = fc["stage"].get<std::string>();
    }
  }
  if (doc.contains("scene") && doc["scene"].is_object() && doc["scene"].contains("name") &&
      doc["scene"]["name"].is_string())
    out.scene_name = doc["scene"]["name"].get<std::string>();
  if (doc.contains("scene") && doc["scene"].is_object() && doc["scene"].contains("seed") &&
      doc["scene"]["seed"].is_number_integer())
    out.scene_seed = doc["scene"]["seed"].get<long long>();
  if (doc.contains("trajectory") && !doc["trajectory"].is_null())
    parse_trajectory(doc["trajectory"], label, out);
  return out;
}

PlanFile load_plan_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw LoadError(path, "", "cannot open file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw LoadError(path, "", "read error");
  return parse_plan_file(text.str(), path);
}

}  // namespace porter::validation
