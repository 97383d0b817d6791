// flocking: Reynolds' three rules (1987) on range and bearing. Each robot broadcasts its heading (8 bytes, a
// little-endian double, arena frame); from what it hears it steers by
//   separation: away from neighbours nearer than `separation` (weighted by how far inside),
//   alignment:  towards the mean of the neighbours' headings, taken relative to its own,
//   cohesion:   towards the centroid of the neighbours (range and bearing, no positions shared),
// weighted by w_separation, w_alignment, w_cohesion, plus a unit "go on" ahead so a flock keeps moving.
// Echoes nearer than `avoid_distance` repel like the walls they are.
#include <swarmform/behaviour.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

namespace {

using namespace swarmform;

constexpr std::array kParams = {
    behaviour::ParamSpec{"separation", 0.5, 0.15, 5.0, "neighbours nearer than this repel, m"},
    behaviour::ParamSpec{"w_separation", 1.5, 0.0, 10.0, "weight of separation"},
    behaviour::ParamSpec{"w_alignment", 1.0, 0.0, 10.0, "weight of alignment"},
    behaviour::ParamSpec{"w_cohesion", 0.5, 0.0, 10.0, "weight of cohesion (per metre to the centroid)"},
    behaviour::ParamSpec{"k_turn", 2.0, 0.0, 20.0, "turn rate per radian of the desired bearing, 1/s"},
    behaviour::ParamSpec{"avoid_distance", 0.4, 0.25, 2.0, "echoes nearer than this repel, m"},
};
enum State : std::int32_t { kAlone = 0, kFlocking = 1 };
constexpr std::array kStates = {
    behaviour::StateSpec{kAlone, "alone", "#9e9e9e"},
    behaviour::StateSpec{kFlocking, "flocking", "#1e88e5"},
};
constexpr std::array kTelemetry = {
    behaviour::TelemetryColumn{"neighbours", "neighbours heard this tick"},
    behaviour::TelemetryColumn{"order",
                               "|mean unit heading| of the robot and its neighbours, 0..1 (1: aligned)"},
};

std::unique_ptr<controller::Controller> make();

const behaviour::Descriptor kDescriptor{
    .name = "flocking",
    .summary = "Reynolds' separation, alignment and cohesion on range and bearing",
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

// The heading in a message: 8 bytes, little-endian IEEE double (the machines we run on are little-endian).
std::vector<std::uint8_t> encode(double heading) {
  std::vector<std::uint8_t> bytes(sizeof heading);
  std::memcpy(bytes.data(), &heading, sizeof heading);
  return bytes;
}
bool decode(const std::vector<std::uint8_t>& bytes, double& heading) {
  if (bytes.size() != sizeof heading) return false;
  std::memcpy(&heading, bytes.data(), sizeof heading);
  return std::isfinite(heading);
}

class Flocking final : public controller::Controller {
 public:
  void init(const Mission& mission, RobotId) override {
    max_speed_ = mission.max_speed;
    separation_ = behaviour::param(mission, kDescriptor, "separation");
    w_sep_ = behaviour::param(mission, kDescriptor, "w_separation");
    w_align_ = behaviour::param(mission, kDescriptor, "w_alignment");
    w_coh_ = behaviour::param(mission, kDescriptor, "w_cohesion");
    k_turn_ = behaviour::param(mission, kDescriptor, "k_turn");
    avoid_ = behaviour::param(mission, kDescriptor, "avoid_distance");
  }

  Command step(const Perception& p) override {
    double sx = 0.0, sy = 0.0;  // separation, robot frame
    double ax = 0.0, ay = 0.0;  // alignment: sum of unit relative headings
    double cx = 0.0, cy = 0.0;  // cohesion: sum of neighbour offsets
    double ox = std::cos(p.pose.theta), oy = std::sin(p.pose.theta);  // order: arena frame, self included
    int headings = 0;
    for (const RabReading& r : p.messages) {
      const double ux = std::cos(r.bearing), uy = std::sin(r.bearing);
      cx += r.range * ux;
      cy += r.range * uy;
      if (r.range < separation_) {
        const double weight = (separation_ - r.range) / separation_;
        sx -= weight * ux;
        sy -= weight * uy;
      }
      double theta = 0.0;
      if (decode(r.data, theta)) {
        ax += std::cos(theta - p.pose.theta);
        ay += std::sin(theta - p.pose.theta);
        ox += std::cos(theta);
        oy += std::sin(theta);
        ++headings;
      }
    }
    const auto n = static_cast<double>(p.messages.size());
    double fx = 1.0, fy = 0.0;  // go on
    if (n > 0) {
      fx += w_sep_ * sx + w_coh_ * cx / n;
      fy += w_sep_ * sy + w_coh_ * cy / n;
    }
    if (headings > 0) {
      fx += w_align_ * ax / headings;
      fy += w_align_ * ay / headings;
    }
    for (std::size_t k = 0; k < kUltrasonicCount; ++k) {
      if (p.ultrasonic[k] >= avoid_) continue;
      const double weight = 3.0 * (avoid_ - p.ultrasonic[k]) / avoid_;
      fx -= weight * std::cos(kUltrasonicAngles[k]);
      fy -= weight * std::sin(kUltrasonicAngles[k]);
    }
    const double bearing = std::atan2(fy, fx);
    Command c;
    behaviour::drive(max_speed_ * std::max(0.0, std::cos(bearing)), k_turn_ * bearing, max_speed_, c);
    c.telemetry.state = n > 0 ? kFlocking : kAlone;
    c.telemetry.extra = {n, std::hypot(ox, oy) / (headings + 1)};
    c.message = encode(p.pose.theta);
    return c;
  }

  void reset() override {}

 private:
  double max_speed_ = 0.1, separation_ = 0.5, w_sep_ = 1.5, w_align_ = 1.0, w_coh_ = 0.5, k_turn_ = 2.0,
         avoid_ = 0.4;
};

std::unique_ptr<controller::Controller> make() {
  return std::make_unique<Flocking>();
}

}  // namespace

SWARMFORM_BEHAVIOUR(kDescriptor)
