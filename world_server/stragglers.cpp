#include "world_server/stragglers.hpp"

namespace swarmform::server {

bool Stragglers::add(dds::PublicationHandle writer, RobotId id, dds_time_t awake) {
  if (!by_writer_.try_emplace(writer, Straggler{id, awake}).second) return false;
  ++total_;
  return true;
}

std::optional<RobotId> Stragglers::remove(dds::PublicationHandle writer) {
  const auto it = by_writer_.find(writer);
  if (it == by_writer_.end()) return std::nullopt;
  const RobotId id = it->second.id;
  by_writer_.erase(it);
  return id;
}

bool Stragglers::holds(RobotId id) const {
  for (const auto& [writer, s] : by_writer_) {
    if (s.id == id) return true;
  }
  return false;
}

bool Stragglers::overdue(dds_time_t awake) const {
  for (const auto& [writer, s] : by_writer_) {
    if (awake - s.since >= kLimit) return true;
  }
  return false;
}

bool Stragglers::recheck_due(dds_time_t now) {
  if (now < next_check_) return false;
  next_check_ = now + kRecheck;
  return true;
}

}  // namespace swarmform::server
