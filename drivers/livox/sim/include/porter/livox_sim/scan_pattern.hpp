#pragma once
// A MID-360-like scan pattern: where the sensor fires its n-th ray.
//
// Four lines (lasers) fire in turn, each at 1/4 of the point rate, through one rotating
// deflector: all lines share the azimuth phi(t) = 2 pi f_az t and line k sweeps the elevation
// range with a triangle wave of frequency f_el, a quarter period apart from the next line:
//   elevation_k(t) = e_min + (e_max - e_min) * tri(f_el t + k / 4),  tri(u) = 1 - |2 frac(u) - 1|.
// With f_az = 10 Hz (one turn per frame) and f_el / f_az = (349 + 0.618...) / 8, neighbouring
// zig-zag segments of one frame are about 1 deg apart in azimuth and consecutive points about
// 1 deg apart in elevation (at 200,000 points/s over 360 x 59 deg); the elevation phase at a
// given azimuth moves by the golden fraction of the segment spacing each frame, so the pattern
// never repeats and the covered fraction of the field of view grows with integration time, like
// the sensor's non-repetitive scan. The exact scan of the real device is not published; this is
// a stand-in with the same field of view, rate, line count and coverage behaviour.
//
// Frames: the sensor's point frame, x forward, y left, z up; azimuth from x towards y,
// elevation from the xy plane towards z.
// Thread-safety: immutable after construction; direction() is reentrant.

#include <cstdint>

#include <Eigen/Core>

namespace porter::livox::sim {

struct ScanPatternParams {
  double point_rate_hz = 200000.0;   ///< points per second, all lines together (> 0)
  double rotation_hz = 10.0;         ///< azimuth turns per second (> 0)
  double elevation_min_deg = -7.0;
  double elevation_max_deg = 52.0;   ///< > elevation_min_deg
  /// Elevation sweeps (triangle periods) per azimuth turn; irrational keeps it non-repetitive.
  double sweeps_per_turn = (349.0 + 0.6180339887498949) / 8.0;
};

class ScanPattern {
 public:
  static constexpr int kLines = 4;

  explicit ScanPattern(const ScanPatternParams& params = {});

  /// Time of point n after the pattern's start, s.
  double time_s(std::uint64_t n) const { return static_cast<double>(n) * dt_s_; }
  /// Line of point n (0..3).
  static int line(std::uint64_t n) { return static_cast<int>(n % kLines); }
  /// Azimuth and elevation of point n, rad.
  void angles(std::uint64_t n, double& azimuth_rad, double& elevation_rad) const;
  /// Unit direction of point n in the sensor frame.
  Eigen::Vector3d direction(std::uint64_t n) const;

  const ScanPatternParams& params() const { return params_; }

 private:
  ScanPatternParams params_;
  double dt_s_;
  double e_min_rad_;
  double e_span_rad_;
  double f_el_hz_;
};

}  // namespace porter::livox::sim
