// The agent's side of sf_sensor: a subscriber in its own partition robot/K, so no process receives another
// robot's packets. Once bound to its world (docs/wire.md "Writer binding") it takes only that world's
// samples of that run and refuses the others, counted.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "common/dds/identity.hpp"
#include "common/dds/participant.hpp"
#include "common/dds/sensor_packet.hpp"
#include "common/dds/waiter.hpp"
#include "common/types.hpp"

namespace swarmform::dds {

// Agent side: a subscriber in partition robot/K with a SensorPacket reader (perceptions and claim answers).
// The liveliness of the world's packet writer is followed by a listener (world_alive), which wakes `waiter`.
class AgentInbox {
 public:
  AgentInbox(const Participant& participant, RobotId self, Waiter& waiter, bool realtime = false);
  ~AgentInbox();
  AgentInbox(const AgentInbox&) = delete;
  AgentInbox& operator=(const AgentInbox&) = delete;

  dds_entity_t packet_condition() const;
  // From now on only samples of `world`'s participant and run are taken; the others are refused (counted,
  // said once a second per writer on stderr as "<who>: refused ..."). Before, only the wire version is
  // checked.
  void bind(const WorldBinding& world, const std::string& who);
  std::uint64_t refused() const;
  // Takes every packet available: `own` receives the newest of robot `self` (true if there was one);
  // `foreign` is increased by the number of packets for any other robot (never expected).
  bool take_packet(SensorSample& own, std::uint64_t& foreign);
  std::optional<ClaimAnswer> take_claim_reply();
  // Writers of this robot's packets alive now, and whether one was ever seen (the world came and went).
  std::uint32_t world_writers_alive() const;
  bool world_seen() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace swarmform::dds
