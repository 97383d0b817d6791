#include "world_server/stall_guard.hpp"

namespace swarmform::server {

bool StallGuard::suspect(dds::PublicationHandle writer, bool gone) {
  const bool after_stall = clock_.stalls() > 0 && clock_.awake() - clock_.last_stall_end() < kSuspectWindow;
  const bool in_flood = flooded_ && clock_.awake() - last_flood_ < kSuspectWindow;
  if (!after_stall && !in_flood) return false;
  Suspect& s = suspects_.try_emplace(writer, Suspect{clock_.awake(), false}).first->second;
  s.gone = s.gone || gone;
  return true;
}

bool StallGuard::clear(dds::PublicationHandle writer) {
  const auto it = suspects_.find(writer);
  if (it == suspects_.end() || it->second.gone) return false;
  suspects_.erase(it);
  ++cleared_;
  return true;
}

void StallGuard::expired(std::vector<dds::PublicationHandle>& out) {
  for (auto it = suspects_.begin(); it != suspects_.end();) {
    if (clock_.awake() - it->second.since >= kGrace) {
      out.push_back(it->first);
      it = suspects_.erase(it);
    } else {
      ++it;
    }
  }
}

}  // namespace swarmform::server
