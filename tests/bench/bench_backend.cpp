// porter-bench-backend: the back-end's measurements. Not a test: prints tables, asserts nothing.
//
//   porter-bench-backend queries            SVSDF / KC-SVSDF time per query point, share in t* search
//   porter-bench-backend scenes [seeds]     the planning pipeline (porter::pipeline::Planner, shipped
//                                           settings, front-end 2 s) on bridge, tunnel, forest:
//                                           back-end solve times where the mid-end's trajectory was
//                                           rejected
//   porter-bench-backend ablation [seeds]   the paper's Table I through the same pipeline as
//                                           porter-plan and scripts/bench-ablation: bridge h_b =
//                                           1.1 .. 0.8, front-end 80 ms, mid-end 100 ms, back-end
//                                           300 ms, kc_svsdf vs svsdf_per_link
//   porter-bench-backend probe [h_b seed fe_budget]  cost along -grad at the warm start, frozen
//                                           ball-search decisions vs Algorithm 1 at every evaluation,
//                                           then 0.3 s and 3 s solves both ways (environment:
//                                           PORTER_PROBE_SLOPES=1 adds slope vs FD along -grad)
//   porter-bench-backend synthetic [seeds]  the back-end alone on fixed colliding warm starts
//                                           (straight pass through the hole, perturbed), which
//                                           isolates it from the front-end
//   porter-bench-backend profile N SCENE H_B FE_BUDGET_S FIRST_SEED REPS
//                                           per seed: obstacle points, one J_s evaluation (averaged
//                                           over REPS) with its work counters, the same evaluation
//                                           with the fast paths' slow references, then a 300 ms solve
// Frozen fixtures: the scenes in config/, the seeds, the payloads of the scenes; the planner
// settings of config/planner/ (the kernel resolution follows the scene). Warm starts come from
// the pipeline (Planner::plan with Stages::kMid: the mid-end's solution, retry included).
// Figures are recorded with the command that made them in the README and the commit messages.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "backend_fixtures.hpp"
#include "porter/pipeline/planner.hpp"
#include "porter/pipeline/settings_yaml.hpp"
#include "porter/backend/backend.hpp"
#include "porter/backend/backend_problem.hpp"
#include "porter/backend/kc_svsdf.hpp"
#include "porter/backend/recheck_margins.hpp"
#include "porter/baselines/safety_models.hpp"
#include "porter/core/payload.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/core/scene_loader.hpp"
#include "porter/core/scene_voxelizer.hpp"
#include "porter/frontend/frontend.hpp"
#include "porter/midend/midend.hpp"
#include "porter/midend/reference_path.hpp"
#include "porter/planner/collision/kernel_collision_checker.hpp"
#include "synthetic_paths.hpp"

namespace {

using namespace porter;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

struct Setup {
  Scene scene;
  OccupancyGrid grid;
  RobotModel model;
  std::unique_ptr<backend::RobotSdf> sdf;
  std::unique_ptr<planner::KernelCollisionChecker> checker;
};

std::unique_ptr<Setup> load(const std::string& scene_name, double h_b, std::uint64_t seed = 0) {
  auto s = std::make_unique<Setup>();
  SceneLoadOptions options;
  if (h_b > 0.0) options.parameter_overrides["h_b"] = h_b;
  if (seed > 0) options.seed = seed;
  s->scene = load_scene(backend::testing::source_dir() + "/config/scenes/" + scene_name + ".yaml", options);
  s->grid = voxelize(s->scene);
  s->model = attach_payload(load_robot_model(backend::testing::source_dir() + "/config/robots/scout_mini_piper/robot.yaml"),
                            load_payload(s->scene.payload_file));
  s->sdf = std::make_unique<backend::RobotSdf>(backend::RobotSdf::build(s->model));
  s->checker = std::make_unique<planner::KernelCollisionChecker>(s->model);
  s->checker->set_map(s->grid);
  return s;
}

/// The shipped planner settings at the scene's resolution, with the given budgets (s) and model.
pipeline::PlannerSettings planner_settings(const Setup& s, double fe_s, double mid_s, double be_s,
                                           baselines::SafetyModel safety = baselines::SafetyModel::kKcSvsdf) {
  pipeline::PlannerSettings ps = pipeline::load_planner_settings(backend::testing::source_dir() + "/config/planner");
  ps.kernels.kernels.resolution_m = s.scene.resolution_m;
  ps.pipeline.frontend_budget_s = fe_s;
  ps.pipeline.midend_budget_s = mid_s;
  ps.pipeline.backend_budget_s = be_s;
  ps.pipeline.safety = safety;
  return ps;
}

pipeline::PlanRequest request(const Setup& s, std::uint64_t seed, pipeline::Stages stages) {
  pipeline::PlanRequest r;
  r.start = pipeline::StartState::at_rest(s.scene.start);
  r.goal = pipeline::GoalSpec::exact(s.scene.goal);
  r.seed = seed;
  r.stages = stages;
  return r;
}

// --- queries --------------------------------------------------------------------------------

void bench_queries() {
  // A warm start that cuts into the wall and the deck (points inside swept volumes included).
  auto s = load("bridge", 0.9);
  JointVector pass;
  pass << 0.0, 0.75, -0.5, 0.2, 0.0, 0.5;
  midend::testing::PathBuilder builder({-2.5, 0.25, 0.0}, pass, 0.4, 0.4);
  builder.straight(5.0, 1);
  const midend::MidEnd mid(s->model);
  const midend::MidendResult m = mid.solve(builder.build(), 1.0);
  backend::SvsdfSafetySettings ss;
  backend::SvsdfSafetyTerm term(s->model, *s->sdf, ss);
  term.prepare(s->grid, *m.trajectory);
  backend::SweptBody body(s->model);
  body.reset(*m.trajectory);
  backend::KcSvsdfSettings ks;
  ks.svsdf.collect_timing = true;
  std::printf("bridge h_b 0.9, straight pass 25 cm off centre (T = %.1f s, %d pieces), %zu obstacle points within the crop\n",
              m.trajectory->total_duration_s(), m.trajectory->num_pieces(), term.points().size());
  for (bool filter : {true, false}) {
    ks.kinematic_filter = filter;
    backend::KcSvsdf kc(*s->sdf, body, ks);
    backend::SvsdfEvaluator eval(*s->sdf, body, ks.svsdf);
    backend::KcSvsdfResult r;
    double t_out = 0, t_in = 0, t_base = 0, t_pay = 0, search_out = 0, search_in = 0;
    int n_out = 0, n_in = 0;
    // Warm the caches once.
    for (const auto& o : term.points()) kc.evaluate(o.p_W, backend::kAllLinks, r);
    kc.svsdf().stats() = backend::SvsdfStats{};
    for (const auto& o : term.points()) {
      const double before = kc.svsdf().stats().search_time_s;
      const auto t0 = Clock::now();
      kc.evaluate(o.p_W, backend::kAllLinks, r);
      const double dt = since(t0);
      const double searched = kc.svsdf().stats().search_time_s - before;
      bool inside = false;
      for (const auto& l : r.links) inside = inside || l.inside;
      (inside ? t_in : t_out) += dt;
      (inside ? search_in : search_out) += searched;
      (inside ? n_in : n_out) += 1;
      backend::SvsdfValue v;
      auto t1 = Clock::now();
      eval.full(0, o.p_W, v);
      t_base += since(t1);
      t1 = Clock::now();
      eval.windowed(kEndEffectorLink, o.p_W, v.t_star_s, v);
      t_pay += since(t1);
    }
    const int n = n_in + n_out;
    std::printf("%-15s KC-SVSDF all 8 links: outside %5d pts %7.1f us/pt (t* search %4.1f%%) | inside %4d pts %7.1f us/pt (t* search %4.1f%%)\n",
                filter ? "kc_svsdf" : "svsdf_per_link", n_out, 1e6 * t_out / std::max(1, n_out),
                100.0 * search_out / std::max(1e-12, t_out), n_in, 1e6 * t_in / std::max(1, n_in),
                100.0 * search_in / std::max(1e-12, t_in));
    if (filter) {
      std::printf("SVSDF g_j alone: base full search %.1f us/pt, payload windowed search %.1f us/pt\n",
                  1e6 * t_base / n, 1e6 * t_pay / n);
    }
  }
  // One evaluation of the penalty (prefilter + the queries it needs), both threads.
  backend::TrajectoryGradient grad;
  grad.reset(m.trajectory->num_pieces());
  backend::SafetyStats st;
  term.evaluate(*m.trajectory, grad, &st);
  const int reps = 20;
  const auto t0 = Clock::now();
  for (int k = 0; k < reps; ++k) term.evaluate(*m.trajectory, grad, &st);
  std::printf("J_s evaluation (cost + gradient): %.2f ms wall, %d of %d points past the AABB prefilter, %d (point, link) queries\n",
              1e3 * since(t0) / reps, st.candidate_points, st.obstacle_points, st.link_queries);
}

// --- pipeline ---------------------------------------------------------------------------------

/// A warm start for the back-end: the pipeline run to the mid-end (retry included).
struct WarmStart {
  bool ok = false;
  std::optional<midend::MidendSolution> solution;
  std::optional<Trajectory> trajectory;
  bool collision_free = false;
  double frontend_s = 0, midend_s = 0;
  std::string note;
};

WarmStart warm_start(pipeline::Planner& planner, const Setup& s, std::uint64_t seed) {
  WarmStart w;
  const pipeline::PlanResult r = planner.plan(request(s, seed, pipeline::Stages::kMid));
  if (r.frontend) w.frontend_s = r.frontend->elapsed_s;
  if (!r.midend || !r.midend->result.trajectory || !r.midend->result.solution) {
    w.note = std::string(planner::to_string(r.status)) + ": " + r.message;
    return w;
  }
  w.midend_s = r.midend->time_s;
  w.ok = true;
  w.solution = r.midend->result.solution;
  w.trajectory = r.midend->result.trajectory;
  w.collision_free = r.midend->acceptance.accepted;
  return w;
}

/// The safety term settings the pipeline uses: s_j from the kernel checker's inflation bounds.
baselines::SafetyTermSettings term_settings(const Setup& s) {
  baselines::SafetyTermSettings ts;
  std::array<double, kNumLinks> inflation{};
  for (int j = 0; j < kNumLinks; ++j) inflation[static_cast<std::size_t>(j)] = s.checker->inflation_bound_m(j);
  backend::apply_recheck_margins(backend::recheck_margins(inflation, s.grid.resolution_m(), *s.sdf), ts.svsdf);
  return ts;
}

backend::BackendResult run_backend(Setup& s, const WarmStart& w, baselines::SafetyModel model, double budget) {
  auto term = baselines::make_safety_term(model, s.model, s.sdf.get(), term_settings(s));
  const backend::BackEnd be(s.model, backend::BackendSettings{});
  const pipeline::KernelAcceptance acceptance(*s.checker);
  return be.solve(*w.solution, s.grid, *term, planner::Deadline(budget), &acceptance);
}

void bench_scenes(int seeds) {
  for (const std::string name : {"bridge", "tunnel", "forest"}) {
    auto s = load(name, -1.0);
    pipeline::Planner planner(s->model, planner_settings(*s, 2.0, 0.3, 0.3));
    planner.set_map(s->grid);
    planner.prepare_backend();
    std::vector<double> times;
    int paths = 0, direct = 0, ok = 0, iters = 0, ran = 0;
    for (int seed = 0; seed < seeds; ++seed) {
      const pipeline::PlanResult r = planner.plan(request(*s, static_cast<std::uint64_t>(seed), pipeline::Stages::kFull));
      if (!r.midend || !r.midend->result.trajectory) continue;
      ++paths;
      direct += r.midend->acceptance.accepted;
      ok += r.success();
      if (!r.backend) continue;
      ++ran;
      times.push_back(r.backend->result.elapsed_s);
      iters += r.backend->result.iterations;
    }
    std::sort(times.begin(), times.end());
    const double median = times.empty() ? 0.0 : times[times.size() / 2];
    double mean = 0.0;
    for (double t : times) mean += t;
    std::printf("%-7s mid-end trajectories %2d/%d (accepted directly %d) | back-end (kc_svsdf, 300 ms budget) ran %d: median %.0f ms, mean %.0f ms, mean iterations %.1f | accepted in the end %d/%d\n",
                name.c_str(), paths, seeds, direct, ran, 1e3 * median, times.empty() ? 0.0 : 1e3 * mean / times.size(),
                ran ? double(iters) / ran : 0.0, ok, paths);
  }
}

void bench_ablation(int seeds) {
  std::printf("h_b   | front-end ok | direct | kc_svsdf success | svsdf_per_link success\n");
  for (double h_b : {1.1, 1.0, 0.9, 0.8}) {
    auto s = load("bridge", h_b);
    int fe_ok = 0, direct = 0, kc = 0, pl = 0;
    for (const baselines::SafetyModel model : {baselines::SafetyModel::kKcSvsdf, baselines::SafetyModel::kSvsdfPerLink}) {
      pipeline::Planner planner(s->model, planner_settings(*s, 0.08, 0.1, 0.3, model));
      planner.set_map(s->grid);
      planner.prepare_backend();
      const bool ours = model == baselines::SafetyModel::kKcSvsdf;
      for (int seed = 1; seed <= seeds; ++seed) {
        const pipeline::PlanResult r = planner.plan(request(*s, static_cast<std::uint64_t>(seed), pipeline::Stages::kFull));
        if (ours) {
          fe_ok += r.frontend && r.frontend->status == planner::Status::kSuccess;
          direct += r.midend && r.midend->acceptance.accepted;
        }
        (ours ? kc : pl) += r.success();
      }
    }
    std::printf("%.1f m | %2d/%d        | %2d     | %2d/%d (%3.0f%%)      | %2d/%d (%3.0f%%)\n", h_b, fe_ok, seeds, direct, kc,
                seeds, 100.0 * kc / seeds, pl, seeds, 100.0 * pl / seeds);
  }
}

void bench_synthetic(int seeds) {
  std::printf("fixed warm starts: straight pass through the hole, lateral offset U(-0.12, 0.12) m, arm pose\n"
              "q = (0, 0.75 + U(-0.1, 0.1), -0.5, U(0.1, 0.6), 0, 0.5); back-end budget 300 ms\n");
  std::printf("h_b   | mid-end in collision | kc_svsdf success | svsdf_per_link success | kc ms (median) | per-link ms\n");
  for (double h_b : {1.1, 1.0, 0.9, 0.8}) {
    auto s = load("bridge", h_b);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int colliding = 0, kc = 0, pl = 0;
    std::vector<double> t_kc, t_pl;
    for (int seed = 0; seed < seeds; ++seed) {
      JointVector q;
      q << 0.0, 0.65 + 0.2 * u(rng), -0.5, 0.1 + 0.5 * u(rng), 0.0, 0.5;
      const double y = -0.12 + 0.24 * u(rng);
      midend::testing::PathBuilder builder({-2.5, y, 0.0}, q, 0.4, 0.4);
      builder.straight(5.0, 1);
      WarmStart w;
      const midend::MidEnd mid(s->model);
      const midend::MidendResult m = mid.solve(builder.build(), 1.0);
      if (!m.ok() || !m.solution) continue;
      w.ok = true;
      w.trajectory = m.trajectory;
      w.solution = m.solution;
      if (!s->checker->check_trajectory(*m.trajectory).in_collision) continue;
      ++colliding;
      const backend::BackendResult a = run_backend(*s, w, baselines::SafetyModel::kKcSvsdf, 0.3);
      const backend::BackendResult b = run_backend(*s, w, baselines::SafetyModel::kSvsdfPerLink, 0.3);
      kc += a.success();
      pl += b.success();
      t_kc.push_back(a.elapsed_s);
      t_pl.push_back(b.elapsed_s);
    }
    std::sort(t_kc.begin(), t_kc.end());
    std::sort(t_pl.begin(), t_pl.end());
    std::printf("%.1f m | %2d of %2d             | %2d/%d (%3.0f%%)      | %2d/%d (%3.0f%%)            | %5.0f          | %5.0f\n", h_b,
                colliding, seeds, kc, colliding, colliding ? 100.0 * kc / colliding : 0.0, pl, colliding,
                colliding ? 100.0 * pl / colliding : 0.0, t_kc.empty() ? 0.0 : 1e3 * t_kc[t_kc.size() / 2],
                t_pl.empty() ? 0.0 : 1e3 * t_pl[t_pl.size() / 2]);
  }
}


void bench_profile(const std::string& name, double h_b, int first_seed, int seeds, double fe_budget, int reps) {
  auto s = load(name, h_b);
  pipeline::Planner planner(s->model, planner_settings(*s, fe_budget, 0.3, 0.3));
  planner.set_map(s->grid);
  for (int seed = first_seed; seed < first_seed + seeds; ++seed) {
    const WarmStart w = warm_start(planner, *s, static_cast<std::uint64_t>(seed));
    if (!w.ok) {
      std::printf("seed %d: %s\n", seed, w.note.c_str());
      continue;
    }
    backend::SvsdfSafetyTerm term(s->model, *s->sdf, term_settings(*s).svsdf);
    auto t0 = Clock::now();
    term.prepare(s->grid, *w.trajectory);
    const double prep = since(t0);
    backend::TrajectoryGradient grad;
    grad.reset(w.trajectory->num_pieces());
    backend::SafetyStats st;
    term.reset_stats();
    t0 = Clock::now();
    for (int k = 0; k < reps; ++k) term.evaluate(*w.trajectory, grad, &st);
    const double ev = since(t0) / reps;
    const backend::SvsdfStats sv = term.svsdf_stats();
    const backend::KcSvsdfStats kc = term.kc_stats();
    std::printf("seed %d: %d pieces T %.1f s, direct %d | prepare %.1f ms, %d points | eval %.1f ms: %d candidates, %d link queries, %d viol, %d inside | searches %lld, samples %lld/%lld/%lld (looked up/visited/in range), exact %lld, skipped %lld | ball it %lld samples %lld\n",
                seed, w.trajectory->num_pieces(), w.trajectory->total_duration_s(), w.collision_free, 1e3 * prep,
                st.obstacle_points, 1e3 * ev, st.candidate_points, st.link_queries, st.violations, st.inside,
                (long long)sv.searches, (long long)sv.samples_evaluated, (long long)sv.samples_visited,
                (long long)sv.samples_in_range,
                (long long)sv.exact_evaluations, (long long)sv.skipped, (long long)kc.ball_iterations,
                (long long)kc.ball_samples);
    {
      // The same evaluation with the slow references of the fast paths (lean t* scan, SDF
      // prefilter level), alternated with the default so that both see the same machine load.
      backend::SvsdfSafetySettings ref_settings = term_settings(*s).svsdf;
      ref_settings.sdf_prefilter = false;
      ref_settings.kc.svsdf.lean_scan = false;
      backend::SvsdfSafetyTerm ref(s->model, *s->sdf, ref_settings);
      ref.prepare(s->grid, *w.trajectory);
      backend::TrajectoryGradient g_ref;
      g_ref.reset(w.trajectory->num_pieces());
      backend::SafetyStats st_ref;
      double fast_s = 0.0, ref_s = 0.0;
      double c_fast = 0.0, c_ref = 0.0;
      for (int k = 0; k < reps; ++k) {
        grad.reset(w.trajectory->num_pieces());
        auto t1 = Clock::now();
        c_fast = term.evaluate(*w.trajectory, grad, &st);
        fast_s += since(t1);
        g_ref.reset(w.trajectory->num_pieces());
        t1 = Clock::now();
        c_ref = ref.evaluate(*w.trajectory, g_ref, &st_ref);
        ref_s += since(t1);
      }
      std::printf("   alternated: eval %.2f ms, reference (lean_scan off, sdf_prefilter off) %.2f ms; J_s %.10g vs %.10g; %d vs %d link queries\n",
                  1e3 * fast_s / reps, 1e3 * ref_s / reps, c_fast, c_ref, st.link_queries, st_ref.link_queries);
    }
    {
      // The selection of points near the warm start (selection_slack_m) against the whole map's
      // points: preparation (a fresh term each, as in a plan), then evaluations alternated.
      backend::SvsdfSafetySettings whole_settings = term_settings(*s).svsdf;
      whole_settings.selection_slack_m = 0.0;
      backend::SvsdfSafetyTerm sel(s->model, *s->sdf, term_settings(*s).svsdf), whole(s->model, *s->sdf, whole_settings);
      auto t1 = Clock::now();
      sel.prepare(s->grid, *w.trajectory);
      const double sel_prep = since(t1);
      t1 = Clock::now();
      whole.prepare(s->grid, *w.trajectory);
      const double whole_prep = since(t1);
      double sel_s = 0.0, whole_s = 0.0, sel_pf = 0.0, whole_pf = 0.0, c_sel = 0.0, c_whole = 0.0;
      backend::SafetyStats a, b;
      for (int k = 0; k < reps; ++k) {
        grad.reset(w.trajectory->num_pieces());
        c_sel = sel.evaluate(*w.trajectory, grad, &a);
        sel_s += a.time_s;
        sel_pf += a.prefilter_s;
        grad.reset(w.trajectory->num_pieces());
        c_whole = whole.evaluate(*w.trajectory, grad, &b);
        whole_s += b.time_s;
        whole_pf += b.prefilter_s;
      }
      {
        // The prefilter's candidate lists (prefilter_slack_m) against the point index searched at
        // every evaluation, evaluations alternated (the lists are read from the second one on).
        backend::SvsdfSafetySettings no_lists = term_settings(*s).svsdf;
        no_lists.prefilter_slack_m = 0.0;
        backend::SvsdfSafetyTerm lists(s->model, *s->sdf, term_settings(*s).svsdf), index(s->model, *s->sdf, no_lists);
        lists.prepare(s->grid, *w.trajectory);
        index.prepare(s->grid, *w.trajectory);
        double l_pf = 0.0, i_pf = 0.0, l_s = 0.0, i_s = 0.0;
        for (int k = 0; k < reps; ++k) {
          grad.reset(w.trajectory->num_pieces());
          lists.evaluate(*w.trajectory, grad, &a);
          l_s += a.time_s;
          l_pf += a.prefilter_s;
          grad.reset(w.trajectory->num_pieces());
          index.evaluate(*w.trajectory, grad, &b);
          i_s += b.time_s;
          i_pf += b.prefilter_s;
        }
        std::printf("   candidate lists: eval %.2f ms (prefilter %.2f) vs index every time %.2f ms (prefilter %.2f); pairs reused %lld, searched %lld\n",
                    1e3 * l_s / reps, 1e3 * l_pf / reps, 1e3 * i_s / reps, 1e3 * i_pf / reps,
                    static_cast<long long>(lists.pairs_reused()), static_cast<long long>(lists.pairs_searched()));
      }
      std::printf("   selection: prepare %.1f ms (%zu points) vs whole map %.1f ms (%zu points); eval %.2f ms (prefilter %.2f) vs %.2f ms (prefilter %.2f); J_s %.10g vs %.10g\n",
                  1e3 * sel_prep, sel.points().size(), 1e3 * whole_prep, whole.points().size(), 1e3 * sel_s / reps,
                  1e3 * sel_pf / reps, 1e3 * whole_s / reps, 1e3 * whole_pf / reps, c_sel, c_whole);
    }
    std::fflush(stdout);
    if (w.collision_free) continue;
    const backend::BackendResult r = run_backend(*s, w, baselines::SafetyModel::kKcSvsdf, 0.3);
    std::printf("   back-end: %s %.0f ms (prepare %.1f ms), iterations %d, evaluations %d, safety %.0f ms, rechecks %d (%.0f ms), rounds %d, J_s %.3g -> %.3g, check %s (link %d) | %s\n",
                planner::to_string(r.status), 1e3 * r.elapsed_s, 1e3 * r.prepare_s, r.iterations, r.evaluations, 1e3 * r.safety_s,
                r.rechecks, 1e3 * r.recheck_s, r.rounds, r.initial_cost.safety, r.final_cost.safety,
                backend::to_string(r.check), r.collision_link, r.message.c_str());
    std::fflush(stdout);
  }
}


/// The back-end cost along -grad at the warm start: f(x0 - a g/|g|) - f(x0) against the
/// first-order prediction -a |g| (a: step in the decision vector's norm), with the ball-search decisions frozen at x0 and without.
void bench_probe(double h_b, int seed, double fe_budget) {
  auto s = load("bridge", h_b);
  pipeline::Planner planner(s->model, planner_settings(*s, fe_budget, 0.3, 0.3));
  planner.set_map(s->grid);
  const WarmStart w = warm_start(planner, *s, static_cast<std::uint64_t>(seed));
  if (!w.ok) {
    std::printf("seed %d: %s\n", seed, w.note.c_str());
    return;
  }
  std::printf("bridge h_b %.1f seed %d: %d pieces, mid-end %s\n", h_b, seed, w.trajectory->num_pieces(),
              w.collision_free ? "collision-free" : "in collision");
  for (bool freeze : {false, true}) {
    baselines::SafetyTermSettings ts = term_settings(*s);
    ts.svsdf.freeze_ball_decisions = freeze;
    backend::SvsdfSafetyTerm term(s->model, *s->sdf, ts.svsdf);
    term.prepare(s->grid, *w.trajectory);
    const midend::MidendLimits limits = midend::MidendLimits::from_robot(s->model);
    backend::BackendProblem problem(w.solution->reference, limits, w.solution->settings, term);
    const Eigen::VectorXd x0 = w.solution->x;
    const int n = problem.num_variables();
    Eigen::VectorXd g(n), x(n);
    backend::BackendCost c0;
    const double f0 = problem.evaluate(x0.data(), g.data(), &c0);
    std::printf("  %s: f0 %.6g (J_s %.6g), |g| %.4g\n", freeze ? "frozen at x0" : "Algorithm 1 every evaluation", f0,
                c0.safety, g.norm());
    for (double a : {1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 3e-3, 1e-2, 5e-2}) {
      x = x0 - (a / g.norm()) * g;
      backend::BackendCost c;
      const double f = problem.evaluate(x.data(), nullptr, &c);
      std::printf("    step %.0e: df %+.6g  (predicted %+.6g), dJ_s %+.6g\n", a, f - f0, -a * g.norm(),
                  c.safety - c0.safety);
    }
    if (freeze && std::getenv("PORTER_PROBE_SLOPES")) {
      const Eigen::VectorXd d = -g / g.norm();
      Eigen::VectorXd ga(n);
      for (int i = 0; i <= 20; ++i) {
        const double a = 5e-4 * i, h = 1e-6;
        x = x0 + a * d;
        backend::BackendCost ca;
        const double fa = problem.evaluate(x.data(), ga.data(), &ca);
        x = x0 + (a + h) * d;
        const double fp = problem.evaluate(x.data(), nullptr, nullptr);
        x = x0 + (a - h) * d;
        const double fm = problem.evaluate(x.data(), nullptr, nullptr);
        std::printf("    a %.4f: f-f0 %+10.4g J_s %.6g slope %+10.5g fd %+10.5g\n", a, fa - f0, ca.safety, ga.dot(d),
                    (fp - fm) / (2 * h));
      }
    }
  }
  for (double budget : {0.3, 3.0}) {
    for (bool freeze : {false, true}) {
      baselines::SafetyTermSettings ts = term_settings(*s);
      ts.svsdf.freeze_ball_decisions = freeze;
      auto term = baselines::make_safety_term(baselines::SafetyModel::kKcSvsdf, s->model, s->sdf.get(), ts);
      const backend::BackEnd be(s->model, backend::BackendSettings{});
      const pipeline::KernelAcceptance acceptance(*s->checker);
      const backend::BackendResult r = be.solve(*w.solution, s->grid, *term, planner::Deadline(budget), &acceptance);
      std::printf("  budget %.1f s, %s: %s %.0f ms, %d it, %d evals, rounds %d, J_s %.3g -> %.3g, check %s | %s\n", budget,
                  freeze ? "frozen" : "not frozen", planner::to_string(r.status), 1e3 * r.elapsed_s, r.iterations,
                  r.evaluations, r.rounds,
                  r.initial_cost.safety, r.final_cost.safety, backend::to_string(r.check), r.message.c_str());
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::string section = argc > 1 ? argv[1] : "queries";
  const int seeds = argc > 2 ? std::atoi(argv[2]) : 20;
  if (section == "queries" || section == "all") bench_queries();
  if (section == "scenes" || section == "all") bench_scenes(seeds);
  if (section == "ablation" || section == "all") bench_ablation(seeds);
  if (section == "synthetic" || section == "all") bench_synthetic(seeds);
  if (section == "probe") {
    const double h_b = argc > 2 ? std::atof(argv[2]) : 1.1;
    const int seed = argc > 3 ? std::atoi(argv[3]) : 12;
    const double fe_budget = argc > 4 ? std::atof(argv[4]) : 0.08;
    bench_probe(h_b, seed, fe_budget);
  }
  if (section == "profile") {
    const std::string scene = argc > 3 ? argv[3] : "bridge";
    const double h_b = argc > 4 ? std::atof(argv[4]) : -1.0;
    const double fe_budget = argc > 5 ? std::atof(argv[5]) : 0.08;
    const int first = argc > 6 ? std::atoi(argv[6]) : 1;
    const int reps = argc > 7 ? std::atoi(argv[7]) : 1;
    bench_profile(scene, h_b, first, seeds, fe_budget, reps);
  }
  return 0;
}
