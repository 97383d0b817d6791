// Reading and checking a behaviour's parameters against its own table (descriptor.hpp). The world checks a
// scenario's values with check_param (and names the file:line); a controller reads them with param(), which
// falls back to the table's default for a parameter the scenario does not set.
#pragma once

#include <map>
#include <string>
#include <string_view>

#include "behaviour/descriptor.hpp"
#include "common/mission.hpp"

namespace swarmform::behaviour {

const ParamSpec* find_param(const Descriptor& d, std::string_view name);

// The value of `name` in `values`, or its default from d's table. Throws std::logic_error when `name` is
// not in the table (a bug in the behaviour, not in the scenario).
double param(const std::map<std::string, double>& values, const Descriptor& d, std::string_view name);
inline double param(const Mission& mission, const Descriptor& d, std::string_view name) {
  return param(mission.params, d, name);
}

// Empty when `value` is acceptable for `name`; otherwise why not ("unknown parameter of behaviour 'x'
// (known: a, b)", "must be in [lo, hi]", "expected a finite number").
std::string check_param(const Descriptor& d, std::string_view name, double value);

// Every parameter of `params` checked; throws swarmform::InputError("<mission>", 0, ...) naming the first bad
// one (robot_agent meets a mission on the wire: no file to name).
void check_params(const Descriptor& d, const std::map<std::string, double>& params);

// The shape's heading as the world checks and measures it (ShapeRules::heading_param): that parameter's
// value, or kShapeUp (the shape as written) when the behaviour names none.
inline constexpr double kShapeUp = 1.5707963267948966;  // pi / 2
double shape_heading(const Mission& mission, const Descriptor& d);

// Empty when d's shape_rules agree with the rest of d (heading_param in its params, motion_state in its
// states, a known anchor); otherwise what is wrong, for the registry to refuse the descriptor.
std::string check_shape_rules(const Descriptor& d);

// "a, b, c": the table's names, for messages.
std::string param_names(const Descriptor& d);

}  // namespace swarmform::behaviour
