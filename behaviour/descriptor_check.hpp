// What a program checks of a behaviour's declarations beyond its parameters (params.hpp): its experiment
// (descriptor.hpp ExperimentSpec) and its sensors, when the registry takes the descriptor; and what an
// experiment returned, against what it declared, when the world concludes a run.
#pragma once

#include <string>
#include <string_view>

#include "behaviour/descriptor.hpp"
#include "behaviour/experiment.hpp"

namespace swarmform::behaviour {

// The Sensor bits this world models (Perception fields it fills). A behaviour that declares another is
// refused: it would read "not equipped" where it expects readings.
inline constexpr std::uint32_t kModelledSensors = kProximity | kGround | kLight | kLidar | kBattery;

// a-z first, then a-z, 0-9 or _: the names a descriptor gives its metrics, parameters, states and columns.
bool lower_case_name(std::string_view s);
// Empty when d's experiment declaration is consistent (outcomes given with a make, success among them, "none"
// not used, metric names and summary keys lower_case and unique, no summary key the world writes, nothing
// declared without a make); otherwise what is wrong, naming the behaviour.
std::string check_experiment(const Descriptor& d);
// A top-level key summary.json's writer writes itself (world_server/run/recording_format.cpp make_summary,
// and summary_outcome's summary_cut): an experiment may neither declare nor return one.
bool world_summary_key(std::string_view key);
// "tick", "count", "number", "ids", "series": a SummaryKind as world.json and `world_server --check` name it.
std::string_view summary_kind_name(SummaryKind kind);
// Whether `value` may stand for a declared field of this kind: null always (not reached), else the kind's own
// alternative (a tick or a count: std::int64_t; a number: double; ids: a list of integers; a series: pairs).
bool summary_value_fits(SummaryKind kind, const experiment::FieldValue& value);
// Empty when d's telemetry columns can head robots.csv's columns: lower_case, unique, and none named as a
// column the recording writes itself (tick, id, ..., net_force, leds); otherwise what is wrong.
std::string check_telemetry(const Descriptor& d);
// "#rrggbb" (hex digits of either case): a state's colour.
bool colour_text(std::string_view s);
// Empty when d's parameter table is well formed: lower_case and unique names, min <= default <= max, all
// finite; otherwise what is wrong, naming the behaviour. A descriptor file's loader says the same with the
// file's key path (descriptor_file.hpp); this holds every descriptor, a plug-in's and a built-in's, to it.
std::string check_param_table(const Descriptor& d);
// Empty when d's states are: values >= 0 and unique, names lower_case and unique, colours "#rrggbb".
std::string check_states(const Descriptor& d);
// Every check above and check_shape_rules (params.hpp), in that order: empty when d may be registered,
// else the first thing wrong.
std::string check_descriptor(const Descriptor& d);
// Empty when every sensor d declares is modelled; otherwise which are not.
std::string check_sensors(const Descriptor& d);
// "proximity, ground": the names of the Sensor bits set in `sensors` (unknown bits as "bit N").
std::string sensor_names(std::uint32_t sensors);
// Empty when `r` is what d's experiment declares (one metric each, a declared outcome); otherwise what it
// did.
std::string check_result(const Descriptor& d, const experiment::Result& r);

}  // namespace swarmform::behaviour
