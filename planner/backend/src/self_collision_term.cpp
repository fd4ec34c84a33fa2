#include "porter/backend/self_collision_term.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace porter::backend {

namespace {
constexpr double kHalfDiagonal = 0.8660254037844386;  // sqrt(3) / 2
constexpr int kLeafSize = 8;

// The fine grid's error bound: every threshold is far inside the fine grid's padding (values
// below ~0.17 m are read there only, link_sdf.hpp), where the field is within it of the exact
// distance; beyond, values exceed every threshold by more than the coarse grid's error.
double field_error(const LinkSdf& sdf) { return sdf.fine().error_bound_m(); }
}  // namespace

std::vector<Eigen::Vector3f> surface_samples(const LinkSdf& sdf, double spacing_m) {
  std::vector<Eigen::Vector3f> out;
  if (sdf.empty() || !(spacing_m > 0.0)) return out;
  const Eigen::AlignedBox3d& box = sdf.body_bounds();
  const Eigen::Vector3d lo = box.min() - Eigen::Vector3d::Constant(spacing_m);
  const Eigen::Vector3i n = ((box.max() - lo) / spacing_m).array().ceil().cast<int>() + 2;
  const double band = kHalfDiagonal * spacing_m;
  for (int z = 0; z < n.z(); ++z)
    for (int y = 0; y < n.y(); ++y)
      for (int x = 0; x < n.x(); ++x) {
        const Eigen::Vector3d p = lo + spacing_m * Eigen::Vector3d(x, y, z);
        Eigen::Vector3d g;
        const double d = sdf.distance(p, &g);
        if (std::abs(d) > band) continue;
        // Onto the zero level along the gradient (the field is a distance: |grad| ~ 1 near the
        // surface); a few steps, as edges and corners bend the level set within one step.
        Eigen::Vector3d s = p;
        double dx = d;
        for (int step = 0; step < 4 && std::abs(dx) > 1e-4; ++step) {
          const double gn = g.norm();
          if (gn < 1e-9) break;
          s -= dx * g / gn;
          dx = sdf.distance(s, &g);
        }
        out.push_back(s.cast<float>());
      }
  return out;
}

SelfCollisionTerm::SelfCollisionTerm(const RobotModel& model, const RobotSdf& sdf,
                                     const std::vector<std::array<int, 2>>& pairs, double check_inflation_m,
                                     const SelfCollisionTermSettings& settings)
    : model_(&model), sdf_(&sdf), settings_(settings), kinematics_(model) {
  auto positive = [](double v) { return v > 0.0 && std::isfinite(v); };
  if (!positive(settings.weight) || !positive(settings.sample_interval_s) || !positive(settings.point_spacing_m) ||
      !(settings.slack_m >= 0.0) || !std::isfinite(settings.slack_m))
    throw std::invalid_argument("SelfCollisionTerm: weight, sample_interval_s and point_spacing_m must be > 0, slack_m >= 0");
  if (!(check_inflation_m >= 0.0) || !std::isfinite(check_inflation_m))
    throw std::invalid_argument("SelfCollisionTerm: check_inflation_m must be >= 0");
  for (int j = 0; j < kNumLinks; ++j) err_m_[static_cast<std::size_t>(j)] = field_error(sdf.link(j));
  std::array<std::vector<Eigen::Vector3f>, kNumLinks> points;
  std::array<bool, kNumLinks> have{}, used{};
  auto samples_of = [&](int j) -> const std::vector<Eigen::Vector3f>& {
    const auto k = static_cast<std::size_t>(j);
    if (!have[k]) {
      points[k] = surface_samples(sdf.link(j), settings.point_spacing_m);
      have[k] = true;
    }
    return points[k];
  };
  for (const auto& pr : pairs) {
    const int p = pr[0], q = pr[1];
    if (p < 0 || p >= kNumLinks || q < 0 || q >= kNumLinks || p == q)
      throw std::invalid_argument("SelfCollisionTerm: bad pair " + std::to_string(p) + "-" + std::to_string(q));
    if (sdf.link(p).empty() || sdf.link(q).empty())
      throw std::invalid_argument("SelfCollisionTerm: pair " + std::to_string(p) + "-" + std::to_string(q) +
                                  " has a link without geometry");
    // Sample the link with fewer surface samples; read the other's field.
    const bool sample_p = samples_of(p).size() < samples_of(q).size();
    Pair e;
    e.a = sample_p ? q : p;
    e.b = sample_p ? p : q;
    const auto ia = static_cast<std::size_t>(e.a), ib = static_cast<std::size_t>(e.b);
    e.threshold_m = check_inflation_m + err_m_[ia] + kHalfDiagonal * settings.point_spacing_m + settings.slack_m;
    set_active_threshold(e, e.threshold_m);
    used[ib] = true;
    pairs_.push_back(e);
  }
  for (int j = 0; j < kNumLinks; ++j) {
    const auto k = static_cast<std::size_t>(j);
    samples_.add_tree(used[k] ? points[k] : std::vector<Eigen::Vector3f>{}, kLeafSize);
  }
}

std::vector<Eigen::Vector3f> SelfCollisionTerm::samples(int link) const { return samples_.points(link); }

void SelfCollisionTerm::prepare(const Trajectory& initial) {
  kappa_.assign(static_cast<std::size_t>(initial.num_pieces()), 2);
  for (int i = 0; i < initial.num_pieces(); ++i) {
    const double k = std::ceil(initial.piece(i).duration_s / settings_.sample_interval_s);
    kappa_[static_cast<std::size_t>(i)] = static_cast<int>(std::clamp(k, 2.0, 1000.0));
  }
  // Each pair's closest approach along the warm start, at the derived thresholds.
  for (Pair& e : pairs_) set_active_threshold(e, e.threshold_m);
  if (!settings_.relative_to_warm_start) return;
  std::vector<double> closest(pairs_.size(), std::numeric_limits<double>::infinity());
  track_min_ = &closest;
  for_each_sample(initial, [&](int, int, double, const JointVector& q) { configuration_cost(q, nullptr, nullptr); });
  track_min_ = nullptr;
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    const double relative = std::max(0.0, closest[k] - settings_.warm_start_slack_m);
    set_active_threshold(pairs_[k], std::min(pairs_[k].threshold_m, relative));
  }
}

void SelfCollisionTerm::set_active_threshold(Pair& e, double threshold_m) const {
  const auto ia = static_cast<std::size_t>(e.a), ib = static_cast<std::size_t>(e.b);
  e.active_m = threshold_m;
  e.reach_m = model_->links[ia].bounding_radius_m + model_->links[ib].bounding_radius_m + threshold_m + err_m_[ia];
}

double SelfCollisionTerm::configuration_cost(const JointVector& q_rad, Eigen::Matrix<double, kNumArmJoints, 1>* grad_q,
                                             SelfCollisionStats* stats) {
  RobotConfiguration config;  // the base at the origin: only the arm matters
  config.q_rad = q_rad;
  kinematics_.compute(config, kEndEffectorLink, ws_);
  if (grad_q) grad_q->setZero();
  if (stats) ++stats->samples;
  double cost = 0.0;
  PointJacobian Ja, Jb;
  for (std::size_t pk = 0; pk < pairs_.size(); ++pk) {
    const Pair& e = pairs_[pk];
    const auto ia = static_cast<std::size_t>(e.a), ib = static_cast<std::size_t>(e.b);
    const Eigen::Matrix3d& R_a = ws_.R_W_L[ia];
    const Eigen::Vector3d& t_a = ws_.t_W_L[ia];
    const Eigen::Matrix3d& R_b = ws_.R_W_L[ib];
    const Eigen::Vector3d& t_b = ws_.t_W_L[ib];
    const Eigen::Vector3d c_a = R_a * model_->links[ia].bounding_center + t_a;
    const Eigen::Vector3d c_b = R_b * model_->links[ib].bounding_center + t_b;
    if ((c_a - c_b).norm() > e.reach_m) continue;
    if (stats) ++stats->pair_tests;
    const LinkSdf& field = sdf_->link(e.a);
    const double err = err_m_[ia];
    const double thr = e.active_m;
    auto to_a = [&](float x, float y, float z, Eigen::Vector3d* p_W) {
      *p_W = R_b * Eigen::Vector3d(x, y, z) + t_b;
      return Eigen::Vector3d(R_a.transpose() * (*p_W - t_a));
    };
    planner::point_tree_any(
        samples_, e.b,
        [&](const planner::PointTreeNode& n) {
          Eigen::Vector3d p_W;
          const Eigen::Vector3d p_a = to_a(n.cx, n.cy, n.cz, &p_W);
          double lower = 0.0;
          field.distance_fast(p_a, &lower);
          return lower - err > static_cast<double>(n.radius_m) + thr;
        },
        [&](float x, float y, float z) {
          Eigen::Vector3d p_W, g_a;
          const Eigen::Vector3d p_a = to_a(x, y, z, &p_W);
          // The trilinear value's lower bound first: the C^1 field is within err of the exact
          // distance, so it is above the threshold too when the bound minus err is.
          double lower = 0.0;
          field.distance_fast(p_a, &lower);
          if (lower - err > thr && !track_min_) return false;
          const double d = field.distance(p_a, grad_q ? &g_a : nullptr);
          if (track_min_) (*track_min_)[pk] = std::min((*track_min_)[pk], d);
          if (stats) {
            ++stats->point_queries;
            stats->min_margin_m = stats->point_queries == 1 ? d - thr : std::min(stats->min_margin_m, d - thr);
          }
          if (d >= thr) return false;
          const double v = thr - d;
          cost += v * v * v;
          if (stats) ++stats->violations;
          if (grad_q) {
            const Eigen::Vector3d n_W = R_a * g_a;
            ChainKinematics::point_jacobian(ws_, e.b, p_W, Jb);
            ChainKinematics::point_jacobian(ws_, e.a, p_W, Ja);
            const Eigen::Matrix<double, 1, kNumArmJoints> dd =
                n_W.transpose() * (Jb.rightCols<kNumArmJoints>() - Ja.rightCols<kNumArmJoints>());
            *grad_q += (-3.0 * v * v) * dd.transpose();
          }
          return false;  // visit every sample
        });
  }
  if (grad_q) *grad_q *= settings_.weight;
  return settings_.weight * cost;
}

double SelfCollisionTerm::evaluate(const Trajectory& trajectory, TrajectoryGradient& grad, SelfCollisionStats* stats) {
  const auto start = std::chrono::steady_clock::now();
  if (static_cast<int>(kappa_.size()) != trajectory.num_pieces()) prepare(trajectory);
  SelfCollisionStats local;
  SelfCollisionStats& st = stats ? *stats : local;
  st = SelfCollisionStats{};
  double total = 0.0;
  Eigen::Matrix<double, kNumArmJoints, 1> gq;
  const TrajVector zero = TrajVector::Zero();
  std::vector<double> d_T(static_cast<std::size_t>(trajectory.num_pieces()), 0.0);
  for_each_sample(trajectory, [&](int i, int k, double tau, const JointVector& q) {
    const double f = configuration_cost(q, &gq, &st);
    if (f == 0.0) return;
    const TrajectoryPiece& piece = trajectory.piece(i);
    const int kappa = kappa_[static_cast<std::size_t>(i)];
    const double h = piece.duration_s / kappa;
    const double omega = (k == 0 || k == kappa) ? 0.5 : 1.0;
    total += omega * h * f;
    TrajVector d_z = TrajVector::Zero();
    d_z.tail<kNumArmJoints>() = gq;
    grad.add_local(i, tau, d_z, 1, zero, omega * h);
    // d/dT_i: the quadrature weight h = T_i / kappa and the sample time tau = k T_i / kappa.
    const TrajVector z_dot = piece_derivative(piece.coeffs, tau, 1);
    d_T[static_cast<std::size_t>(i)] += omega * (f / kappa + h * d_z.dot(z_dot) * k / kappa);
  });
  for (int i = 0; i < trajectory.num_pieces(); ++i) grad.add_duration(i, d_T[static_cast<std::size_t>(i)]);
  st.cost = total;
  st.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return total;
}

}  // namespace porter::backend
