// The Foxglove WebSocket protocol (`foxglove.websocket.v1`, github.com/foxglove/ws-protocol docs/spec.md) on
// the viewer's socket, so Foxglove connects to ws://HOST:PORT with no plug-in. JSON encoding; five channels:
//   /scene             foxglove.SceneUpdate   the arena (walls, obstacles, goal, the floor and its regions,
//                                            the light sources as spheres); the robots as cylinders in
//                                            their state's colour with a heading arrow, their id as text and
//                                            their lit LEDs as small spheres on top; the parent links, the
//                                            ultrasonic rays (live) and the leader's ring as lines; in a
//                                            mixed swarm (world.json `groups`) each robot in its own
//                                            group's state colours, edged in its group's colour
//   /robots/poses      foxglove.PosesInFrame  every robot's pose (frame "arena", z = 0)
//   /tf                foxglove.FrameTransforms  arena -> robot_<id> for each robot
//   /robots/telemetry  swarmform.RobotTelemetry  per robot: state (and its name, by its group's behaviour),
//                                            its group (mixed swarms), label, parent, leader, net force,
//                                            last wheel speeds
//   /metrics           swarmform.Metrics      per tick numbers for the Plot panel: alive, shape error, net
//                                            force (mean, max, each robot's)
// The schemas are JSON Schema written here for the fields we send (schemaEncoding "jsonschema"). Every
// message carries its tick (a `tick` field, or the entities' metadata). Log time: the wall time given by the
// caller (live: when the frame arrived), else the run's start (set_start_ns) plus tick / tick_rate.
// Capability `clientPublish`: a client advertises a channel on topic /control (encoding json) and publishes
// the page's commands ({"cmd": "pause"} ...), which the caller routes as a page's (control_command).
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
// world.json's goal as it stands at `tick` ({x, y, radius}, moved by its goal_moves; viewer.js goalAt), or
// null when the run has none.
nlohmann::json goal_at(const nlohmann::json& world, std::uint64_t tick);

class Foxglove {
 public:
  // `world`: world.json of the run (arena, obstacles, goal, tick_rate); may be null until it is read.
  void set_world(const nlohmann::json& world);
  bool has_world() const { return world_.is_object(); }
  // A replay's frames come from robots.csv, which holds no readings, neighbours heard or commands: the
  // telemetry leaves those fields out instead of sending zeros.
  void set_recorded(bool recorded) { recorded_ = recorded; }

  // The server's first messages to a new client: serverInfo, advertise.
  std::vector<std::string> hello() const;
  // The wall time (ns since 1970) the run started: a replay's log times are this plus tick / tick_rate.
  void set_start_ns(std::uint64_t ns) { start_ns_ = ns; }
  // A client's text message (subscribe / unsubscribe / advertise / unadvertise); returns a status message to
  // send back, or "".
  std::string on_text(std::uint64_t client, const std::string& text);
  // A client's binary message. A Client Message Data on its /control channel: `command` is its payload (the
  // page's protocol); anything else: `status` says what is wrong.
  struct ClientMessage {
    std::string command;
    std::string status;
  };
  ClientMessage on_binary(std::uint64_t client, const std::string& bytes) const;
  void forget(std::uint64_t client) {
    subscriptions_.erase(client);
    control_channels_.erase(client);
  }
  // A status message (level 0 info, 1 warning, 2 error) as the protocol's JSON text.
  static std::string status(int level, const std::string& message);
  // Log time of `tick` in ns: the run's start plus tick / tick_rate.
  std::uint64_t log_ns(std::uint64_t tick) const;

  // The binary Message Data messages of `frame` for every subscription (of `only` when it is not 0): (client,
  // bytes). `stamp_ns`: the log time (0: log_ns(frame.tick)).
  std::vector<std::pair<std::uint64_t, std::string>> messages(const dds::ObserveFrameData& frame,
                                                              std::uint64_t only = 0,
                                                              std::uint64_t stamp_ns = 0);

  static constexpr std::uint32_t kScene = 1;
  static constexpr std::uint32_t kPoses = 2;
  static constexpr std::uint32_t kTelemetry = 3;
  static constexpr std::uint32_t kTransforms = 4;
  static constexpr std::uint32_t kMetrics = 5;
  static constexpr std::uint32_t kChannels = 5;

 private:
  // `with_arena`: the static entities; `with_obstacles`: the obstacles as they stand at the frame's tick.
  nlohmann::json scene(const dds::ObserveFrameData& frame, const nlohmann::json& stamp, bool with_arena,
                       bool with_obstacles) const;
  nlohmann::json poses(const dds::ObserveFrameData& frame, const nlohmann::json& stamp) const;
  nlohmann::json telemetry(const dds::ObserveFrameData& frame, const nlohmann::json& stamp) const;
  nlohmann::json transforms(const dds::ObserveFrameData& frame, const nlohmann::json& stamp) const;
  nlohmann::json metrics(const dds::ObserveFrameData& frame, const nlohmann::json& stamp) const;
  double seconds(std::uint64_t tick) const;

  nlohmann::json world_;

 public:
  // A mixed swarm's robot groups as world.json gives them, read once by set_world: each robot's state names
  // and colours come from its own group's behaviour, and it is edged in its group's colour.
  struct StateLook {
    std::string name, colour;
  };
  struct RobotGroup {
    std::string name, edge;
    std::int64_t first = 0, count = 0;
    std::map<std::int32_t, StateLook> states;
  };

 private:
  std::vector<RobotGroup> groups_;
  bool recorded_ = false;
  std::uint64_t start_ns_ = 0;
  // client -> its advertised /control channel ids
  std::map<std::uint64_t, std::map<std::uint32_t, std::string>> control_channels_;
  struct Subscription {
    std::uint32_t channel = 0;
    bool arena_sent = false;         // /scene: the static entities go once per subscription
    std::size_t events_applied = 0;  // the world events the obstacles last sent stood after
  };
  // client -> subscription id -> subscription
  std::map<std::uint64_t, std::map<std::uint32_t, Subscription>> subscriptions_;
};

}  // namespace swarmform::viewer
