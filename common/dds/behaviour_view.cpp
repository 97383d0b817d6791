#include "common/dds/behaviour_view.hpp"

namespace swarmform::dds {

BehaviourView describe_behaviour(const std::string& name, const behaviour::Descriptor* d) {
  BehaviourView v;
  v.name = name;
  v.telemetry_fields = {"state"};
  if (d == nullptr) return v;
  for (const auto& s : d->states)
    v.states.push_back(StateStyleRow{s.value, std::string(s.name), std::string(s.colour)});
  for (const auto& t : d->telemetry) v.columns.emplace_back(t.name);
  v.telemetry_fields.insert(v.telemetry_fields.end(), v.columns.begin(), v.columns.end());
  return v;
}

}  // namespace swarmform::dds
