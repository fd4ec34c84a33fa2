#include "porter/backend/svsdf.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "scope_timer.hpp"

namespace porter::backend {
namespace {

using detail::ScopeTimer;

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Values closer than this are equal for the t* search (rounding of a field value near a
/// converged minimum), m.
constexpr double kRoundoff_m = 1e-12;

}  // namespace

SvsdfEvaluator::SvsdfEvaluator(const RobotSdf& sdf, const SweptBody& body, const SvsdfSettings& settings)
    : sdf_(&sdf), body_(&body), settings_(settings) {}

double SvsdfEvaluator::evaluate_at(int link, const Eigen::Vector3d& p, double t_s, double* dsdt) {
  ++stats_.exact_evaluations;
  body_->evaluate(t_s, state_, link);
  const Eigen::Matrix3d& R = state_.kin.R_W_L[static_cast<std::size_t>(link)];
  const Eigen::Vector3d p_L = R.transpose() * (p - state_.kin.t_W_L[static_cast<std::size_t>(link)]);
  Eigen::Vector3d g_L;
  const double f = sdf_->link(link).distance(p_L, dsdt ? &g_L : nullptr);
  if (dsdt) {
    const Eigen::Vector3d grad_W = R * g_L;
    PointJacobian J;
    ChainKinematics::point_jacobian(state_.kin, link, p, J);
    *dsdt = -grad_W.dot(J * state_.config_rate);
  }
  return f;
}

void SvsdfEvaluator::clear_scan() {
  const auto samples = static_cast<std::size_t>(body_->num_samples());
  if (values_.size() != samples) {
    values_.assign(samples, kInf);
  } else {
    for (int k : touched_) values_[static_cast<std::size_t>(k)] = kInf;
  }
  touched_.clear();
}

double SvsdfEvaluator::scan(int link, const Eigen::Vector3d& p, int k_lo, int k_hi, int hint_k, bool dense_lower,
                            double level_cap, double margin_override, bool uniform_skip) {
  clear_scan();
  const LinkSdf& sdf = sdf_->link(link);
  const Eigen::AlignedBox3d& box = sdf.body_bounds();
  const double err = sdf.fine().error_bound_m();
  // Either interpolant (fine or coarse grid) is within err_any of the true signed distance.
  const double err_any = std::max(err, sdf.coarse().error_bound_m());
  // The box bounds below hold the true distance; the value looked up is within err_any of it
  // (the coarse grid's bound where the fine grid does not reach). Subtracting only the fine
  // grid's err let the scan miss samples whose coarse value was lower
  // than the box distance - err: the scan's minimum was then not the samples' minimum
  // (fast_paths_test compares the scans on this).
  const double box_err = err_any;
  const double step = body_->max_step_m(link);
  double best = kInf;
  const double margin = margin_override >= 0.0 ? margin_override : 2.0 * step + 2.0 * err;
  // Samples above the level cannot matter: above best + margin they cannot hold a kept minimum,
  // above level_cap the caller does not use the value.
  const auto level = [&]() { return std::min(best + margin, level_cap); };
  const int n = k_hi - k_lo + 1;
  if (dense_lower) lower_.assign(static_cast<std::size_t>(n), kInf);
  stats_.samples_in_range += n;
  auto set_lower = [&](int k, double v) {
    if (dense_lower) lower_[static_cast<std::size_t>(k - k_lo)] = v;
  };
  int evaluated = 0;
  // Looks sample k up; returns a lower bound on the true signed distance there (for the skip).
  auto look_up = [&](int k, const Eigen::Vector3d& p_L, double box_d) {
    double sd_lower = box_d;
    const double v = sdf.distance_fast(p_L, &sd_lower);
    values_[static_cast<std::size_t>(k)] = v;
    touched_.push_back(k);
    set_lower(k, v);
    ++evaluated;
    best = std::min(best, v);
    return std::max(box_d, sd_lower);
  };
  // Level 1: the link's world box over each piece bounds the field from below for all of the
  // piece's samples; pieces are visited from the closest box and skipped once their bound exceeds
  // the best value found + margin (margin: the scan's values can be refined down by one step of
  // motion, and the two interpolants differ by up to 2 err).
  const int pieces = body_->trajectory().num_pieces();
  const int last_sample = body_->num_samples() - 1;
  piece_order_.clear();
  for (int i = body_->sample_piece(k_lo); i < pieces; ++i) {
    const int a = std::max(k_lo, body_->piece_first_sample(i));
    const int b = std::min(k_hi, i + 1 < pieces ? body_->piece_first_sample(i + 1) - 1 : last_sample);
    if (a > b) {
      if (body_->piece_first_sample(i) > k_hi) break;
      continue;
    }
    const double lb = body_->piece_box(link, i).exteriorDistance(p) - box_err;
    if (dense_lower) {
      for (int k = a; k <= b; ++k) lower_[static_cast<std::size_t>(k - k_lo)] = lb;
    }
    piece_order_.push_back({lb, a, b});
  }
  std::sort(piece_order_.begin(), piece_order_.end(),
            [](const PieceRange& x, const PieceRange& y) { return x.lower < y.lower; });
  // A first guess (the previous evaluation's t*): a tight `best` from the start prunes the most.
  if (hint_k >= k_lo && hint_k <= k_hi) {
    const Eigen::Vector3d p_L = body_->sample_pose(hint_k, link).apply(p);
    look_up(hint_k, p_L, box.exteriorDistance(p_L));
  }
  for (const PieceRange& range : piece_order_) {
    if (range.lower > level()) break;
    if (best == kInf) {
      if (range.lower > level_cap) break;
      // Seed: the sample whose link-frame box is nearest to p.
      int seed = range.first;
      double seed_d = kInf;
      for (int k = range.first; k <= range.last; ++k) {
        const double d = box.exteriorDistance(body_->sample_pose(k, link).apply(p));
        if (d < seed_d) {
          seed_d = d;
          seed = k;
        }
      }
      look_up(seed, body_->sample_pose(seed, link).apply(p), seed_d);
    }
    // Level 2 and 3, swept in time with a Lipschitz skip: the true signed distance of p to the
    // link changes by at most step between neighbouring samples (no link point moves more), and
    // each interpolant is within err_any of it. A sample whose lower bound L holds every sample
    // i steps on above L - i step - err_any; those above best + margin are skipped unvisited.
    int k = range.first;
    while (k <= range.last) {
      ++stats_.samples_visited;
      double sd_lower;
      if (values_[static_cast<std::size_t>(k)] != kInf) {
        sd_lower = values_[static_cast<std::size_t>(k)] - err_any;  // the hint or the seed
      } else {
        const Eigen::Vector3d p_L = body_->sample_pose(k, link).apply(p);
        const double box_d = box.exteriorDistance(p_L);
        if (box_d - box_err > level()) {
          sd_lower = box_d;
          set_lower(k, box_d - box_err);
        } else {
          sd_lower = look_up(k, p_L, box_d);
        }
      }
      // The motion bound is summed over the actual intervals (each at most `step`), so slow
      // stretches of the trajectory are skipped in longer strides than the uniform bound allows;
      // every skipped sample is still proven above the level (scan_reference() checks this).
      const double slack = sd_lower - err_any - level();
      int skip = 0;
      if (slack > 0.0 && uniform_skip) {
        const double span = static_cast<double>(range.last - k);
        const double steps = step > 0.0 ? std::ceil(slack / step) - 1.0 : span;
        skip = static_cast<int>(std::min(span, std::max(0.0, steps)));
        for (int i = 1; dense_lower && i <= skip; ++i) set_lower(k + i, sd_lower - i * step - err_any);
      } else if (slack > 0.0) {
        skip = body_->samples_within_motion(link, k, range.last, slack);
        for (int i = 1; dense_lower && i <= skip; ++i) {
          set_lower(k + i, sd_lower - body_->motion_bound_m(link, k, k + i) - err_any);
        }
      }
      k += 1 + skip;
    }
  }
  stats_.samples_evaluated += evaluated;
  return best;
}

SvsdfEvaluator::Candidate SvsdfEvaluator::refine(int link, const Eigen::Vector3d& p, double a,
                                                 double t_k, double b, double lo, double hi) {
  Candidate c = bracket_minimum(link, p, a, t_k, b, lo, hi);
  // The bracket's root is a local minimum, but an earlier evaluated point may be lower when the
  // field wiggles between samples (a minimum and a maximum within one step, far out in the
  // coarse grid). Then look for the minimum next to that point, once, in a narrow bracket.
  if (!c.stationary && c.in_interior) {
    const double step = 0.25 * body_->settings().scan_dt_s;
    Candidate again = bracket_minimum(link, p, std::max(lo, c.t - step), c.t, std::min(hi, c.t + step), lo, hi);
    if (again.f <= c.f) c = again;
  }
  return c;
}

SvsdfEvaluator::Candidate SvsdfEvaluator::bracket_minimum(int link, const Eigen::Vector3d& p, double a,
                                                          double t_k, double b, double lo, double hi) {
  // Every exact evaluation is offered to keep(): the search's best state is kept so that finish()
  // needs no further forward kinematics.
  auto keep = [this](double f) {
    if (f < kept_f_) {
      kept_f_ = f;
      kept_ = state_;
    }
  };
  double d_k = 0.0;
  Candidate best{t_k, evaluate_at(link, p, t_k, &d_k)};
  keep(best.f);
  if (d_k == 0.0) {
    best.stationary = true;
    return best;
  }
  // Bracket the zero of the derivative. The scan ranks samples with the trilinear field while the
  // refinement follows the C^1 one, so the minimum may lie a little beyond the sample bracket: walk
  // on by whole samples (at most kMaxWalk) until the derivative changes sign or the search ends.
  constexpr int kMaxWalk = 8;
  double l, r, dl, dr, f_l, f_r;  // the bracket [l, r]: derivative signs and values at its ends
  if (d_k > 0.0) {
    if (a >= t_k) return best;
    r = t_k;
    dr = d_k;
    f_r = best.f;
    l = a;
    double fl = evaluate_at(link, p, l, &dl);
    keep(fl);
    if (fl < best.f) best = {l, fl};
    for (int walk = 0; dl >= 0.0 && l > lo && walk < kMaxWalk; ++walk) {
      r = l;
      dr = dl;
      f_r = fl;
      const int k = body_->first_sample_at_or_after(l) - 1;
      l = k >= 0 ? std::max(lo, body_->sample_time(k)) : lo;
      if (l >= r) l = lo;
      fl = evaluate_at(link, p, l, &dl);
      keep(fl);
      if (fl < best.f) best = {l, fl};
    }
    if (dl >= 0.0) return best;
    f_l = fl;
  } else {
    if (b <= t_k) return best;
    l = t_k;
    dl = d_k;
    f_l = best.f;
    r = b;
    double fr = evaluate_at(link, p, r, &dr);
    keep(fr);
    if (fr < best.f) best = {r, fr};
    for (int walk = 0; dr <= 0.0 && r < hi && walk < kMaxWalk; ++walk) {
      l = r;
      dl = dr;
      f_l = fr;
      int k = body_->first_sample_at_or_after(r);
      if (k < body_->num_samples() && body_->sample_time(k) <= r) ++k;
      r = k < body_->num_samples() ? std::min(hi, body_->sample_time(k)) : hi;
      if (r <= l) r = hi;
      fr = evaluate_at(link, p, r, &dr);
      keep(fr);
      if (fr < best.f) best = {r, fr};
    }
    if (dr <= 0.0) return best;
    f_r = fr;
  }
  // Illinois regula falsi on the derivative (continuous: the field is C^1); bisection when the
  // secant leaves the bracket.
  int side = 0;
  for (int it = 0; it < settings_.max_refine_iterations && r - l > settings_.time_tolerance_s; ++it) {
    double m = (l * dr - r * dl) / (dr - dl);
    if (!(m > l && m < r)) m = 0.5 * (l + r);
    double dm = 0.0;
    const double fm = evaluate_at(link, p, m, &dm);
    keep(fm);
    if (fm < best.f) best = {m, fm};
    if (dm > 0.0) {
      r = m;
      dr = dm;
      f_r = fm;
      if (side == 1) dl *= 0.5;
      side = 1;
    } else if (dm < 0.0) {
      l = m;
      dl = dm;
      f_l = fm;
      if (side == -1) dr *= 0.5;
      side = -1;
    } else {
      break;
    }
  }
  // Stationary when the best point is the bracket's (converged) root; an earlier evaluated point
  // that is lower means another minimum lies near it (see refine()).
  // A point outside the bracket that is lower only by rounding (the values near a converged
  // minimum agree to ~1e-16 m) is not another minimum: the bracket's end is the answer.
  const double root_f = std::min(f_l, f_r);
  if (!(best.t >= l - settings_.time_tolerance_s && best.t <= r + settings_.time_tolerance_s) &&
      best.f >= root_f - kRoundoff_m) {
    best = {f_l <= f_r ? l : r, root_f};
  }
  if (best.t >= l - settings_.time_tolerance_s && best.t <= r + settings_.time_tolerance_s) {
    best.stationary = true;
  } else {
    best.in_interior = best.t > lo && best.t < hi;
  }
  return best;
}

void SvsdfEvaluator::finish(int link, const Eigen::Vector3d& p, const Candidate& best, double t_lo,
                            double t_hi, SvsdfValue& out) {
  if (!(kept_f_ == best.f && kept_.t_s == best.t)) {
    ++stats_.exact_evaluations;
    body_->evaluate(best.t, kept_, link);
  }
  out.far = false;
  const BodyState& st = kept_;
  const Eigen::Matrix3d& R = st.kin.R_W_L[static_cast<std::size_t>(link)];
  const Eigen::Vector3d p_L = R.transpose() * (p - st.kin.t_W_L[static_cast<std::size_t>(link)]);
  Eigen::Vector3d g_L;
  out.g = sdf_->link(link).distance(p_L, &g_L);
  out.t_star_s = st.t_s;
  out.grad_p = R * g_L;
  PointJacobian J;
  ChainKinematics::point_jacobian(st.kin, link, p, J);
  out.d_config = -J.transpose() * out.grad_p;
  PointSensitivity& s = out.sensitivity;
  s.t_s = st.t_s;
  s.piece = st.piece;
  s.tau_s = st.tau_s;
  s.at_end = st.at_end;
  s.stationary = best.stationary;
  s.heading_order = st.heading_order;
  body_->config_to_flat(st, out.d_config, s.d_z, s.d_heading);
  const double tol = settings_.time_tolerance_s;
  out.on_window_edge = (t_lo > 0.0 && best.t <= t_lo + tol) ||
                       (t_hi < body_->duration_s() && best.t >= t_hi - tol);
}

void SvsdfEvaluator::full(int link, const Eigen::Vector3d& p_W, SvsdfValue& out) {
  search(link, p_W, 0.0, body_->duration_s(), out);
}

void SvsdfEvaluator::windowed(int link, const Eigen::Vector3d& p_W, double t_center_s, SvsdfValue& out) {
  const double dt = settings_.window_half_width_s;
  search(link, p_W, t_center_s - dt, t_center_s + dt, out);
}

void SvsdfEvaluator::search(int link, const Eigen::Vector3d& p, double t_lo_s, double t_hi_s,
                            SvsdfValue& out) {
  search(link, p, t_lo_s, t_hi_s, out, SearchOptions{});
}

void SvsdfEvaluator::search(int link, const Eigen::Vector3d& p, double t_lo_s, double t_hi_s,
                            SvsdfValue& out, const SearchOptions& options) {
  const ScopeTimer timer(settings_.collect_timing ? &stats_.search_time_s : nullptr);
  ScanProfile* profile = options.profile;
  ++stats_.searches;
  kept_f_ = kInf;
  if (profile) profile->lower.clear();
  const double total = body_->duration_s();
  const double lo = std::clamp(t_lo_s, 0.0, total);
  const double hi = std::clamp(t_hi_s, lo, total);
  if (sdf_->link(link).empty()) {
    out = SvsdfValue{};
    out.g = LinkSdf::kNoGeometryDistance_m;
    out.t_star_s = lo;
    return;
  }
  const int k_lo = body_->first_sample_at_or_after(lo);
  int k_hi = body_->first_sample_at_or_after(hi);
  if (k_hi >= body_->num_samples() || body_->sample_time(k_hi) > hi) --k_hi;
  if (k_lo > k_hi) {
    finish(link, p, refine(link, p, lo, 0.5 * (lo + hi), hi, lo, hi), lo, hi, out);
    out.band_lo_s = out.band_hi_s = out.t_star_s;
    return;
  }
  int hint_k = -1;
  if (std::isfinite(options.hint_t_s)) {
    hint_k = std::min(body_->first_sample_at_or_after(options.hint_t_s), body_->num_samples() - 1);
  }
  const double reach = body_->max_step_m(link) + 2.0 * sdf_->link(link).fine().error_bound_m();
  const double level_cap = options.prune_above_skip ? options.skip_above + reach : kInf;
  // What the search reads from the scan: minima within `reach` of the coarse minimum (the rest
  // are dropped below), each with its two neighbours compared against it (a neighbour left out is
  // above the level, hence above any such minimum, so it compares the same), and the samples
  // within the tie band. The reference scan also looks up the samples within the neighbours'
  // reach (2 max_step + 2 err); the lean one stops at what is read.
  const bool lean = settings_.lean_scan && profile == nullptr;
  double margin_override = -1.0;
  if (options.coarse_only) {
    margin_override = std::max(0.0, options.band);
  } else if (lean) {
    margin_override = std::max(reach, options.band);
  }
  double coarse = scan(link, p, k_lo, k_hi, hint_k, profile != nullptr, level_cap, margin_override, !lean);
  // The cap pruned at a level below best + margin, and the value is needed after all: some
  // samples that could hold a kept minimum may have been skipped, so scan again without the cap.
  const double margin = margin_override >= 0.0
                            ? margin_override
                            : 2.0 * body_->max_step_m(link) + 2.0 * sdf_->link(link).fine().error_bound_m();
  if (!options.coarse_only && coarse <= level_cap && level_cap < coarse + margin) {
    coarse = scan(link, p, k_lo, k_hi, hint_k, profile != nullptr, kInf, margin_override, !lean);
  }
  if (profile) {
    profile->k_lo = k_lo;
    profile->lower.assign(lower_.begin(), lower_.end());
    profile->order.clear();
  }

  const auto value = [this](int k) { return values_[static_cast<std::size_t>(k)]; };
  if (options.coarse_only || coarse > options.skip_above + reach) {
    ++stats_.skipped;
    out = SvsdfValue{};
    out.far = true;
    // With every sample pruned, the level that proved g > skip_above.
    out.g = std::isfinite(coarse) ? coarse : options.skip_above + reach;
    int best = touched_.empty() ? (hint_k >= k_lo && hint_k <= k_hi ? hint_k : k_lo) : touched_[0];
    for (int k : touched_) {
      if (value(k) < value(best) || (value(k) == value(best) && k < best)) best = k;
    }
    out.t_star_s = body_->sample_time(best);
    out.band_lo_s = out.band_hi_s = out.t_star_s;
    if (options.band >= 0.0) {
      for (int k : touched_) {
        if (value(k) > coarse + options.band) continue;
        out.band_lo_s = std::min(out.band_lo_s, body_->sample_time(k));
        out.band_hi_s = std::max(out.band_hi_s, body_->sample_time(k));
      }
    }
    return;
  }
  // Local minima among the looked-up samples (a skipped sample is above best + margin, so it
  // never hides a minimum that can be kept below).
  minima_.clear();
  for (int k : touched_) {
    const double v = value(k);
    const double left = k > k_lo ? value(k - 1) : kInf;
    const double right = k < k_hi ? value(k + 1) : kInf;
    if (v <= left && v < right) minima_.push_back(k - k_lo);
  }
  const int n = k_hi - k_lo + 1;
  const auto by_value = [&](int a, int b) {
    const double va = value(k_lo + a), vb = value(k_lo + b);
    return va < vb || (va == vb && a < b);
  };
  int keep = std::min(static_cast<int>(minima_.size()), std::max(1, settings_.max_local_minima));
  std::partial_sort(minima_.begin(), minima_.begin() + keep, minima_.end(), by_value);
  // A minimum can only beat the best one after refinement if its sample value is within the
  // largest drop between samples (one step of motion) plus the two interpolants' difference.
  while (keep > 1 && value(k_lo + minima_[static_cast<std::size_t>(keep) - 1]) >
                         value(k_lo + minima_[0]) + reach) {
    --keep;
  }

  Candidate best{lo, kInf};
  for (int m = 0; m < keep; ++m) {
    const int i = minima_[static_cast<std::size_t>(m)];
    const int k = k_lo + i;
    const double a = i > 0 ? body_->sample_time(k - 1) : lo;
    const double b = i + 1 < n ? body_->sample_time(k + 1) : hi;
    const Candidate c = refine(link, p, a, body_->sample_time(k), b, lo, hi);
    if (c.f < best.f) best = c;
  }
  finish(link, p, best, lo, hi, out);
  out.band_lo_s = out.band_hi_s = out.t_star_s;
  if (options.band >= 0.0) {
    for (int k : touched_) {
      if (value(k) > out.g + options.band) continue;
      out.band_lo_s = std::min(out.band_lo_s, body_->sample_time(k));
      out.band_hi_s = std::max(out.band_hi_s, body_->sample_time(k));
    }
  }
}

double SvsdfEvaluator::coarse_minimum(int link, const Eigen::Vector3d& p, double t_lo_s, double t_hi_s) {
  const double total = body_->duration_s();
  const double lo = std::clamp(t_lo_s, 0.0, total);
  const double hi = std::clamp(t_hi_s, lo, total);
  if (sdf_->link(link).empty()) return LinkSdf::kNoGeometryDistance_m;
  const int k_lo = body_->first_sample_at_or_after(lo);
  int k_hi = body_->first_sample_at_or_after(hi);
  if (k_hi >= body_->num_samples() || body_->sample_time(k_hi) > hi) --k_hi;
  if (k_lo > k_hi) return evaluate_at(link, p, 0.5 * (lo + hi), nullptr);
  return scan(link, p, k_lo, k_hi, -1, false, kInf, -1.0, !settings_.lean_scan);
}

}  // namespace porter::backend
