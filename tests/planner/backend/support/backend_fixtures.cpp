#include "backend_fixtures.hpp"

#include <cmath>
#include <cstdlib>
#include <map>
#include <memory>
#include <mutex>

#include "porter/core/payload.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"

namespace porter::backend::testing {

std::string source_dir() {
  const char* env = std::getenv("PORTER_SOURCE_DIR");
  return env ? env : PORTER_SOURCE_DIR;
}

namespace {
std::mutex& cache_mutex() {
  static std::mutex m;
  return m;
}
}  // namespace

const RobotModel& robot(const std::string& payload) {
  static std::map<std::string, std::unique_ptr<RobotModel>> cache;
  std::lock_guard<std::mutex> lock(cache_mutex());
  auto it = cache.find(payload);
  if (it != cache.end()) return *it->second;
  RobotModel bare = load_robot_model(source_dir() + "/config/robots/scout_mini_piper/robot.yaml");
  auto model = std::make_unique<RobotModel>(
      payload.empty() ? bare
                      : attach_payload(bare, load_payload(source_dir() + "/config/payloads/" + payload + ".yaml")));
  return *cache.emplace(payload, std::move(model)).first->second;
}

const RobotSdf& robot_sdf(const std::string& payload) {
  const RobotModel& model = robot(payload);
  static std::map<std::string, std::unique_ptr<RobotSdf>> cache;
  std::lock_guard<std::mutex> lock(cache_mutex());
  auto it = cache.find(payload);
  if (it != cache.end()) return *it->second;
  auto sdf = std::make_unique<RobotSdf>(RobotSdf::build(model));
  return *cache.emplace(payload, std::move(sdf)).first->second;
}

Trajectory random_trajectory(const RobotModel& model, std::uint64_t seed, const RandomTrajectoryOptions& o) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  JointVector carry;
  carry << 0.0, 1.2, -1.0, 0.0, 0.6, 0.0;
  const JointVector lo = model.lower_limits(), hi = model.upper_limits();

  const int n = o.pieces;
  std::vector<TrajVector> pos(static_cast<std::size_t>(n) + 1), vel(pos.size()), acc(pos.size());
  double heading = unit(rng) * 3.14159;
  Eigen::Vector2d p(unit(rng), unit(rng));
  for (int k = 0; k <= n; ++k) {
    const double speed = o.base_speed_mps * (1.0 + 0.3 * unit(rng));
    const Eigen::Vector2d dir(std::cos(heading), std::sin(heading));
    TrajVector z, v, a;
    z.head<2>() = p;
    v.head<2>() = o.eta * speed * dir;
    a.head<2>() = 0.2 * Eigen::Vector2d(unit(rng), unit(rng));
    for (int j = 0; j < kNumArmJoints; ++j) {
      const double mid = std::clamp(carry[j], lo[j] + 0.3, hi[j] - 0.3);
      z[2 + j] = std::clamp(mid + o.joint_amplitude_rad * unit(rng), lo[j] + 0.05, hi[j] - 0.05);
      v[2 + j] = 0.3 * unit(rng);
      a[2 + j] = 0.3 * unit(rng);
    }
    pos[static_cast<std::size_t>(k)] = z;
    vel[static_cast<std::size_t>(k)] = v;
    acc[static_cast<std::size_t>(k)] = a;
    heading += o.turn_rate_radps * o.piece_duration_s * unit(rng);
    const Eigen::Vector2d next_dir(std::cos(heading), std::sin(heading));
    p += o.eta * speed * o.piece_duration_s * 0.5 * (dir + next_dir);
  }
  std::vector<TrajectoryPiece> pieces;
  for (int k = 0; k < n; ++k) {
    TrajectoryPiece piece;
    piece.duration_s = o.piece_duration_s * (1.0 + 0.2 * unit(rng));
    piece.eta = o.eta;
    const auto s = static_cast<std::size_t>(k);
    piece.coeffs = quintic_hermite(pos[s], vel[s], acc[s], pos[s + 1], vel[s + 1], acc[s + 1], piece.duration_s);
    pieces.push_back(piece);
  }
  const Eigen::Vector2d v0 = o.eta * vel[0].head<2>();
  return *Trajectory::create(pieces, std::atan2(v0.y(), v0.x())).trajectory;
}

Trajectory perturbed(const Trajectory& traj, int piece, int row, int col, double delta) {
  std::vector<TrajectoryPiece> pieces = traj.pieces();
  if (row >= 0) {
    pieces[static_cast<std::size_t>(piece)].coeffs(row, col) += delta;
  } else {
    pieces[static_cast<std::size_t>(piece)].duration_s += delta;
  }
  return *Trajectory::create(pieces, traj.start_yaw_rad()).trajectory;
}

Eigen::Vector3d point_near(const SweptBody& body, int link, std::mt19937& rng, double spread) {
  std::uniform_real_distribution<double> u(0.0, 1.0), s(-1.0, 1.0);
  BodyState st;
  body.evaluate(u(rng) * body.duration_s(), st);
  const Eigen::AlignedBox3d& b = body.model().links[static_cast<std::size_t>(link)].bounds;
  const Eigen::Vector3d p_L = b.min() + b.sizes().cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)));
  const auto l = static_cast<std::size_t>(link);
  return st.kin.R_W_L[l] * p_L + st.kin.t_W_L[l] + spread * Eigen::Vector3d(s(rng), s(rng), s(rng));
}

}  // namespace porter::backend::testing
