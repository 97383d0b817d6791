#include "behaviour/params.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "common/input_error.hpp"

namespace swarmform::behaviour {

const ParamSpec* find_param(const Descriptor& d, std::string_view name) {
  for (const ParamSpec& p : d.params) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

double param(const std::map<std::string, double>& values, const Descriptor& d, std::string_view name) {
  const ParamSpec* spec = find_param(d, name);
  if (spec == nullptr) {
    throw std::logic_error("behaviour '" + std::string(d.name) + "' reads parameter '" + std::string(name) +
                           "', which is not in its table");
  }
  auto it = values.find(std::string(name));
  return it != values.end() ? it->second : spec->default_value;
}

double shape_heading(const Mission& mission, const Descriptor& d) {
  const std::string_view name = d.shape_rules.heading_param;
  return name.empty() ? kShapeUp : param(mission, d, name);
}

std::string check_shape_rules(const Descriptor& d) {
  const ShapeRules& r = d.shape_rules;
  const std::string where = "behaviour '" + std::string(d.name) + "': shape_rules.";
  if (r.anchor != ShapeAnchor::Unknown && r.anchor != ShapeAnchor::NearestOrigin) {
    return where + "anchor " + std::to_string(static_cast<std::int32_t>(r.anchor)) + " is not a ShapeAnchor";
  }
  if (!r.heading_param.empty() && find_param(d, r.heading_param) == nullptr) {
    return where + "heading_param '" + std::string(r.heading_param) + "' is not one of its parameters (" +
           param_names(d) + ")";
  }
  if (r.motion_state != ShapeRules::kNoState) {
    bool listed = false;
    for (const StateSpec& st : d.states) listed = listed || st.value == r.motion_state;
    if (!listed)
      return where + "motion_state " + std::to_string(r.motion_state) + " is not one of its states";
  }
  return {};
}

std::string param_names(const Descriptor& d) {
  std::string known;
  for (const ParamSpec& p : d.params) known += (known.empty() ? "" : ", ") + std::string(p.name);
  return known.empty() ? "none" : known;
}

std::string check_param(const Descriptor& d, std::string_view name, double value) {
  const ParamSpec* spec = find_param(d, name);
  if (spec == nullptr) {
    return "unknown parameter of behaviour '" + std::string(d.name) + "' (known: " + param_names(d) + ")";
  }
  if (!std::isfinite(value)) return "expected a finite number";
  if (value < spec->min_value || value > spec->max_value) {
    std::ostringstream why;
    why << "must be in [" << spec->min_value << ", " << spec->max_value << "]";
    return why.str();
  }
  return {};
}

void check_params(const Descriptor& d, const std::map<std::string, double>& params) {
  for (const auto& [name, value] : params) {
    const std::string why = check_param(d, name, value);
    if (!why.empty()) {
      throw InputError("<mission>", 0,
                       "behaviour '" + std::string(d.name) + "' parameter '" + name +
                           "' = " + std::to_string(value) + ": " + why);
    }
  }
}

}  // namespace swarmform::behaviour
