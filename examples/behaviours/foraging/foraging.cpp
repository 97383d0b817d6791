// foraging: robots search the arena for food areas marked dark on the floor, take an item when their ground
// sensors find one, carry it home to the nest (a mid-grey area of the floor, with a light above it that the
// carriers steer to) and drop it there, then search again. Where an obstacle hides the light, a carrier
// steers to the last place it stood on the nest (its positioning sensor: every robot has been on the nest, it
// starts there). Searching is a random walk (legs of random length and turn rate from the robot's own
// behaviour::RobotRandom); the infrared ring turns the robot away from walls, obstacles and robots on the
// way. The LEDs say whether a robot carries: yellow with an item, blue without.
//
// The ground sensors read 0 black .. 1 white: below `food_below` is food, between `nest_low` and `nest_high`
// the nest, anything brighter the bare floor (the scenario's `floor:` paints them; a coloured region reads
// its grey level, docs/scenario-format.md).
//
// Its experiment counts deliveries: a live robot whose state goes from carrying to searching has dropped an
// item at the nest (the controller drops only there). The outcome is `foraged` when the swarm delivered at
// least `target_items`, else `not_foraged`.
#include <swarmform/behaviour.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace {

using namespace swarmform;

constexpr std::array kParams = {
    behaviour::ParamSpec{"speed_fraction", 1.0, 0.05, 1.0, "cruise speed as a fraction of max_speed"},
    behaviour::ParamSpec{"k_turn", 3.0, 0.0, 20.0, "turn rate per radian of the light's bearing, 1/s"},
    behaviour::ParamSpec{"food_below", 0.25, 0.0, 1.0, "a ground reading below this is food"},
    behaviour::ParamSpec{"nest_low", 0.35, 0.0, 1.0,
                         "a ground reading from this up to nest_high is the nest"},
    behaviour::ParamSpec{"nest_high", 0.75, 0.0, 1.0,
                         "a ground reading from nest_low up to this is the nest"},
    behaviour::ParamSpec{"dark", 0.015, 0.0, 1.0, "every light reading below this: the light is hidden"},
    behaviour::ParamSpec{"avoid_reading", 0.1, 0.0, 1.0,
                         "turn away when a front infrared reading passes this (0.1: about 9 cm)"},
    behaviour::ParamSpec{
        "escape_time", 1.5, 0.0, 30.0,
        "after an obstacle, carry on straight this long before steering to the light again, s"},
    behaviour::ParamSpec{"target_items", 3.0, 0.0, 1e6,
                         "the experiment: foraged once this many are delivered"},
};
enum State : std::int32_t { kSearching = 0, kCarrying = 1 };
constexpr std::array kStates = {
    behaviour::StateSpec{kSearching, "searching", "#1e88e5"},
    behaviour::StateSpec{kCarrying, "carrying", "#f9a825"},
};
constexpr std::array kTelemetry = {
    behaviour::TelemetryColumn{"delivered", "items this robot has dropped at the nest so far"},
    behaviour::TelemetryColumn{"ground", "the darkest ground reading this tick, 0..1"},
};

constexpr std::array kMetrics = {
    behaviour::MetricSpec{"items_delivered", "items dropped at the nest by live robots over the run"},
    behaviour::MetricSpec{"first_delivery_tick", "the tick of the first delivery (null: none)"},
    behaviour::MetricSpec{"carrying_at_end", "live robots carrying an item at the end"},
};
constexpr std::array<std::string_view, 2> kOutcomes = {"foraged", "not_foraged"};

constexpr Rgb kCarryingLed{255, 200, 0};
constexpr Rgb kSearchingLed{0, 0, 255};

std::unique_ptr<controller::Controller> make();
std::unique_ptr<experiment::Experiment> make_experiment();

const behaviour::Descriptor kDescriptor{
    .name = "foraging",
    .summary = "search for food on the floor, carry each item home to the nest under the light",
    .params = kParams,
    .states = kStates,
    .telemetry = kTelemetry,
    .needs_shape = false,
    .needs_goal = false,
    .shape_rules = {},
    .make = &make,
    .sensors = behaviour::kGround | behaviour::kLight | behaviour::kProximity,
    .experiment = {.metrics = kMetrics,
                   .summary = {},
                   .outcomes = kOutcomes,
                   .success = "foraged",
                   .make = &make_experiment},
};

class Foraging final : public controller::Controller {
 public:
  void init(const Mission& mission, RobotId self) override {
    mission_ = mission;
    self_ = self;
    rng_ = behaviour::RobotRandom(mission, self);
    leg_ticks_left_ = 0;
    carrying_ = false;
    delivered_ = 0;
    max_speed_ = mission.max_speed;
    speed_ = behaviour::param(mission, kDescriptor, "speed_fraction") * mission.max_speed;
    k_turn_ = behaviour::param(mission, kDescriptor, "k_turn");
    food_below_ = behaviour::param(mission, kDescriptor, "food_below");
    nest_low_ = behaviour::param(mission, kDescriptor, "nest_low");
    nest_high_ = behaviour::param(mission, kDescriptor, "nest_high");
    avoid_ = behaviour::param(mission, kDescriptor, "avoid_reading");
    dark_ = behaviour::param(mission, kDescriptor, "dark");
    knows_nest_ = false;
    escape_ticks_ =
        static_cast<int>(behaviour::param(mission, kDescriptor, "escape_time") * mission.tick_rate);
    escape_left_ = 0;
  }

  Command step(const Perception& p) override {
    if (!p.ground || !p.light || !p.proximity)
      throw std::logic_error("foraging: ground, light or proximity not equipped");
    bool on_food = false, on_nest = false;
    for (const double g : *p.ground) {
      on_food = on_food || g < food_below_;
      on_nest = on_nest || (g >= nest_low_ && g <= nest_high_);
    }
    if (on_nest) {
      nest_ = {p.pose.x, p.pose.y};
      knows_nest_ = true;
    }
    if (!carrying_ && on_food && !on_nest) {
      carrying_ = true;  // take an item
    } else if (carrying_ && on_nest) {
      carrying_ = false;  // drop it at the nest
      ++delivered_;
    }
    // The light over the nest: its bearing from the brightest sensor and its two neighbours.
    const auto& light = *p.light;
    const std::size_t k =
        static_cast<std::size_t>(std::max_element(light.begin(), light.end()) - light.begin());
    double lx = 0.0, ly = 0.0;
    for (const std::size_t j : {(k + kLightCount - 1) % kLightCount, k, (k + 1) % kLightCount}) {
      lx += light[j] * std::cos(kProximityAngles[j]);
      ly += light[j] * std::sin(kProximityAngles[j]);
    }
    const bool sees_light = light[k] >= dark_ && lx * lx + ly * ly > 1e-12;

    double v = speed_;
    double w = wander();
    if (carrying_ && (sees_light || knows_nest_)) {  // home: to the light, or to where the nest was
      const double bearing =
          sees_light ? std::atan2(ly, lx)
                     : std::remainder(std::atan2(nest_.y - p.pose.y, nest_.x - p.pose.x) - p.pose.theta,
                                      2.0 * std::numbers::pi);
      w = k_turn_ * bearing;
      v = speed_ * std::max(0.0, std::cos(bearing));
    }
    // The infrared ring's front half: past avoid_reading, turn away from the side the readings weigh on
    // (right when even), faster and slower the nearer the nearest body (stopped at a reading of 0.5, about 6
    // cm).
    double ahead = 0.0, left_minus_right = 0.0;
    for (std::size_t j = 0; j < kProximityCount; ++j) {
      if (std::cos(kProximityAngles[j]) < -1e-9) continue;  // behind
      ahead = std::max(ahead, (*p.proximity)[j]);
      left_minus_right += std::sin(kProximityAngles[j]) * (*p.proximity)[j];
    }
    if (ahead > avoid_) {
      w = (left_minus_right >= 0.0 ? -1.0 : 1.0) * 2.0 * max_speed_ / kWheelSpacing *
          std::min(1.0, ahead + 0.3);
      v = speed_ * std::max(0.0, 1.0 - 2.0 * ahead);
      escape_left_ = escape_ticks_;
    } else if (escape_left_ > 0) {
      // Just clear of a body: straight on for a while, so it slides past the body's edge instead of turning
      // back into it (the light pulls a carrier straight back otherwise).
      --escape_left_;
      w = 0.0;
      v = speed_;
    }
    Command c;
    behaviour::drive(v, w, max_speed_, c);
    c.leds.fill(carrying_ ? kCarryingLed : kSearchingLed);
    c.telemetry.state = carrying_ ? kCarrying : kSearching;
    c.telemetry.extra = {static_cast<double>(delivered_),
                         *std::min_element(p.ground->begin(), p.ground->end())};
    return c;
  }

  void reset() override { init(mission_, self_); }

 private:
  // The random walk's turn rate: nearly straight legs of 2..6 s at up to 0.3 rad/s each side (tight circles
  // would search the same spot over and over).
  double wander() {
    if (leg_ticks_left_ <= 0) {
      turn_rate_ = rng_.uniform(-0.3, 0.3);
      leg_ticks_left_ = static_cast<int>(rng_.uniform(2.0, 6.0) * mission_.tick_rate);
    }
    --leg_ticks_left_;
    return turn_rate_;
  }

  Mission mission_;
  RobotId self_ = 0;
  behaviour::RobotRandom rng_{0, 0};
  int leg_ticks_left_ = 0;
  double turn_rate_ = 0.0;  // rad/s, this leg's
  int escape_ticks_ = 15, escape_left_ = 0;
  Vec2 nest_;  // the last place it stood on the nest
  bool knows_nest_ = false;
  bool carrying_ = false;
  int delivered_ = 0;
  double max_speed_ = 0.1, speed_ = 0.1, k_turn_ = 3.0, food_below_ = 0.25, nest_low_ = 0.35,
         nest_high_ = 0.75, avoid_ = 0.1, dark_ = 0.015;
};

// Deliveries from the robots' reported states, tick to tick.
class ForagingExperiment final : public experiment::Experiment {
 public:
  void init(const Mission& mission, std::size_t robots) override {
    target_ = behaviour::param(mission, kDescriptor, "target_items");
    was_carrying_.assign(robots, false);
  }

  void observe(const experiment::Truth& truth) override {
    carrying_ = 0;
    for (const auto& r : truth.robots) {
      if (r.id >= was_carrying_.size()) continue;
      const bool carrying = r.alive && r.telemetry->state == kCarrying;
      if (r.alive && was_carrying_[r.id] && !carrying) {
        ++delivered_;
        if (first_tick_ < 0) first_tick_ = static_cast<double>(truth.tick);
      }
      was_carrying_[r.id] = carrying;
      carrying_ += carrying ? 1 : 0;
    }
  }

  experiment::Result conclude() override {
    experiment::Result r;
    r.metrics = {static_cast<double>(delivered_),
                 first_tick_ < 0 ? std::numeric_limits<double>::quiet_NaN() : first_tick_,
                 static_cast<double>(carrying_)};
    r.outcome = static_cast<double>(delivered_) >= target_ ? "foraged" : "not_foraged";
    return r;
  }

 private:
  double target_ = 3.0;
  std::vector<bool> was_carrying_;
  std::size_t delivered_ = 0, carrying_ = 0;
  double first_tick_ = -1.0;
};

std::unique_ptr<controller::Controller> make() {
  return std::make_unique<Foraging>();
}
std::unique_ptr<experiment::Experiment> make_experiment() {
  return std::make_unique<ForagingExperiment>();
}

}  // namespace

SWARMFORM_BEHAVIOUR(kDescriptor)
