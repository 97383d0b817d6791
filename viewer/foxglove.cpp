#include "viewer/foxglove.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>

namespace swarmform::viewer {

namespace {

using nlohmann::json;

// ---- the schemas (JSON Schema of the fields sent)
// ----------------------------------------------------------

json number() {
  return {{"type", "number"}};
}
json object(json properties) {
  return {{"type", "object"}, {"properties", std::move(properties)}};
}
json array_of(json items) {
  return {{"type", "array"}, {"items", std::move(items)}};
}
json time_schema() {
  return object(
      {{"sec", {{"type", "integer"}, {"minimum", 0}}}, {"nsec", {{"type", "integer"}, {"minimum", 0}}}});
}
json vector3_schema() {
  return object({{"x", number()}, {"y", number()}, {"z", number()}});
}
json pose_schema() {
  return object(
      {{"position", vector3_schema()},
       {"orientation", object({{"x", number()}, {"y", number()}, {"z", number()}, {"w", number()}})}});
}
json color_schema() {
  return object({{"r", number()}, {"g", number()}, {"b", number()}, {"a", number()}});
}

std::string scene_update_schema() {
  const json cube = object({{"pose", pose_schema()}, {"size", vector3_schema()}, {"color", color_schema()}});
  const json cylinder = object({{"pose", pose_schema()},
                                {"size", vector3_schema()},
                                {"bottom_scale", number()},
                                {"top_scale", number()},
                                {"color", color_schema()}});
  const json sphere =
      object({{"pose", pose_schema()}, {"size", vector3_schema()}, {"color", color_schema()}});
  const json arrow = object({{"pose", pose_schema()},
                             {"shaft_length", number()},
                             {"shaft_diameter", number()},
                             {"head_length", number()},
                             {"head_diameter", number()},
                             {"color", color_schema()}});
  // LinePrimitive: type 0 LINE_STRIP, 1 LINE_LOOP, 2 LINE_LIST (foxglove.LineType).
  const json line = object({{"type", {{"type", "integer"}}},
                            {"pose", pose_schema()},
                            {"thickness", number()},
                            {"scale_invariant", {{"type", "boolean"}}},
                            {"points", array_of(vector3_schema())},
                            {"color", color_schema()},
                            {"colors", array_of(color_schema())},
                            {"indices", array_of({{"type", "integer"}})}});
  const json text = object({{"pose", pose_schema()},
                            {"billboard", {{"type", "boolean"}}},
                            {"font_size", number()},
                            {"scale_invariant", {{"type", "boolean"}}},
                            {"color", color_schema()},
                            {"text", {{"type", "string"}}}});
  const json entity = object(
      {{"timestamp", time_schema()},
       {"frame_id", {{"type", "string"}}},
       {"id", {{"type", "string"}}},
       {"lifetime", object({{"sec", {{"type", "integer"}}}, {"nsec", {{"type", "integer"}}}})},
       {"frame_locked", {{"type", "boolean"}}},
       {"metadata", array_of(object({{"key", {{"type", "string"}}}, {"value", {{"type", "string"}}}}))},
       {"arrows", array_of(arrow)},
       {"cubes", array_of(cube)},
       {"cylinders", array_of(cylinder)},
       {"lines", array_of(line)},
       {"spheres", array_of(sphere)},
       {"texts", array_of(text)}});
  json s = object({{"deletions", array_of(object({{"timestamp", time_schema()},
                                                  {"type", {{"type", "integer"}}},
                                                  {"id", {{"type", "string"}}}}))},
                   {"entities", array_of(entity)}});
  s["title"] = "foxglove.SceneUpdate";
  return s.dump();
}

std::string poses_schema() {
  json s = object({{"timestamp", time_schema()},
                   {"frame_id", {{"type", "string"}}},
                   {"poses", array_of(pose_schema())},
                   {"tick", {{"type", "integer"}}}});
  s["title"] = "foxglove.PosesInFrame";
  return s.dump();
}

std::string transforms_schema() {
  const json transform = object({{"timestamp", time_schema()},
                                 {"parent_frame_id", {{"type", "string"}}},
                                 {"child_frame_id", {{"type", "string"}}},
                                 {"translation", vector3_schema()},
                                 {"rotation", pose_schema()["properties"]["orientation"]}});
  json s = object({{"transforms", array_of(transform)}, {"tick", {{"type", "integer"}}}});
  s["title"] = "foxglove.FrameTransforms";
  return s.dump();
}

std::string metrics_schema() {
  json s = object({{"timestamp", time_schema()},
                   {"tick", {{"type", "integer"}}},
                   {"alive", {{"type", "integer"}}},
                   {"formation_tick", {{"type", "integer"}}},
                   {"shape_error", number()},
                   {"net_force_mean", number()},
                   {"net_force_max", number()},
                   {"net_force", array_of(number())}});
  s["title"] = "swarmform.Metrics";
  return s.dump();
}

std::string telemetry_schema() {
  const json robot = object({{"id", {{"type", "integer"}}},
                             {"alive", {{"type", "boolean"}}},
                             {"state", {{"type", "integer"}}},
                             {"state_name", {{"type", "string"}}},
                             {"group", {{"type", "string"}}},
                             {"label", {{"type", "integer"}}},
                             {"parent", {{"type", "integer"}}},
                             {"leader", {{"type", "boolean"}}},
                             {"net_force", number()},
                             {"left_speed", number()},
                             {"right_speed", number()},
                             {"heard", array_of({{"type", "integer"}})},
                             // Its behaviour's own telemetry columns (its group's): name -> number.
                             {"columns", {{"type", "object"}, {"additionalProperties", number()}}}});
  json s =
      object({{"timestamp", time_schema()}, {"tick", {{"type", "integer"}}}, {"robots", array_of(robot)}});
  s["title"] = "swarmform.RobotTelemetry";
  return s.dump();
}

// ---- values -----------------------------------------------------------------------------------------------

json pose(double x, double y, double z, double yaw);
json rgba(const std::string& hex, double a = 1.0);
json time_of_ns(std::uint64_t ns) {
  return {{"sec", ns / 1000000000U}, {"nsec", ns % 1000000000U}};
}
json point(double x, double y, double z) {
  return {{"x", x}, {"y", y}, {"z", z}};
}
// A LinePrimitive in the arena's frame.
json lines(int type, double thickness, json points, const json& colour) {
  return {{"type", type},
          {"pose", pose(0, 0, 0, 0)},
          {"thickness", thickness},
          {"scale_invariant", false},
          {"points", std::move(points)},
          {"color", colour},
          {"colors", json::array()},
          {"indices", json::array()}};
}
json pose(double x, double y, double z, double yaw) {
  return {{"position", {{"x", x}, {"y", y}, {"z", z}}},
          {"orientation", {{"x", 0.0}, {"y", 0.0}, {"z", std::sin(yaw / 2)}, {"w", std::cos(yaw / 2)}}}};
}
json rgba(const std::string& hex, double a) {
  unsigned r = 0, g = 0, b = 0;
  if (hex.size() == 7 && hex[0] == '#') {
    r = static_cast<unsigned>(std::stoul(hex.substr(1, 2), nullptr, 16));
    g = static_cast<unsigned>(std::stoul(hex.substr(3, 2), nullptr, 16));
    b = static_cast<unsigned>(std::stoul(hex.substr(5, 2), nullptr, 16));
  }
  return {{"r", r / 255.0}, {"g", g / 255.0}, {"b", b / 255.0}, {"a", a}};
}
bool hex_colour(const std::string& s) {
  return s.size() == 7 && s[0] == '#' &&
         s.find_first_not_of("0123456789abcdefABCDEF", 1) == std::string::npos;
}
double num(const json& j, const char* key, double fallback) {
  return j.is_object() && j.contains(key) && j[key].is_number() ? j[key].get<double>() : fallback;
}

// A floor colour of world.json ("#rrggbb", or null with a grey level 0..1) as a hex colour.
std::string floor_hex(const json& o) {
  if (o.contains("colour") && o["colour"].is_string() && hex_colour(o["colour"].get<std::string>()))
    return o["colour"].get<std::string>();
  const int v = static_cast<int>(std::lround(std::clamp(num(o, "grey", 1.0), 0.0, 1.0) * 255.0));
  char text[8];
  std::snprintf(text, sizeof text, "#%02x%02x%02x", v, v, v);
  return text;
}

// The floor (its base colour under the arena unless plain white, then its regions in painting order, each a
// little higher so that a later one lies on top) and the light sources, as world.json gives them.
void floor_and_lights(const json& world, json& cubes, json& cylinders, json& spheres) {
  const json& f = world.value("floor", json());
  const json& a = world.value("arena", json::object());
  if (f.is_object() && a.contains("centre")) {
    // A plain white floor draws nothing, as on the page and in the pictures.
    const bool plain = num(f, "grey", 1.0) >= 1.0 && !(f.contains("colour") && f["colour"].is_string());
    if (!plain)
      cubes.push_back({{"pose", pose(a["centre"][0], a["centre"][1], -0.006, 0)},
                       {"size", {{"x", a.value("width", 0.0)}, {"y", a.value("height", 0.0)}, {"z", 0.002}}},
                       {"color", rgba(floor_hex(f))}});
    double z = -0.004;
    for (const json& r : f.value("regions", json::array())) {
      if (!r.is_object() || !r.contains("centre")) continue;
      const double x = r["centre"][0], y = r["centre"][1];
      z += 0.0001;
      if (r.value("kind", "") == "circle") {
        const double d = 2 * num(r, "radius", 0.0);
        cylinders.push_back({{"pose", pose(x, y, z, 0)},
                             {"size", {{"x", d}, {"y", d}, {"z", 0.002}}},
                             {"bottom_scale", 1.0},
                             {"top_scale", 1.0},
                             {"color", rgba(floor_hex(r))}});
      } else if (r.contains("half_extents")) {
        cubes.push_back({{"pose", pose(x, y, z, num(r, "yaw", 0.0))},
                         {"size",
                          {{"x", 2 * r["half_extents"][0].get<double>()},
                           {"y", 2 * r["half_extents"][1].get<double>()},
                           {"z", 0.002}}},
                         {"color", rgba(floor_hex(r))}});
      }
    }
  }
  for (const json& l : world.value("lights", json::array())) {
    if (!l.is_object() || !l.contains("position")) continue;
    spheres.push_back({{"pose", pose(l["position"][0], l["position"][1], num(l, "height", 0.0), 0)},
                       {"size", {{"x", 0.15}, {"y", 0.15}, {"z", 0.15}}},
                       {"color", rgba("#ffd600")}});
  }
}

// A mixed swarm's robot groups (world.json `groups`, docs/recording-format.md "Robot groups"): each robot
// takes its state's name and colour from its own group's behaviour and is edged in its group's colour, as the
// page (viewer.js GROUP_OUTLINES) and the pictures (scene.py GROUP_EDGES) draw it. Without groups every robot
// has the frame's states and no edge.
constexpr std::array<const char*, 6> kGroupEdges = {"#263238", "#d81b60", "#ff6f00",
                                                    "#00897b", "#5e35b1", "#6d4c41"};
using StateLook = Foxglove::StateLook;
using RobotGroup = Foxglove::RobotGroup;
std::map<std::int32_t, StateLook> states_by_value(const json& list) {
  std::map<std::int32_t, StateLook> out;
  if (!list.is_array()) return out;
  for (const json& s : list) {
    if (!s.is_object() || !s.contains("value") || !s["value"].is_number_integer()) continue;
    const std::string colour = s.value("colour", std::string());
    out[s["value"].get<std::int32_t>()] = {s.value("name", std::string()),
                                           hex_colour(colour) ? colour : "#000000"};
  }
  return out;
}
std::vector<RobotGroup> robot_groups(const json& world) {
  std::vector<RobotGroup> out;
  if (!world.is_object() || !world.contains("groups") || !world["groups"].is_array()) return out;
  for (const json& g : world["groups"]) {
    if (!g.is_object()) continue;
    RobotGroup group;
    group.name = g.value("name", std::string());
    group.edge = kGroupEdges[out.size() % kGroupEdges.size()];
    group.first = g.value("first_id", std::int64_t{0});
    group.count = g.value("count", std::int64_t{0});
    if (g.contains("behaviour_descriptor") && g["behaviour_descriptor"].is_object())
      group.states = states_by_value(g["behaviour_descriptor"].value("states", json::array()));
    out.push_back(std::move(group));
  }
  return out;
}
// The robot's group (nullptr without groups, or for an id none lists).
const RobotGroup* group_of(const std::vector<RobotGroup>& groups, std::int64_t id) {
  for (const auto& g : groups) {
    if (id >= g.first && id < g.first + g.count) return &g;
  }
  return nullptr;
}
// The name and colour of a robot's state: its group's when it has one, else the frame's.
StateLook state_look(const std::map<std::int32_t, StateLook>& frame_states, const RobotGroup* group,
                     std::int32_t state) {
  const auto& table = group != nullptr ? group->states : frame_states;
  const auto s = table.find(state);
  return s != table.end() ? s->second : StateLook{"state " + std::to_string(state), "#000000"};
}
std::map<std::int32_t, StateLook> frame_states(const dds::ObserveFrameData& f) {
  std::map<std::int32_t, StateLook> out;
  for (const auto& s : f.states) out[s.value] = {s.name, hex_colour(s.colour) ? s.colour : "#000000"};
  return out;
}

void put_u32(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
void put_u64(std::string& out, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}

}  // namespace

std::vector<std::string> Foxglove::hello() const {
  const json info = {{"op", "serverInfo"},
                     {"name", "swarmform swarm_viewer"},
                     {"capabilities", {"clientPublish"}},
                     {"supportedEncodings", {"json"}},
                     {"metadata",
                      {{"frame", "arena: x right, y up, metres; robots at z = 0; robot_<id> on /tf"},
                       {"control",
                        "advertise a client channel on topic /control (encoding json, schemaName "
                        "swarmform.Control) and publish {\"cmd\": \"pause\" | \"resume\" | \"step\" | "
                        "\"speed\" | \"kill\", \"value\": N} (live) or {\"cmd\": \"play\" | "
                        "\"pause\" | \"seek\" | \"speed\", \"value\": X} (replay)"}}}};
  json channels = json::array();
  channels.push_back({{"id", kScene},
                      {"topic", "/scene"},
                      {"encoding", "json"},
                      {"schemaName", "foxglove.SceneUpdate"},
                      {"schema", scene_update_schema()},
                      {"schemaEncoding", "jsonschema"}});
  channels.push_back({{"id", kPoses},
                      {"topic", "/robots/poses"},
                      {"encoding", "json"},
                      {"schemaName", "foxglove.PosesInFrame"},
                      {"schema", poses_schema()},
                      {"schemaEncoding", "jsonschema"}});
  channels.push_back({{"id", kTelemetry},
                      {"topic", "/robots/telemetry"},
                      {"encoding", "json"},
                      {"schemaName", "swarmform.RobotTelemetry"},
                      {"schema", telemetry_schema()},
                      {"schemaEncoding", "jsonschema"}});
  channels.push_back({{"id", kTransforms},
                      {"topic", "/tf"},
                      {"encoding", "json"},
                      {"schemaName", "foxglove.FrameTransforms"},
                      {"schema", transforms_schema()},
                      {"schemaEncoding", "jsonschema"}});
  channels.push_back({{"id", kMetrics},
                      {"topic", "/metrics"},
                      {"encoding", "json"},
                      {"schemaName", "swarmform.Metrics"},
                      {"schema", metrics_schema()},
                      {"schemaEncoding", "jsonschema"}});
  return {info.dump(), json{{"op", "advertise"}, {"channels", channels}}.dump()};
}

std::string Foxglove::on_text(std::uint64_t client, const std::string& text) {
  const json m = json::parse(text, nullptr, false);
  const std::string op =
      m.is_object() && m.contains("op") && m["op"].is_string() ? m["op"].get<std::string>() : "";
  auto& mine = subscriptions_[client];
  if (op == "subscribe" && m.contains("subscriptions") && m["subscriptions"].is_array()) {
    for (const json& s : m["subscriptions"]) {
      if (!s.is_object() || !s.contains("id") || !s["id"].is_number_unsigned() || !s.contains("channelId") ||
          !s["channelId"].is_number_unsigned()) {
        return status(2, "subscribe: each subscription needs an unsigned id and channelId");
      }
      const auto channel = s["channelId"].get<std::uint64_t>();
      if (channel < kScene || channel > kChannels)
        return status(2, "subscribe: no channel " + std::to_string(channel));
      const auto id = static_cast<std::uint32_t>(s["id"].get<std::uint64_t>());
      if (mine.count(id) != 0)
        return status(2, "subscribe: subscription id " + std::to_string(id) + " in use");
      mine[id] = Subscription{static_cast<std::uint32_t>(channel), false};
    }
    return "";
  }
  if (op == "unsubscribe" && m.contains("subscriptionIds") && m["subscriptionIds"].is_array()) {
    for (const json& id : m["subscriptionIds"]) {
      if (id.is_number_unsigned()) mine.erase(static_cast<std::uint32_t>(id.get<std::uint64_t>()));
    }
    return "";
  }
  if (op == "advertise" && m.contains("channels") && m["channels"].is_array()) {
    // clientPublish: the one topic a client may publish is /control, JSON.
    for (const json& c : m["channels"]) {
      if (!c.is_object() || !c.contains("id") || !c["id"].is_number_unsigned())
        return status(2, "advertise: each channel needs an unsigned id");
      const std::string topic = c.value("topic", std::string());
      const std::string encoding = c.value("encoding", std::string());
      if (topic != "/control" || encoding != "json")
        return status(2, "advertise: this server takes topic /control, encoding json only (got " + topic +
                             ", " + encoding + ")");
      auto& channels = control_channels_[client];
      if (channels.size() >= 16) return status(2, "advertise: at most 16 client channels");
      channels[static_cast<std::uint32_t>(c["id"].get<std::uint64_t>())] = topic;
    }
    return "";
  }
  if (op == "unadvertise" && m.contains("channelIds") && m["channelIds"].is_array()) {
    for (const json& id : m["channelIds"]) {
      if (id.is_number_unsigned())
        control_channels_[client].erase(static_cast<std::uint32_t>(id.get<std::uint64_t>()));
    }
    return "";
  }
  return status(1, "not supported by this server: " + text.substr(0, 60));
}

Foxglove::ClientMessage Foxglove::on_binary(std::uint64_t client, const std::string& bytes) const {
  if (bytes.size() < 5 || bytes[0] != '\x01')
    return {"", status(2, "binary message: expected Client Message Data (opcode 1, channel id, payload)")};
  std::uint32_t channel = 0;
  for (int i = 0; i < 4; ++i)
    channel |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[1 + i])) << (8 * i);
  const auto c = control_channels_.find(client);
  if (c == control_channels_.end() || c->second.count(channel) == 0)
    return {"", status(2, "client message on channel " + std::to_string(channel) + ", not advertised")};
  return {bytes.substr(5), ""};
}

std::string Foxglove::status(int level, const std::string& message) {
  return json{{"op", "status"}, {"level", level}, {"message", message}}.dump();
}

std::uint64_t Foxglove::log_ns(std::uint64_t tick) const {
  return start_ns_ + static_cast<std::uint64_t>(std::llround(seconds(tick) * 1e9));
}

double Foxglove::seconds(std::uint64_t tick) const {
  const double rate = num(world_, "tick_rate", 10.0);
  return static_cast<double>(tick) / (rate > 0 ? rate : 10.0);
}

namespace {

// How many of world.json's list `key` (by tick) are at or before `tick`.
std::size_t listed_up_to(const json& world, const char* key, std::uint64_t tick) {
  std::size_t n = 0;
  for (const json& e : world.value(key, json::array())) {
    if (!e.is_object() || e.value("tick", std::uint64_t{0}) > tick) break;  // world.json lists them by tick
    ++n;
  }
  return n;
}

}  // namespace

std::size_t events_up_to(const json& world, std::uint64_t tick) {
  return listed_up_to(world, "world_events", tick);
}

json goal_at(const json& world, std::uint64_t tick) {
  json goal = world.value("goal", json());
  if (!goal.is_object()) return json();
  const std::size_t moved = listed_up_to(world, "goal_moves", tick);
  if (moved > 0) goal = world["goal_moves"][moved - 1];
  return goal;
}

json obstacles_at(const json& world, std::uint64_t tick) {
  json now = world.value("obstacles", json::array());
  if (!now.is_array()) return json::array();
  const json events = world.value("world_events", json::array());
  const std::size_t applied = events_up_to(world, tick);
  for (std::size_t i = 0; i < applied; ++i) {
    const json& e = events[i];
    const std::size_t k = e.value("obstacle", now.size());
    if (k >= now.size() || !now[k].is_object()) continue;
    json& o = now[k];
    const std::string what = e.value("do", "");
    if (what == "appear") o["present"] = true;
    if (what == "disappear") o["present"] = false;
    if (what == "move") {
      if (e.contains("centre")) o["centre"] = e["centre"];
      if (e.contains("yaw") && e["yaw"].is_number()) o["yaw"] = e["yaw"];
    }
  }
  json present = json::array();
  for (json& o : now) {
    if (!o.is_object() || o.value("present", true)) present.push_back(std::move(o));
  }
  return present;
}

void Foxglove::set_world(const json& world) {
  world_ = world;
  groups_ = robot_groups(world);
}

json Foxglove::scene(const dds::ObserveFrameData& f, const json& stamp, bool with_arena,
                     bool with_obstacles) const {
  const json tick_meta = json::array({{{"key", "tick"}, {"value", std::to_string(f.tick)}}});
  const double radius = num(world_, "robot_radius", kRobotRadius);
  const auto states = frame_states(f);
  const auto& groups = groups_;
  json entities = json::array();
  if (with_arena && world_.is_object()) {
    json cubes = json::array(), cylinders = json::array();
    const json& a = world_.value("arena", json::object());
    if (a.value("walls", false) && a.contains("centre")) {
      const double cx = a["centre"][0], cy = a["centre"][1], w = a.value("width", 0.0),
                   h = a.value("height", 0.0);
      const double t = a.value("wall_thickness", 0.1);
      const json wall = rgba("#424242");
      cubes.push_back({{"pose", pose(cx, cy + (h + t) / 2, 0.1, 0)},
                       {"size", {{"x", w + 2 * t}, {"y", t}, {"z", 0.2}}},
                       {"color", wall}});
      cubes.push_back({{"pose", pose(cx, cy - (h + t) / 2, 0.1, 0)},
                       {"size", {{"x", w + 2 * t}, {"y", t}, {"z", 0.2}}},
                       {"color", wall}});
      cubes.push_back({{"pose", pose(cx - (w + t) / 2, cy, 0.1, 0)},
                       {"size", {{"x", t}, {"y", h}, {"z", 0.2}}},
                       {"color", wall}});
      cubes.push_back({{"pose", pose(cx + (w + t) / 2, cy, 0.1, 0)},
                       {"size", {{"x", t}, {"y", h}, {"z", 0.2}}},
                       {"color", wall}});
    }
    json spheres = json::array();
    floor_and_lights(world_, cubes, cylinders, spheres);
    entities.push_back({{"timestamp", stamp},
                        {"frame_id", "arena"},
                        {"id", "arena"},
                        {"lifetime", {{"sec", 0}, {"nsec", 0}}},
                        {"frame_locked", false},
                        {"metadata", tick_meta},
                        {"cubes", cubes},
                        {"cylinders", cylinders},
                        {"spheres", spheres},
                        {"texts", json::array()}});
  }
  if (with_obstacles && world_.is_object()) {
    // Their own entity with the goal, sent again whenever a world event has changed them or moved it (it
    // replaces the one before).
    json cubes = json::array(), cylinders = json::array();
    if (const json g = goal_at(world_, f.tick); g.is_object()) {
      const double d = 2 * g.value("radius", 0.5);
      cylinders.push_back({{"pose", pose(g.value("x", 0.0), g.value("y", 0.0), 0.005, 0)},
                           {"size", {{"x", d}, {"y", d}, {"z", 0.01}}},
                           {"bottom_scale", 1.0},
                           {"top_scale", 1.0},
                           {"color", rgba("#8e24aa", 0.35)}});
    }
    for (const json& o : obstacles_at(world_, f.tick)) {
      if (!o.is_object() || !o.contains("centre")) continue;
      const double x = o["centre"][0], y = o["centre"][1];
      if (o.value("kind", "") == "cylinder") {
        const double d = 2 * o.value("radius", 0.1);
        cylinders.push_back({{"pose", pose(x, y, 0.15, 0)},
                             {"size", {{"x", d}, {"y", d}, {"z", 0.3}}},
                             {"bottom_scale", 1.0},
                             {"top_scale", 1.0},
                             {"color", rgba("#6d4c41")}});
      } else if (o.contains("half_extents")) {
        const double hx = o["half_extents"][0], hy = o["half_extents"][1];
        cubes.push_back({{"pose", pose(x, y, 0.15, o.value("yaw", 0.0))},
                         {"size", {{"x", 2 * hx}, {"y", 2 * hy}, {"z", 0.3}}},
                         {"color", rgba("#6d4c41")}});
      }
    }
    entities.push_back({{"timestamp", stamp},
                        {"frame_id", "arena"},
                        {"id", "obstacles"},
                        {"lifetime", {{"sec", 0}, {"nsec", 0}}},
                        {"frame_locked", false},
                        {"metadata", tick_meta},
                        {"cubes", cubes},
                        {"cylinders", cylinders},
                        {"spheres", json::array()},
                        {"texts", json::array()}});
  }
  json cylinders = json::array(), texts = json::array(), leds = json::array(), arrows = json::array();
  json links = json::array(), rays = json::array(), rings = json::array(), edges = json::array();
  std::map<std::uint32_t, const dds::ObservedRobotRow*> by_id;
  for (const auto& r : f.robots) by_id[r.id] = &r;
  for (const auto& r : f.robots) {
    // Heading: an arrow from the centre to past the rim, on top of the body.
    arrows.push_back({{"pose", pose(r.pose.x, r.pose.y, kRobotHeight + 0.005, r.pose.theta)},
                      {"shaft_length", 1.1 * radius},
                      {"shaft_diameter", 0.2 * radius},
                      {"head_length", 0.5 * radius},
                      {"head_diameter", 0.6 * radius},
                      {"color", rgba(r.alive ? "#212121" : "#9e9e9e")}});
    if (!r.alive) continue;
    const auto p = r.parent >= 0 ? by_id.find(static_cast<std::uint32_t>(r.parent)) : by_id.end();
    if (p != by_id.end()) {
      links.push_back(point(r.pose.x, r.pose.y, 0.02));
      links.push_back(point(p->second->pose.x, p->second->pose.y, 0.02));
    }
    if (!recorded_) {
      // The ultrasonic rays (live frames only: robots.csv does not hold them), from the sensor on the rim to
      // the reading's end.
      for (std::size_t k = 0; k < kUltrasonicCount; ++k) {
        const double a = r.pose.theta + kUltrasonicAngles[k];
        const double c = std::cos(a), s = std::sin(a);
        rays.push_back(point(r.pose.x + radius * c, r.pose.y + radius * s, 0.03));
        rays.push_back(point(r.pose.x + (radius + r.ultrasonic[k]) * c,
                             r.pose.y + (radius + r.ultrasonic[k]) * s, 0.03));
      }
    }
    if (r.leader) {
      json ring = json::array();
      for (int k = 0; k < 32; ++k) {
        const double a = 2.0 * std::numbers::pi * k / 32;
        ring.push_back(
            point(r.pose.x + 1.6 * radius * std::cos(a), r.pose.y + 1.6 * radius * std::sin(a), 0.01));
      }
      rings.push_back(lines(1, 0.015, std::move(ring), rgba("#ffb300")));
    }
  }
  for (const auto& r : f.robots) {
    // The lit LEDs on top, as the pictures draw them: at 0.55 of the radius from the centre, 120 degrees
    // apart, LED 0 ahead (scripts/swarmform/scene.py led_positions).
    for (std::size_t k = 0; k < kLedCount; ++k) {
      const Rgb& c = r.leds[k];
      if (c.r == 0 && c.g == 0 && c.b == 0) continue;
      const double a = r.pose.theta + 2.0 * std::numbers::pi / 3.0 * (k == 0 ? 0.0 : k == 1 ? 1.0 : -1.0);
      const double d = 0.5 * radius;
      leds.push_back({{"pose", pose(r.pose.x + 0.55 * radius * std::cos(a),
                                    r.pose.y + 0.55 * radius * std::sin(a), kRobotHeight + d / 2, 0)},
                      {"size", {{"x", d}, {"y", d}, {"z", d}}},
                      {"color", {{"r", c.r / 255.0}, {"g", c.g / 255.0}, {"b", c.b / 255.0}, {"a", 1.0}}}});
    }
    const RobotGroup* group = group_of(groups, r.id);
    const std::string colour = !r.alive ? "#bdbdbd" : state_look(states, group, r.state).colour;
    if (group != nullptr) {
      json edge = json::array();
      for (int k = 0; k < 32; ++k) {
        const double a = 2.0 * std::numbers::pi * k / 32;
        edge.push_back(
            point(r.pose.x + 1.15 * radius * std::cos(a), r.pose.y + 1.15 * radius * std::sin(a), 0.005));
      }
      edges.push_back(lines(1, 0.012, std::move(edge), rgba(group->edge)));
    }
    cylinders.push_back({{"pose", pose(r.pose.x, r.pose.y, kRobotHeight / 2, r.pose.theta)},
                         {"size", {{"x", 2 * radius}, {"y", 2 * radius}, {"z", kRobotHeight}}},
                         {"bottom_scale", 1.0},
                         {"top_scale", 1.0},
                         {"color", rgba(colour)}});
    texts.push_back({{"pose", pose(r.pose.x, r.pose.y, kRobotHeight + 0.05, 0)},
                     {"billboard", true},
                     {"font_size", 14.0},
                     {"scale_invariant", true},
                     {"color", rgba("#263238")},
                     {"text", std::to_string(r.id)}});
  }
  entities.push_back({{"timestamp", stamp},
                      {"frame_id", "arena"},
                      {"id", "robots"},
                      {"lifetime", {{"sec", 0}, {"nsec", 0}}},
                      {"frame_locked", false},
                      {"metadata", tick_meta},
                      {"arrows", arrows},
                      {"cubes", json::array()},
                      {"cylinders", cylinders},
                      {"spheres", leds},
                      {"texts", texts}});
  // The lines, each their own entity (a layer that Foxglove's scene tree toggles).
  auto line_entity = [&](const char* id, json primitives) {
    entities.push_back({{"timestamp", stamp},
                        {"frame_id", "arena"},
                        {"id", id},
                        {"lifetime", {{"sec", 0}, {"nsec", 0}}},
                        {"frame_locked", false},
                        {"metadata", tick_meta},
                        {"lines", std::move(primitives)}});
  };
  line_entity("parent_links", json::array({lines(2, 0.01, std::move(links), rgba("#546e7a"))}));
  if (!recorded_)
    line_entity("ultrasonic_rays", json::array({lines(2, 0.005, std::move(rays), rgba("#e53935"))}));
  line_entity("leader", std::move(rings));
  if (!groups.empty()) line_entity("group_edges", std::move(edges));
  // Every primitive list in every entity, empty or not: a reader need not know which an entity uses.
  for (json& e : entities) {
    for (const char* k : {"arrows", "cubes", "cylinders", "lines", "spheres", "texts"}) {
      if (!e.contains(k)) e[k] = json::array();
    }
  }
  return {{"deletions", json::array()}, {"entities", entities}};
}

json Foxglove::poses(const dds::ObserveFrameData& f, const json& stamp) const {
  json list = json::array();
  for (const auto& r : f.robots) list.push_back(pose(r.pose.x, r.pose.y, 0.0, r.pose.theta));
  return {{"timestamp", stamp}, {"frame_id", "arena"}, {"poses", list}, {"tick", f.tick}};
}

json Foxglove::transforms(const dds::ObserveFrameData& f, const json& stamp) const {
  json list = json::array();
  for (const auto& r : f.robots) {
    const json p = pose(r.pose.x, r.pose.y, 0.0, r.pose.theta);
    list.push_back({{"timestamp", stamp},
                    {"parent_frame_id", "arena"},
                    {"child_frame_id", "robot_" + std::to_string(r.id)},
                    {"translation", p["position"]},
                    {"rotation", p["orientation"]}});
  }
  return {{"transforms", list}, {"tick", f.tick}};
}

json Foxglove::metrics(const dds::ObserveFrameData& f, const json& stamp) const {
  json forces = json::array();
  double sum = 0.0, most = 0.0;
  std::size_t alive = 0;
  for (const auto& r : f.robots) {
    forces.push_back(r.net_force);
    if (!r.alive) continue;
    ++alive;
    sum += r.net_force;
    most = std::max(most, r.net_force);
  }
  json m = {{"timestamp", stamp},
            {"tick", f.tick},
            {"alive", alive},
            {"formation_tick", f.formation_tick},
            {"net_force_mean", alive > 0 ? sum / static_cast<double>(alive) : 0.0},
            {"net_force_max", most},
            {"net_force", forces}};
  // Left out until there is one: a Plot panel draws nothing rather than a -1.
  if (f.shape_error >= 0) m["shape_error"] = f.shape_error;
  return m;
}

json Foxglove::telemetry(const dds::ObserveFrameData& f, const json& stamp) const {
  const auto states = frame_states(f);
  const auto& groups = groups_;
  json list = json::array();
  for (const auto& r : f.robots) {
    const RobotGroup* group = group_of(groups, r.id);
    json robot = {{"id", r.id},         {"alive", r.alive},
                  {"state", r.state},   {"state_name", state_look(states, group, r.state).name},
                  {"label", r.label},   {"parent", r.parent},
                  {"leader", r.leader}, {"net_force", r.net_force}};
    if (group != nullptr) robot["group"] = group->name;
    json columns = json::object();
    const auto& names = f.columns_of(r.id);
    for (std::size_t k = 0; k < names.size() && k < r.extra.size(); ++k) {
      if (std::isfinite(r.extra[k])) columns[names[k]] = r.extra[k];
    }
    robot["columns"] = std::move(columns);
    if (!recorded_) {
      robot["left_speed"] = r.left_speed;
      robot["right_speed"] = r.right_speed;
      robot["heard"] = r.heard;
    }
    list.push_back(std::move(robot));
  }
  return {{"timestamp", stamp}, {"tick", f.tick}, {"robots", list}};
}

std::vector<std::pair<std::uint64_t, std::string>> Foxglove::messages(const dds::ObserveFrameData& f,
                                                                      std::uint64_t only,
                                                                      std::uint64_t stamp_ns) {
  std::vector<std::pair<std::uint64_t, std::string>> out;
  std::string cached[kChannels + 1];
  const std::uint64_t stamp = stamp_ns != 0 ? stamp_ns : log_ns(f.tick);
  const json when = time_of_ns(stamp);
  // The world events and goal moves so far: the same for every subscription.
  const std::size_t events = events_up_to(world_, f.tick) + listed_up_to(world_, "goal_moves", f.tick);
  for (auto& [client, subs] : subscriptions_) {
    if (only != 0 && client != only) continue;
    for (auto& [id, sub] : subs) {
      std::string payload;
      if (sub.channel == kScene) {
        const bool arena = !sub.arena_sent && world_.is_object();
        const bool obstacles = world_.is_object() && (arena || events != sub.events_applied);
        payload = scene(f, when, arena, obstacles).dump();
        sub.arena_sent = sub.arena_sent || arena;
        if (obstacles) sub.events_applied = events;
      } else {
        std::string& c = cached[sub.channel];
        if (c.empty()) {
          c = (sub.channel == kPoses        ? poses(f, when)
               : sub.channel == kTelemetry  ? telemetry(f, when)
               : sub.channel == kTransforms ? transforms(f, when)
                                            : metrics(f, when))
                  .dump();
        }
        payload = c;
      }
      std::string bytes;
      bytes.reserve(13 + payload.size());
      bytes.push_back(static_cast<char>(0x01));  // Message Data
      put_u32(bytes, id);
      put_u64(bytes, stamp);
      bytes += payload;
      out.emplace_back(client, std::move(bytes));
    }
  }
  return out;
}

}  // namespace swarmform::viewer
