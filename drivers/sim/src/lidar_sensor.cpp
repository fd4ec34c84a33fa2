#include "porter/sim/lidar_sensor.hpp"

#include <time.h>

#include <chrono>

namespace porter::sim {
namespace {

double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace

LidarSensor::LidarSensor(const livox::sim::Mid360SimParams& params, const World& world,
                         PacketSink sink)
    : world_(&world), sink_(std::move(sink)), obstacles_version_(world.obstacles_version()) {
  // The state function reads the world of the advance() in progress: the SimSensor contract
  // makes robot_at(t) exact for every t the ray caster asks for (inside that interval).
  lidar_ = std::make_unique<livox::sim::SimulatedMid360>(
      params, world.robot(), world.obstacles(),
      [this](double t_s) { return world_->robot_at(t_s).config; });
}

void LidarSensor::advance(const World& world, double t0_s, double t1_s) {
  const double cpu0 = thread_cpu_s();
  world_ = &world;
  if (!started_) {
    started_ = true;
    if (lidar_->params().time_type != livox::TimeType::kNoSync) {
      lidar_->set_sensor_time_at_zero_ns(world.utime_origin() * 1000);
    }
  }
  if (world.obstacles_version() != obstacles_version_) {
    const auto begin = std::chrono::steady_clock::now();
    lidar_->set_obstacles(world.obstacles());
    last_rebuild_s_ =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    obstacles_version_ = world.obstacles_version();
    ++rebuilds_;
  }
  packets_.clear();
  lidar_->advance(t0_s, t1_s, packets_);
  if (!packets_.empty() && sink_) sink_(packets_);
  cpu_s_ += thread_cpu_s() - cpu0;
}

}  // namespace porter::sim
