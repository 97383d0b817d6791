// The mission on sf_mission: the world publishes it once, durably (an agent started late still gets it),
// and an agent takes it, checked (common/mission_check.hpp), before it makes anything else.
#pragma once

#include <cstdint>
#include <optional>

#include "common/dds/entity.hpp"
#include "common/dds/identity.hpp"
#include "common/dds/participant.hpp"
#include "common/mission.hpp"

namespace swarmform::dds {

struct MissionAnnouncement {
  Mission mission;
  std::uint32_t robots = 0;     // robots in the run (ids 0..robots-1)
  std::uint64_t run_nonce = 0;  // random per run (the launcher's --run-nonce, or the world's own draw)
  bool realtime = false;   // the pace of sf_sensor / sf_command (qos.hpp): an agent creates them after this
  ParticipantKey world{};  // reader side: the participant of the writer it came from
};

class MissionWriter {
 public:
  explicit MissionWriter(const Participant& participant);
  void publish(const MissionAnnouncement& announcement);

 private:
  Entity writer_;
};

class RefusalLog;

class MissionReader {
 public:
  explicit MissionReader(const Participant& participant);
  dds_entity_t condition() const { return condition_.get(); }
  // A mission of this wire version (and of run `want_nonce`, when given), if one arrived; the newest if
  // several. Others are refused through `refusals` (said once a second per writer). Throws InputError
  // ("<mission>: what") if an acceptable one is malformed.
  std::optional<MissionAnnouncement> take(std::optional<std::uint64_t> want_nonce, RefusalLog& refusals);

 private:
  Entity reader_;
  Entity condition_;
};

}  // namespace swarmform::dds
