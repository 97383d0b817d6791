// A minimal ideal world for controller tests that do not need physics: differential-drive kinematics, a
// range-filtered medium delivering at t+1 with exact range and bearing, optional loss, no ultrasonic echoes.
// The real World (world_server/world) is used by the in-process simulation tests (tests/sim/formation).
#pragma once

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "common/mission.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller::testing {

class MiniWorld {
 public:
  MiniWorld(const Mission& mission, std::vector<Pose2D> poses, double loss = 0.0, std::uint32_t seed = 1)
      : mission_(mission), poses_(std::move(poses)), loss_(loss), rng_(seed) {
    for (std::size_t i = 0; i < poses_.size(); ++i) {
      controllers_.push_back(make_controller(mission_, static_cast<RobotId>(i)));
      alive_.push_back(true);
      outbox_.emplace_back();
      last_.emplace_back();
    }
  }

  void step() {
    const double dt = 1.0 / mission_.tick_rate;
    std::vector<std::vector<std::uint8_t>> sent(poses_.size());
    for (std::size_t i = 0; i < poses_.size(); ++i) {
      if (!alive_[i]) continue;
      Perception p;
      p.tick = tick_;
      p.pose = poses_[i];
      p.ultrasonic.fill(kUltrasonicMaxRange);
      std::bernoulli_distribution lost(loss_);
      for (std::size_t j = 0; j < poses_.size(); ++j) {
        if (j == i || !alive_[j] || outbox_[j].empty()) continue;
        const double dx = poses_[j].x - poses_[i].x, dy = poses_[j].y - poses_[i].y;
        const double r = std::hypot(dx, dy);
        if (r > mission_.comm_range || lost(rng_)) continue;
        p.messages.push_back(
            {static_cast<RobotId>(j), r, wrap_angle(std::atan2(dy, dx) - poses_[i].theta), outbox_[j]});
      }
      last_[i] = controllers_[i]->step(p);
      sent[i] = last_[i].message;
    }
    for (std::size_t i = 0; i < poses_.size(); ++i) {
      if (!alive_[i]) continue;
      const auto& c = last_[i];
      const double v = (c.left_speed + c.right_speed) / 2.0;
      const double w = (c.right_speed - c.left_speed) / kWheelSpacing;
      poses_[i].x += v * std::cos(poses_[i].theta) * dt;
      poses_[i].y += v * std::sin(poses_[i].theta) * dt;
      poses_[i].theta = wrap_angle(poses_[i].theta + w * dt);
    }
    outbox_ = std::move(sent);
    ++tick_;
  }

  void kill(std::size_t i) {
    alive_[i] = false;
    outbox_[i].clear();
  }
  bool alive(std::size_t i) const { return alive_[i]; }
  Tick tick() const { return tick_; }
  const Pose2D& pose(std::size_t i) const { return poses_[i]; }
  const Command& last(std::size_t i) const { return last_[i]; }
  std::size_t size() const { return poses_.size(); }
  // Smallest centre distance between two live robots.
  double min_separation() const {
    double best = 1e9;
    for (std::size_t i = 0; i < poses_.size(); ++i) {
      for (std::size_t j = i + 1; j < poses_.size(); ++j) {
        if (!alive_[i] || !alive_[j]) continue;
        best = std::min(best, std::hypot(poses_[i].x - poses_[j].x, poses_[i].y - poses_[j].y));
      }
    }
    return best;
  }

 private:
  Mission mission_;
  std::vector<Pose2D> poses_;
  double loss_;
  std::mt19937 rng_;
  std::vector<std::unique_ptr<Controller>> controllers_;
  std::vector<bool> alive_;
  std::vector<std::vector<std::uint8_t>> outbox_;
  std::vector<Command> last_;
  Tick tick_ = 0;
};

// Robots on a jittered grid of `pitch` metres around `centre`, headings random, from `seed`.
inline std::vector<Pose2D> grid_start(std::size_t n, Vec2 centre, double pitch, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.15 * pitch, 0.15 * pitch), heading(-3.14159, 3.14159);
  const auto side = static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(n))));
  std::vector<Pose2D> out;
  for (std::size_t i = 0; i < n; ++i) {
    const double gx = static_cast<double>(i % side) - static_cast<double>(side - 1) / 2.0;
    const double gy = static_cast<double>(i / side) - static_cast<double>(side - 1) / 2.0;
    out.push_back({centre.x + gx * pitch + jitter(rng), centre.y + gy * pitch + jitter(rng), heading(rng)});
  }
  return out;
}

}  // namespace swarmform::controller::testing
