// aggregation: every robot drives towards the centroid of the neighbours it hears (range and bearing only; no
// positions are shared), turns away from what its ultrasonics see close ahead, and stops once the centroid is
// within `stop_distance`. A robot that hears nobody drives straight on until it does. The swarm gathers into
// clusters, one per connected group.
#include <swarmform/behaviour.hpp>

#include <algorithm>
#include <array>
#include <cmath>

namespace {

using namespace swarmform;

constexpr std::array kParams = {
    behaviour::ParamSpec{"speed_fraction", 1.0, 0.05, 1.0, "cruise speed as a fraction of max_speed"},
    behaviour::ParamSpec{"k_turn", 2.0, 0.0, 20.0, "turn rate per radian of the centroid's bearing, 1/s"},
    behaviour::ParamSpec{"stop_distance", 0.35, 0.15, 5.0,
                         "stop when the neighbours' centroid is this near, m"},
    behaviour::ParamSpec{"avoid_distance", 0.3, 0.25, 2.0, "turn away from echoes nearer than this ahead, m"},
};
enum State : std::int32_t { kAlone = 0, kApproaching = 1, kGathered = 2 };
constexpr std::array kStates = {
    behaviour::StateSpec{kAlone, "alone", "#9e9e9e"},
    behaviour::StateSpec{kApproaching, "approaching", "#1e88e5"},
    behaviour::StateSpec{kGathered, "gathered", "#2e7d32"},
};
constexpr std::array kTelemetry = {
    behaviour::TelemetryColumn{"neighbours", "neighbours heard this tick"},
    behaviour::TelemetryColumn{"centroid_distance", "distance to their centroid, m (0 when alone)"},
};

std::unique_ptr<controller::Controller> make();

const behaviour::Descriptor kDescriptor{
    .name = "aggregation",
    .summary = "drive to the centroid of the neighbours heard, stop when close",
    .params = kParams,
    .states = kStates,
    .telemetry = kTelemetry,
    .needs_shape = false,
    .needs_goal = false,
    .shape_rules = {},
    .make = &make,
};

class Aggregation final : public controller::Controller {
 public:
  void init(const Mission& mission, RobotId) override {
    max_speed_ = mission.max_speed;
    speed_ = behaviour::param(mission, kDescriptor, "speed_fraction") * mission.max_speed;
    k_turn_ = behaviour::param(mission, kDescriptor, "k_turn");
    stop_ = behaviour::param(mission, kDescriptor, "stop_distance");
    avoid_ = behaviour::param(mission, kDescriptor, "avoid_distance");
  }

  Command step(const Perception& p) override {
    Command c;
    double cx = 0.0, cy = 0.0;  // centroid in the robot's frame (+x ahead, +y left)
    for (const RabReading& r : p.messages) {
      cx += r.range * std::cos(r.bearing);
      cy += r.range * std::sin(r.bearing);
    }
    const auto n = static_cast<double>(p.messages.size());
    const double distance = n > 0 ? std::hypot(cx, cy) / n : 0.0;
    double v = speed_;
    double w = 0.0;
    std::int32_t state = kAlone;
    if (n > 0 && distance <= stop_) {
      v = 0.0;
      state = kGathered;
    } else if (n > 0) {
      w = k_turn_ * std::atan2(cy, cx);
      v = speed_ * std::max(0.0, std::cos(std::atan2(cy, cx)));  // turn first, then go
      state = kApproaching;
    }
    // Ultrasonics 1..3 face the front: an echo there turns the robot on the spot, away from its side.
    const double left = std::min(p.ultrasonic[3], p.ultrasonic[4]);
    const double right = std::min(p.ultrasonic[0], p.ultrasonic[1]);
    if (state != kGathered && std::min({p.ultrasonic[1], p.ultrasonic[2], p.ultrasonic[3]}) < avoid_) {
      v = 0.0;
      w = (left < right ? -1.0 : 1.0) * 2.0 * max_speed_ / kWheelSpacing;
    }
    drive(v, w, c);
    c.telemetry.state = state;
    c.telemetry.extra = {n, distance};
    c.message = {1};  // a one-byte beacon: being heard is all the others need
    return c;
  }

  void reset() override {}

 private:
  // Linear speed v (m/s) and turn rate w (rad/s) to wheel speeds, scaled down together to the speed limit.
  void drive(double v, double w, Command& c) const {
    double l = v - w * kWheelSpacing / 2.0;
    double r = v + w * kWheelSpacing / 2.0;
    const double top = std::max(std::abs(l), std::abs(r));
    if (top > max_speed_) {
      l *= max_speed_ / top;
      r *= max_speed_ / top;
    }
    // The scaling can land a rounding error above the limit, which the world would clamp and count.
    c.left_speed = std::clamp(l, -max_speed_, max_speed_);
    c.right_speed = std::clamp(r, -max_speed_, max_speed_);
  }

  double max_speed_ = 0.1, speed_ = 0.1, k_turn_ = 2.0, stop_ = 0.35, avoid_ = 0.3;
};

std::unique_ptr<controller::Controller> make() {
  return std::make_unique<Aggregation>();
}

}  // namespace

SWARMFORM_BEHAVIOUR(kDescriptor)
