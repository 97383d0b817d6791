#include "behaviour/descriptor_check.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <variant>
#include <vector>

#include "behaviour/known_columns.hpp"
#include "behaviour/params.hpp"

namespace swarmform::behaviour {
namespace {

constexpr std::array<std::pair<std::uint32_t, std::string_view>, 5> kSensorNames = {{
    {kProximity, "proximity"},
    {kLight, "light"},
    {kGround, "ground"},
    {kLidar, "lidar"},
    {kBattery, "battery"},
}};

std::string outcome_list(const ExperimentSpec& e) {
  std::string s;
  for (std::string_view o : e.outcomes) s += (s.empty() ? "" : ", ") + std::string(o);
  return s;
}

}  // namespace

bool lower_case_name(std::string_view s) {
  if (s.empty() || !(s[0] >= 'a' && s[0] <= 'z')) return false;
  return std::all_of(s.begin(), s.end(),
                     [](char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_'; });
}

std::string check_experiment(const Descriptor& d) {
  const ExperimentSpec& e = d.experiment;
  const std::string where = "behaviour '" + std::string(d.name) + "': experiment: ";
  if (e.make == nullptr) {
    if (!e.metrics.empty() || !e.summary.empty() || !e.outcomes.empty() || !e.success.empty())
      return where + "metrics, summary keys, outcomes or success declared without a make";
    return {};
  }
  if (e.outcomes.empty()) return where + "declares no outcomes";
  for (std::size_t i = 0; i < e.outcomes.size(); ++i) {
    if (e.outcomes[i].empty() || e.outcomes[i] == "none" || e.outcomes[i] == "experiment_failed")
      return where + "outcome '" + std::string(e.outcomes[i]) + "' is empty or reserved";
    for (std::size_t j = 0; j < i; ++j) {
      if (e.outcomes[j] == e.outcomes[i]) return where + "outcome '" + std::string(e.outcomes[i]) + "' twice";
    }
  }
  if (std::find(e.outcomes.begin(), e.outcomes.end(), e.success) == e.outcomes.end())
    return where + "success '" + std::string(e.success) + "' is not one of its outcomes (" + outcome_list(e) +
           ")";
  for (std::size_t i = 0; i < e.metrics.size(); ++i) {
    const std::string_view name = e.metrics[i].name;
    if (!lower_case_name(name)) return where + "metric '" + std::string(name) + "' is not a lower_case name";
    for (std::size_t j = 0; j < i; ++j) {
      if (e.metrics[j].name == name) return where + "metric '" + std::string(name) + "' twice";
    }
  }
  for (std::size_t i = 0; i < e.summary.size(); ++i) {
    const std::string key(e.summary[i].key);
    if (!lower_case_name(key)) return where + "summary key '" + key + "' is not a lower_case name";
    if (world_summary_key(key)) return where + "summary key '" + key + "' is one the world writes itself";
    if (summary_kind_name(e.summary[i].kind).empty())
      return where + "summary key '" + key + "' has an unknown kind " +
             std::to_string(static_cast<std::int32_t>(e.summary[i].kind));
    for (std::size_t j = 0; j < i; ++j) {
      if (e.summary[j].key == key) return where + "summary key '" + key + "' twice";
    }
  }
  return {};
}

bool world_summary_key(std::string_view key) {
  // make_summary's own keys, summary_outcome's summary_cut and world_server's own (input_dropped,
  // mass_losses, RunSession::set_summary_field), and a robot group's first_id and count, beside which a
  // group's experiment writes its keys (groups.NAME); a test holds make_summary to this list.
  static constexpr std::array<std::string_view, 42> kKeys = {"format",
                                                             "version",
                                                             "scenario",
                                                             "shape_file",
                                                             "behaviour",
                                                             "robots",
                                                             "labels",
                                                             "seed",
                                                             "mode",
                                                             "ticks",
                                                             "wall_seconds",
                                                             "ticks_per_second",
                                                             "robot_ticks_per_second",
                                                             "steady_from_tick",
                                                             "steady_ticks_per_second",
                                                             "alive_at_end",
                                                             "deaths",
                                                             "rejoins",
                                                             "collisions_robot_robot",
                                                             "collisions_robot_obstacle",
                                                             "leader_changes",
                                                             "fragmentations",
                                                             "graph_rejoins",
                                                             "max_components",
                                                             "outcome",
                                                             "success",
                                                             "behaviour_metrics",
                                                             "experiment_error",
                                                             "silent_robots",
                                                             "command_verdicts",
                                                             "params",
                                                             "states_at_end",
                                                             "telemetry_mean_at_end",
                                                             "trajectory_sha256",
                                                             "end_reason",
                                                             "provenance",
                                                             "groups",
                                                             "summary_cut",
                                                             "input_dropped",
                                                             "mass_losses",
                                                             "first_id",
                                                             "count"};
  return std::find(kKeys.begin(), kKeys.end(), key) != kKeys.end();
}

std::string_view summary_kind_name(SummaryKind kind) {
  switch (kind) {
    case SummaryKind::Tick:
      return "tick";
    case SummaryKind::Count:
      return "count";
    case SummaryKind::Number:
      return "number";
    case SummaryKind::Ids:
      return "ids";
    case SummaryKind::Series:
      return "series";
  }
  return {};
}

bool summary_value_fits(SummaryKind kind, const experiment::FieldValue& value) {
  if (std::holds_alternative<std::monostate>(value)) return true;
  switch (kind) {
    case SummaryKind::Tick:
    case SummaryKind::Count:
      return std::holds_alternative<std::int64_t>(value);
    case SummaryKind::Number:
      return std::holds_alternative<double>(value);
    case SummaryKind::Ids:
      return std::holds_alternative<std::vector<std::int64_t>>(value);
    case SummaryKind::Series:
      return std::holds_alternative<std::vector<experiment::SeriesPoint>>(value);
  }
  return false;
}

std::string check_telemetry(const Descriptor& d) {
  // robots.csv's own columns (docs/recording-format.md): a telemetry column of the same name would make the
  // file ambiguous to every reader. The known columns (known_columns.hpp) are recorded in robots.csv's own
  // column of their name: they may be declared, with their meaning.
  constexpr std::array<std::string_view, 8> kRecorded = {"tick",  "id",    "x",     "y",
                                                         "theta", "alive", "state", "leds"};
  const std::string where = "behaviour '" + std::string(d.name) + "': telemetry column '";
  for (std::size_t i = 0; i < d.telemetry.size(); ++i) {
    const std::string_view name = d.telemetry[i].name;
    if (!lower_case_name(name)) return where + std::string(name) + "' is not a lower_case name";
    if (std::find(kRecorded.begin(), kRecorded.end(), name) != kRecorded.end())
      return where + std::string(name) + "' is one of robots.csv's own columns";
    if (name == kLabelColumn && !d.needs_shape)
      return where + std::string(name) + "' is a place in a shape: the behaviour must declare needs_shape";
    for (std::size_t j = 0; j < i; ++j) {
      if (d.telemetry[j].name == name) return where + std::string(name) + "' twice";
    }
  }
  return {};
}

bool colour_text(std::string_view s) {
  return s.size() == 7 && s[0] == '#' && std::all_of(s.begin() + 1, s.end(), [](char c) {
           return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F');
         });
}

std::string check_param_table(const Descriptor& d) {
  const std::string where = "behaviour '" + std::string(d.name) + "': parameter '";
  for (std::size_t i = 0; i < d.params.size(); ++i) {
    const ParamSpec& p = d.params[i];
    const std::string name(p.name);
    if (!lower_case_name(p.name)) return where + name + "' is not a lower_case name";
    for (std::size_t j = 0; j < i; ++j) {
      if (d.params[j].name == p.name) return where + name + "' twice";
    }
    if (!std::isfinite(p.min_value) || !std::isfinite(p.max_value) || !std::isfinite(p.default_value))
      return where + name + "': min, max and default must be finite";
    if (!(p.min_value <= p.default_value && p.default_value <= p.max_value))
      return where + name + "': default " + std::to_string(p.default_value) + " is outside [min, max] = [" +
             std::to_string(p.min_value) + ", " + std::to_string(p.max_value) + "]";
  }
  return {};
}

std::string check_states(const Descriptor& d) {
  const std::string where = "behaviour '" + std::string(d.name) + "': state ";
  for (std::size_t i = 0; i < d.states.size(); ++i) {
    const StateSpec& st = d.states[i];
    const std::string name(st.name);
    if (st.value < 0) return where + "'" + name + "' has value " + std::to_string(st.value) + " (< 0)";
    if (!lower_case_name(st.name)) return where + "'" + name + "' is not a lower_case name";
    if (!colour_text(st.colour))
      return where + "'" + name + "': colour '" + std::string(st.colour) + "' is not \"#rrggbb\"";
    for (std::size_t j = 0; j < i; ++j) {
      if (d.states[j].value == st.value) return where + "value " + std::to_string(st.value) + " twice";
      if (d.states[j].name == st.name) return where + "'" + name + "' twice";
    }
  }
  return {};
}

std::string check_descriptor(const Descriptor& d) {
  for (auto check : {check_param_table, check_states, check_shape_rules, check_experiment, check_telemetry,
                     check_sensors}) {
    if (std::string why = check(d); !why.empty()) return why;
  }
  return {};
}

std::string sensor_names(std::uint32_t sensors) {
  std::string s;
  for (std::uint32_t bit = 0; bit < 32; ++bit) {
    const std::uint32_t mask = 1U << bit;
    if ((sensors & mask) == 0) continue;
    std::string name = "bit " + std::to_string(bit);
    for (const auto& [m, n] : kSensorNames) {
      if (m == mask) name = std::string(n);
    }
    s += (s.empty() ? "" : ", ") + name;
  }
  return s;
}

std::string check_sensors(const Descriptor& d) {
  const std::uint32_t unmodelled = d.sensors & ~kModelledSensors;
  if (unmodelled == 0) return {};
  return "behaviour '" + std::string(d.name) + "' declares sensor " + sensor_names(unmodelled) +
         ", which this world does not model yet (docs/behaviour-api.md, \"Sensors and actuators\")";
}

std::string check_result(const Descriptor& d, const experiment::Result& r) {
  const ExperimentSpec& e = d.experiment;
  if (r.metrics.size() != e.metrics.size()) {
    return "returned " + std::to_string(r.metrics.size()) + " metrics, declares " +
           std::to_string(e.metrics.size());
  }
  if (std::find(e.outcomes.begin(), e.outcomes.end(), r.outcome) == e.outcomes.end())
    return "returned outcome '" + r.outcome + "', not one of: " + outcome_list(e);
  for (std::size_t k = 0; k < r.metrics.size(); ++k) {
    if (std::isinf(r.metrics[k])) {
      return "returned metric '" + std::string(e.metrics[k].name) +
             "' infinite (NaN says not reached; summary.json holds numbers)";
    }
  }
  return {};
}

}  // namespace swarmform::behaviour
