#include "world_server/run/metrics_tracker.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/robot_state.hpp"

namespace swarmform::world {

namespace {

// The largest distance of a label's grid place from the centre of all of them, in m.
double shape_radius(const ShapeMatrix& shape, double grid_spacing) {
  double sx = 0.0;
  double sy = 0.0;
  int n = 0;
  for (int row = 0; row < shape.rows; ++row) {
    for (int col = 0; col < shape.cols; ++col) {
      if (shape.at(row, col) < 0) continue;
      sx += col;
      sy += row;
      ++n;
    }
  }
  if (n == 0) return 0.0;
  sx /= n;
  sy /= n;
  double r = 0.0;
  for (int row = 0; row < shape.rows; ++row) {
    for (int col = 0; col < shape.cols; ++col) {
      if (shape.at(row, col) >= 0) r = std::max(r, std::hypot(col - sx, row - sy));
    }
  }
  return r * grid_spacing;
}

}  // namespace

MetricsTracker::MetricsTracker(const Mission& mission)
    : shape_(mission.shape),
      grid_spacing_(mission.grid_spacing),
      goal_(mission.goal),
      goal_region_radius_(mission.goal_radius + shape_radius(mission.shape, mission.grid_spacing)) {}

bool MetricsTracker::in_motion_window(Tick tick) const {
  return metrics_.motion_start_tick && tick >= *metrics_.motion_start_tick &&
         (!metrics_.goal_tick || tick <= *metrics_.goal_tick);
}

void MetricsTracker::observe(Tick tick, const std::vector<RobotTruth>& robots, ContactCounts contacts) {
  metrics_.collisions_robot_robot += contacts.robot_robot;
  metrics_.collisions_robot_obstacle += contacts.robot_obstacle;

  constexpr auto kReady = static_cast<std::int32_t>(RobotState::Ready);
  constexpr auto kMotion = static_cast<std::int32_t>(RobotState::Motion);
  constexpr auto kArrived = static_cast<std::int32_t>(RobotState::Arrived);

  // One pass over the robots: the shape robots, whether all are ready, whether any is in motion.
  std::vector<LabelledPosition> shape_robots;
  std::vector<RobotId> shape_ids;
  bool all_ready = true;
  bool all_arrived = true;
  bool any_motion = false;
  std::uint32_t at_goal = 0;
  Vec2 centroid;
  for (const auto& r : robots) {
    if (!r.alive) continue;
    if (r.telemetry.state == kMotion) any_motion = true;
    if (r.telemetry.label < 0) continue;
    shape_robots.push_back({r.telemetry.label, {r.pose.x, r.pose.y}});
    shape_ids.push_back(r.id);
    if (r.telemetry.state < kReady) all_ready = false;
    if (r.telemetry.state != kArrived) all_arrived = false;
    if (std::hypot(r.pose.x - goal_.x, r.pose.y - goal_.y) <= goal_region_radius_) ++at_goal;
    centroid.x += r.pose.x;
    centroid.y += r.pose.y;
  }
  const bool have_shape = !shape_robots.empty();
  if (have_shape) {
    centroid.x /= static_cast<double>(shape_robots.size());
    centroid.y /= static_cast<double>(shape_robots.size());
  }

  if (!metrics_.motion_start_tick && any_motion) metrics_.motion_start_tick = tick;

  if (!metrics_.formation_tick && have_shape && all_ready) {
    metrics_.formation_tick = tick;
    metrics_.shape_error_at_formation = shape_error(shape_, grid_spacing_, shape_robots);
  }

  if (metrics_.formation_tick) {
    const auto error = shape_error(shape_, grid_spacing_, shape_robots);
    if (error) {
      metrics_.distortion.emplace_back(tick, *error);
      if (in_motion_window(tick)) {
        metrics_.peak_distortion = std::max(metrics_.peak_distortion.value_or(0.0), *error);
        distortion_sum_ += *error;
        ++distortion_count_;
        metrics_.mean_distortion = distortion_sum_ / static_cast<double>(distortion_count_);
      }
    }
    metrics_.arrived = at_goal;
    if (!metrics_.goal_tick && have_shape && (at_goal == shape_robots.size() || all_arrived)) {
      metrics_.goal_tick = tick;
      metrics_.shape_error_at_goal = error;
    }
  }

  // Centroid path over the motion ticks; only between two ticks with the same shape robots.
  if (in_motion_window(tick) && have_shape) {
    if (previous_centroid_ && shape_ids == previous_shape_ids_) {
      metrics_.path_length +=
          std::hypot(centroid.x - previous_centroid_->x, centroid.y - previous_centroid_->y);
    }
    previous_centroid_ = centroid;
  } else {
    previous_centroid_.reset();
  }
  previous_shape_ids_ = std::move(shape_ids);
}

void MetricsTracker::count_event(const nlohmann::ordered_json& event) {
  const std::string kind = event.value("kind", "");
  const Tick tick = event.value("tick", Tick{0});
  const auto id = event.value("id", std::int64_t{-1});
  if (kind == "death") {
    metrics_.deaths.push_back({static_cast<RobotId>(id), tick});
  } else if (kind == "rejoin") {
    metrics_.rejoins.push_back({static_cast<RobotId>(id), tick});
  } else if (kind == "leader") {
    if (leader_seen_) ++metrics_.leader_changes;
    leader_seen_ = true;
  } else if (kind == "fragment") {
    ++metrics_.fragmentations;
  } else if (kind == "rejoin_graph") {
    ++metrics_.graph_rejoins;
  }
}

void MetricsTracker::note_components(std::size_t components) {
  metrics_.max_components = std::max(metrics_.max_components, static_cast<std::uint32_t>(components));
}

}  // namespace swarmform::world
