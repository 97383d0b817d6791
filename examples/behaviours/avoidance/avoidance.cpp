// avoidance: every robot wanders (legs of random length and turn rate from its own behaviour::RobotRandom)
// and avoids walls, obstacles and the other robots with its infrared ring alone, Braitenberg-style: each
// reading of the ring's front half turns the robot away from its side in proportion to the reading, and the
// nearest body ahead slows it down, stops it, and at touching distance backs it off. A body dead ahead (no
// side to turn from) turns it to a side it draws at random and keeps until the way is clear. LEDs: green
// while the ring is clear, red while it avoids.
//
// Its experiment measures the run on the true poses and the obstacles' true geometry: contacts (a robot's
// body touching a wall, an obstacle or another robot; each robot counts its own touches), the closest any
// robot came to anything, and how far the robots travelled. The outcome is `avoided` when there were at most
// `max_contacts` contacts and the robots' mean path was at least `min_travel` of what max_speed allows over
// the run (keeping clear by standing still is no success), `stalled` when it was shorter, `collided`
// otherwise.
#include <swarmform/behaviour.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace {

using namespace swarmform;

constexpr std::array kParams = {
    behaviour::ParamSpec{"speed_fraction", 1.0, 0.05, 1.0, "cruise speed as a fraction of max_speed"},
    behaviour::ParamSpec{"k_avoid", 8.0, 0.0, 50.0, "turn rate per unit of side reading, rad/s"},
    behaviour::ParamSpec{"clear_reading", 0.05, 0.0, 1.0, "every front reading below this: the way is clear"},
    behaviour::ParamSpec{"max_contacts", 0.0, 0.0, 1e6,
                         "the experiment: at most this many contacts, else collided"},
    behaviour::ParamSpec{
        "min_travel", 0.5, 0.0, 1.0,
        "the experiment: the mean path over max_speed x the run's time must reach this, else stalled"},
};
enum State : std::int32_t { kCruising = 0, kAvoiding = 1 };
constexpr std::array kStates = {
    behaviour::StateSpec{kCruising, "cruising", "#2e7d32"},
    behaviour::StateSpec{kAvoiding, "avoiding", "#e53935"},
};
constexpr std::array kTelemetry = {
    behaviour::TelemetryColumn{"nearest", "the highest infrared reading of the ring's front half, 0..1"},
};

constexpr std::array kMetrics = {
    behaviour::MetricSpec{"contacts",
                          "touches: a robot's body coming into contact with a wall, obstacle or robot"},
    behaviour::MetricSpec{"min_clearance", "the smallest gap between a robot's body and anything, m"},
    behaviour::MetricSpec{"mean_distance_travelled", "live robots' mean path length, m"},
};
constexpr std::array<std::string_view, 3> kOutcomes = {"avoided", "collided", "stalled"};

std::unique_ptr<controller::Controller> make();
std::unique_ptr<experiment::Experiment> make_experiment();

const behaviour::Descriptor kDescriptor{
    .name = "avoidance",
    .summary = "wander, avoiding walls, obstacles and robots with the infrared ring (Braitenberg)",
    .params = kParams,
    .states = kStates,
    .telemetry = kTelemetry,
    .needs_shape = false,
    .needs_goal = false,
    .shape_rules = {},
    .make = &make,
    .sensors = behaviour::kProximity,
    .experiment = {.metrics = kMetrics,
                   .summary = {},
                   .outcomes = kOutcomes,
                   .success = "avoided",
                   .make = &make_experiment},
};

class Avoidance final : public controller::Controller {
 public:
  void init(const Mission& mission, RobotId self) override {
    mission_ = mission;
    self_ = self;
    rng_ = behaviour::RobotRandom(mission, self);
    leg_ticks_left_ = 0;
    side_ = 0.0;
    max_speed_ = mission.max_speed;
    speed_ = behaviour::param(mission, kDescriptor, "speed_fraction") * mission.max_speed;
    k_avoid_ = behaviour::param(mission, kDescriptor, "k_avoid");
    clear_ = behaviour::param(mission, kDescriptor, "clear_reading");
  }

  Command step(const Perception& p) override {
    if (!p.proximity) throw std::logic_error("avoidance: proximity not equipped");
    double away = 0.0;   // > 0: the bodies seen are on the right, turn left
    double block = 0.0;  // how near the nearest body ahead is, 0..1
    double nearest = 0.0;
    for (std::size_t k = 0; k < kProximityCount; ++k) {
      const double a = kProximityAngles[k];
      if (std::cos(a) < -1e-9) continue;  // behind
      const double reading = (*p.proximity)[k];
      away -= std::sin(a) * reading;
      block = std::max(block, std::cos(a) * reading);
      nearest = std::max(nearest, reading);
    }
    if (leg_ticks_left_ <= 0) {  // the wander: a new leg of 1..4 s at up to 0.5 rad/s each side
      wander_ = rng_.uniform(-0.5, 0.5);
      leg_ticks_left_ = static_cast<int>(rng_.uniform(1.0, 4.0) * mission_.tick_rate);
    }
    --leg_ticks_left_;
    double w = wander_;
    double v = speed_;
    State state = kCruising;
    if (nearest > clear_) {
      state = kAvoiding;
      if (side_ == 0.0) side_ = rng_.uniform() < 0.5 ? -1.0 : 1.0;
      // Dead ahead the sides cancel: turn to the side drawn for this encounter.
      if (std::abs(away) < 0.5 * block) away = side_ * block;
      w = k_avoid_ * away;
      v = speed_ * std::clamp(1.0 - 2.0 * block, -0.3, 1.0);  // stop at 0.5 (about 6 cm), back off nearer
    } else {
      side_ = 0.0;
    }
    Command c;
    behaviour::drive(v, w, max_speed_, c);
    c.leds.fill(state == kAvoiding ? Rgb{255, 0, 0} : Rgb{0, 255, 0});
    c.telemetry.state = state;
    c.telemetry.extra = {nearest};
    return c;
  }

  void reset() override { init(mission_, self_); }

 private:
  Mission mission_;
  RobotId self_ = 0;
  behaviour::RobotRandom rng_{0, 0};
  int leg_ticks_left_ = 0;
  double wander_ = 0.0;  // rad/s, this leg's
  double side_ = 0.0;    // the side drawn for this encounter with a body dead ahead (0: none yet)
  double max_speed_ = 0.1, speed_ = 0.1, k_avoid_ = 8.0, clear_ = 0.05;
};

// The gap between a robot's body and the nearest wall, obstacle or other robot, from the truth's geometry.
class AvoidanceExperiment final : public experiment::Experiment {
 public:
  void init(const Mission& mission, std::size_t robots) override {
    max_contacts_ = behaviour::param(mission, kDescriptor, "max_contacts");
    min_travel_ = behaviour::param(mission, kDescriptor, "min_travel");
    max_speed_ = mission.max_speed;
    tick_rate_ = mission.tick_rate;
    touching_.assign(robots, false);
    travelled_.assign(robots, 0.0);
    last_.assign(robots, Pose2D{});
  }

  void observe(const experiment::Truth& truth) override {
    last_tick_ = truth.tick;
    for (const auto& r : truth.robots) {
      if (!r.alive || r.id >= touching_.size()) continue;
      if (truth.tick > 0) travelled_[r.id] += std::hypot(r.pose.x - last_[r.id].x, r.pose.y - last_[r.id].y);
      last_[r.id] = r.pose;
      const double gap = clearance(truth, r);
      min_clearance_ = std::min(min_clearance_, gap);
      const bool touching = gap < kTouch;
      if (touching && !touching_[r.id]) ++contacts_;
      touching_[r.id] = touching;
    }
  }

  experiment::Result conclude() override {
    double sum = 0.0;
    for (const double d : travelled_) sum += d;
    const double mean = travelled_.empty() ? 0.0 : sum / static_cast<double>(travelled_.size());
    experiment::Result r;
    const double nan = std::numeric_limits<double>::quiet_NaN();  // nothing to measure from (no walls, alone)
    r.metrics = {static_cast<double>(contacts_),
                 std::isinf(min_clearance_) ? nan : std::max(min_clearance_, 0.0), mean};
    r.outcome = static_cast<double>(contacts_) > max_contacts_                                   ? "collided"
                : mean < min_travel_ * max_speed_ * static_cast<double>(last_tick_) / tick_rate_ ? "stalled"
                                                                                                 : "avoided";
    return r;
  }

 private:
  static constexpr double kTouch = 0.002;  // m: a gap this small is a touch (the physics keeps bodies apart)

  static double clearance(const experiment::Truth& truth, const experiment::RobotTruth& r) {
    double gap = std::numeric_limits<double>::infinity();
    const Vec2 p{r.pose.x, r.pose.y};
    if (truth.arena.walls) {
      const double hx = truth.arena.width / 2.0, hy = truth.arena.height / 2.0;
      gap = std::min({hx - std::abs(p.x - truth.arena.centre.x), hy - std::abs(p.y - truth.arena.centre.y)});
    }
    for (const auto& o : truth.obstacles) {
      const double dx = p.x - o.centre.x, dy = p.y - o.centre.y;
      if (o.kind == experiment::ObstacleTruth::Kind::Cylinder) {
        gap = std::min(gap, std::hypot(dx, dy) - o.radius);
      } else {  // the point in the box's frame, then its distance to the rectangle (0 inside)
        const double c = std::cos(o.yaw), s = std::sin(o.yaw);
        const double bx = std::abs(c * dx + s * dy) - o.half_extents.x;
        const double by = std::abs(-s * dx + c * dy) - o.half_extents.y;
        gap =
            std::min(gap, std::hypot(std::max(bx, 0.0), std::max(by, 0.0)) + std::min(std::max(bx, by), 0.0));
      }
    }
    for (const auto& other : truth.robots) {
      if (other.id != r.id)
        gap = std::min(gap, std::hypot(p.x - other.pose.x, p.y - other.pose.y) - kRobotRadius);
    }
    return gap - kRobotRadius;
  }

  double max_contacts_ = 0.0, min_travel_ = 0.5, max_speed_ = 0.1, tick_rate_ = 10.0;
  Tick last_tick_ = 0;
  std::vector<bool> touching_;
  std::vector<double> travelled_;
  std::vector<Pose2D> last_;
  std::size_t contacts_ = 0;
  double min_clearance_ = std::numeric_limits<double>::infinity();
};

std::unique_ptr<controller::Controller> make() {
  return std::make_unique<Avoidance>();
}
std::unique_ptr<experiment::Experiment> make_experiment() {
  return std::make_unique<AvoidanceExperiment>();
}

}  // namespace

SWARMFORM_BEHAVIOUR(kDescriptor)
