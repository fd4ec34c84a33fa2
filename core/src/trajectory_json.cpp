#include "porter/core/trajectory_json.hpp"

#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

namespace porter {
namespace {

using nlohmann::json;

// 256 pieces take ~30 kB; 64 MiB bounds what a document may make the parser allocate.
constexpr std::size_t kMaxJsonBytes = std::size_t{64} << 20;

// Returns an error message for the first key of obj that is not in allowed, or "".
std::string unknown_key(const json& obj, const std::string& where,
                        std::initializer_list<const char*> allowed) {
  for (auto it = obj.begin(); it != obj.end(); ++it) {
    bool found = false;
    for (const char* a : allowed) found = found || it.key() == a;
    if (!found) return where + (where.empty() ? "" : ".") + it.key() + ": unknown key";
  }
  return {};
}

// Reads obj[key] as a number into *out; returns an error message or "".
std::string read_number(const json& obj, const std::string& where, const char* key, double* out) {
  const std::string name = where + (where.empty() ? "" : ".") + key;
  const auto it = obj.find(key);
  if (it == obj.end()) return name + ": missing key";
  if (!it->is_number()) return name + ": expected a number";
  *out = it->get<double>();
  return {};
}

std::string read_integer(const json& obj, const std::string& where, const char* key,
                         long long* out) {
  const std::string name = where + (where.empty() ? "" : ".") + key;
  const auto it = obj.find(key);
  if (it == obj.end()) return name + ": missing key";
  if (!it->is_number_integer()) return name + ": expected an integer";
  *out = it->get<long long>();
  return {};
}

TrajectoryResult failure(std::string error) {
  TrajectoryResult r;
  r.error = std::move(error);
  return r;
}

}  // namespace

std::string to_json(const Trajectory& trajectory, int indent) {
  json doc = json::object();
  doc["dimension"] = kTrajDim;
  doc["degree"] = kTrajDegree;
  doc["start_yaw_rad"] = trajectory.start_yaw_rad();
  json pieces = json::array();
  for (const TrajectoryPiece& p : trajectory.pieces()) {
    json coeffs = json::array();
    for (int k = 0; k < kTrajNumCoeffs; ++k) {
      json row = json::array();
      for (int d = 0; d < kTrajDim; ++d) row.push_back(p.coeffs(k, d));
      coeffs.push_back(std::move(row));
    }
    pieces.push_back({{"duration_s", p.duration_s}, {"eta", p.eta}, {"coeffs", std::move(coeffs)}});
  }
  doc["pieces"] = std::move(pieces);
  return doc.dump(indent < 0 ? -1 : indent);
}

static TrajectoryResult parse_document(const std::string& text) {
  if (text.size() > kMaxJsonBytes) {
    return failure("document of " + std::to_string(text.size()) + " bytes exceeds the " +
                   std::to_string(kMaxJsonBytes) + "-byte limit");
  }
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::exception& e) {
    // parse_error, and out_of_range for a number beyond double (1e309).
    return failure(std::string("not valid JSON: ") + e.what());
  } catch (const std::exception& e) {
    return failure(std::string("cannot read the JSON document: ") + e.what());
  }
  if (!doc.is_object()) return failure("expected a JSON object at the top level");
  std::string err = unknown_key(doc, "", {"dimension", "degree", "start_yaw_rad", "pieces"});
  if (!err.empty()) return failure(err);

  long long dimension = 0, degree = 0;
  if (!(err = read_integer(doc, "", "dimension", &dimension)).empty()) return failure(err);
  if (dimension != kTrajDim) {
    return failure("dimension: expected " + std::to_string(kTrajDim) + " (got " +
                   std::to_string(dimension) + ")");
  }
  if (!(err = read_integer(doc, "", "degree", &degree)).empty()) return failure(err);
  if (degree != kTrajDegree) {
    return failure("degree: expected " + std::to_string(kTrajDegree) + " (got " +
                   std::to_string(degree) + ")");
  }
  double start_yaw_rad = 0.0;
  if (!(err = read_number(doc, "", "start_yaw_rad", &start_yaw_rad)).empty()) return failure(err);

  const auto pit = doc.find("pieces");
  if (pit == doc.end()) return failure("pieces: missing key");
  if (!pit->is_array()) return failure("pieces: expected an array");

  std::vector<TrajectoryPiece> pieces;
  pieces.reserve(pit->size());
  for (size_t i = 0; i < pit->size(); ++i) {
    const json& jp = (*pit)[i];
    const std::string where = "pieces[" + std::to_string(i) + "]";
    if (!jp.is_object()) return failure(where + ": expected an object");
    if (!(err = unknown_key(jp, where, {"duration_s", "eta", "coeffs"})).empty()) {
      return failure(err);
    }
    TrajectoryPiece p;
    if (!(err = read_number(jp, where, "duration_s", &p.duration_s)).empty()) return failure(err);
    long long eta = 0;
    if (!(err = read_integer(jp, where, "eta", &eta)).empty()) return failure(err);
    if (eta != 1 && eta != -1) {
      return failure(where + ".eta: must be +1 or -1 (got " + std::to_string(eta) + ")");
    }
    p.eta = static_cast<int>(eta);
    const auto cit = jp.find("coeffs");
    if (cit == jp.end()) return failure(where + ".coeffs: missing key");
    if (!cit->is_array() || cit->size() != static_cast<size_t>(kTrajNumCoeffs)) {
      return failure(where + ".coeffs: expected an array of " + std::to_string(kTrajNumCoeffs) +
                     " rows");
    }
    for (int k = 0; k < kTrajNumCoeffs; ++k) {
      const json& row = (*cit)[static_cast<size_t>(k)];
      const std::string rname = where + ".coeffs[" + std::to_string(k) + "]";
      if (!row.is_array() || row.size() != static_cast<size_t>(kTrajDim)) {
        return failure(rname + ": expected an array of " + std::to_string(kTrajDim) + " numbers");
      }
      for (int d = 0; d < kTrajDim; ++d) {
        const json& x = row[static_cast<size_t>(d)];
        if (!x.is_number()) {
          return failure(rname + "[" + std::to_string(d) + "]: expected a number");
        }
        p.coeffs(k, d) = x.get<double>();
      }
    }
    pieces.push_back(std::move(p));
  }
  return Trajectory::create(std::move(pieces), start_yaw_rad);
}

TrajectoryResult trajectory_from_json(const std::string& text) {
  try {
    return parse_document(text);
  } catch (const std::exception& e) {  // std::bad_alloc: the header promises no exception
    return failure(std::string("cannot read the JSON document: ") + e.what());
  }
}

}  // namespace porter
