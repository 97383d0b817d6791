#include "robot_agent/controller/neighbours.hpp"

#include <algorithm>

#include "robot_agent/controller/drive.hpp"

namespace swarmform::controller {

namespace {
// The entry of the id-sorted `list` with `id`, or where it would be inserted (const or not).
template <class List>
auto first_not_below(List& list, RobotId id) {
  return std::lower_bound(list.begin(), list.end(), id,
                          [](const auto& entry, RobotId key) { return entry.first < key; });
}
}  // namespace

void NeighbourTable::update(const Perception& perception, RobotId self, std::uint64_t own_digest) {
  now_ = perception.tick;
  for (const auto& reading : perception.messages) {
    if (reading.sender == self) continue;
    // Decoded straight into the neighbour's own message: its vectors keep their capacity from tick to tick,
    // so a tick of ~73 messages allocates nothing once they have grown, and nothing is copied or swapped
    // (decoding into a scratch message and swapping it in cost ~100 instructions a message).
    auto it = locate(reading.sender);
    const bool known = it != live_.end() && it->first == reading.sender;
    if (!known) {
      it = live_.insert(it, {reading.sender, Neighbour{}});
      slot_[reading.sender % kSlotCount] = static_cast<std::uint32_t>(it - live_.begin());
    }
    Neighbour& n = it->second;
    // An undecodable message, or one whose inner sender is not the one the medium saw (a forgery or a bug),
    // is dropped, and so is its sender: its last good message was overwritten. It is remembered as last heard
    // at its last good tick, as if it had expired then.
    if (!decode_message_into(reading.data, n.message, own_digest) || n.message.sender != reading.sender) {
      ++dropped_;
      if (known) expired_[reading.sender] = n.last_heard;
      live_.erase(it);
      continue;
    }
    n.id = reading.sender;
    n.range = reading.range;
    n.bearing = reading.bearing;
    n.azimuth = wrap_angle(perception.pose.theta + reading.bearing);
    n.last_heard = now_;
  }
  std::erase_if(live_, [&](const auto& entry) {
    if (now_ - entry.second.last_heard < static_cast<Tick>(timeout_)) return false;
    expired_[entry.first] = entry.second.last_heard;
    return true;
  });
}

NeighbourList::iterator NeighbourTable::locate(RobotId id) {
  std::uint32_t& slot = slot_[id % kSlotCount];
  if (slot < live_.size() && live_[slot].first == id) return live_.begin() + slot;
  auto it = first_not_below(live_, id);
  slot = static_cast<std::uint32_t>(it - live_.begin());
  return it;
}

const Neighbour* NeighbourTable::find(RobotId id) const {
  auto it = first_not_below(live_, id);
  return it == live_.end() || it->first != id ? nullptr : &it->second;
}

bool NeighbourTable::fresh(RobotId id) const {
  const Neighbour* n = find(id);
  return n != nullptr && n->last_heard == now_;
}

std::optional<Tick> NeighbourTable::last_heard(RobotId id) const {
  if (const Neighbour* n = find(id)) return n->last_heard;
  auto it = expired_.find(id);
  if (it == expired_.end()) return std::nullopt;
  return it->second;
}

void NeighbourTable::clear() {
  live_.clear();
  expired_.clear();
  now_ = 0;
  dropped_ = 0;
}

}  // namespace swarmform::controller
