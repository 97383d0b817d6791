// What the Foxglove channels send (viewer/foxglove.hpp), read back from the bytes a client gets: the floor
// and its regions, the light sources, each robot's lit LEDs, heading, parent link, rays and the leader's
// ring; the frame transforms, the metrics, log times and ticks; the clientPublish capability and its /control
// channel.
#include "viewer/foxglove.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>

namespace swarmform::viewer {
namespace {

using nlohmann::json;

const json kWorld = json::parse(R"({
  "arena": {"centre": [0, 0], "width": 4, "height": 2, "walls": false},
  "obstacles": [],
  "robot_radius": 0.0704,
  "floor": {"grey": 0.5, "colour": null, "image": null, "regions": [
    {"kind": "circle", "centre": [1, 0.5], "radius": 0.3, "grey": 0.0, "colour": null},
    {"kind": "rectangle", "centre": [-1, 0], "half_extents": [0.5, 0.25], "yaw": 0.3, "grey": 0.3,
     "colour": "#ff0000"}]},
  "lights": [{"position": [1.5, -0.5], "height": 0.7, "intensity": 2.0}]
})");

// The SceneUpdate a new subscriber to /scene gets for `frame`: the Message Data's JSON after its 13 bytes.
json first_scene(const dds::ObserveFrameData& frame) {
  Foxglove fox;
  fox.set_world(kWorld);
  EXPECT_EQ(fox.on_text(7, R"({"op":"subscribe","subscriptions":[{"id":1,"channelId":1}]})"), "");
  const auto out = fox.messages(frame);
  EXPECT_EQ(out.size(), 1U);
  EXPECT_EQ(out[0].second[0], '\x01');
  return json::parse(out[0].second.substr(13));
}

const json& entity(const json& scene, const std::string& id) {
  for (const json& e : scene["entities"]) {
    if (e["id"] == id) return e;
  }
  throw std::runtime_error("no entity " + id);
}

TEST(Foxglove, SceneCarriesTheFloorItsRegionsAndTheLights) {
  dds::ObserveFrameData frame;
  const json scene = first_scene(frame);
  const json& arena = entity(scene, "arena");
  // The floor's base (grey 0.5) over the arena, then the rectangle in its colour; the circle in black.
  const json& base = arena["cubes"][0];
  EXPECT_DOUBLE_EQ(base["size"]["x"].get<double>(), 4.0);
  EXPECT_DOUBLE_EQ(base["size"]["y"].get<double>(), 2.0);
  EXPECT_NEAR(base["color"]["r"].get<double>(), 128.0 / 255.0, 1e-12);
  const json& rect = arena["cubes"][1];
  EXPECT_DOUBLE_EQ(rect["pose"]["position"]["x"].get<double>(), -1.0);
  EXPECT_DOUBLE_EQ(rect["size"]["x"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(rect["color"]["r"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(rect["color"]["g"].get<double>(), 0.0);
  const json& disc = arena["cylinders"][0];
  EXPECT_DOUBLE_EQ(disc["pose"]["position"]["x"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(disc["size"]["x"].get<double>(), 0.6);
  EXPECT_DOUBLE_EQ(disc["color"]["r"].get<double>(), 0.0);
  // The region listed later lies above the one before it.
  EXPECT_GT(rect["pose"]["position"]["z"].get<double>(), disc["pose"]["position"]["z"].get<double>());
  // A plain white floor has no base: the regions alone.
  Foxglove white;
  json world = kWorld;
  world["floor"]["grey"] = 1.0;
  white.set_world(world);
  EXPECT_EQ(white.on_text(7, R"({"op":"subscribe","subscriptions":[{"id":1,"channelId":1}]})"), "");
  const json plain = json::parse(white.messages(dds::ObserveFrameData{})[0].second.substr(13));
  EXPECT_EQ(entity(plain, "arena")["cubes"].size(), 1U);
  ASSERT_EQ(arena["spheres"].size(), 1U);
  const json& light = arena["spheres"][0]["pose"]["position"];
  EXPECT_DOUBLE_EQ(light["x"].get<double>(), 1.5);
  EXPECT_DOUBLE_EQ(light["y"].get<double>(), -0.5);
  EXPECT_DOUBLE_EQ(light["z"].get<double>(), 0.7);
}

TEST(Foxglove, SceneCarriesEachRobotsLitLedsInTheirColours) {
  dds::ObserveFrameData frame;
  frame.robots.resize(2);
  frame.robots[0].id = 0;
  frame.robots[0].pose = Pose2D{1.0, 0.0, 0.0};
  frame.robots[0].leds[0] = Rgb{255, 0, 0};  // LED 0, ahead
  frame.robots[0].leds[2] = Rgb{0, 0, 51};
  frame.robots[1].id = 1;  // every LED off: none drawn
  const json scene = first_scene(frame);
  const json& robots = entity(scene, "robots");
  ASSERT_EQ(robots["spheres"].size(), 2U);
  const json& ahead = robots["spheres"][0];
  EXPECT_NEAR(ahead["pose"]["position"]["x"].get<double>(), 1.0 + 0.55 * 0.0704, 1e-12);
  EXPECT_NEAR(ahead["pose"]["position"]["y"].get<double>(), 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(ahead["color"]["r"].get<double>(), 1.0);
  const json& right = robots["spheres"][1];
  EXPECT_LT(right["pose"]["position"]["y"].get<double>(), 0.0);  // LED 2 at -120 degrees
  EXPECT_DOUBLE_EQ(right["color"]["b"].get<double>(), 0.2);
}

// The SceneUpdate a subscriber to /scene gets for an empty frame of `tick`.
json scene_at(Foxglove& fox, std::uint64_t tick) {
  dds::ObserveFrameData frame;
  frame.tick = tick;
  const auto out = fox.messages(frame);
  EXPECT_EQ(out.size(), 1U);
  return json::parse(out.at(0).second.substr(13));
}

TEST(Foxglove, ObstaclesAreSentAgainAsTheWorldEventsChangeThem) {
  // A box there from the start that disappears at tick 5, a post absent until tick 8 and moved at tick 9.
  json world = kWorld;
  world["obstacles"] = json::parse(R"([
    {"kind": "box", "centre": [1, 0], "half_extents": [0.2, 0.1], "yaw": 0.0},
    {"kind": "cylinder", "centre": [-1, 0], "radius": 0.1, "present": false}])");
  world["world_events"] = json::parse(R"([
    {"tick": 5, "obstacle": 0, "do": "disappear"},
    {"tick": 8, "obstacle": 1, "do": "appear"},
    {"tick": 9, "obstacle": 1, "do": "move", "centre": [-1.5, 0.5], "yaw": null}])");
  Foxglove fox;
  fox.set_world(world);
  ASSERT_EQ(fox.on_text(7, R"({"op":"subscribe","subscriptions":[{"id":1,"channelId":1}]})"), "");
  const auto has = [](const json& scene, const std::string& id) {
    for (const json& e : scene["entities"]) {
      if (e["id"] == id) return true;
    }
    return false;
  };
  const json first = scene_at(fox, 0);
  EXPECT_EQ(entity(first, "obstacles")["cubes"].size(), 1U);
  EXPECT_EQ(entity(first, "obstacles")["cylinders"].size(), 0U);
  EXPECT_FALSE(has(scene_at(fox, 4), "obstacles")) << "nothing changed: not sent again";
  const json gone = scene_at(fox, 5);
  EXPECT_FALSE(has(gone, "arena"));
  EXPECT_EQ(entity(gone, "obstacles")["cubes"].size(), 0U);
  EXPECT_EQ(entity(scene_at(fox, 8), "obstacles")["cylinders"].size(), 1U);
  const json moved = entity(scene_at(fox, 9), "obstacles");
  ASSERT_EQ(moved["cylinders"].size(), 1U);
  EXPECT_DOUBLE_EQ(moved["cylinders"][0]["pose"]["position"]["x"].get<double>(), -1.5);
  EXPECT_DOUBLE_EQ(moved["cylinders"][0]["pose"]["position"]["y"].get<double>(), 0.5);
  // A replay sought back before the events: the obstacles as they stood then.
  EXPECT_EQ(entity(scene_at(fox, 2), "obstacles")["cubes"].size(), 1U);
}

TEST(Foxglove, TheGoalIsDrawnWhereItStandsAndSentAgainWhenItMoves) {
  json world = kWorld;
  world["goal"] = json::parse(R"({"x": 1.0, "y": 0.0, "radius": 0.5})");
  world["goal_moves"] = json::parse(R"([{"tick": 6, "x": -1.0, "y": 0.5, "radius": 0.25}])");
  Foxglove fox;
  fox.set_world(world);
  ASSERT_EQ(fox.on_text(7, R"({"op":"subscribe","subscriptions":[{"id":1,"channelId":1}]})"), "");
  const auto goal_disc = [](const json& scene) {
    const json& c = entity(scene, "obstacles")["cylinders"];
    EXPECT_EQ(c.size(), 1U);  // the goal only: this world has no obstacle
    return c.at(0);
  };
  const json first = goal_disc(scene_at(fox, 0));
  EXPECT_DOUBLE_EQ(first["pose"]["position"]["x"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(first["size"]["x"].get<double>(), 1.0);
  for (const json& e : scene_at(fox, 5)["entities"])
    EXPECT_NE(e["id"], "obstacles") << "nothing moved: not sent";
  const json moved = goal_disc(scene_at(fox, 6));
  EXPECT_DOUBLE_EQ(moved["pose"]["position"]["x"].get<double>(), -1.0);
  EXPECT_DOUBLE_EQ(moved["pose"]["position"]["y"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(moved["size"]["x"].get<double>(), 0.5);
  EXPECT_EQ(goal_at(world, 3)["x"], 1.0);  // a replay sought back: where it stood then
  EXPECT_TRUE(goal_at(kWorld, 3).is_null());
}

// Every channel's Message Data for `frame` to a client subscribed to all five (subscription id = channel id):
// channel -> (log time, payload).
std::map<std::uint32_t, std::pair<std::uint64_t, json>> all_channels(Foxglove& fox,
                                                                     const dds::ObserveFrameData& f,
                                                                     std::uint64_t stamp = 0) {
  std::map<std::uint32_t, std::pair<std::uint64_t, json>> out;
  for (const auto& [client, bytes] : fox.messages(f, 0, stamp)) {
    std::uint32_t sub = 0;
    std::uint64_t ns = 0;
    for (int i = 0; i < 4; ++i)
      sub |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[1 + i])) << (8 * i);
    for (int i = 0; i < 8; ++i)
      ns |= static_cast<std::uint64_t>(static_cast<unsigned char>(bytes[5 + i])) << (8 * i);
    out[sub] = {ns, json::parse(bytes.substr(13))};
  }
  return out;
}

void subscribe_all(Foxglove& fox) {
  ASSERT_EQ(
      fox.on_text(7, R"({"op":"subscribe","subscriptions":[{"id":1,"channelId":1},{"id":2,"channelId":2},
      {"id":3,"channelId":3},{"id":4,"channelId":4},{"id":5,"channelId":5}]})"),
      "");
}

dds::ObserveFrameData three_robots() {
  // Robot 0 leads, facing +y; robot 1's parent is 0; robot 2 is dead (its parent 0 is not drawn).
  dds::ObserveFrameData f;
  f.tick = 25;
  f.robots.resize(3);
  for (std::uint32_t i = 0; i < 3; ++i) {
    f.robots[i].id = i;
    f.robots[i].pose = Pose2D{static_cast<double>(i), 1.0, 0.0};
    f.robots[i].net_force = 0.5 * i;
    f.robots[i].ultrasonic.fill(0.4);
  }
  f.robots[0].pose.theta = std::numbers::pi / 2;
  f.robots[0].leader = true;
  f.robots[1].parent = 0;
  f.robots[2].parent = 0;
  f.robots[2].alive = false;
  f.shape_error = 0.07;
  return f;
}

TEST(Foxglove, AdvertisesClientPublishAndTakesCommandsOnControlOnly) {
  Foxglove fox;
  fox.set_world(kWorld);
  const auto hello = fox.hello();
  const json info = json::parse(hello[0]);
  EXPECT_EQ(info["capabilities"], json({"clientPublish"}));
  EXPECT_EQ(info["supportedEncodings"], json({"json"}));
  std::map<std::string, std::string> topics;
  const json advertise = json::parse(hello[1]);
  for (const json& c : advertise["channels"])
    topics[c["topic"].get<std::string>()] = c["schemaName"].get<std::string>();
  EXPECT_EQ(topics["/tf"], "foxglove.FrameTransforms");
  EXPECT_EQ(topics["/metrics"], "swarmform.Metrics");
  EXPECT_EQ(topics.size(), 5U);
  // Another topic is refused; /control is taken, and its messages come back as the page's commands.
  EXPECT_NE(fox.on_text(7, R"({"op":"advertise","channels":[{"id":3,"topic":"/other","encoding":"json"}]})"),
            "");
  ASSERT_EQ(fox.on_text(7, R"({"op":"advertise","channels":[{"id":4,"topic":"/control","encoding":"json",
      "schemaName":"swarmform.Control"}]})"),
            "");
  const std::string pause = std::string("\x01\x04\x00\x00\x00", 5) + R"({"cmd":"pause"})";
  const auto got = fox.on_binary(7, pause);
  EXPECT_EQ(got.command, R"({"cmd":"pause"})");
  EXPECT_EQ(got.status, "");
  // Another client, or a channel not advertised: an error status, no command.
  EXPECT_EQ(fox.on_binary(8, pause).command, "");
  EXPECT_NE(fox.on_binary(8, pause).status, "");
  const auto stray = fox.on_binary(7, std::string("\x01\x09\x00\x00\x00{}", 7));
  EXPECT_EQ(stray.command, "");
  EXPECT_NE(json::parse(stray.status)["level"], 0);
  ASSERT_EQ(fox.on_text(7, R"({"op":"unadvertise","channelIds":[4]})"), "");
  EXPECT_EQ(fox.on_binary(7, pause).command, "");
}

TEST(Foxglove, LogTimeIsTheRunsWallTimeAndEveryMessageCarriesItsTick) {
  Foxglove fox;
  json world = kWorld;
  world["tick_rate"] = 10.0;
  fox.set_world(world);
  const std::uint64_t start = 1796630400ULL * 1000000000ULL;  // 2026-12-07 08:00 UTC
  fox.set_start_ns(start);
  subscribe_all(fox);
  const auto got = all_channels(fox, three_robots());
  ASSERT_EQ(got.size(), 5U);
  for (const auto& [channel, message] : got) {
    EXPECT_EQ(message.first, start + 2500000000ULL) << "channel " << channel << ": start + 25 / 10 s";
  }
  EXPECT_EQ(got.at(Foxglove::kPoses).second["tick"], 25);
  EXPECT_EQ(got.at(Foxglove::kTelemetry).second["tick"], 25);
  EXPECT_EQ(got.at(Foxglove::kTransforms).second["tick"], 25);
  EXPECT_EQ(got.at(Foxglove::kMetrics).second["tick"], 25);
  EXPECT_EQ(got.at(Foxglove::kPoses).second["timestamp"], json({{"sec", 1796630402}, {"nsec", 500000000}}));
  for (const json& e : got.at(Foxglove::kScene).second["entities"]) {
    EXPECT_EQ(e["metadata"][0], json({{"key", "tick"}, {"value", "25"}})) << e["id"];
    EXPECT_EQ(e["timestamp"]["sec"], 1796630402);
  }
  // Live: the caller's wall time.
  EXPECT_EQ(all_channels(fox, three_robots(), 42).at(Foxglove::kTransforms).first, 42U);
}

TEST(Foxglove, TransformsAndMetricsForThePlotPanel) {
  Foxglove fox;
  fox.set_world(kWorld);
  subscribe_all(fox);
  const auto got = all_channels(fox, three_robots());
  const json& tf = got.at(Foxglove::kTransforms).second["transforms"];
  ASSERT_EQ(tf.size(), 3U);
  EXPECT_EQ(tf[1]["parent_frame_id"], "arena");
  EXPECT_EQ(tf[1]["child_frame_id"], "robot_1");
  EXPECT_DOUBLE_EQ(tf[1]["translation"]["x"].get<double>(), 1.0);
  EXPECT_NEAR(tf[0]["rotation"]["z"].get<double>(), std::sin(std::numbers::pi / 4), 1e-12);
  const json& m = got.at(Foxglove::kMetrics).second;
  EXPECT_EQ(m["alive"], 2);
  EXPECT_DOUBLE_EQ(m["shape_error"].get<double>(), 0.07);
  EXPECT_DOUBLE_EQ(m["net_force_mean"].get<double>(), 0.25);  // the live ones: 0 and 0.5
  EXPECT_DOUBLE_EQ(m["net_force_max"].get<double>(), 0.5);
  EXPECT_EQ(m["net_force"], json({0.0, 0.5, 1.0}));
  dds::ObserveFrameData before = three_robots();
  before.shape_error = -1;
  EXPECT_FALSE(all_channels(fox, before).at(Foxglove::kMetrics).second.contains("shape_error"))
      << "no shape error yet: left out, not -1";
}

TEST(Foxglove, SceneDrawsHeadingParentLinksRaysAndTheLeader) {
  Foxglove fox;
  fox.set_world(kWorld);
  subscribe_all(fox);
  const json scene = all_channels(fox, three_robots()).at(Foxglove::kScene).second;
  const json& arrows = entity(scene, "robots")["arrows"];
  ASSERT_EQ(arrows.size(), 3U);
  const json& q = arrows[0]["pose"]["orientation"];
  EXPECT_NEAR(2 * std::atan2(q["z"].get<double>(), q["w"].get<double>()), std::numbers::pi / 2, 1e-12);
  // One link: 1 -> 0 (the dead robot's is not drawn).
  const json& links = entity(scene, "parent_links")["lines"][0];
  EXPECT_EQ(links["type"], 2);
  ASSERT_EQ(links["points"].size(), 2U);
  EXPECT_DOUBLE_EQ(links["points"][0]["x"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(links["points"][1]["x"].get<double>(), 0.0);
  // Five rays a live robot, from the rim to the reading: robot 0 faces +y, its middle ray goes up.
  const json& rays = entity(scene, "ultrasonic_rays")["lines"][0]["points"];
  ASSERT_EQ(rays.size(), 2U * 5 * 2);
  EXPECT_NEAR(rays[4]["y"].get<double>(), 1.0 + 0.0704, 1e-9);
  EXPECT_NEAR(rays[5]["y"].get<double>(), 1.0 + 0.0704 + 0.4, 1e-9);
  // The leader's ring around robot 0 only.
  const json& rings = entity(scene, "leader")["lines"];
  ASSERT_EQ(rings.size(), 1U);
  EXPECT_EQ(rings[0]["type"], 1);
  EXPECT_NEAR(rings[0]["points"][0]["x"].get<double>(), 1.6 * 0.0704, 1e-9);
  // A replay has no rays to draw (robots.csv does not hold them).
  Foxglove replay;
  replay.set_world(kWorld);
  replay.set_recorded(true);
  subscribe_all(replay);
  for (const json& e : all_channels(replay, three_robots()).at(Foxglove::kScene).second["entities"])
    EXPECT_NE(e["id"], "ultrasonic_rays");
}

// A mixed swarm (world.json `groups`): each robot in its own group's state colours and names, edged in its
// group's colour (the page's and the pictures' edges); the frame's states are the first group's only.
TEST(Foxglove, AMixedSwarmsRobotsTakeTheirOwnGroupsStatesAndEdges) {
  json world = kWorld;
  world["groups"] = json::parse(R"([
    {"name": "shapers", "first_id": 0, "count": 2,
     "behaviour_descriptor": {"states": [{"value": 0, "name": "idle", "colour": "#ff0000"}]}},
    {"name": "movers", "first_id": 2, "count": 1,
     "behaviour_descriptor": {"states": [{"value": 0, "name": "walking", "colour": "#0000ff"}]}}])");
  dds::ObserveFrameData f = three_robots();
  f.robots[2].alive = true;
  f.states = {{0, "idle", "#ff0000"}};
  // Each group's own telemetry columns name its robots' values.
  f.columns = {"seen"};
  f.groups = {{0, 2, "paper", {}, {"seen"}}, {2, 1, "random_walk", {}, {"speed", "turns"}}};
  f.robots[0].extra = {3.0};
  f.robots[2].extra = {0.25, std::nan("")};
  Foxglove fox;
  fox.set_world(world);
  subscribe_all(fox);
  const auto got = all_channels(fox, f);
  const json& bodies = entity(got.at(Foxglove::kScene).second, "robots")["cylinders"];
  ASSERT_EQ(bodies.size(), 3U);
  EXPECT_DOUBLE_EQ(bodies[0]["color"]["r"].get<double>(), 1.0);  // a shaper, idle: red
  EXPECT_DOUBLE_EQ(bodies[2]["color"]["b"].get<double>(), 1.0);  // the mover, walking: blue
  EXPECT_DOUBLE_EQ(bodies[2]["color"]["r"].get<double>(), 0.0);
  const json& edges = entity(got.at(Foxglove::kScene).second, "group_edges")["lines"];
  ASSERT_EQ(edges.size(), 3U);
  EXPECT_EQ(edges[0]["color"], edges[1]["color"]);
  EXPECT_NE(edges[0]["color"], edges[2]["color"]);
  const json& robots = got.at(Foxglove::kTelemetry).second["robots"];
  EXPECT_EQ(robots[0]["state_name"], "idle");
  EXPECT_EQ(robots[0]["group"], "shapers");
  EXPECT_EQ(robots[2]["state_name"], "walking");
  EXPECT_EQ(robots[2]["group"], "movers");
  EXPECT_EQ(robots[0]["columns"], json({{"seen", 3.0}}));
  EXPECT_EQ(robots[1]["columns"], json::object());           // nothing reported yet
  EXPECT_EQ(robots[2]["columns"], json({{"speed", 0.25}}));  // a value not finite is left out
  // Without groups: the frame's states for every robot, no edges, no group.
  Foxglove plain;
  plain.set_world(kWorld);
  subscribe_all(plain);
  const auto one = all_channels(plain, f);
  EXPECT_DOUBLE_EQ(
      entity(one.at(Foxglove::kScene).second, "robots")["cylinders"][2]["color"]["r"].get<double>(), 1.0);
  for (const json& e : one.at(Foxglove::kScene).second["entities"]) EXPECT_NE(e["id"], "group_edges");
  EXPECT_FALSE(one.at(Foxglove::kTelemetry).second["robots"][2].contains("group"));
}

}  // namespace
}  // namespace swarmform::viewer
