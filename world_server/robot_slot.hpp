// What the DDS world server keeps of one robot between and within rounds (Server holds one a robot, by id).
#pragma once

#include <cstdint>

#include "common/types.hpp"
#include "world_server/dds_bridge.hpp"

namespace swarmform::server {

struct RobotSlot {
  // Its owner (the agent that claimed the id): the owner's claim nonce, and the generation raised at each
  // revival; both go on its perceptions (docs/wire.md "Identity and the claim protocol").
  std::uint64_t owner_nonce = 0;
  std::uint32_t generation = 1;
  // A packet went to the current owner since its claim: only then is the owner's liveliness judged (pump).
  // Before, a lapse is not a loss: the agent is quiet until its first packet (docs/wire.md).
  bool judged = false;

  // The newest command taken, reused every tick (its message buffer keeps its capacity).
  Command latest;
  Tick latest_tick = 0;                      // its tick
  dds::PublicationHandle latest_writer = 0;  // its writer (the owner's)
  bool fresh = false;                        // taken since the last apply

  // This round: its command is still awaited (lockstep), and when its packet went out (realtime, for
  // late_commands).
  bool waiting = false;
  dds_time_t written_at = 0;
};

}  // namespace swarmform::server
