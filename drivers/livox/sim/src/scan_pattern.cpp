#include "porter/livox_sim/scan_pattern.hpp"

#include <cmath>

namespace porter::livox::sim {
namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kRadPerDeg = kPi / 180.0;
}  // namespace

ScanPattern::ScanPattern(const ScanPatternParams& params)
    : params_(params),
      dt_s_(1.0 / params.point_rate_hz),
      e_min_rad_(params.elevation_min_deg * kRadPerDeg),
      e_span_rad_((params.elevation_max_deg - params.elevation_min_deg) * kRadPerDeg),
      f_el_hz_(params.sweeps_per_turn * params.rotation_hz) {}

void ScanPattern::angles(std::uint64_t n, double& azimuth_rad, double& elevation_rad) const {
  // Double phases stay exact to ~1e-8 of a turn for a day of scanning (n < 2^35).
  const double t = static_cast<double>(n) / params_.point_rate_hz;
  auto frac = [](double x) { return x - std::floor(x); };
  const double az_turns = frac(params_.rotation_hz * t);
  const double el_phase = frac(f_el_hz_ * t + static_cast<double>(line(n)) / kLines);
  const double tri = 1.0 - std::fabs(2.0 * el_phase - 1.0);
  azimuth_rad = 2.0 * kPi * az_turns;
  elevation_rad = e_min_rad_ + e_span_rad_ * tri;
}

Eigen::Vector3d ScanPattern::direction(std::uint64_t n) const {
  double az = 0.0, el = 0.0;
  angles(n, az, el);
  const double c = std::cos(el);
  return {c * std::cos(az), c * std::sin(az), std::sin(el)};
}

}  // namespace porter::livox::sim
