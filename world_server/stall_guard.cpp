#include "world_server/stall_guard.hpp"

namespace swarmform::server {

bool StallGuard::suspect(dds::PublicationHandle writer, bool gone) {
  const bool after_stall = clock_.stalls() > 0 && clock_.awake() - clock_.last_stall_end() < kSuspectWindow;
  const bool in_flood = flooded_ && clock_.awake() - last_flood_ < kSuspectWindow;
  if (!after_stall && !in_flood) return false;
  Suspect& s = suspects_.try_emplace(writer, Suspect{clock_.awake(), false}).first->second;
  s.gone = s.gone || gone;
  lately_[writer].since = clock_.awake();
  return true;
}

bool StallGuard::clear(dds::PublicationHandle writer) {
  const auto it = suspects_.find(writer);
  if (it == suspects_.end() || it->second.gone) return false;
  suspects_.erase(it);
  ++cleared_;
  ++lately_[writer].clears;
  return true;
}

void StallGuard::died(dds::PublicationHandle writer) {
  const auto it = lately_.find(writer);
  if (it == lately_.end()) return;
  cleared_ -= it->second.clears;
  ++died_;
  lately_.erase(it);
}

std::optional<dds_time_t> StallGuard::take_lost_at(dds::PublicationHandle writer) {
  const auto it = expired_lost_at_.find(writer);
  if (it == expired_lost_at_.end()) return std::nullopt;
  const dds_time_t t = it->second;
  expired_lost_at_.erase(it);
  return t;
}

void StallGuard::expired(std::vector<dds::PublicationHandle>& out) {
  for (auto it = suspects_.begin(); it != suspects_.end();) {
    if (clock_.awake() - it->second.since >= kGrace) {
      out.push_back(it->first);
      expired_lost_at_[it->first] = it->second.since;
      it = suspects_.erase(it);
    } else {
      ++it;
    }
  }
  for (auto it = lately_.begin(); it != lately_.end();) {
    if (clock_.awake() - it->second.since >= kRecent && suspects_.count(it->first) == 0) {
      it = lately_.erase(it);
    } else {
      ++it;
    }
  }
}

}  // namespace swarmform::server
