// The QoS of every swarmform endpoint, in one function, so the world, the agents, the bench pair and the test
// programs cannot disagree (a mismatch silently unmatches a reader from a writer).
#pragma once

#include "common/dds/entity.hpp"

namespace swarmform::dds {

enum class Channel {
  Mission,     // world -> agents: reliable, transient-local, keep-last 1 (agents started late still get it)
  Sensor,      // world -> agent: reliable, volatile, keep-last 1 per instance (only the newest perception
               // matters; claim answers are another instance, re-sent when the agent re-sends its claim)
  Command,     // agents -> world: reliable, volatile, keep-all (a flood of spoofed samples for an id can
               // never push the owner's command out of the world's reader before it is taken)
  WorldState,  // world -> viewers: best effort, keep-last 1
};

// Liveliness on every endpoint: AUTOMATIC, this lease (NOTES-DEPENDENCIES "Death detection").
inline constexpr dds_duration_t kLivelinessLease = DDS_MSECS(500);

// The QoS for readers and writers of `channel` (the same object serves both sides).
Qos make_qos(Channel channel);

}  // namespace swarmform::dds
