// dispersion: every robot backs away from the neighbours it hears closer than `spacing` (a repulsion summed
// over them, each weighted by how far inside `spacing` it is) and stops once nobody is nearer than
// (1 - tolerance) x spacing. Walls and obstacles seen by the ultrasonics repel the same way. The swarm
// spreads out to about `spacing` apart, as far as the arena and the communication range let it.
#include <swarmform/behaviour.hpp>

#include <algorithm>
#include <array>
#include <cmath>

namespace {

using namespace swarmform;

constexpr std::array kParams = {
    behaviour::ParamSpec{"spacing", 1.0, 0.2, 10.0, "distance wanted from every neighbour, m"},
    behaviour::ParamSpec{"speed_fraction", 1.0, 0.05, 1.0, "top speed as a fraction of max_speed"},
    behaviour::ParamSpec{"k_turn", 2.0, 0.0, 20.0, "turn rate per radian of the escape bearing, 1/s"},
    behaviour::ParamSpec{"wall_distance", 0.4, 0.25, 2.0,
                         "echoes nearer than this repel like a neighbour, m"},
    behaviour::ParamSpec{"tolerance", 0.1, 0.0, 0.9,
                         "settled once no neighbour is nearer than (1 - this) x spacing"},
};
enum State : std::int32_t { kSpreading = 0, kSettled = 1 };
constexpr std::array kStates = {
    behaviour::StateSpec{kSpreading, "spreading", "#ff9800"},
    behaviour::StateSpec{kSettled, "settled", "#2e7d32"},
};
constexpr std::array kTelemetry = {
    behaviour::TelemetryColumn{"nearest", "range of the nearest neighbour heard, m (-1: none)"},
};

std::unique_ptr<controller::Controller> make();

const behaviour::Descriptor kDescriptor{
    .name = "dispersion",
    .summary = "move away from neighbours closer than `spacing`, stop when none is",
    .params = kParams,
    .states = kStates,
    .telemetry = kTelemetry,
    .needs_shape = false,
    .needs_goal = false,
    .shape_rules = {},
    .make = &make,
    .sensors = 0,
    .experiment = {},
};

class Dispersion final : public controller::Controller {
 public:
  void init(const Mission& mission, RobotId) override {
    max_speed_ = mission.max_speed;
    speed_ = behaviour::param(mission, kDescriptor, "speed_fraction") * mission.max_speed;
    spacing_ = behaviour::param(mission, kDescriptor, "spacing");
    k_turn_ = behaviour::param(mission, kDescriptor, "k_turn");
    wall_ = behaviour::param(mission, kDescriptor, "wall_distance");
    tolerance_ = behaviour::param(mission, kDescriptor, "tolerance");
  }

  Command step(const Perception& p) override {
    double fx = 0.0, fy = 0.0;  // the push, robot frame
    double nearest = -1.0;
    for (const RabReading& r : p.messages) {
      if (nearest < 0.0 || r.range < nearest) nearest = r.range;
      if (r.range >= spacing_) continue;
      const double weight = (spacing_ - r.range) / spacing_;
      fx -= weight * std::cos(r.bearing);
      fy -= weight * std::sin(r.bearing);
    }
    bool echo = false;
    for (std::size_t k = 0; k < kUltrasonicCount; ++k) {
      if (p.ultrasonic[k] >= wall_) continue;
      echo = true;
      const double weight = (wall_ - p.ultrasonic[k]) / wall_;
      fx -= weight * std::cos(kUltrasonicAngles[k]);
      fy -= weight * std::sin(kUltrasonicAngles[k]);
    }
    Command c;
    const double push = std::hypot(fx, fy);
    const bool settled = !echo && (nearest < 0.0 || nearest >= (1.0 - tolerance_) * spacing_);
    if (!settled) {
      const double bearing = std::atan2(fy, fx);
      // Forward when the escape lies ahead, backward when it lies behind (the robot need not turn round).
      const bool ahead = std::abs(bearing) <= M_PI / 2.0;
      const double heading_error = ahead ? bearing : std::remainder(bearing + M_PI, 2.0 * M_PI);
      const double v =
          (ahead ? 1.0 : -1.0) * speed_ * std::min(1.0, 3.0 * push) * std::abs(std::cos(bearing));
      behaviour::drive(v, k_turn_ * heading_error, max_speed_, c);
    }
    c.telemetry.state = settled ? kSettled : kSpreading;
    c.telemetry.extra = {nearest};
    c.message = {1};  // a beacon: being heard is all the others need
    return c;
  }

  void reset() override {}

 private:
  double max_speed_ = 0.1, speed_ = 0.1, spacing_ = 1.0, k_turn_ = 2.0, wall_ = 0.4, tolerance_ = 0.1;
};

std::unique_ptr<controller::Controller> make() {
  return std::make_unique<Dispersion>();
}

}  // namespace

SWARMFORM_BEHAVIOUR(kDescriptor)
