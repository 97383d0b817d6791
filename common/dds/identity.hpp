// How the wire names who is who (docs/wire.md "Writer binding"): a remote writer by its publication handle,
// a participant by its GUID, the world an agent is bound to, and robot K's partition.
// Identity is the writer: an agent claims an id with a CLAIM sample on the command topic, and the world binds
// the id to that sample's publication handle; later commands from any other writer are not the owner's.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "common/types.hpp"

namespace swarmform::dds {

using PublicationHandle = std::uint64_t;  // dds_instance_handle_t of a remote writer, as a reader sees it

// A participant's GUID (its key in DDS discovery), as 16 bytes.
using ParticipantKey = std::array<std::uint8_t, 16>;
std::string to_string(const ParticipantKey& key);  // hex

// The world an agent listens to: the participant that wrote the mission it took, and that mission's run.
struct WorldBinding {
  ParticipantKey participant{};
  std::uint64_t run_nonce = 0;
};

// "robot/<id>": the partition of robot `id`'s packets (and, under DDS Security, of its commands).
std::string robot_partition(RobotId id);

}  // namespace swarmform::dds
