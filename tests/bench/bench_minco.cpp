// MINCO / mid-end micro-benchmarks.
//
//   cmake --build <build> --target porter-bench-minco
//   <build>/tests/bench/porter-bench-minco --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
//
// Fixtures are frozen (tests/planner/midend/support/synthetic_paths.*): a straight line with
// N pieces for the per-piece costs and forest_slalom(50) (~20 m, 50 nodes, one reverse
// manoeuvre, arm motion) for the full solve. Do not modify them or the numbers stop being
// comparable.
//
//   (time_per_piece is CPU time per iteration divided by the number of pieces: "512n" = 512 ns.)
//   BM_MincoCore/N        MincoS3<8> alone: solve + energy + energy gradient + adjoint propagation
//   BM_CostGradNoPenalty/N the mid-end cost + gradient with energy and time only (per piece)
//   BM_CostGradFull/N      the mid-end cost + gradient with every penalty (kappa = 16)
//   BM_SolveForest/budget  full mid-end solve of the forest path with that budget (ms; 0 = 10 s)
//   BM_SolveScene/scene/seed full mid-end solve (the planner's 100 ms budget) of the real
//                          front-end path of config/scenes/{bridge,tunnel,forest}.yaml (scene 0, 1,
//                          2) for that seed (front-end run once at start-up with a 5 s budget, so
//                          that it stops on its iteration count and the path does not depend on
//                          machine load; skipped when it fails). The counter "valid" is 1 when the
//                          trajectory passes every check of trajectory_checks.hpp (1 ms sampling).
//   BM_SolveForestConverged same, with a tighter stop test (relative decrease 1e-4), for the
//                          duration the optimizer reaches when it is given time
//
// Figures are recorded in the README (Performance) with the command that made them.

#include <benchmark/benchmark.h>

#include <optional>
#include <string>

#include "porter/midend/midend.hpp"
#include "porter/midend/midend_problem.hpp"
#include "porter/midend/reference_path.hpp"
#include "porter/minco/minco_s3.hpp"
#include "scene_paths.hpp"
#include "synthetic_paths.hpp"
#include "trajectory_checks.hpp"

namespace {

using namespace porter;
using namespace porter::midend;

void BM_MincoCore(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  using M = minco::MincoS3<8>;
  M m;
  M::BoundaryState head = M::BoundaryState::Zero(), tail = M::BoundaryState::Zero();
  tail.col(0).setConstant(0.4 * n);
  M::Waypoints q(8, n - 1);
  for (int i = 0; i < n - 1; ++i) q.col(i).setConstant(0.4 * (i + 1));
  Eigen::VectorXd t = Eigen::VectorXd::Constant(n, 0.5);
  M::Vector w = M::Vector::Ones();
  M::Coefficients gc(6 * n, 8);
  Eigen::VectorXd gt(n), gt_total(n);
  M::Waypoints gq;
  M::BoundaryState gh, gtl;
  for (auto _ : state) {
    t[0] += 1e-12;
    m.generate(head, tail, q, t);
    gc.setZero();
    gt.setZero();
    benchmark::DoNotOptimize(m.energy(w));
    m.add_energy_gradient(w, gc, gt);
    m.propagate_gradient(gc, gt, gq, gt_total, gh, gtl);
    benchmark::DoNotOptimize(gt_total.data());
  }
  state.counters["time_per_piece"] =
      benchmark::Counter(static_cast<double>(n) * state.iterations(),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_MincoCore)->Arg(10)->Arg(30)->Arg(100);

void cost_grad(benchmark::State& state, std::uint32_t terms) {
  const int n = static_cast<int>(state.range(0));
  MidendSettings settings;
  settings.max_edges_per_piece = 1;  // N pieces for N edges: comparable per-piece numbers
  const MidendLimits limits = MidendLimits::from_robot(testing::scout_mini_piper_model());
  const ReferenceBuild ref = build_reference_path(testing::straight_line(n), limits, settings);
  MidendProblem problem(ref.path, limits, settings);
  problem.set_terms(terms);
  Eigen::VectorXd x = problem.initial_guess();
  Eigen::VectorXd g(problem.num_variables());
  for (auto _ : state) {
    x[0] += 1e-12;
    benchmark::DoNotOptimize(problem.evaluate(x, &g, nullptr));
    benchmark::DoNotOptimize(g.data());
  }
  state.counters["pieces"] = problem.num_pieces();
  state.counters["time_per_piece"] =
      benchmark::Counter(static_cast<double>(problem.num_pieces()) * state.iterations(),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_CostGradNoPenalty(benchmark::State& state) { cost_grad(state, kTermEnergy | kTermTime); }
BENCHMARK(BM_CostGradNoPenalty)->Arg(10)->Arg(30)->Arg(100);

void BM_CostGradFull(benchmark::State& state) { cost_grad(state, kTermAll); }
BENCHMARK(BM_CostGradFull)->Arg(10)->Arg(30)->Arg(100);

void BM_SolveForest(benchmark::State& state) {
  const double budget_s = state.range(0) > 0 ? 1e-3 * state.range(0) : 10.0;
  const MidEnd midend(testing::scout_mini_piper_model());
  const planner::WholeBodyPath path = testing::forest_slalom(50);
  MidendResult r;
  for (auto _ : state) {
    r = midend.solve(path, budget_s);
    benchmark::DoNotOptimize(r.final_cost.total());
  }
  state.counters["iterations"] = r.iterations;
  state.counters["evaluations"] = r.evaluations;
  state.counters["pieces"] = r.num_pieces;
  state.counters["T_total_s"] = r.ok() ? r.trajectory->total_duration_s() : -1.0;
  state.counters["penalty"] = r.final_cost.penalties();
  state.counters["converged"] = r.status == planner::Status::kConverged ||
                                r.status == planner::Status::kConvergedWithWarning;
  state.SetLabel(to_string(r.status));
}
BENCHMARK(BM_SolveForest)->Arg(30)->Arg(0)->Unit(benchmark::kMillisecond)->Iterations(5);

void BM_SolveScene(benchmark::State& state) {
  static const char* kScenes[] = {"bridge", "tunnel", "forest"};
  const char* scene = kScenes[state.range(0)];
  const std::optional<testing::ScenePath> sp = testing::frontend_path(scene, static_cast<std::uint64_t>(state.range(1)), 5.0);
  if (!sp) {
    state.SkipWithError("the front-end found no path");
    return;
  }
  const MidEnd midend(testing::shipped_robot(""));
  MidendResult r;
  for (auto _ : state) {
    r = midend.solve(sp->path, 0.1);  // the planner's mid-end budget
    benchmark::DoNotOptimize(r.final_cost.total());
  }
  state.counters["iterations"] = r.iterations;
  state.counters["evaluations"] = r.evaluations;
  state.counters["pieces"] = r.num_pieces;
  state.counters["segments"] = r.num_segments;
  state.counters["T_total_s"] = r.ok() ? r.trajectory->total_duration_s() : -1.0;
  state.counters["valid"] =
      r.ok() && testing::violations(testing::check_trajectory(*r.trajectory, sp->path, midend.limits(), midend.settings()))
                    .empty();
  state.SetLabel(std::string(scene) + " " + to_string(r.status));
}
BENCHMARK(BM_SolveScene)
    ->ArgsProduct({{0, 1, 2}, {1, 2, 3, 4, 5}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(5);

void BM_SolveForestConverged(benchmark::State& state) {
  MidendSettings settings;
  settings.relative_cost_tolerance = 1e-4;
  const MidEnd midend(testing::scout_mini_piper_model(), settings);
  const planner::WholeBodyPath path = testing::forest_slalom(50);
  MidendResult r;
  for (auto _ : state) {
    r = midend.solve(path, 10.0);
    benchmark::DoNotOptimize(r.final_cost.total());
  }
  state.counters["iterations"] = r.iterations;
  state.counters["evaluations"] = r.evaluations;
  state.counters["T_total_s"] = r.ok() ? r.trajectory->total_duration_s() : -1.0;
  state.counters["penalty"] = r.final_cost.penalties();
  state.SetLabel(to_string(r.status));
}
BENCHMARK(BM_SolveForestConverged)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
