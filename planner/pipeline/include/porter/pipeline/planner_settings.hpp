#pragma once
// Everything a Planner is built with besides the robot: the stage budgets, the collision and
// safety models (the paper's ablations are one field each), the pipeline's own choices (mid-end
// retry, goal defaults) and each stage's settings. Every field has an in-class default; the
// shipped config/planner/*.yaml files repeat them and settings_yaml.hpp loads them strictly.
// Plain data; copy freely.

#include <string>

#include "porter/backend/backend_settings.hpp"
#include "porter/backend/self_collision_term.hpp"
#include "porter/baselines/safety_models.hpp"
#include "porter/baselines/sphere_collision_checker.hpp"
#include "porter/frontend/frontend.hpp"
#include "porter/midend/midend_settings.hpp"
#include "porter/planner/collision/kernel_robot.hpp"

namespace porter::pipeline {

struct PipelineSettings {
  /// Time budgets, s (> 0). The front-end's covers its whole search; the mid-end's each of its
  /// solves (a retry gets the same again; the acceptance test is not counted); the back-end's
  /// covers the warm-start choice, its obstacle preparation and the optimization, not the
  /// per-link SDF build (once per Planner) nor the final acceptance test.
  double frontend_budget_s = 1.0;
  double midend_budget_s = 0.1;
  double backend_budget_s = 0.3;
  /// The front-end's collision model: kKernels (the paper's chain-decomposed kernels) or kSpheres
  /// (the REMANI / TOPAY-style sphere-ESDF baseline, then also the back-end's safety term). The
  /// acceptance test is the kernel trajectory check either way, so runs stay comparable.
  baselines::CollisionModel collision = baselines::CollisionModel::kKernels;
  /// The back-end's safety term with kKernels: kKcSvsdf (KC-SVSDF, Algorithm 1) or kSvsdfPerLink
  /// (each link's SVSDF alone, the paper's ablation baseline). kSpheres is chosen by `collision`.
  baselines::SafetyModel safety = baselines::SafetyModel::kKcSvsdf;
  /// The back-end's self-collision penalty next to the safety term (not in the paper; false
  /// reproduces the paper's back-end). Needs the SVSDF terms' link SDFs (unused with kSpheres).
  bool self_collision_term = true;
  /// Mid-end retry (not in the paper): a mid-end trajectory that is not accepted is solved once
  /// more with the arm residual bound rho_m times this, closer to the front-end's arm path
  /// (collision-free by the kernel motion check, self-collision included). The retry replaces
  /// the first solve when the first hits itself or when the retry is accepted; otherwise the
  /// back-end starts from the retry, or from the one of the two with the lower safety penalty
  /// (choose_warm_start_by_safety). Only a
  /// self-collision is retried when the plan stops at the mid-end. Measured on the bridge
  /// ablation: 0.5 and 0.25 both fix the self-colliding runs; 0.5 keeps more freedom for the
  /// obstacle terms. (0, 1]; 1 turns the retry off.
  double retry_arm_residual_scale = 0.5;
  /// When both mid-end solves were rejected: true evaluates the safety penalty J_s of both and
  /// the back-end starts from the lower (two J_s preparations and first evaluations, with no
  /// earlier t* to start their searches from, taken from the back-end's budget); false starts
  /// from the retry without that choice. Measured (docs/realtime.md) at the default 300 ms
  /// back-end budget: the choice took a median 305 ms on tunnel, the whole budget, and the
  /// optimizer then made no iteration in 13 of 19 runs, so the default is false; with budgets that
  /// leave the optimizer time (the bridge's recorded runs in tests) it can pay off.
  bool choose_warm_start_by_safety = false;
  /// Goal tolerances for requests that give none (GoalSpec), m and rad (>= 0).
  double goal_position_tolerance_m = 0.1;
  double goal_yaw_tolerance_rad = 0.1;
  /// Free arm goals: seeded random arm configurations tried after the start's, nearest first
  /// (>= 0).
  int free_arm_candidates = 200;
};

struct PlannerSettings {
  PipelineSettings pipeline;
  /// The kernel checker's robot side (kernels.resolution_m must equal the maps' voxel size) and
  /// its map settings (safety margin, distance cap).
  planner::KernelCheckerSettings kernels;
  /// The sphere baseline's checker (collision = kSpheres); its self-collision test is off by
  /// default (the cover's ~10 cm inflation makes the arm's spheres touch the base's at the shipped
  /// scenes' start pose: the acceptance test's kernel check covers self-collision).
  baselines::SphereCheckerSettings spheres;
  frontend::FrontendSettings frontend;
  midend::MidendSettings midend;
  backend::BackendSettings backend;
  /// The back-end's terms. The SVSDF terms' per-link margins are derived from the kernel check's
  /// inflation (backend/recheck_margins.hpp) when the Planner builds them.
  baselines::SafetyTermSettings safety_terms;
  backend::SelfCollisionTermSettings self_collision;

  PlannerSettings() { spheres.check_self_collision = false; }
};

/// Checks every documented range (the stages' own validate_settings included); false with *why
/// naming the first bad field ("pipeline.midend_budget_s must be > 0", "midend: ...").
bool validate_settings(const PlannerSettings& settings, std::string* why);

}  // namespace porter::pipeline
