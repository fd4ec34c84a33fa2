#include "porter/sim/pose_sensors.hpp"

#include <cmath>

namespace porter::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Calls fn(t) for every grid time k * period in (t0, t1].
template <class Fn>
void for_grid(double period_s, double t0_s, double t1_s, Fn&& fn) {
  if (!(period_s > 0) || !(t1_s > t0_s)) return;
  // The first k with k * period > t0 (a small tolerance keeps a grid time equal to t0 out).
  long long k = static_cast<long long>(std::floor(t0_s / period_s + 1e-9)) + 1;
  for (; static_cast<double>(k) * period_s <= t1_s + 1e-9; ++k) fn(static_cast<double>(k) * period_s);
}

}  // namespace

TruthSensor::TruthSensor(double rate_hz, Callback callback)
    : period_s_(rate_hz > 0 ? 1.0 / rate_hz : 0.0), callback_(std::move(callback)) {}

void TruthSensor::advance(const World& world, double t0_s, double t1_s) {
  for_grid(period_s_, t0_s, t1_s, [&](double t) {
    if (callback_) callback_(world.robot_at(t));
  });
}

LioPoseSensor::LioPoseSensor(double rate_hz, const LioNoise& noise, Callback callback)
    : period_s_(rate_hz > 0 ? 1.0 / rate_hz : 0.0),
      noise_(noise),
      rng_(noise.seed),
      callback_(std::move(callback)) {}

void LioPoseSensor::advance(const World& world, double t0_s, double t1_s) {
  for_grid(period_s_, t0_s, t1_s, [&](double t) {
    const RobotSample truth = world.robot_at(t);
    PoseSample sample;
    sample.t_s = t;
    sample.pose_W = truth.config.base;
    if (noise_.position_sigma_m > 0 || noise_.yaw_sigma_rad > 0) {
      sample.pose_W.x_m += noise_.position_sigma_m * normal_(rng_);
      sample.pose_W.y_m += noise_.position_sigma_m * normal_(rng_);
      double yaw = sample.pose_W.yaw_rad + noise_.yaw_sigma_rad * normal_(rng_);
      yaw = std::remainder(yaw, 2.0 * kPi);
      sample.pose_W.yaw_rad = yaw;
      const double p2 = noise_.position_sigma_m * noise_.position_sigma_m;
      sample.covariance[0 * 6 + 0] = p2;
      sample.covariance[1 * 6 + 1] = p2;
      sample.covariance[5 * 6 + 5] = noise_.yaw_sigma_rad * noise_.yaw_sigma_rad;
      sample.has_covariance = true;
    }
    if (callback_) callback_(sample);
  });
}

}  // namespace porter::sim
