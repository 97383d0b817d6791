#include "robot_agent/controller/neighbours.hpp"

#include <algorithm>

#include "robot_agent/controller/drive.hpp"

namespace swarmform::controller {

void NeighbourTable::update(const Perception& perception, RobotId self) {
  now_ = perception.tick;
  for (const auto& reading : perception.messages) {
    if (reading.sender == self) continue;
    // Decode into the scratch message and swap it in: the vectors' capacity circulates between the scratch
    // and the neighbours, so a tick of ~73 messages allocates nothing once they have grown.
    // A message whose inner sender is not the one the medium saw is a forgery or a bug: ignore it.
    if (!decode_message_into(reading.data, scratch_) || scratch_.sender != reading.sender) {
      ++dropped_;
      continue;
    }
    auto it = std::lower_bound(live_.begin(), live_.end(), reading.sender,
                               [](const auto& entry, RobotId id) { return entry.first < id; });
    if (it == live_.end() || it->first != reading.sender)
      it = live_.insert(it, {reading.sender, Neighbour{}});
    Neighbour& n = it->second;
    n.id = reading.sender;
    n.range = reading.range;
    n.bearing = reading.bearing;
    n.azimuth = wrap_angle(perception.pose.theta + reading.bearing);
    std::swap(n.message, scratch_);
    n.last_heard = now_;
    ever_heard_[reading.sender] = now_;
  }
  std::erase_if(live_, [&](const auto& entry) {
    return now_ - entry.second.last_heard >= static_cast<Tick>(timeout_);
  });
}

const Neighbour* NeighbourTable::find(RobotId id) const {
  auto it = std::lower_bound(live_.begin(), live_.end(), id,
                             [](const auto& entry, RobotId key) { return entry.first < key; });
  return it == live_.end() || it->first != id ? nullptr : &it->second;
}

bool NeighbourTable::fresh(RobotId id) const {
  const Neighbour* n = find(id);
  return n != nullptr && n->last_heard == now_;
}

std::optional<Tick> NeighbourTable::last_heard(RobotId id) const {
  auto it = ever_heard_.find(id);
  if (it == ever_heard_.end()) return std::nullopt;
  return it->second;
}

void NeighbourTable::clear() {
  live_.clear();
  ever_heard_.clear();
  now_ = 0;
  dropped_ = 0;
}

}  // namespace swarmform::controller
