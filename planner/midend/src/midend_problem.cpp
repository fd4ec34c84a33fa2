#include "porter/midend/midend_problem.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "porter/minco/time_map.hpp"
#include "porter/midend/diff_drive.hpp"
#include "piece_sampler.hpp"
#include "sample_penalty.hpp"

namespace porter::midend {
namespace {

constexpr std::uint32_t kSampledTerms = kTermWheelVelocity | kTermWheelAcceleration |
                                        kTermJointPosition | kTermJointVelocity |
                                        kTermJointAcceleration | kTermResidualBase |
                                        kTermResidualArm | kTermMinSpeed;

TrajVector node_vector(const RobotConfiguration& c) {
  TrajVector z;
  z << c.base.x_m, c.base.y_m, c.q_rad;
  return z;
}

}  // namespace

MidendProblem::MidendProblem(ReferencePath reference, const MidendLimits& limits,
                             const MidendSettings& settings)
    : reference_(std::move(reference)), limits_(limits), settings_(settings) {
  penalty_.kind = settings_.penalty_kind;
  penalty_.mu = settings_.penalty_smoothing;
  energy_weights_.setConstant(settings_.energy_weight_joint);
  energy_weights_.head<2>().setConstant(settings_.energy_weight_base);
  set_terms(kTermAll);

  const int num_segments = static_cast<int>(reference_.segments.size());
  int offset = 0;
  segment_layout_.resize(num_segments);
  for (int s = 0; s < num_segments; ++s) {
    const int m = reference_.segments[s].num_pieces();
    segment_layout_[s].pieces = m;
    segment_layout_[s].q_offset = offset;
    offset += kTrajDim * (m - 1);
    segment_layout_[s].tau_offset = offset;
    offset += m;
  }
  for (int s = 0; s < num_segments; ++s) {
    const ReferenceSegment& seg = reference_.segments[s];
    const int m = seg.num_pieces();
    SegmentLayout& l = segment_layout_[s];
    l.min_speed.assign(m, 0.0);
    l.kappa.assign(m, 0);
    l.fractions.resize(m);
    for (int i = 0; i < m; ++i) {
      const int edges = seg.edges_in_piece(i);
      double moved = 0.0;
      for (int e = seg.knots[i]; e < seg.knots[i + 1]; ++e) {
        moved += std::hypot(seg.nodes[e + 1].base.x_m - seg.nodes[e].base.x_m,
                            seg.nodes[e + 1].base.y_m - seg.nodes[e].base.y_m);
      }
      // The non-singular speed, but never above slow_reference_fraction of the reference's own
      // speed over the piece (initial duration): where the front-end creeps (a large arm motion
      // over a few millimetres of base path, typically its last edge onto the goal), forcing
      // v_ns would push the base past the next node and make it reverse inside the segment.
      const double v_ref = moved / seg.durations_s[i];
      l.min_speed[i] = moved < settings_.min_segment_length_m
                           ? 0.0
                           : std::min(settings_.min_speed_fraction * limits_.nonsingular_speed_mps,
                                      settings_.slow_reference_fraction * v_ref);
      l.kappa[i] = seg.intervals[i];
      for (int k = 0; k <= edges; ++k) l.fractions[i].push_back(seg.fraction_in_piece(i, k));
    }
    l.still = seg.base_still;
    if (l.still) l.still_base = Eigen::Vector2d(seg.nodes.front().base.x_m, seg.nodes.front().base.y_m);
    // The base rests at the global start (unless the start state moves it) and goal and where a
    // still segment begins or ends. No speed is kept on the piece leaving the global start.
    l.rest_start = !l.still && (s == 0 ? reference_.start.base_at_rest() : reference_.segments[s - 1].base_still);
    l.rest_end = !l.still && (s + 1 == num_segments ? reference_.end.base_at_rest() : reference_.segments[s + 1].base_still);
    if (l.rest_start || (s == 0 && !reference_.cut_start_position)) l.min_speed.front() = 0.0;
    if (l.rest_end) l.min_speed.back() = 0.0;
  }
  gear_layout_.resize(num_segments > 0 ? num_segments - 1 : 0);
  for (int g = 0; g + 1 < num_segments; ++g) {
    GearLayout& gl = gear_layout_[g];
    gl.offset = offset;
    offset += kGearVars;
    const int still = reference_.segments[g].base_still ? g : reference_.segments[g + 1].base_still ? g + 1 : -1;
    gl.rest = still >= 0;
    if (gl.rest) gl.base = segment_layout_[still].still_base;
  }
  time_scale_index_ = offset++;  // global log time scale (conditioning; see header)
  num_variables_ = offset;

  node_dir_.resize(num_segments);
  for (int s = 0; s < num_segments; ++s) {
    for (const RobotConfiguration& n : reference_.segments[s].nodes) {
      node_dir_[s].push_back({std::cos(n.base.yaw_rad), std::sin(n.base.yaw_rad)});
    }
  }
  extra_grad_.coeffs.resize(reference_.num_pieces());
  extra_grad_.durations_s.resize(reference_.num_pieces());

  minco_.resize(num_segments);
  durations_.resize(num_segments);
  dtdtau_.resize(num_segments);
  grad_c_.resize(num_segments);
  grad_t_.resize(num_segments);
  waypoints_.resize(num_segments);
  grad_q_.resize(num_segments);
  for (int s = 0; s < num_segments; ++s) {
    const int m = segment_layout_[s].pieces;
    durations_[s].resize(m);
    dtdtau_[s].resize(m);
    grad_c_[s].resize(minco::kPieceCoeffs * m, kTrajDim);
    grad_t_[s].resize(m);
    waypoints_[s].resize(kTrajDim, m - 1);
    grad_q_[s].resize(kTrajDim, m - 1);
  }
  int max_kappa = 1;
  for (const SegmentLayout& l : segment_layout_) {
    for (const int kappa : l.kappa) max_kappa = std::max(max_kappa, kappa);
  }
  sample_work_.assign(static_cast<std::size_t>(detail::sampler_work_size(max_kappa)), 0.0);
}

Eigen::VectorXd MidendProblem::initial_guess() const {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(num_variables_);
  const int num_segments = static_cast<int>(reference_.segments.size());
  for (int s = 0; s < num_segments; ++s) {
    const ReferenceSegment& seg = reference_.segments[s];
    const SegmentLayout& l = segment_layout_[s];
    for (int i = 0; i + 1 < l.pieces; ++i) {
      x.segment<kTrajDim>(l.q_offset + kTrajDim * i) = node_vector(seg.nodes[seg.knots[i + 1]]);
    }
    for (int i = 0; i < l.pieces; ++i) {
      x[l.tau_offset + i] = minco::tau_from_duration(seg.durations_s[i]);
    }
    if (s + 1 < num_segments) {
      const RobotConfiguration& gear = seg.nodes.back();
      const int o = gear_layout_[s].offset;
      x.segment<kTrajDim>(o) = node_vector(gear);
      x[o + kTrajDim] = gear.base.yaw_rad;
    }
  }
  return x;
}

bool MidendProblem::build_segment(int s, const double* x) {
  const int num_segments = static_cast<int>(reference_.segments.size());
  const ReferenceSegment& seg = reference_.segments[s];
  const SegmentLayout& l = segment_layout_[s];
  const double eta = seg.eta;
  const double vns = limits_.nonsingular_speed_mps;

  auto gear_state = [&](int g, Minco::BoundaryState& st) {
    const double* gx = x + gear_layout_[g].offset;
    st.col(0) = Eigen::Map<const TrajVector>(gx);
    if (gear_layout_[g].rest) {  // base held at the still segment's pose, at rest; arm free
      st.col(0).head<2>() = gear_layout_[g].base;
      st.col(1).head<2>().setZero();
      st.col(2).head<2>().setZero();
      st.col(1).tail<kNumArmJoints>() = Eigen::Map<const JointVector>(gx + kTrajDim + 1);
      st.col(2).tail<kNumArmJoints>() = Eigen::Map<const JointVector>(gx + kTrajDim + 1 + kNumArmJoints);
      return;
    }
    const double theta = gx[kTrajDim];
    st(0, 1) = eta * vns * std::cos(theta);
    st(1, 1) = eta * vns * std::sin(theta);
    st.col(1).tail<kNumArmJoints>() = Eigen::Map<const JointVector>(gx + kTrajDim + 1);
    st(0, 2) = 0.0;
    st(1, 2) = 0.0;
    st.col(2).tail<kNumArmJoints>() =
        Eigen::Map<const JointVector>(gx + kTrajDim + 1 + kNumArmJoints);
  };

  Minco::BoundaryState head = Minco::BoundaryState::Zero();
  Minco::BoundaryState tail = Minco::BoundaryState::Zero();
  if (s == 0) {
    head.col(0) = reference_.cut_start_position ? *reference_.cut_start_position : node_vector(seg.nodes.front());
    head.col(1) = reference_.start.velocity;
    head.col(2) = reference_.start.acceleration;
  } else {
    gear_state(s - 1, head);
  }
  if (s + 1 == num_segments) {
    tail.col(0) = reference_.cut_end_position ? *reference_.cut_end_position : node_vector(seg.nodes.back());
    tail.col(1) = reference_.end.velocity;
    tail.col(2) = reference_.end.acceleration;
  } else {
    gear_state(s, tail);
  }
  waypoints_[s] = Eigen::Map<const Minco::Waypoints>(x + l.q_offset, kTrajDim, l.pieces - 1);
  if (l.still) waypoints_[s].topRows<2>().colwise() = l.still_base;
  for (int i = 0; i < l.pieces; ++i) {
    const double tau = x[l.tau_offset + i];
    const double scale = std::exp(x[time_scale_index_]);
    durations_[s][i] = scale * minco::duration_from_tau(tau);
    dtdtau_[s][i] = scale * minco::duration_derivative(tau);
  }
  if (!head.allFinite() || !tail.allFinite() || !waypoints_[s].allFinite()) return false;
  return minco_[s].generate(head, tail, waypoints_[s], durations_[s]);
}

void MidendProblem::set_terms(std::uint32_t mask) {
  terms_ = mask;
  sampler_ = std::make_shared<const detail::SamplerConstants>(limits_, settings_, mask);
}

double MidendProblem::piece_penalty(int s, int i, CostBreakdown* breakdown) {
  const ReferenceSegment& seg = reference_.segments[s];
  const double min_speed_mps = segment_layout_[s].min_speed[i];
  if (!reference_sampling_) {
    detail::PieceInputs in;
    in.eta = seg.eta;
    in.num_edges = seg.edges_in_piece(i);
    in.nodes = &seg.nodes[seg.knots[i]];
    in.dirs = &node_dir_[s][seg.knots[i]];
    in.fractions = segment_layout_[s].fractions[i].data();
    in.min_speed_mps = min_speed_mps;
    in.base_still = segment_layout_[s].still;
    static_assert(Minco::kStorage == Eigen::RowMajor, "the fast sampler reads row-major blocks");
    const int row = minco::kPieceCoeffs * i;
    return detail::sample_piece(*sampler_, in, minco_[s].coefficients().row(row).data(),
                                durations_[s][i], segment_layout_[s].kappa[i], sample_work_.data(),
                                grad_c_[s].row(row).data(), &grad_t_[s][i], breakdown);
  }
  detail::SamplePenalty integrand;
  integrand.limits = &limits_;
  integrand.settings = &settings_;
  integrand.penalty = penalty_;
  integrand.terms = terms_;
  integrand.eta = seg.eta;
  integrand.num_edges = seg.edges_in_piece(i);
  integrand.nodes = &seg.nodes[seg.knots[i]];
  integrand.fractions = segment_layout_[s].fractions[i].data();
  integrand.duration_s = durations_[s][i];
  integrand.min_speed_mps = min_speed_mps;
  integrand.base_still = segment_layout_[s].still;
  integrand.breakdown = breakdown;
  return minco::integrate_piece_penalty<kTrajDim>(
      minco_[s].piece(i), durations_[s][i], segment_layout_[s].kappa[i], integrand,
      grad_c_[s].middleRows<minco::kPieceCoeffs>(minco::kPieceCoeffs * i), grad_t_[s][i]);
}

double MidendProblem::boundary_heading(int s, bool at_start, CostBreakdown* breakdown) {
  const ReferenceSegment& seg = reference_.segments[s];
  const int i = at_start ? 0 : segment_layout_[s].pieces - 1;
  const double t = at_start ? 0.0 : durations_[s][i];
  const RobotConfiguration& node = at_start ? seg.nodes.front() : seg.nodes.back();
  const auto c = minco_[s].piece(i);
  const minco::Basis b3 = minco::basis(t, 3);
  const Eigen::Vector2d j = c.leftCols<2>().transpose() * b3;
  const Eigen::Vector2d u =
      seg.eta * Eigen::Vector2d(std::cos(node.base.yaw_rad), std::sin(node.base.yaw_rad));
  const double eps2 = settings_.boundary_jerk_guard_mps3 * settings_.boundary_jerk_guard_mps3;
  const double q = j.squaredNorm();
  const double n2 = q + eps2;
  const double n = std::sqrt(n2);
  const double gate = q / n2;
  const double cosine = u.dot(j) / n;
  const double w = settings_.weight_boundary_heading;
  // h = sqrt(chord^2 + delta^2) - delta with chord^2 = 2 (1 - cos) ~ angle^2: about w |angle| away
  // from alignment, an exact penalty for the constraint angle = 0. Its pull towards the node's
  // heading does not fade as the angle shrinks (w (1 - cos) ~ w angle^2 / 2 did: the other terms,
  // mainly time, then held the start or goal heading 0.02-0.07 rad off, a pull F of about
  // w * angle <= 0.07 w). With a pull F < w the optimum is where w angle / sqrt(angle^2 +
  // delta^2) = F, i.e. angle = delta F / sqrt(w^2 - F^2): about 1e-4 rad for F = 0.07 w. delta
  // only rounds the kink (a smooth cost for L-BFGS); 2 mrad keeps that residual two orders of
  // magnitude inside the 0.02 rad a goal pose is asked to be reached within.
  constexpr double kDelta = 2e-3;
  const double chord2 = std::max(0.0, 2.0 * (1.0 - cosine));
  const double root = std::sqrt(chord2 + kDelta * kDelta);
  const double h = root - kDelta;
  const double dh_dcos = -1.0 / root;
  const double cost = w * gate * h;
  const Eigen::Vector2d dgate = (2.0 * eps2 / (n2 * n2)) * j;
  const Eigen::Vector2d dcos = u / n - (u.dot(j) / (n2 * n)) * j;
  const Eigen::Vector2d dj = w * (dgate * h + gate * dh_dcos * dcos);
  auto gc = grad_c_[s].middleRows<minco::kPieceCoeffs>(minco::kPieceCoeffs * i);
  gc.leftCols<2>().noalias() += b3 * dj.transpose();
  if (!at_start) {
    const Eigen::Vector2d snap = c.leftCols<2>().transpose() * minco::basis(t, 4);
    grad_t_[s][i] += dj.dot(snap);
  }
  if (breakdown) breakdown->boundary_heading += cost;
  return cost;
}

double MidendProblem::cut_jerk(int s, bool at_start, const Eigen::Vector2d& held, CostBreakdown* breakdown) {
  const int i = at_start ? 0 : segment_layout_[s].pieces - 1;
  const double t = at_start ? 0.0 : durations_[s][i];
  const auto c = minco_[s].piece(i);
  const minco::Basis b3 = minco::basis(t, 3);
  const Eigen::Vector2d d = c.leftCols<2>().transpose() * b3 - held;
  const double w = reference_.cut_jerk_weight;
  const double cost = w * d.squaredNorm();
  const Eigen::Vector2d dj = 2.0 * w * d;
  auto gc = grad_c_[s].middleRows<minco::kPieceCoeffs>(minco::kPieceCoeffs * i);
  gc.leftCols<2>().noalias() += b3 * dj.transpose();
  if (!at_start) {
    const Eigen::Vector2d snap = c.leftCols<2>().transpose() * minco::basis(t, 4);
    grad_t_[s][i] += dj.dot(snap);
  }
  if (breakdown) breakdown->cut_jerk += cost;
  return cost;
}

double MidendProblem::rest_rates(int s, bool at_start, CostBreakdown* breakdown) {
  const bool wv = (terms_ & kTermWheelVelocity) && settings_.weight_wheel_velocity > 0.0;
  const bool wa = (terms_ & kTermWheelAcceleration) && settings_.weight_wheel_acceleration > 0.0;
  if (!wv && !wa) return 0.0;
  const int i = at_start ? 0 : segment_layout_[s].pieces - 1;
  const double t = at_start ? 0.0 : durations_[s][i];
  const auto c = minco_[s].piece(i);
  const minco::Basis b3 = minco::basis(t, 3), b4 = minco::basis(t, 4), b5 = minco::basis(t, 5);
  const Eigen::Vector2d u = 0.5 * (c.leftCols<2>().transpose() * b3);
  const Eigen::Vector2d u1 = (1.0 / 6.0) * (c.leftCols<2>().transpose() * b4);
  const Eigen::Vector2d u2 = (1.0 / 12.0) * (c.leftCols<2>().transpose() * b5);
  // omega = (u x u1) / n2, alpha = (u x u2) / n2 - 2 (u x u1)(u . u1) / n2^2, n2 = |u|^2 + eps^2.
  const double eps = 0.5 * settings_.boundary_jerk_guard_mps3;
  const double n2 = u.squaredNorm() + eps * eps;
  const double cr1 = cross2(u, u1), cr2 = cross2(u, u2), d1 = u.dot(u1);
  const double omega = cr1 / n2;
  const double alpha = cr2 / n2 - 2.0 * cr1 * d1 / (n2 * n2);
  const Eigen::Vector2d dcr1_du(u1.y(), -u1.x()), dcr1_du1(-u.y(), u.x());
  const Eigen::Vector2d dcr2_du(u2.y(), -u2.x()), dcr2_du2(-u.y(), u.x());
  const Eigen::Vector2d domega_du = dcr1_du / n2 - (2.0 * cr1 / (n2 * n2)) * u;
  const Eigen::Vector2d domega_du1 = dcr1_du1 / n2;
  const Eigen::Vector2d dalpha_du = dcr2_du / n2 - (2.0 * cr2 / (n2 * n2)) * u -
                                    (2.0 / (n2 * n2)) * (dcr1_du * d1 + cr1 * u1) +
                                    (8.0 * cr1 * d1 / (n2 * n2 * n2)) * u;
  const Eigen::Vector2d dalpha_du1 = -(2.0 / (n2 * n2)) * (dcr1_du1 * d1 + cr1 * u);
  const Eigen::Vector2d dalpha_du2 = dcr2_du2 / n2;

  const int kappa = segment_layout_[s].kappa[i];
  const double weight_s = 0.5 * durations_[s][i] / kappa;  // a trapezoid end sample
  const double half_over_r = 0.5 * limits_.track_width_m / limits_.wheel_radius_m;
  const double lf = settings_.limit_penalty_fraction;  // penalties start at lf * limit
  double cost = 0.0, cost_v = 0.0, cost_a = 0.0;
  Eigen::Vector2d gu = Eigen::Vector2d::Zero(), gu1 = Eigen::Vector2d::Zero(),
                  gu2 = Eigen::Vector2d::Zero();
  for (const double side : {-1.0, 1.0}) {  // the speed and a_b are zero at rest
    double dphi = 0.0;
    if (wv) {
      const double w = side * half_over_r * omega;
      const double inv = 1.0 / (lf * lf * limits_.wheel_omega_max_radps * limits_.wheel_omega_max_radps);
      cost_v += settings_.weight_wheel_velocity * penalty_.value(w * w * inv - 1.0, &dphi);
      const double k = settings_.weight_wheel_velocity * dphi * 2.0 * w * inv * side * half_over_r;
      gu += k * weight_s * domega_du;
      gu1 += k * weight_s * domega_du1;
    }
    if (wa) {
      const double a = side * half_over_r * alpha;
      const double inv = 1.0 / (lf * lf * limits_.wheel_alpha_max_radps2 * limits_.wheel_alpha_max_radps2);
      cost_a += settings_.weight_wheel_acceleration * penalty_.value(a * a * inv - 1.0, &dphi);
      const double k = settings_.weight_wheel_acceleration * dphi * 2.0 * a * inv * side * half_over_r;
      gu += k * weight_s * dalpha_du;
      gu1 += k * weight_s * dalpha_du1;
      gu2 += k * weight_s * dalpha_du2;
    }
  }
  cost = weight_s * (cost_v + cost_a);
  if (cost == 0.0 && gu.isZero() && gu1.isZero() && gu2.isZero()) return 0.0;
  // u = jerk/2, u1 = snap/6, u2 = crackle/12 of the piece at t.
  const Eigen::Vector2d gj = 0.5 * gu, gs = gu1 / 6.0, gc = gu2 / 12.0;
  auto grad = grad_c_[s].middleRows<minco::kPieceCoeffs>(minco::kPieceCoeffs * i);
  grad.leftCols<2>().noalias() += b3 * gj.transpose() + b4 * gs.transpose() + b5 * gc.transpose();
  grad_t_[s][i] += (cost_v + cost_a) * 0.5 / kappa;
  if (!at_start) {
    const Eigen::Vector2d snap = c.leftCols<2>().transpose() * b4;
    const Eigen::Vector2d crackle = c.leftCols<2>().transpose() * b5;
    grad_t_[s][i] += gj.dot(snap) + gs.dot(crackle);
  }
  if (breakdown) {
    breakdown->wheel_velocity += weight_s * cost_v;
    breakdown->wheel_acceleration += weight_s * cost_a;
  }
  return cost;
}

double MidendProblem::evaluate(const double* x, double* grad, CostBreakdown* breakdown) {
  CostBreakdown local;
  CostBreakdown& b = breakdown ? *breakdown : local;
  b = CostBreakdown{};
  const int num_segments = static_cast<int>(reference_.segments.size());
  auto fail = [&]() {
    if (grad) std::fill(grad, grad + num_variables_, 0.0);
    return std::numeric_limits<double>::infinity();
  };

  for (int s = 0; s < num_segments; ++s) {
    if (!build_segment(s, x)) return fail();
    grad_c_[s].setZero();
    grad_t_[s].setZero();
    if (terms_ & kTermEnergy) {
      b.energy += minco_[s].energy(energy_weights_);
      minco_[s].add_energy_gradient(energy_weights_, grad_c_[s], grad_t_[s]);
    }
    if (terms_ & kTermTime) {
      b.time += settings_.time_weight_per_s * durations_[s].sum();
      grad_t_[s].array() += settings_.time_weight_per_s;
    }
    if (terms_ & kSampledTerms) {
      for (int i = 0; i < segment_layout_[s].pieces; ++i) piece_penalty(s, i, &b);
    }
    const SegmentLayout& l = segment_layout_[s];
    if (l.rest_start) rest_rates(s, true, &b);
    if (l.rest_end) rest_rates(s, false, &b);
    if ((terms_ & kTermBoundaryHeading) && settings_.weight_boundary_heading > 0.0) {
      if (l.rest_start) boundary_heading(s, true, &b);
      if (l.rest_end) boundary_heading(s, false, &b);
    }
    if ((terms_ & kTermBoundaryHeading) && reference_.cut_jerk_weight > 0.0) {
      if (s == 0 && reference_.cut_start_base_jerk) cut_jerk(s, true, *reference_.cut_start_base_jerk, &b);
      if (s + 1 == num_segments && reference_.cut_end_base_jerk) cut_jerk(s, false, *reference_.cut_end_base_jerk, &b);
    }
  }
  extra_skipped_ = false;
  if ((terms_ & kTermExtra) && extra_cost_) {
    if (b.total() > extra_cutoff_)
      extra_skipped_ = true;
    else
      extra_cost(x, grad != nullptr, &b);
  }
  const double cost = b.total();
  if (!std::isfinite(cost)) return fail();
  if (!grad) return cost;

  std::fill(grad, grad + num_variables_, 0.0);
  const double vns = limits_.nonsingular_speed_mps;
  auto add_gear = [&](int g, double eta, const Minco::BoundaryState& gs) {
    const int o = gear_layout_[g].offset;
    const double theta = x[o + kTrajDim];
    const bool rest = gear_layout_[g].rest;  // base position and theta unused: zero gradient
    for (int k = rest ? 2 : 0; k < kTrajDim; ++k) grad[o + k] += gs(k, 0);
    if (!rest) grad[o + kTrajDim] += eta * vns * (-gs(0, 1) * std::sin(theta) + gs(1, 1) * std::cos(theta));
    for (int d = 0; d < kNumArmJoints; ++d) {
      grad[o + kTrajDim + 1 + d] += gs(2 + d, 1);
      grad[o + kTrajDim + 1 + kNumArmJoints + d] += gs(2 + d, 2);
    }
  };
  for (int s = 0; s < num_segments; ++s) {
    const SegmentLayout& l = segment_layout_[s];
    Minco::BoundaryState gh, gt;
    minco_[s].propagate_gradient(grad_c_[s], grad_t_[s], grad_q_[s], grad_t_total_, gh, gt);
    Eigen::Map<Minco::Waypoints>(grad + l.q_offset, kTrajDim, l.pieces - 1) = grad_q_[s];
    if (l.still) Eigen::Map<Minco::Waypoints>(grad + l.q_offset, kTrajDim, l.pieces - 1).topRows<2>().setZero();
    for (int i = 0; i < l.pieces; ++i) {
      grad[l.tau_offset + i] = grad_t_total_[i] * dtdtau_[s][i];
      grad[time_scale_index_] += grad_t_total_[i] * durations_[s][i];
    }
    const double eta = reference_.segments[s].eta;
    if (s > 0) add_gear(s - 1, eta, gh);
    if (s + 1 < num_segments) add_gear(s, eta, gt);
  }
  for (int k = 0; k < num_variables_; ++k) {
    if (!std::isfinite(grad[k])) return fail();
  }
  return cost;
}

double MidendProblem::extra_cost(const double* x, bool want_grad, CostBreakdown* breakdown) {
  // The MINCO systems are built for x (evaluate() calls this after build_segment()).
  std::vector<TrajectoryPiece> all;
  all.reserve(static_cast<std::size_t>(num_pieces()));
  const int num_segments = static_cast<int>(reference_.segments.size());
  for (int s = 0; s < num_segments; ++s) {
    for (int i = 0; i < segment_layout_[s].pieces; ++i) {
      TrajectoryPiece p;
      p.duration_s = durations_[s][i];
      p.eta = reference_.segments[s].eta;
      p.coeffs = minco_[s].piece(i);
      all.push_back(p);
    }
  }
  TrajectoryResult tr = Trajectory::create(std::move(all), start_yaw_rad());
  if (!tr.ok()) {
    breakdown->extra = std::numeric_limits<double>::infinity();
    return breakdown->extra;
  }
  for (auto& c : extra_grad_.coeffs) c.setZero();
  std::fill(extra_grad_.durations_s.begin(), extra_grad_.durations_s.end(), 0.0);
  const double k = extra_cost_(*tr.trajectory, want_grad ? &extra_grad_ : nullptr);
  breakdown->extra = std::isfinite(k) ? k : std::numeric_limits<double>::infinity();
  if (!want_grad || !std::isfinite(k)) return breakdown->extra;
  if (extra_grad_.coeffs.size() != static_cast<std::size_t>(num_pieces()) ||
      extra_grad_.durations_s.size() != static_cast<std::size_t>(num_pieces())) {
    extra_grad_.coeffs.resize(static_cast<std::size_t>(num_pieces()));  // the callee resized them
    extra_grad_.durations_s.resize(static_cast<std::size_t>(num_pieces()));
    breakdown->extra = std::numeric_limits<double>::infinity();
    return breakdown->extra;
  }
  int global = 0;
  for (int s = 0; s < num_segments; ++s) {
    for (int i = 0; i < segment_layout_[s].pieces; ++i, ++global) {
      grad_c_[s].middleRows<minco::kPieceCoeffs>(minco::kPieceCoeffs * i) +=
          extra_grad_.coeffs[static_cast<std::size_t>(global)];
      grad_t_[s][i] += extra_grad_.durations_s[static_cast<std::size_t>(global)];
    }
  }
  return breakdown->extra;
}

std::vector<TrajectoryPiece> MidendProblem::pieces(const double* x) {
  std::vector<TrajectoryPiece> out;
  const int num_segments = static_cast<int>(reference_.segments.size());
  for (int s = 0; s < num_segments; ++s) {
    if (!build_segment(s, x)) return {};
    for (int i = 0; i < segment_layout_[s].pieces; ++i) {
      TrajectoryPiece p;
      p.duration_s = durations_[s][i];
      p.eta = reference_.segments[s].eta;
      p.coeffs = minco_[s].piece(i);
      if (segment_layout_[s].still) {  // exactly at rest (the solve leaves rounding residue)
        p.coeffs.col(0).setZero();
        p.coeffs.col(1).setZero();
        p.coeffs(0, 0) = segment_layout_[s].still_base.x();
        p.coeffs(0, 1) = segment_layout_[s].still_base.y();
      }
      out.push_back(p);
    }
  }
  return out;
}

}  // namespace porter::midend
