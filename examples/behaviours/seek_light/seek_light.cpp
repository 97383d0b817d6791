// seek_light, phototaxis: every robot drives towards the brightest light its 8 light sensors see (the
// brightest sensor's direction, refined by its two neighbours' readings, so two lights are never averaged
// into a point between them), turns away from what the front half of its infrared ring sees, and random-walks
// (its own behaviour::RobotRandom) while it sees no light at all. Its LEDs: yellow while it sees a light, off
// while it searches, red while it avoids. (The built-in `phototaxis` is another behaviour: this one is a
// plug-in with an experiment of its own.)
//
// Its experiment judges the run from the true poses against the scenario's `goal:` (the place under the light
// and the radius that counts as there; the controller never reads it): the outcome is `reached` once every
// live robot stands within the goal's radius at one tick (the run then ends), else `not_reached`.
#include <swarmform/behaviour.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace {

using namespace swarmform;

constexpr std::array kParams = {
    behaviour::ParamSpec{"speed_fraction", 1.0, 0.05, 1.0, "cruise speed as a fraction of max_speed"},
    behaviour::ParamSpec{"k_turn", 3.0, 0.0, 20.0, "turn rate per radian of the light's bearing, 1/s"},
    behaviour::ParamSpec{"avoid_reading", 0.1, 0.0, 1.0,
                         "turn away when a front infrared reading passes this (0.1: about 9 cm)"},
    behaviour::ParamSpec{
        "escape_time", 1.5, 0.0, 30.0,
        "after an obstacle, drive on straight this long before steering to the light again, s"},
    behaviour::ParamSpec{"dark", 0.015, 0.0, 1.0, "every light reading below this: no light seen, search"},
};
enum State : std::int32_t { kSearching = 0, kHoming = 1, kAvoiding = 2 };
constexpr std::array kStates = {
    behaviour::StateSpec{kSearching, "searching", "#9e9e9e"},
    behaviour::StateSpec{kHoming, "homing", "#f9a825"},
    behaviour::StateSpec{kAvoiding, "avoiding", "#e53935"},
};
constexpr std::array kTelemetry = {
    behaviour::TelemetryColumn{"brightest", "the brightest light reading this tick, 0..1"},
    behaviour::TelemetryColumn{"light_bearing", "the light's bearing in the robot frame, rad (0 when none)"},
};

constexpr std::array kMetrics = {
    behaviour::MetricSpec{"reached_at_end", "live robots within the goal's radius at the end"},
    behaviour::MetricSpec{"all_reached_tick", "first tick every live robot stood within it (null: never)"},
    behaviour::MetricSpec{"mean_distance_to_light", "live robots' mean distance to the goal at the end, m"},
};
constexpr std::array<std::string_view, 2> kOutcomes = {"reached", "not_reached"};

std::unique_ptr<controller::Controller> make();
std::unique_ptr<experiment::Experiment> make_experiment();

const behaviour::Descriptor kDescriptor{
    .name = "seek_light",
    .summary = "drive to the brightest light, turn away from what the infrared ring sees",
    .params = kParams,
    .states = kStates,
    .telemetry = kTelemetry,
    .needs_shape = false,
    .needs_goal = false,
    .shape_rules = {},
    .make = &make,
    .sensors = behaviour::kLight | behaviour::kProximity,
    .experiment = {.metrics = kMetrics,
                   .summary = {},
                   .outcomes = kOutcomes,
                   .success = "reached",
                   .make = &make_experiment},
};

class SeekLight final : public controller::Controller {
 public:
  void init(const Mission& mission, RobotId self) override {
    mission_ = mission;
    self_ = self;
    rng_ = behaviour::RobotRandom(mission, self);
    leg_ticks_left_ = 0;
    max_speed_ = mission.max_speed;
    speed_ = behaviour::param(mission, kDescriptor, "speed_fraction") * mission.max_speed;
    k_turn_ = behaviour::param(mission, kDescriptor, "k_turn");
    avoid_ = behaviour::param(mission, kDescriptor, "avoid_reading");
    dark_ = behaviour::param(mission, kDescriptor, "dark");
    escape_ticks_ =
        static_cast<int>(behaviour::param(mission, kDescriptor, "escape_time") * mission.tick_rate);
    escape_left_ = 0;
  }

  Command step(const Perception& p) override {
    if (!p.light || !p.proximity) throw std::logic_error("seek_light: light or proximity not equipped");
    const auto& light = *p.light;
    const std::size_t k =
        static_cast<std::size_t>(std::max_element(light.begin(), light.end()) - light.begin());
    const double brightest = light[k];
    double v = speed_;
    double w = 0.0;
    double bearing = 0.0;
    State state = kHoming;
    if (brightest < dark_) {
      // No light: a random walk of nearly straight legs (2..6 s at up to 0.3 rad/s each side), which leaves a
      // shadow sooner than tight circles would.
      state = kSearching;
      if (leg_ticks_left_ <= 0) {
        turn_rate_ = rng_.uniform(-0.3, 0.3);
        leg_ticks_left_ = static_cast<int>(rng_.uniform(2.0, 6.0) * mission_.tick_rate);
      }
      --leg_ticks_left_;
      w = turn_rate_;
    } else {
      // The brightest sensor's direction, pulled towards the brighter of its neighbours.
      const std::size_t n = kLightCount;
      double x = 0.0, y = 0.0;
      for (const std::size_t j : {(k + n - 1) % n, k, (k + 1) % n}) {
        x += light[j] * std::cos(kProximityAngles[j]);
        y += light[j] * std::sin(kProximityAngles[j]);
      }
      bearing = std::atan2(y, x);
      w = k_turn_ * bearing;
      v = speed_ * std::max(0.0, std::cos(bearing));  // turn first, then go
    }
    // The front half of the ring: its readings weighted by how far left (+) or right (-) each sensor faces
    // say which side the bodies are on; past avoid_reading it turns away from that side (right when even),
    // faster and slower the nearer the nearest body is (stopped at a reading of 0.5, about 6 cm).
    double ahead = 0.0, left_minus_right = 0.0;
    for (std::size_t j = 0; j < kProximityCount; ++j) {
      if (std::cos(kProximityAngles[j]) < -1e-9) continue;  // behind
      ahead = std::max(ahead, (*p.proximity)[j]);
      left_minus_right += std::sin(kProximityAngles[j]) * (*p.proximity)[j];
    }
    if (ahead > avoid_) {
      state = kAvoiding;
      const double away = left_minus_right >= 0.0 ? -1.0 : 1.0;
      w = away * 2.0 * max_speed_ / kWheelSpacing * std::min(1.0, ahead + 0.3);
      v = speed_ * std::max(0.0, 1.0 - 2.0 * ahead);
      escape_left_ = escape_ticks_;
    } else if (escape_left_ > 0 && state == kHoming) {
      // Just clear of an obstacle between it and the light: straight on for a while, so it slides past the
      // obstacle's edge instead of turning back into it (the light pulls it straight back otherwise).
      --escape_left_;
      state = kAvoiding;
      w = 0.0;
      v = speed_;
    }
    Command c;
    behaviour::drive(v, w, max_speed_, c);
    const Rgb colour = state == kHoming ? Rgb{255, 200, 0} : state == kAvoiding ? Rgb{255, 0, 0} : Rgb{};
    c.leds.fill(colour);
    c.telemetry.state = state;
    c.telemetry.extra = {brightest, bearing};
    return c;
  }

  void reset() override { init(mission_, self_); }

 private:
  Mission mission_;
  RobotId self_ = 0;
  behaviour::RobotRandom rng_{0, 0};
  int leg_ticks_left_ = 0;
  double turn_rate_ = 0.0;  // rad/s, this leg's
  int escape_ticks_ = 15, escape_left_ = 0;
  double max_speed_ = 0.1, speed_ = 0.1, k_turn_ = 3.0, avoid_ = 0.1, dark_ = 0.015;
};

// Distances from the true poses to the goal's centre (the scenario's `goal:`, placed under the light).
class SeekLightExperiment final : public experiment::Experiment {
 public:
  void init(const Mission& mission, std::size_t) override {
    if (!mission.has_goal) {
      throw std::invalid_argument(
          "the scenario gives no goal: (the place under the light and the radius that counts as reached)");
    }
    goal_ = mission.goal;
    radius_ = mission.goal_radius;
  }

  void observe(const experiment::Truth& truth) override {
    live_ = 0;
    reached_ = 0;
    distance_sum_ = 0.0;
    for (const auto& r : truth.robots) {
      if (!r.alive) continue;
      const double d = std::hypot(r.pose.x - goal_.x, r.pose.y - goal_.y);
      ++live_;
      reached_ += d <= radius_ ? 1 : 0;
      distance_sum_ += d;
    }
    if (live_ > 0 && reached_ == live_ && all_reached_tick_ < 0)
      all_reached_tick_ = static_cast<double>(truth.tick);
  }

  // Every live robot is there: nothing more to see.
  bool done() const override { return all_reached_tick_ >= 0; }

  experiment::Result conclude() override {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    experiment::Result r;
    r.metrics = {static_cast<double>(reached_), all_reached_tick_ < 0 ? nan : all_reached_tick_,
                 live_ == 0 ? nan : distance_sum_ / static_cast<double>(live_)};
    r.outcome = all_reached_tick_ >= 0 ? "reached" : "not_reached";
    return r;
  }

 private:
  Vec2 goal_;
  double radius_ = 0.0;
  std::size_t live_ = 0, reached_ = 0;
  double distance_sum_ = 0.0;
  double all_reached_tick_ = -1.0;
};

std::unique_ptr<controller::Controller> make() {
  return std::make_unique<SeekLight>();
}
std::unique_ptr<experiment::Experiment> make_experiment() {
  return std::make_unique<SeekLightExperiment>();
}

}  // namespace

SWARMFORM_BEHAVIOUR(kDescriptor)
