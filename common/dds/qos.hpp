// The QoS of every swarmform endpoint, in one function, so the world, the agents, the bench pair and the test
// programs cannot disagree (a mismatch silently unmatches a reader from a writer).
#pragma once

#include "common/dds/entity.hpp"

namespace swarmform::dds {

// Sensor is reliable in lockstep (a lost sample would stall the round until its deadline and change the run)
// and best effort in realtime (a lost sample is a missed tick, and reliability costs every process a
// heartbeat, an acknowledgement and two more thread wake-ups a tick: see README.md). Command is reliable in
// both: a best-effort command topic let any process on the host send the world commands faster than its
// receive thread takes datagrams; the world's socket buffer filled and the kernel dropped the honest agents'
// commands and liveliness with the flood's (docs/faults.md "A 20 s flood, measured"). Reliable, a writer
// has at most its unacknowledged window in flight, and a best-effort writer does not match at all.
enum class Pace { Lockstep, Realtime };

enum class Channel {
  Mission,     // world -> agents: reliable, transient-local, keep-last 1 (agents started late still get it)
  Sensor,      // world -> agent: reliable, volatile, keep-last 1 per instance (only the newest perception
               // matters; claim answers are another instance, re-sent when the agent re-sends its claim)
  Command,     // agents -> world: reliable in both paces, volatile, keep-all (a flood of spoofed samples
               // for an id can never push the owner's command out of the world's reader before it is taken)
  WorldState,  // world -> viewers: best effort, keep-last 1
  Observe,     // world -> its viewer: reliable, keep-last 1 (the newest frame is what matters)
  Control,     // viewer -> world: reliable, keep-last 256
};

// Liveliness of the agents' command writers (and the world's command reader): MANUAL_BY_TOPIC, this lease,
// so the world sees a SIGKILLed agent within ~0.5 s (docs/wire.md "Liveliness, stalls and deaths"). Every
// command written renews it at the world; an agent with nothing to write asserts it every
// kLivelinessAssertPeriod (CommandWriter::keep_alive). AUTOMATIC cost a reliable participant message with its
// heartbeat and acknowledgement every 0.4 s per agent, whatever the agent wrote: at 256 agents ~1,960
// submessages a second in the ~4,700 datagrams a second at the world's discovery socket while they connect,
// and ~850 of its 1,166 datagrams a second during the run (BENCHMARKS.md).
inline constexpr dds_duration_t kLivelinessLease = DDS_MSECS(500);
// Three assertions per lease: a lost one (they are best effort) does not cost the agent its liveliness.
inline constexpr dds_duration_t kLivelinessAssertPeriod = kLivelinessLease / 3;
// Liveliness of the world's writers (mission, packets, world state): an agent notices a dead world within
// this. Longer than the agents' lease because the world asserts its liveliness to every agent (see qos.cpp).
inline constexpr dds_duration_t kWorldLivelinessLease = DDS_SECS(2);

// The QoS for readers and writers of `channel` (the same object serves both sides).
Qos make_qos(Channel channel, Pace pace = Pace::Lockstep);

}  // namespace swarmform::dds
