// aggregation: every robot drives towards the centroid of the neighbours it hears (range and bearing only; no
// positions are shared), turns away from what its ultrasonics see close ahead, and stops once the centroid is
// within `stop_distance`, its LEDs green. A robot that hears nobody random-walks (legs of random length and
// turn rate, from its own behaviour::RobotRandom) until it does. The swarm gathers into clusters, one per
// connected group.
//
// Its experiment judges the run from the true poses: robots whose centres are within 2 x stop_distance of
// each other are in one cluster (transitively); the outcome is `gathered` when every live robot ends in one
// cluster, else `scattered`; summary.json's `stragglers` lists the live robots outside the largest cluster.
#include <swarmform/behaviour.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <vector>

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

constexpr std::array kMetrics = {
    behaviour::MetricSpec{"clusters", "clusters of live robots at the end"},
    behaviour::MetricSpec{"largest_cluster", "live robots in the largest cluster at the end"},
    behaviour::MetricSpec{"gathered_tick", "first tick every live robot stood in one cluster (null: never)"},
    behaviour::MetricSpec{"mean_distance_to_centroid",
                          "live robots' mean distance to their centroid at the end, m"},
    behaviour::MetricSpec{"green_at_end", "live robots showing green LEDs (gathered) at the end"},
};
// Its own top-level summary.json key (Result::summary), declared so `--expect 'stragglers == 0'` is checked
// before the run.
constexpr std::array kSummary = {
    behaviour::SummarySpec{"stragglers", behaviour::SummaryKind::Ids,
                           "live robots outside the largest cluster at the end (ids)"},
};
constexpr std::array<std::string_view, 2> kOutcomes = {"gathered", "scattered"};

std::unique_ptr<controller::Controller> make();
std::unique_ptr<experiment::Experiment> make_experiment();

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
    .sensors = 0,
    .experiment = {.metrics = kMetrics,
                   .summary = kSummary,
                   .outcomes = kOutcomes,
                   .success = "gathered",
                   .make = &make_experiment},
};

class Aggregation final : public controller::Controller {
 public:
  void init(const Mission& mission, RobotId self) override {
    mission_ = mission;
    self_ = self;
    rng_ = behaviour::RobotRandom(mission, self);
    leg_ticks_left_ = 0;
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
    if (n == 0) {  // a random walk: a new leg of 1..4 s at a turn rate of up to 1 rad/s each side
      if (leg_ticks_left_ <= 0) {
        turn_rate_ = rng_.uniform(-1.0, 1.0);
        leg_ticks_left_ = static_cast<int>(rng_.uniform(1.0, 4.0) * mission_.tick_rate);
      }
      --leg_ticks_left_;
      w = turn_rate_;
    } else if (distance <= stop_) {
      v = 0.0;
      state = kGathered;
    } else {
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
    behaviour::drive(v, w, max_speed_, c);
    c.leds.fill(state == kGathered ? Rgb{0, 255, 0} : Rgb{});
    c.telemetry.state = state;
    c.telemetry.extra = {n, distance};
    c.message = {1};  // a one-byte beacon: being heard is all the others need
    return c;
  }

  void reset() override { init(mission_, self_); }

 private:
  Mission mission_;
  RobotId self_ = 0;
  behaviour::RobotRandom rng_{0, 0};
  int leg_ticks_left_ = 0;
  double turn_rate_ = 0.0;  // rad/s, this leg's
  double max_speed_ = 0.1, speed_ = 0.1, k_turn_ = 2.0, stop_ = 0.35, avoid_ = 0.3;
};

// Clusters of the live robots: robots within `link` of each other, transitively (O(N^2) a tick: an example's
// swarm is small).
class AggregationExperiment final : public experiment::Experiment {
 public:
  void init(const Mission& mission, std::size_t) override {
    link_ = 2.0 * behaviour::param(mission, kDescriptor, "stop_distance");
  }

  void observe(const experiment::Truth& truth) override {
    live_.clear();
    live_ids_.clear();
    green_ = 0;
    for (const auto& r : truth.robots) {
      if (!r.alive) continue;
      live_.push_back({r.pose.x, r.pose.y});
      live_ids_.push_back(static_cast<std::int64_t>(r.id));
      green_ += r.leds[0] == Rgb{0, 255, 0} ? 1 : 0;
    }
    sizes_ = cluster_sizes();
    if (sizes_.size() == 1 && gathered_tick_ < 0) gathered_tick_ = static_cast<double>(truth.tick);
  }

  experiment::Result conclude() override {
    double cx = 0.0, cy = 0.0;
    for (const Vec2& p : live_) {
      cx += p.x;
      cy += p.y;
    }
    const auto n = static_cast<double>(live_.size());
    double mean = 0.0;
    for (const Vec2& p : live_) mean += std::hypot(p.x - cx / n, p.y - cy / n) / n;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    experiment::Result r;
    r.metrics = {static_cast<double>(sizes_.size()),
                 sizes_.empty() ? 0.0 : static_cast<double>(*std::max_element(sizes_.begin(), sizes_.end())),
                 gathered_tick_ < 0 ? nan : gathered_tick_, live_.empty() ? nan : mean,
                 static_cast<double>(green_)};
    r.outcome = sizes_.size() == 1 ? "gathered" : "scattered";
    r.summary = {{"stragglers", stragglers()}};
    return r;
  }

 private:
  std::size_t root(std::size_t i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  }
  std::vector<std::size_t> cluster_sizes() {
    parent_.resize(live_.size());
    std::iota(parent_.begin(), parent_.end(), std::size_t{0});
    for (std::size_t i = 0; i < live_.size(); ++i) {
      for (std::size_t j = i + 1; j < live_.size(); ++j) {
        if (std::hypot(live_[i].x - live_[j].x, live_[i].y - live_[j].y) <= link_) parent_[root(i)] = root(j);
      }
    }
    std::vector<std::size_t> count(live_.size(), 0);
    for (std::size_t i = 0; i < live_.size(); ++i) ++count[root(i)];
    std::vector<std::size_t> sizes;
    for (std::size_t c : count) {
      if (c > 0) sizes.push_back(c);
    }
    return sizes;
  }
  // The live robots outside the largest cluster of the last observe (the first of the largest, when tied).
  std::vector<std::int64_t> stragglers() {
    std::vector<std::size_t> count(live_.size(), 0);
    for (std::size_t i = 0; i < live_.size(); ++i) ++count[root(i)];
    std::vector<std::int64_t> out;
    if (count.empty()) return out;
    const auto largest =
        static_cast<std::size_t>(std::max_element(count.begin(), count.end()) - count.begin());
    for (std::size_t i = 0; i < live_.size(); ++i) {
      if (root(i) != largest) out.push_back(live_ids_[i]);
    }
    return out;
  }

  double link_ = 0.8;  // m
  double gathered_tick_ = -1.0;
  std::size_t green_ = 0;
  std::vector<Vec2> live_;
  std::vector<std::int64_t> live_ids_;  // live_'s robots' ids
  std::vector<std::size_t> parent_;
  std::vector<std::size_t> sizes_;
};

std::unique_ptr<controller::Controller> make() {
  return std::make_unique<Aggregation>();
}
std::unique_ptr<experiment::Experiment> make_experiment() {
  return std::make_unique<AggregationExperiment>();
}

}  // namespace

SWARMFORM_BEHAVIOUR(kDescriptor)
