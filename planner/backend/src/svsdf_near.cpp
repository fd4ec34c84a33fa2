// SvsdfEvaluator's ball-search support (svsdf.hpp): refinement from a known sample and the coarse
// minimum near a profiled point. Split from svsdf.cpp (the scan and the full search).
#include <algorithm>
#include <cmath>
#include <limits>

#include "porter/backend/svsdf.hpp"
#include "scope_timer.hpp"

namespace porter::backend {
namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
using detail::ScopeTimer;
}  // namespace


void SvsdfEvaluator::refine_sample(int link, const Eigen::Vector3d& p, int k, double t_lo_s, double t_hi_s,
                                   SvsdfValue& out) {
  const ScopeTimer timer(settings_.collect_timing ? &stats_.search_time_s : nullptr);
  ++stats_.searches;
  kept_f_ = kInf;
  const double total = body_->duration_s();
  const double lo = std::clamp(t_lo_s, 0.0, total);
  const double hi = std::clamp(t_hi_s, lo, total);
  const double t_k = std::clamp(body_->sample_time(k), lo, hi);
  const double a = k > 0 ? std::max(lo, body_->sample_time(k - 1)) : lo;
  const double b = k + 1 < body_->num_samples() ? std::min(hi, body_->sample_time(k + 1)) : hi;
  finish(link, p, refine(link, p, a, t_k, b, lo, hi), lo, hi, out);
  out.band_lo_s = out.band_hi_s = out.t_star_s;
}

double SvsdfEvaluator::coarse_minimum_near(int link, const Eigen::Vector3d& y, ScanProfile& profile,
                                           double radius_m, double abort_below, int* argmin_k) {
  const ScopeTimer timer(settings_.collect_timing ? &stats_.search_time_s : nullptr);
  const LinkSdf& sdf = sdf_->link(link);
  const int n = static_cast<int>(profile.lower.size());
  if (n == 0 || sdf.empty()) {
    if (argmin_k) *argmin_k = -1;
    return sdf.empty() ? LinkSdf::kNoGeometryDistance_m : kInf;
  }
  const Eigen::AlignedBox3d& box = sdf.body_bounds();
  const double err = sdf.fine().error_bound_m();
  const double margin = 2.0 * body_->max_step_m(link) + 2.0 * err;
  // Both interpolants are convex combinations of a 1-Lipschitz field's nodes: their slope is at
  // most sqrt(3) (per-axis node differences <= h), hence the factor on the radius.
  const double slack = 1.75 * radius_m + margin;
  // Instants in order of p's proximity: y's minimum is usually among the first (early abort for
  // losing directions), and once p's bound minus the slack exceeds the best, so do all later ones.
  stats_.samples_in_range += n;
  if (profile.order.size() != profile.lower.size()) {
    profile.order.resize(profile.lower.size());
    for (std::size_t i = 0; i < profile.order.size(); ++i) profile.order[i] = static_cast<int>(i);
    std::sort(profile.order.begin(), profile.order.end(), [&profile](int a, int b) {
      return profile.lower[static_cast<std::size_t>(a)] < profile.lower[static_cast<std::size_t>(b)];
    });
  }
  const int seed = profile.order[0];
  double best = sdf.distance_fast(body_->sample_pose(profile.k_lo + seed, link).apply(y));
  int best_k = profile.k_lo + seed;
  int evaluated = 1;
  for (int r = 1; r < n && best >= abort_below; ++r) {
    const int i = profile.order[static_cast<std::size_t>(r)];
    if (profile.lower[static_cast<std::size_t>(i)] - slack > best) break;
    const Eigen::Vector3d y_L = body_->sample_pose(profile.k_lo + i, link).apply(y);
    if (box.exteriorDistance(y_L) - err > best + margin) continue;
    const double v = sdf.distance_fast(y_L);
    ++evaluated;
    if (v < best) {
      best = v;
      best_k = profile.k_lo + i;
    }
  }
  stats_.samples_evaluated += evaluated;
  if (argmin_k) *argmin_k = best_k;
  return best;
}

}  // namespace porter::backend
