// The world's side of the DDS wire: its endpoints in one bundle, and the conversions from the world's own
// types (Scenario, World) to what goes on the wire. The IDL itself stays behind common/dds/wire.hpp.
#pragma once

#include <cstdint>
#include <vector>

#include "common/dds/signal_watch.hpp"
#include "common/dds/wire.hpp"
#include "world_server/world/scenario.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::server {

// Declared in the order they must be built (participant first) and torn down (in reverse).
struct WorldLink {
  // realtime: the per-tick topics are best effort (common/dds/qos.hpp Pace), as the mission tells the agents.
  // run_nonce: stamped on every sample the world writes (docs/wire.md "Run nonce").
  WorldLink(const dds::DdsSettings& settings, std::size_t robots, bool realtime, std::uint64_t run_nonce);

  dds::Participant participant;
  dds::Waiter waiter;
  dds::MissionWriter mission;
  dds::RobotChannels robots;
  dds::CommandReader commands;
  dds::WorldStateWriter state;
};

// What the agents are told: the scenario's mission, the robot count and this run's nonce.
dds::MissionAnnouncement mission_of(const world::Scenario& scenario, std::uint64_t run_nonce);

// One row per robot for observers (rows reused: no allocation once sized).
void pose_rows(const world::World& world, std::vector<dds::RobotPoseRow>& rows);

}  // namespace swarmform::server
