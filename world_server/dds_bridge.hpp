// The world's side of the DDS wire: its endpoints in one bundle, and the conversions from the world's own
// types (Scenario, World) to what goes on the wire. The IDL itself stays inside common/dds/.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "behaviour/known_columns.hpp"
#include "common/dds/command_reader.hpp"
#include "common/dds/identity.hpp"
#include "common/dds/mission_endpoints.hpp"
#include "common/dds/participant.hpp"
#include "common/dds/robot_channels.hpp"
#include "common/dds/signal_watch.hpp"
#include "common/dds/waiter.hpp"
#include "common/dds/world_state_endpoints.hpp"
#include "world_server/world/scenario.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::server {

// The world's faces (docs/wire.md "Faces"): one participant per block of dds::kRobotsPerFace robots, each in
// a Cyclone domain instance of its own, so an agent discovers only its own face's per-robot writers. Face 0
// also carries the world state and the viewer's endpoints.
struct WorldFaces {
  WorldFaces(const dds::DdsSettings& settings, std::size_t robots);
  std::vector<std::unique_ptr<dds::Participant>> faces;
  std::vector<const dds::Participant*> list() const;
};

// The mission on every face (each face's agents read it from their own face).
class FaceMissions {
 public:
  explicit FaceMissions(const WorldFaces& faces);
  void publish(const dds::MissionAnnouncement& announcement);

 private:
  std::vector<std::unique_ptr<dds::MissionWriter>> writers_;
};

// Every face's command reader, read as one (the world's pump).
class FaceCommands {
 public:
  // samples_per_window: each writer's budget on the receive thread (dds::ReceiveBudget).
  FaceCommands(const WorldFaces& faces, dds::Waiter& waiter, bool realtime, std::uint32_t accept_ids,
               std::uint32_t samples_per_window);
  // As dds::CommandReader::take, over every face (each sample's `face` says whose reader took it). A call
  // that empties every reader tells the waiter (Waiter::drained); one that stops at `max_samples` wakes it,
  // so that the next wait does not sleep on what is left.
  std::size_t take(std::vector<dds::CommandSample>& buf, std::size_t max_samples = dds::kMaxCommandTake);
  void take_liveliness_changes(std::vector<dds::CommandReader::LivelinessChange>& out);
  std::uint64_t filtered() const;
  // As dds::CommandReader's, over every face.
  void set_window(std::uint64_t window);
  void take_budget_drops(std::vector<dds::ReceiveBudget::Drops>& out);
  std::uint64_t over_budget() const;
  // The authenticated robot of `writer`, asked of the reader of `face` (the one that took its sample).
  std::optional<RobotId> authenticated_robot(std::uint32_t face, dds::PublicationHandle writer);
  // Whether `writer` is still matched by the reader of `face` (dds::CommandReader::matched).
  bool matched(std::uint32_t face, dds::PublicationHandle writer) const;
  // `writer`'s GUID and its participant's, asked of the reader of `face` (dds::CommandReader::remote).
  std::optional<dds::RemoteWriter> remote(std::uint32_t face, dds::PublicationHandle writer) const;

 private:
  dds::Waiter& waiter_;  // counts the readers' samples (dds::Waiter, "Counted arrivals")
  std::vector<std::unique_ptr<dds::CommandReader>> readers_;
};

// Declared in the order they must be built (participants first) and torn down (in reverse).
struct WorldLink {
  // realtime: the per-tick topics are best effort (common/dds/qos.hpp Pace), as the mission tells the agents.
  // run_nonce: stamped on every sample the world writes (docs/wire.md "Run nonce").
  // samples_per_window: each command writer's budget on the receive thread (dds::ReceiveBudget).
  WorldLink(const dds::DdsSettings& settings, std::size_t robots, bool realtime, std::uint64_t run_nonce,
            std::uint32_t samples_per_window);

  WorldFaces faces;
  dds::Participant& participant;  // face 0: the world state, the viewer
  dds::Waiter waiter;
  FaceMissions mission;
  dds::RobotChannels robots;
  FaceCommands commands;
  dds::WorldStateWriter state;
};

// What the agents are told: the scenario's mission, the robot count and this run's nonce.
dds::MissionAnnouncement mission_of(const world::Scenario& scenario, std::uint64_t run_nonce);

// One row per robot for observers (rows reused: no allocation once sized); its label from `known` (by id,
// world::known_columns_by_robot), -1 where its behaviour reports none.
void pose_rows(const world::World& world, const std::vector<behaviour::KnownColumns>& known,
               std::vector<dds::RobotPoseRow>& rows);

}  // namespace swarmform::server
