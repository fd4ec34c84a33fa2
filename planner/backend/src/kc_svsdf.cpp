#include "porter/backend/kc_svsdf.hpp"

#include <algorithm>
#include <cmath>

namespace porter::backend {
namespace {

constexpr double kGoldenAngle = 2.399963229728653;  // pi (3 - sqrt 5)

/// Columns of the 9-D configuration that joint i drives: 0 -> base (x, y, yaw), i >= 1 -> q_i.
int first_column(int joint) { return joint == 0 ? 0 : 2 + joint; }
int column_count(int joint) { return joint == 0 ? 3 : 1; }

}  // namespace

void KcSvsdfStats::add(const KcSvsdfStats& o) {
  queries += o.queries;
  links_computed += o.links_computed;
  inside_links += o.inside_links;
  ball_iterations += o.ball_iterations;
  ball_samples += o.ball_samples;
  ball_filtered += o.ball_filtered;
  filter_relaxed += o.filter_relaxed;
  window_edge_hits += o.window_edge_hits;
  replays += o.replays;
  surrogates += o.surrogates;
}

void KcSvsdfResult::add_gradient(const Trajectory& trajectory, int link, double weight,
                                 TrajectoryGradient& grad) const {
  const LinkDistance& l = links[static_cast<std::size_t>(link)];
  for (std::size_t k = 0; k < l.terms.size(); ++k) grad.add(trajectory, l.terms[k], weight * l.weights[k]);
}

KcSvsdf::KcSvsdf(const RobotSdf& sdf, const SweptBody& body, const KcSvsdfSettings& settings)
    : settings_(settings), eval_(sdf, body, settings.svsdf) {
  const int n = std::max(4, settings_.ball_samples);
  lattice_.resize(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    const double z = 1.0 - (2.0 * k + 1.0) / n;
    const double rho = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = kGoldenAngle * k;
    lattice_[static_cast<std::size_t>(k)] = Eigen::Vector3d(rho * std::cos(phi), rho * std::sin(phi), z);
  }
  a_.reserve(static_cast<std::size_t>(settings_.max_iterations));
}

void KcSvsdf::evaluate(const Eigen::Vector3d& p, std::uint32_t needed, KcSvsdfResult& out, double d_cap,
                       const TimeHints* hints, BallDecisions* decisions, bool record) {
  ++stats_.queries;
  hints_ = hints;
  decisions_ = decisions;
  record_ = record;
  for (LinkDistance& l : out.links) {
    l.computed = false;
    l.far = false;
    l.terms.clear();
    l.weights.clear();
  }
  out.G.setZero();
  d_cap_ = d_cap;
  // The base's t0* only centres the windows of links 1..7 (+- dt, seconds wide): when the base's
  // own D is not asked for, or is above the cap, its scan's best sample is t0* (half a scan step
  // from the refined one) and the base is not refined; ensure() refines it if the filter needs its
  // escape.
  SearchOptions base_options;
  base_options.skip_above = d_cap;
  base_options.coarse_only = !(needed & 1u);
  base_options.prune_above_skip = false;
  base_options.band = settings_.svsdf.base_tie_band_m;
  base_options.hint_t_s = hint(0);
  eval_.search(0, p, 0.0, eval_.body().duration_s(), base_, base_options);
  out.t0_star_s = base_.t_star_s;
  const double dt = settings_.svsdf.window_half_width_s;
  out.window_lo_s = base_.band_lo_s - dt;
  out.window_hi_s = base_.band_hi_s + dt;
  for (int j = 0; j < kNumLinks; ++j) {
    if (needed & (1u << j)) ensure(j, p, out, false);
  }
}

void KcSvsdf::ensure(int j, const Eigen::Vector3d& p, KcSvsdfResult& out, bool exact) {
  LinkDistance& l = out.links[static_cast<std::size_t>(j)];
  if (l.computed && !(exact && l.far)) return;
  ++stats_.links_computed;
  SvsdfValue v;
  SearchOptions options;
  options.skip_above = exact ? std::numeric_limits<double>::infinity() : d_cap_;
  options.hint_t_s = hint(j);
  if (j == 0) {
    if (exact && base_.far) {
      SearchOptions refine_base;
      refine_base.hint_t_s = base_.t_star_s;
      eval_.search(0, p, 0.0, eval_.body().duration_s(), base_, refine_base);
    }
    v = base_;
  } else {
    eval_.search(j, p, out.window_lo_s, out.window_hi_s, v, options);
    stats_.window_edge_hits += v.on_window_edge;
  }
  l.far = v.far;
  if (v.far) {
    // Farther than the cap: only the value (an upper bound within one step) is known.
    l.g = v.g;
    l.d = v.g;
    l.t_star_s = v.t_star_s;
    l.inside = false;
    l.escape.setZero();
    l.grad_p.setZero();
    l.terms.clear();
    l.weights.clear();
    l.computed = true;
    return;
  }
  l.replayed = false;
  l.surrogate = false;
  l.g = v.g;
  l.t_star_s = v.t_star_s;
  l.iterations = 0;
  l.converged = true;
  l.filter_relaxed = false;
  l.saturated = false;
  l.on_window_edge = false;
  if (v.g > 0.0) {
    l.on_window_edge = v.on_window_edge;
    l.inside = false;
    l.d = v.g;
    l.grad_p = v.grad_p;
    l.escape = v.d_config;  // -J_j^T grad g_j
    l.terms.assign(1, v.sensitivity);
    l.weights.assign(1, 1.0);
  } else {
    ++stats_.inside_links;
    l.inside = true;
    const bool frozen = decisions_ && !record_;
    if (frozen && !(*decisions_)[static_cast<std::size_t>(j)].valid) {
      // No decision taken for this pair at the last refresh: g_j(p) stands for D (see header).
      ++stats_.surrogates;
      l.surrogate = true;
      l.d = v.g;
      l.grad_p = v.grad_p;
      l.escape = v.d_config;
      l.on_window_edge = v.on_window_edge;
      l.terms.assign(1, v.sensitivity);
      l.weights.assign(1, 1.0);
    } else {
      if (settings_.kinematic_filter && j >= 2 && !frozen) {
        ensure(j - 2, p, out, true);
        ensure(j - 1, p, out, true);
      }
      // The ball search reads p's profile over the window (the base's g_0 came from the full
      // search; the searches above did not keep one): search the window again with the profile.
      SearchOptions with_profile;
      with_profile.profile = &profile_;
      with_profile.hint_t_s = v.t_star_s;
      eval_.search(j, p, out.window_lo_s, out.window_hi_s, v, with_profile);
      if (frozen) {
        replay(j, p, v, (*decisions_)[static_cast<std::size_t>(j)], out);
      } else {
        ball_search(j, p, v, out);
      }
    }
  }
  l.computed = true;
  out.G += l.escape;
}

void KcSvsdf::ball_search(int j, const Eigen::Vector3d& p, const SvsdfValue& at_p, KcSvsdfResult& out) {
  LinkDistance& l = out.links[static_cast<std::size_t>(j)];
  const SweptBody& body = eval_.body();
  body.evaluate(at_p.t_star_s, state_, j);
  PointJacobian J;
  ChainKinematics::point_jacobian(state_.kin, j, p, J);

  // KinematicFilter as half-spaces on the direction s (y = p + r s): escape_y = -r J^T s, so
  // escape_y[i] . G[i] >= 0  <=>  s . w_i <= 0 with w_i = sum over joint i's columns c of G_c J_c.
  std::array<Eigen::Vector3d, 2> w;
  int num_constraints = 0;
  if (settings_.kinematic_filter && j >= 2) {
    for (int i : {j - 2, j - 1}) {
      Eigen::Vector3d wi = Eigen::Vector3d::Zero();
      double G_norm2 = 0.0;
      for (int c = first_column(i); c < first_column(i) + column_count(i); ++c) {
        double G_c = 0.0;  // links i..j-1 are the only contributors to joint i's entries
        for (int u = i; u < j; ++u) G_c += out.links[static_cast<std::size_t>(u)].escape[c];
        wi += G_c * J.col(c);
        G_norm2 += G_c * G_c;
      }
      // No consensus on this joint yet: the sign test would follow rounding noise.
      if (G_norm2 < settings_.consensus_tolerance * settings_.consensus_tolerance) continue;
      w[static_cast<std::size_t>(num_constraints++)] = wi;
    }
  }

  double r = settings_.initial_radius_m;
  a_.clear();
  directions_.clear();
  l.terms.clear();
  l.weights.clear();
  term_grads_.clear();
  Eigen::Vector3d s_final = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d hint = at_p.grad_p;
  bool stopped = false;
  for (int it = 0; it < settings_.max_iterations && !stopped; ++it) {
    ++stats_.ball_iterations;
    const double c = std::cos(kGoldenAngle * it), s = std::sin(kGoldenAngle * it);
    double best = -std::numeric_limits<double>::infinity();
    Eigen::Vector3d best_dir = Eigen::Vector3d::UnitZ();
    int best_k = -1;
    int survivors = 0;
    for (int pass = 0; pass < 2 && survivors == 0; ++pass) {
      const bool filter = pass == 0 && num_constraints > 0;
      if (pass == 1) {
        if (num_constraints == 0) break;
        l.filter_relaxed = true;
        ++stats_.filter_relaxed;
      }
      // Visit the directions starting from the one closest to the last worst violator (at first
      // the field's gradient at p, which points to the nearest boundary): the max is found early
      // and the other scans stop sooner. The set, hence the result, does not change.
      const int count = static_cast<int>(lattice_.size());
      int first = 0;
      double align = -2.0;
      for (int k = 0; k < count; ++k) {
        const Eigen::Vector3d& d0 = lattice_[static_cast<std::size_t>(k)];
        const double a = Eigen::Vector3d(c * d0.x() - s * d0.y(), s * d0.x() + c * d0.y(), d0.z()).dot(hint);
        if (a > align) {
          align = a;
          first = k;
        }
      }
      for (int step = 0; step < count; ++step) {
        const Eigen::Vector3d& d0 = lattice_[static_cast<std::size_t>((first + step) % count)];
        const Eigen::Vector3d dir(c * d0.x() - s * d0.y(), s * d0.x() + c * d0.y(), d0.z());
        if (filter) {
          bool keep = true;
          for (int k = 0; k < num_constraints; ++k) keep = keep && dir.dot(w[static_cast<std::size_t>(k)]) <= 0.0;
          if (!keep) {
            ++stats_.ball_filtered;
            continue;
          }
        }
        ++survivors;
        ++stats_.ball_samples;
        int k = -1;
        // Max over directions of a min over time: a direction whose running minimum drops below
        // the best so far cannot be the worst violator, so its scan stops there.
        const double g = eval_.coarse_minimum_near(j, p + r * dir, profile_, r, best, &k);
        if (g > best) {
          best = g;
          best_dir = dir;
          best_k = k;
        }
      }
    }
    s_final = best_dir;
    hint = best_dir;
    if (best < settings_.epsilon_m) break;  // every survivor is (nearly) inside
    // Refine g_j(y*) from its coarse minimum, within the window.
    SvsdfValue vy;
    eval_.refine_sample(j, p + r * best_dir, best_k, out.window_lo_s, out.window_hi_s, vy);
    if (vy.g < settings_.epsilon_m) break;
    l.on_window_edge = l.on_window_edge || vy.on_window_edge;
    // r <- r - g(y*); record the term for the gradient recursion.
    l.terms.push_back(vy.sensitivity);
    term_grads_.push_back(vy.grad_p);
    a_.push_back(vy.grad_p.dot(best_dir));
    directions_.push_back(best_dir);
    ++l.iterations;
    r -= vy.g;
    if (r <= 0.0) {
      r = 0.0;
      stopped = true;
    }
    if (it + 1 == settings_.max_iterations) l.converged = false;
  }
  l.d = -r;
  l.escape = J.transpose() * (-r * s_final);  // J^T (p - y*), y* = p + r s
  if (decisions_ && record_) {
    BallDecision& rec = (*decisions_)[static_cast<std::size_t>(j)];
    rec.valid = true;
    rec.directions = directions_;
    rec.final_direction = s_final;
  }
  finish_terms(l, at_p);
}

void KcSvsdf::replay(int j, const Eigen::Vector3d& p, const SvsdfValue& at_p, const BallDecision& rec,
                     KcSvsdfResult& out) {
  ++stats_.replays;
  LinkDistance& l = out.links[static_cast<std::size_t>(j)];
  l.replayed = true;
  eval_.body().evaluate(at_p.t_star_s, state_, j);
  PointJacobian J;
  ChainKinematics::point_jacobian(state_.kin, j, p, J);
  double r = settings_.initial_radius_m;
  a_.clear();
  l.terms.clear();
  l.weights.clear();
  term_grads_.clear();
  for (const Eigen::Vector3d& dir : rec.directions) {
    ++stats_.ball_iterations;
    ++stats_.ball_samples;
    const Eigen::Vector3d y = p + r * dir;
    int k = -1;
    eval_.coarse_minimum_near(j, y, profile_, r, -std::numeric_limits<double>::infinity(), &k);
    SvsdfValue vy;
    eval_.refine_sample(j, y, k, out.window_lo_s, out.window_hi_s, vy);
    l.on_window_edge = l.on_window_edge || vy.on_window_edge;
    l.terms.push_back(vy.sensitivity);
    term_grads_.push_back(vy.grad_p);
    a_.push_back(vy.grad_p.dot(dir));
    ++l.iterations;
    r -= vy.g;
    if (r <= 0.0) {
      r = 0.0;
      break;
    }
  }
  l.d = -r;
  l.escape = J.transpose() * (-r * rec.final_direction);
  finish_terms(l, at_p);
}

void KcSvsdf::finish_terms(LinkDistance& l, const SvsdfValue& at_p) {
  if (l.terms.empty()) {
    // Saturated at -r0: no dependence on the trajectory; fall back to g_j(p)'s gradient.
    l.saturated = -l.d >= settings_.initial_radius_m;
    l.terms.assign(1, at_p.sensitivity);
    l.weights.assign(1, 1.0);
    l.grad_p = at_p.grad_p;
    l.on_window_edge = at_p.on_window_edge;
    return;
  }
  // c_k = prod_{m > k} (1 - a_m).
  const std::size_t K = l.terms.size();
  l.weights.assign(K, 1.0);
  for (std::size_t k = K - 1; k-- > 0;) l.weights[k] = l.weights[k + 1] * (1.0 - a_[k + 1]);
  l.grad_p.setZero();
  for (std::size_t k = 0; k < K; ++k) l.grad_p += l.weights[k] * term_grads_[k];
}

}  // namespace porter::backend
