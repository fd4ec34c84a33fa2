#include "porter/pipeline/planner.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "goal.hpp"
#include "porter/backend/recheck_margins.hpp"
#include "stages.hpp"

namespace porter::pipeline {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

const PlannerSettings& validated(const PlannerSettings& s) {
  std::string why;
  if (!validate_settings(s, &why)) throw std::invalid_argument("planner settings: " + why);
  return s;
}

Eigen::AlignedBox2d map_xy(const OccupancyGrid& grid) {
  const Eigen::AlignedBox3d b = grid.bounds_W();
  return Eigen::AlignedBox2d(b.min().head<2>(), b.max().head<2>());
}

/// Why the start state cannot be planned from ("" when it can): finite, a wrapped heading, on the
/// map, and a moving base must move along its heading.
std::string start_state_problem(const StartState& s, const Eigen::AlignedBox2d& map_xy_W) {
  const auto& b = s.config.base;
  if (!std::isfinite(b.x_m) || !std::isfinite(b.y_m) || !std::isfinite(b.yaw_rad) || !s.config.q_rad.allFinite())
    return "start pose or joint angles not finite";
  // A heading is an angle in (-pi, pi] up to a few turns; anything larger is a unit or wrapping
  // mistake upstream, and would cost precision in every yaw the stages derive from it.
  if (std::abs(b.yaw_rad) > 1e3) return "start yaw " + std::to_string(b.yaw_rad) + " rad is not a wrapped heading";
  if (!map_xy_W.contains(Eigen::Vector2d(b.x_m, b.y_m))) {
    char buf[200];
    std::snprintf(buf, sizeof buf, "start base position (%.3f, %.3f) m is outside the map (x %.3f..%.3f, y %.3f..%.3f m)",
                  b.x_m, b.y_m, map_xy_W.min().x(), map_xy_W.max().x(), map_xy_W.min().y(), map_xy_W.max().y());
    return buf;
  }
  if (!s.velocity.allFinite() || !s.acceleration.allFinite()) return "start velocity or acceleration not finite";
  const Eigen::Vector2d v = s.velocity.head<2>();
  const double speed = v.norm();
  if (speed <= 1e-9) return "";
  const Eigen::Vector2d heading(std::cos(s.config.base.yaw_rad), std::sin(s.config.base.yaw_rad));
  const double cross = heading.x() * v.y() - heading.y() * v.x();
  if (std::abs(cross) > 1e-3 * speed) return "start base velocity is not along the base heading (a diff-drive base moves along x_B)";
  return "";
}

}  // namespace

const char* to_string(Stages s) {
  switch (s) {
    case Stages::kFront: return "front";
    case Stages::kMid: return "mid";
    case Stages::kFull: return "full";
  }
  return "unknown";
}

Planner::Planner(RobotModel model, PlannerSettings settings)
    : model_(std::move(model)),
      settings_(validated(settings)),
      midend_(model_, settings_.midend),
      backend_(model_, settings_.backend) {
  const auto t0 = Clock::now();
  kernel_robot_ = std::make_shared<const planner::KernelRobot>(model_, settings_.kernels);
  kernels_ = std::make_unique<planner::KernelCollisionChecker>(kernel_robot_, settings_.kernels.map);
  if (settings_.pipeline.collision == baselines::CollisionModel::kSpheres)
    spheres_ = std::make_unique<baselines::SphereCollisionChecker>(model_, settings_.spheres);
  acceptance_ = std::make_shared<KernelAcceptance>(*kernels_);
  frontend_ = std::make_unique<frontend::FrontEnd>(model_, frontend_checker(), settings_.frontend);
  setup_.kernels_s = seconds_since(t0);
}

const planner::CollisionChecker& Planner::frontend_checker() const {
  if (spheres_) return *spheres_;
  return *kernels_;
}

void Planner::set_acceptance(std::shared_ptr<const planner::TrajectoryAcceptance> acceptance) {
  acceptance_ = acceptance ? std::move(acceptance) : std::make_shared<KernelAcceptance>(*kernels_);
  // The back-end's margins follow the acceptance test's: rebuild its terms when they change.
  if (setup_.backend_ready && acceptance_->clearance_margin_m() != setup_.safety_margin_m) {
    setup_.backend_ready = false;
    self_term_.reset();
    safety_term_.reset();  // the per-link SDFs depend on the robot only and stay
  }
}

MapUpdate Planner::set_map(const OccupancyGrid& map_W) {
  const auto t0 = Clock::now();
  MapUpdate u;
  const double h = kernel_robot_->resolution_m();
  if (!(std::abs(map_W.resolution_m() - h) <= 1e-9 * h)) {
    u.message = "map resolution " + std::to_string(map_W.resolution_m()) + " m differs from the planner's " +
                std::to_string(h) + " m (kernels.resolution_m)";
    return u;
  }
  try {
    kernels_->set_map(map_W);
    if (spheres_) spheres_->set_map(map_W);
    frontend_->set_map(map_W);
    map_W_ = map_W;
  } catch (const std::exception& e) {  // a grid the kernels cannot use (empty, ground off a voxel boundary)
    has_map_ = false;
    u.message = e.what();
    return u;
  }
  has_map_ = true;
  u.ok = true;
  u.incremental = kernels_->last_map_update().incremental;
  u.changed_voxels = kernels_->last_map_update().changed_voxels;
  u.time_s = seconds_since(t0);
  return u;
}

void Planner::prepare_backend() {
  if (setup_.backend_ready) return;
  const auto t0 = Clock::now();
  const PipelineSettings& p = settings_.pipeline;
  baselines::SafetyModel kind = p.safety;
  if (p.collision == baselines::CollisionModel::kSpheres) kind = baselines::SafetyModel::kSpheres;
  baselines::SafetyTermSettings terms = settings_.safety_terms;
  if (kind != baselines::SafetyModel::kSpheres) {
    if (!sdf_) sdf_ = backend::RobotSdf::build(model_);
    // s_j per link from what the acceptance test demands (recheck_margins.hpp): the kernel check's
    // inflation, or the exact clearance margin of a test that states one. The obstacles lie inside
    // their occupied voxels, so a link whose distance to every voxel box is at least the margin
    // keeps it to the obstacles too; a trajectory with a zero penalty then passes the test.
    // The ground keeps the kernel-derived margin either way: the exact test's kernel filter does
    // not dilate the ground, and with the margin alone the payload was left grazing it.
    std::array<double, kNumLinks> inflation{}, kernel_inflation{};
    const double margin_m = acceptance_->clearance_margin_m();
    for (int j = 0; j < kNumLinks; ++j) {
      kernel_inflation[static_cast<std::size_t>(j)] = kernels_->inflation_bound_m(j);
      inflation[static_cast<std::size_t>(j)] = margin_m >= 0.0 ? margin_m : kernels_->inflation_bound_m(j);
    }
    setup_.safety_margin_m = margin_m;
    backend::RecheckMargins margins = backend::recheck_margins(inflation, kernel_robot_->resolution_m(), *sdf_);
    margins.ground_m = backend::recheck_margins(kernel_inflation, kernel_robot_->resolution_m(), *sdf_).ground_m;
    backend::apply_recheck_margins(margins, terms.svsdf);
    if (p.self_collision_term) {
      // The self-collision penalty on the pairs the acceptance test examines.
      const planner::SelfCollisionChecker& self = kernel_robot_->self_collision();
      self_term_ = std::make_unique<backend::SelfCollisionTerm>(model_, *sdf_, self.checked_pairs(),
                                                                self.inflation_bound_m(), settings_.self_collision);
    }
  }
  safety_term_ = baselines::make_safety_term(kind, model_, sdf_ ? &*sdf_ : nullptr, terms);
  setup_.backend_s = seconds_since(t0);
  setup_.backend_ready = true;
}

PlanResult Planner::plan(const PlanRequest& req) {
  const auto t0 = Clock::now();
  const PipelineSettings& p = settings_.pipeline;
  PlanResult r;
  auto finish = [&](planner::Status status, std::string message) {
    r.status = status;
    r.message = std::move(message);
    r.total_s = seconds_since(t0);
    return std::move(r);
  };
  if (!has_map_) return finish(planner::Status::kNoMap, "no map: set_map() was not called (or refused the map)");
  if (req.cancel && req.cancel->requested()) return finish(planner::Status::kCanceled, "canceled");

  // 1. The start state and the goal.
  if (std::string why = start_state_problem(req.start, map_xy(map_W_)); !why.empty())
    return finish(planner::Status::kInvalidStart, why);
  r.goal = detail::resolve_goal(model_, frontend_checker(), map_xy(map_W_), kernel_robot_->resolution_m(), req.goal,
                                req.start.config.q_rad, p, req.seed);

  // 2. Front-end. It validates the start and the goal again (an unresolved goal is handed over as
  // given, so that its report says what is wrong with the start first, then with the goal).
  r.frontend = frontend_->plan(req.start.config, r.goal.config, planner::Deadline(p.frontend_budget_s, req.cancel), req.seed);
  const frontend::FrontendResult& fe = *r.frontend;
  if (fe.status == planner::Status::kInvalidGoal && r.goal.status != planner::Status::kSuccess)
    return finish(fe.status, r.goal.message);
  if (fe.status != planner::Status::kSuccess) return finish(fe.status, fe.message);
  const double speed = req.start.velocity.head<2>().norm();
  if (speed > 1e-9) {
    const Eigen::Vector2d heading(std::cos(req.start.config.base.yaw_rad), std::sin(req.start.config.base.yaw_rad));
    const int eta = heading.dot(req.start.velocity.head<2>()) >= 0.0 ? 1 : -1;
    if (fe.path.segments.front().eta != eta)
      return finish(planner::Status::kInvalidStart,
                    std::string("the base moves ") + (eta > 0 ? "forward" : "in reverse") +
                        " at the start, but the front-end's path begins " + (eta > 0 ? "in reverse" : "forward"));
  }
  if (req.stages == Stages::kFront) return finish(planner::Status::kSuccess, "");

  // 3. Mid-end, its acceptance test and the retry.
  r.midend = detail::run_midend(midend_, fe.path, req.start, p, req.stages, *acceptance_, *kernels_, req.cancel);
  const MidendReport& mid = *r.midend;
  if (!mid.result.trajectory) return finish(mid.result.status, mid.result.message);
  r.trajectory = mid.result.trajectory;
  r.final_check = FinalCheck{"midend", acceptance_->name(), mid.acceptance, mid.acceptance_s};
  if (mid.acceptance.accepted) return finish(planner::Status::kSuccess, "");
  const std::string rejected = "mid-end trajectory rejected by the acceptance test (" + acceptance_->name() + ", link " +
                               std::to_string(mid.acceptance.link) + ")";
  if (req.cancel && req.cancel->requested()) return finish(planner::Status::kCanceled, "canceled");
  if (req.stages == Stages::kMid) return finish(planner::Status::kInCollision, rejected);
  if (!mid.result.solution) return finish(planner::Status::kInCollision, rejected + "; no mid-end solution for the back-end");

  // 4. Back-end.
  const auto t_setup = Clock::now();
  const bool build = !setup_.backend_ready;
  try {
    prepare_backend();
  } catch (const std::exception& e) {  // settings validate_settings() does not cover
    return finish(planner::Status::kInvalidInput, std::string("back-end setup: ") + e.what());
  }
  const double setup_s = build ? seconds_since(t_setup) : 0.0;
  r.setup_s += setup_s;
  // The caller's time left, when longer than the back-end's own budget (NaN and inf: not used).
  double backend_budget_s = p.backend_budget_s;
  const double left_s = req.time_available_s - seconds_since(t0);
  if (std::isfinite(req.time_available_s) && left_s > backend_budget_s) backend_budget_s = left_s;
  r.backend = detail::run_backend(backend_, mid, map_W_, *safety_term_, self_term_.get(), backend_budget_s,
                                  p.choose_warm_start_by_safety, *acceptance_, req.cancel);
  BackendReport& be = *r.backend;
  be.setup_s = setup_s;
  const backend::BackendResult& b = be.result;
  if (b.ok()) {
    r.trajectory = b.trajectory;
    r.final_check = FinalCheck{"backend", acceptance_->name(),
                               planner::AcceptanceResult{b.check == backend::SafetyCheck::kCollisionFree, b.collision_link, -1},
                               b.check_s};
  }
  if (b.success()) return finish(planner::Status::kSuccess, "");
  if (b.status == planner::Status::kCanceled) return finish(planner::Status::kCanceled, "back-end: canceled");
  if (b.ok())
    return finish(planner::Status::kInCollision,
                  "back-end trajectory rejected by the acceptance test (" + acceptance_->name() + ", link " +
                      std::to_string(b.collision_link) + ")");
  return finish(b.status, "back-end: " + b.message);
}

}  // namespace porter::pipeline
