// What the Foxglove channel /scene sends (viewer/foxglove.hpp), read back from the bytes a client gets: the
// floor and its regions, the light sources, and each robot's lit LEDs.
#include "viewer/foxglove.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

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
  const auto scene_at = [&](std::uint64_t tick) {
    dds::ObserveFrameData frame;
    frame.tick = tick;
    const auto out = fox.messages(frame);
    EXPECT_EQ(out.size(), 1U);
    return json::parse(out[0].second.substr(13));
  };
  const auto has = [](const json& scene, const std::string& id) {
    for (const json& e : scene["entities"]) {
      if (e["id"] == id) return true;
    }
    return false;
  };
  const json first = scene_at(0);
  EXPECT_EQ(entity(first, "obstacles")["cubes"].size(), 1U);
  EXPECT_EQ(entity(first, "obstacles")["cylinders"].size(), 0U);
  EXPECT_FALSE(has(scene_at(4), "obstacles")) << "nothing changed: not sent again";
  const json gone = scene_at(5);
  EXPECT_FALSE(has(gone, "arena"));
  EXPECT_EQ(entity(gone, "obstacles")["cubes"].size(), 0U);
  EXPECT_EQ(entity(scene_at(8), "obstacles")["cylinders"].size(), 1U);
  const json moved = entity(scene_at(9), "obstacles");
  ASSERT_EQ(moved["cylinders"].size(), 1U);
  EXPECT_DOUBLE_EQ(moved["cylinders"][0]["pose"]["position"]["x"].get<double>(), -1.5);
  EXPECT_DOUBLE_EQ(moved["cylinders"][0]["pose"]["position"]["y"].get<double>(), 0.5);
  // A replay sought back before the events: the obstacles as they stood then.
  EXPECT_EQ(entity(scene_at(2), "obstacles")["cubes"].size(), 1U);
}

}  // namespace
}  // namespace swarmform::viewer
