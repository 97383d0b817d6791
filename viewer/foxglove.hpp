// The Foxglove WebSocket protocol (`foxglove.websocket.v1`, github.com/foxglove/ws-protocol docs/spec.md) on
// the viewer's socket, so Foxglove connects to ws://HOST:PORT with no plug-in. JSON encoding; three channels:
//   /scene             foxglove.SceneUpdate   the arena (walls, obstacles, goal, the floor and its regions,
//                                            the light sources as spheres) and the robots as cylinders in
//                                            their state's colour with their id as text and their lit LEDs
//                                            as small spheres on top
//   /robots/poses      foxglove.PosesInFrame  every robot's pose (frame "arena", z = 0)
//   /robots/telemetry  swarmform.RobotTelemetry  per robot: state (and its name), label, parent, leader, net
//                                            force, last wheel speeds
// The schemas are JSON Schema written here for the fields we send (schemaEncoding "jsonschema"). Message
// timestamps are the run's simulated time (tick / tick_rate).
#pragma once

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/dds/observe_wire.hpp"

namespace swarmform::viewer {

// world.json's world_events at or before `tick` (they are listed by tick), and its obstacles as they stand
// then, the present ones only (world_server/world/world_events.hpp; viewer.js obstaclesAt draws the same).
std::size_t events_up_to(const nlohmann::json& world, std::uint64_t tick);
nlohmann::json obstacles_at(const nlohmann::json& world, std::uint64_t tick);

class Foxglove {
 public:
  // `world`: world.json of the run (arena, obstacles, goal, tick_rate); may be null until it is read.
  void set_world(const nlohmann::json& world) { world_ = world; }
  bool has_world() const { return world_.is_object(); }
  // A replay's frames come from robots.csv, which holds no readings, neighbours heard or commands: the
  // telemetry leaves those fields out instead of sending zeros.
  void set_recorded(bool recorded) { recorded_ = recorded; }

  // The server's first messages to a new client: serverInfo, advertise.
  std::vector<std::string> hello() const;
  // A client's text message (subscribe / unsubscribe); returns a status message to send back, or "".
  std::string on_text(std::uint64_t client, const std::string& text);
  void forget(std::uint64_t client) { subscriptions_.erase(client); }

  // The binary Message Data messages of `frame` for every subscription (of `only` when it is not 0): (client,
  // bytes).
  std::vector<std::pair<std::uint64_t, std::string>> messages(const dds::ObserveFrameData& frame,
                                                              std::uint64_t only = 0);

  static constexpr std::uint32_t kScene = 1;
  static constexpr std::uint32_t kPoses = 2;
  static constexpr std::uint32_t kTelemetry = 3;

 private:
  // `with_arena`: the static entities; `with_obstacles`: the obstacles as they stand at the frame's tick.
  nlohmann::json scene(const dds::ObserveFrameData& frame, bool with_arena, bool with_obstacles) const;
  nlohmann::json poses(const dds::ObserveFrameData& frame) const;
  nlohmann::json telemetry(const dds::ObserveFrameData& frame) const;
  double seconds(std::uint64_t tick) const;

  nlohmann::json world_;
  bool recorded_ = false;
  struct Subscription {
    std::uint32_t channel = 0;
    bool arena_sent = false;         // /scene: the static entities go once per subscription
    std::size_t events_applied = 0;  // the world events the obstacles last sent stood after
  };
  // client -> subscription id -> subscription
  std::map<std::uint64_t, std::map<std::uint32_t, Subscription>> subscriptions_;
};

}  // namespace swarmform::viewer
