#include "world_server/run/param_flags.hpp"

#include <cmath>

#include "behaviour/params.hpp"
#include "common/input_error.hpp"

namespace swarmform::world {

std::vector<ParamOverride> parse_param_flags(const std::vector<std::string>& texts) {
  std::vector<ParamOverride> out;
  for (const std::string& text : texts) {
    const auto eq = text.find('=');
    const std::string name = eq == std::string::npos ? std::string() : text.substr(0, eq);
    const std::string value_text = eq == std::string::npos ? std::string() : text.substr(eq + 1);
    double value = 0.0;
    std::size_t used = 0;
    try {
      value = std::stod(value_text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (name.empty() || used == 0 || used != value_text.size() || !std::isfinite(value)) {
      throw InputError(
          "command line", 0,
          "--param '" + text + "': expected NAME=VALUE, VALUE a finite number (e.g. k_move=0.5)");
    }
    out.push_back({text, name, value});
  }
  return out;
}

void check_param_flags(const std::vector<std::string>& texts, const Mission& mission,
                       behaviour::Registry& behaviours) {
  if (texts.empty()) return;
  std::string names;
  for (const std::string& text : texts) names += (names.empty() ? "" : " ") + text;
  try {
    // The behaviour's own check of every parameter (its controller's init); a behaviour described by a file
    // has no controller here: its table alone.
    const behaviour::Descriptor& d = behaviours.resolve(mission);
    if (d.make == nullptr) {
      behaviour::check_params(d, mission.params);
    } else {
      (void)behaviour::make_controller(d, mission, 0);
    }
  } catch (const InputError& e) {
    std::string why = e.what();
    if (const std::string prefix = e.file() + ": "; why.rfind(prefix, 0) == 0) why.erase(0, prefix.size());
    throw InputError("command line", 0, "--param " + names + ": " + why);
  }
}

}  // namespace swarmform::world
