#include "plan_args.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace porter::app {

const char* to_string(Stages s) {
  switch (s) {
    case Stages::kFront: return "front";
    case Stages::kMid: return "mid";
    case Stages::kFull: return "full";
  }
  return "unknown";
}

const char* to_string(SafetyArg s) { return s == SafetyArg::kKcSvsdf ? "kc_svsdf" : "svsdf_per_link"; }

const char* to_string(CollisionArg c) { return c == CollisionArg::kKernels ? "kernels" : "spheres"; }

const char* to_string(AcceptanceArg a) { return a == AcceptanceArg::kExact ? "exact" : "kernels"; }

std::string plan_usage() {
  return "usage: porter-plan --scene FILE [--seed N] [--set NAME=VALUE]... [--payload FILE]\n"
         "                   [--robot FILE] [--planner-config DIR] [--stages front|mid|full]\n"
         "                   [--frontend-budget-ms MS] [--midend-budget-ms MS] [--backend-budget-ms MS]\n"
         "                   [--backend-iterations N] [--safety kc_svsdf|svsdf_per_link]\n"
         "                   [--collision kernels|spheres] [--self-collision-term on|off]\n"
         "                   [--warm-start retry|lowest-js]\n"
         "                   [--acceptance exact|kernels] [--clearance-margin-m M] [--out FILE] [--quiet]\n"
         "  --scene FILE            scene YAML (config/scenes/*.yaml)\n"
         "  --seed N                seed of the scene's random obstacles and of the planner\n"
         "                          (default: the scene file's seed)\n"
         "  --set NAME=VALUE        override a scene parameter (e.g. --set h_b=0.9); repeatable\n"
         "  --payload FILE          payload YAML replacing the scene's\n"
         "  --robot FILE            robot.yaml (default: robots/scout_mini_piper/robot.yaml of the\n"
         "                          config directory: ./config, else found from the executable)\n"
         "  --planner-config DIR    planner settings (default: planner/ of the config directory)\n"
         "  --stages S              front (path search only), mid (+ MINCO mid-end), full (+ back-end)\n"
         "  The flags below override the planner settings (defaults in config/planner/*.yaml):\n"
         "  --frontend-budget-ms MS front-end time budget (shipped: 1000)\n"
         "  --midend-budget-ms MS   mid-end optimization budget (shipped: 100)\n"
         "  --backend-budget-ms MS  back-end optimization budget (shipped: 300)\n"
         "  --backend-iterations N  back-end L-BFGS iteration cap (shipped: 200); with a large\n"
         "                          budget the run no longer depends on the machine's speed\n"
         "  --safety S              back-end safety term: kc_svsdf (KC-SVSDF, shipped) or\n"
         "                          svsdf_per_link (each link's SVSDF alone, the ablation baseline)\n"
         "  --collision C           kernels (shipped) or spheres (sphere-ESDF baseline in the\n"
         "                          front-end and as the back-end term; not with --safety); the\n"
         "                          acceptance test is the same either way\n"
         "  --self-collision-term on|off  the back-end's self-collision penalty next to the safety\n"
         "                          term (shipped: on; not part of the paper, off for comparison)\n"
         "  --warm-start W          when both mid-end solves were rejected, the back-end starts from\n"
         "                          the retry (shipped) or from the one with the lower J_s\n"
         "                          (lowest-js: two J_s evaluations taken from its budget)\n"
         "  --acceptance A          the test a trajectory must pass to be executed: kernels (default:\n"
         "                          the kernel check on the voxel map, inflated by 8-14 cm) or exact\n"
         "                          (exact geometry against the scene's obstacles and the ground,\n"
         "                          clearance >= the margin, no self-collision)\n"
         "  --clearance-margin-m M  least exact clearance with --acceptance exact (default 0.02)\n"
         "  --out FILE              write the JSON result there\n"
         "  --quiet                 print nothing on success\n"
         "exit codes: 0 success, 1 planning failed (incl. a final trajectory in collision), 2 bad\n"
         "            arguments, 3 unreadable/invalid file or unwritable output, 4 invalid start\n"
         "            or goal\n";
}

namespace {

double parse_number(const std::string& flag, const std::string& text) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || errno != 0 || !std::isfinite(v))
    throw ArgsError(flag + ": '" + text + "' is not a finite number");
  return v;
}

std::uint64_t parse_seed(const std::string& text) {
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos)
    throw ArgsError("--seed: '" + text + "' is not a non-negative integer");
  errno = 0;
  const unsigned long long v = std::strtoull(text.c_str(), nullptr, 10);
  if (errno != 0) throw ArgsError("--seed: '" + text + "' is too large");
  return static_cast<std::uint64_t>(v);
}

}  // namespace

PlanArgs parse_plan_args(int argc, const char* const* argv) {
  PlanArgs a;
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw ArgsError(flag + " needs a value");
      return argv[++i];
    };
    if (flag == "--help" || flag == "-h") {
      a.help = true;
    } else if (flag == "--scene") {
      a.scene_path = value();
    } else if (flag == "--seed") {
      a.seed = parse_seed(value());
      a.seed_given = true;
    } else if (flag == "--set") {
      const std::string kv = value();
      const auto eq = kv.find('=');
      if (eq == std::string::npos || eq == 0) throw ArgsError("--set: expected NAME=VALUE, got '" + kv + "'");
      a.overrides[kv.substr(0, eq)] = parse_number("--set " + kv.substr(0, eq), kv.substr(eq + 1));
    } else if (flag == "--payload") {
      a.payload_path = value();
    } else if (flag == "--robot") {
      a.robot_path = value();
    } else if (flag == "--planner-config") {
      a.planner_config_dir = value();
    } else if (flag == "--stages") {
      const std::string s = value();
      if (s == "front") a.stages = Stages::kFront;
      else if (s == "mid") a.stages = Stages::kMid;
      else if (s == "full") a.stages = Stages::kFull;
      else throw ArgsError("--stages: expected front, mid or full, got '" + s + "'");
    } else if (flag == "--frontend-budget-ms" || flag == "--midend-budget-ms" || flag == "--backend-budget-ms") {
      const double ms = parse_number(flag, value());
      // Above an hour a stage budget is a unit mistake, not a plan anyone waits for.
      if (!(ms > 0.0 && ms <= 3.6e6)) throw ArgsError(flag + " must be in (0, 3600000] ms");
      (flag == "--frontend-budget-ms" ? a.frontend_budget_ms
                                      : flag == "--midend-budget-ms" ? a.midend_budget_ms : a.backend_budget_ms) = ms;
    } else if (flag == "--backend-iterations") {
      const std::string v = value();
      if (v.empty() || v.size() > 9 || v.find_first_not_of("0123456789") != std::string::npos || std::stoi(v) < 1)
        throw ArgsError("--backend-iterations: '" + v + "' is not a positive integer");
      a.backend_max_iterations = std::stoi(v);
    } else if (flag == "--safety") {
      const std::string s = value();
      if (s == "kc_svsdf") a.safety = SafetyArg::kKcSvsdf;
      else if (s == "svsdf_per_link") a.safety = SafetyArg::kSvsdfPerLink;
      else throw ArgsError("--safety: expected kc_svsdf or svsdf_per_link, got '" + s + "'");
    } else if (flag == "--collision") {
      const std::string c = value();
      if (c == "kernels") a.collision = CollisionArg::kKernels;
      else if (c == "spheres") a.collision = CollisionArg::kSpheres;
      else throw ArgsError("--collision: expected kernels or spheres, got '" + c + "'");
    } else if (flag == "--self-collision-term") {
      const std::string v = value();
      if (v == "on") a.self_collision_term = true;
      else if (v == "off") a.self_collision_term = false;
      else throw ArgsError("--self-collision-term: expected on or off, got '" + v + "'");
    } else if (flag == "--warm-start") {
      const std::string v = value();
      if (v == "lowest-js") a.choose_warm_start_by_safety = true;
      else if (v == "retry") a.choose_warm_start_by_safety = false;
      else throw ArgsError("--warm-start: expected retry or lowest-js, got '" + v + "'");
    } else if (flag == "--acceptance") {
      const std::string v = value();
      if (v == "exact") a.acceptance = AcceptanceArg::kExact;
      else if (v == "kernels") a.acceptance = AcceptanceArg::kKernels;
      else throw ArgsError("--acceptance: expected exact or kernels, got '" + v + "'");
    } else if (flag == "--clearance-margin-m") {
      const double m = parse_number(flag, value());
      if (!(m >= 0.0)) throw ArgsError("--clearance-margin-m must be >= 0");
      a.clearance_margin_m = m;
    } else if (flag == "--out") {
      a.out_path = value();
    } else if (flag == "--quiet") {
      a.quiet = true;
    } else {
      throw ArgsError("unknown argument '" + flag + "'");
    }
  }
  if (!a.help && a.scene_path.empty()) throw ArgsError("--scene is required");
  if (a.safety && a.collision == CollisionArg::kSpheres)
    throw ArgsError("--safety does not apply with --collision spheres (the back-end uses the sphere term)");
  return a;
}

}  // namespace porter::app
