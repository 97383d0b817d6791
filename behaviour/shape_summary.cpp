// The shape measures as an experiment's summary.json fields (shape_metrics.hpp, summary_fields): the keys and
// types summary.json has always had for the paper's runs, so sweeps and reports read them unchanged.
#include <array>
#include <cstdint>
#include <string>
#include <utility>

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
  // In kSummaryFields' order, by its keys: the declaration and what is returned cannot part.
  std::array<experiment::FieldValue, kSummaryFields.size()> values = {
      tick_or_null(m.formation_tick),
      number_or_null(m.shape_error_at_formation),
      tick_or_null(m.motion_start_tick),
      number_or_null(m.motion_ticks_minimum),
      tick_or_null(m.goal_tick),
      number_or_null(m.shape_error_at_goal),
      number_or_null(m.peak_distortion),
      number_or_null(m.mean_distortion),
      m.path_length,
      static_cast<std::int64_t>(m.arrived),
      std::move(stuck),
      stuck_count,
      m.distortion};
  std::vector<experiment::SummaryField> fields;
  fields.reserve(kSummaryFields.size());
  for (std::size_t k = 0; k < kSummaryFields.size(); ++k) {
    fields.push_back({std::string(kSummaryFields[k].key), std::move(values[k])});
  }
  return fields;
}

}  // namespace swarmform::shape_metrics
