// The shape measures as an experiment's summary.json fields (shape_metrics.hpp, summary_fields): the keys and
// types summary.json has always had for the paper's runs, so sweeps and reports read them unchanged.
#include <cstdint>

#include "behaviour/shape_metrics.hpp"

namespace swarmform::shape_metrics {

namespace {

experiment::FieldValue tick_or_null(const std::optional<Tick>& t) {
  if (!t) return std::monostate{};
  return static_cast<std::int64_t>(*t);
}

experiment::FieldValue number_or_null(const std::optional<double>& v) {
  if (!v) return std::monostate{};
  return *v;
}

}  // namespace

std::vector<experiment::SummaryField> summary_fields(const Measures& m) {
  std::vector<std::int64_t> stuck(m.stuck_robots.begin(), m.stuck_robots.end());
  const auto stuck_count = static_cast<std::int64_t>(stuck.size());
  return {{"formation_tick", tick_or_null(m.formation_tick)},
          {"shape_error_at_formation", number_or_null(m.shape_error_at_formation)},
          {"motion_start_tick", tick_or_null(m.motion_start_tick)},
          {"motion_ticks_minimum", number_or_null(m.motion_ticks_minimum)},
          {"goal_tick", tick_or_null(m.goal_tick)},
          {"shape_error_at_goal", number_or_null(m.shape_error_at_goal)},
          {"peak_distortion", number_or_null(m.peak_distortion)},
          {"mean_distortion", number_or_null(m.mean_distortion)},
          {"path_length", m.path_length},
          {"arrived", static_cast<std::int64_t>(m.arrived)},
          {"stuck_robots", std::move(stuck)},
          {"stuck_robot_count", stuck_count},
          {"distortion", m.distortion}};
}

}  // namespace swarmform::shape_metrics
