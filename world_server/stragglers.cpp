#include "world_server/stragglers.hpp"

namespace swarmform::server {

bool Stragglers::add(dds::PublicationHandle writer, RobotId id) {
  if (!by_writer_.try_emplace(writer, id).second) return false;
  ++total_;
  return true;
}

std::optional<RobotId> Stragglers::remove(dds::PublicationHandle writer) {
  const auto it = by_writer_.find(writer);
  if (it == by_writer_.end()) return std::nullopt;
  const RobotId id = it->second;
  by_writer_.erase(it);
  return id;
}

bool Stragglers::recheck_due(dds_time_t now) {
  if (now < next_check_) return false;
  next_check_ = now + kRecheck;
  return true;
}

}  // namespace swarmform::server
