#include "robot_agent/controller/neighbours.hpp"

#include <algorithm>

#include "robot_agent/controller/drive.hpp"

namespace swarmform::controller {

namespace {
// Swaps what a decode writes, field by field: cheaper than std::swap's three moves of the whole message.
void swap_message(RobotMessage& a, RobotMessage& b) {
  std::swap(a.sender, b.sender);
  std::swap(a.state, b.state);
  std::swap(a.label, b.label);
  std::swap(a.pose, b.pose);
  std::swap(a.has_origin, b.has_origin);
  std::swap(a.origin, b.origin);
  std::swap(a.seed_candidate, b.seed_candidate);
  std::swap(a.seed_distance, b.seed_distance);
  std::swap(a.table_digest, b.table_digest);
  a.free_labels.swap(b.free_labels);
  a.entries.swap(b.entries);
  a.motion.swap(b.motion);
}

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
    // Decode into the scratch message and swap it in: the vectors' capacity circulates between the scratch
    // and the neighbours, so a tick of ~73 messages allocates nothing once they have grown.
    // A message whose inner sender is not the one the medium saw is a forgery or a bug: ignore it.
    if (!decode_message_into(reading.data, scratch_, own_digest) || scratch_.sender != reading.sender) {
      ++dropped_;
      continue;
    }
    auto it = locate(reading.sender);
    if (it == live_.end() || it->first != reading.sender) {
      it = live_.insert(it, {reading.sender, Neighbour{}});
      slot_[reading.sender % kSlotCount] = static_cast<std::uint32_t>(it - live_.begin());
    }
    Neighbour& n = it->second;
    n.id = reading.sender;
    n.range = reading.range;
    n.bearing = reading.bearing;
    n.azimuth = wrap_angle(perception.pose.theta + reading.bearing);
    swap_message(n.message, scratch_);
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
