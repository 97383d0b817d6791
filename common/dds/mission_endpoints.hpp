// The mission on sf_mission: the world publishes it once, durably (an agent started late still gets it),
// and an agent takes it, checked (common/mission_check.hpp), before it makes anything else.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "common/dds/entity.hpp"
#include "common/dds/identity.hpp"
#include "common/dds/participant.hpp"
#include "common/mission.hpp"

namespace swarmform::dds {

// A robot group of the run (docs/scenario-format.md "Groups"): robots first_id..first_id+count-1 are told
// `mission` (the run's mission with the group's behaviour and parameters).
struct MissionGroup {
  RobotId first_id = 0;
  std::uint32_t count = 0;
  Mission mission;
};

struct MissionAnnouncement {
  Mission mission;                   // with groups: the first group's until own_group() picks the robot's
  std::vector<MissionGroup> groups;  // empty: every robot is told `mission`
  std::uint32_t robots = 0;          // robots in the run (ids 0..robots-1)
  std::uint64_t run_nonce = 0;       // random per run (the launcher's --run-nonce, or the world's own draw)
  bool realtime = false;   // the pace of sf_sensor / sf_command (qos.hpp): an agent creates them after this
  ParticipantKey world{};  // reader side: the participant of the writer it came from
};

// `a.mission` becomes robot `id`'s own group's (no change without groups, or for an id beyond the run's
// robots).
void take_own_group(MissionAnnouncement& a, RobotId id);

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
