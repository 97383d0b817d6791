#include "viewer/foxglove.hpp"

#include <algorithm>
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
       {"cubes", array_of(cube)},
       {"cylinders", array_of(cylinder)},
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
  json s = object(
      {{"timestamp", time_schema()}, {"frame_id", {{"type", "string"}}}, {"poses", array_of(pose_schema())}});
  s["title"] = "foxglove.PosesInFrame";
  return s.dump();
}

std::string telemetry_schema() {
  const json robot = object({{"id", {{"type", "integer"}}},
                             {"alive", {{"type", "boolean"}}},
                             {"state", {{"type", "integer"}}},
                             {"state_name", {{"type", "string"}}},
                             {"label", {{"type", "integer"}}},
                             {"parent", {{"type", "integer"}}},
                             {"leader", {{"type", "boolean"}}},
                             {"net_force", number()},
                             {"left_speed", number()},
                             {"right_speed", number()},
                             {"heard", array_of({{"type", "integer"}})}});
  json s =
      object({{"timestamp", time_schema()}, {"tick", {{"type", "integer"}}}, {"robots", array_of(robot)}});
  s["title"] = "swarmform.RobotTelemetry";
  return s.dump();
}

// ---- values -----------------------------------------------------------------------------------------------

json time_of(double s) {
  const double whole = std::floor(std::max(0.0, s));
  return {{"sec", static_cast<std::int64_t>(whole)}, {"nsec", static_cast<std::int64_t>((s - whole) * 1e9)}};
}
json pose(double x, double y, double z, double yaw) {
  return {{"position", {{"x", x}, {"y", y}, {"z", z}}},
          {"orientation", {{"x", 0.0}, {"y", 0.0}, {"z", std::sin(yaw / 2)}, {"w", std::cos(yaw / 2)}}}};
}
json rgba(const std::string& hex, double a = 1.0) {
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
                     {"capabilities", json::array()},
                     {"metadata", {{"frame", "arena: x right, y up, metres; robots at z = 0"}}}};
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
  return {info.dump(), json{{"op", "advertise"}, {"channels", channels}}.dump()};
}

std::string Foxglove::on_text(std::uint64_t client, const std::string& text) {
  const json m = json::parse(text, nullptr, false);
  const std::string op =
      m.is_object() && m.contains("op") && m["op"].is_string() ? m["op"].get<std::string>() : "";
  auto status = [](int level, const std::string& message) {
    return json{{"op", "status"}, {"level", level}, {"message", message}}.dump();
  };
  auto& mine = subscriptions_[client];
  if (op == "subscribe" && m.contains("subscriptions") && m["subscriptions"].is_array()) {
    for (const json& s : m["subscriptions"]) {
      if (!s.is_object() || !s.contains("id") || !s["id"].is_number_unsigned() || !s.contains("channelId") ||
          !s["channelId"].is_number_unsigned()) {
        return status(2, "subscribe: each subscription needs an unsigned id and channelId");
      }
      const auto channel = s["channelId"].get<std::uint64_t>();
      if (channel < kScene || channel > kTelemetry)
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
  return status(1, "not supported by this server: " + text.substr(0, 60));
}

double Foxglove::seconds(std::uint64_t tick) const {
  const double rate = num(world_, "tick_rate", 10.0);
  return static_cast<double>(tick) / (rate > 0 ? rate : 10.0);
}

std::size_t events_up_to(const json& world, std::uint64_t tick) {
  std::size_t n = 0;
  for (const json& e : world.value("world_events", json::array())) {
    if (!e.is_object() || e.value("tick", std::uint64_t{0}) > tick) break;  // world.json lists them by tick
    ++n;
  }
  return n;
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

json Foxglove::scene(const dds::ObserveFrameData& f, bool with_arena, bool with_obstacles) const {
  const json stamp = time_of(seconds(f.tick));
  const double radius = num(world_, "robot_radius", kRobotRadius);
  std::map<std::int32_t, std::string> colours;
  for (const auto& s : f.states) colours[s.value] = hex_colour(s.colour) ? s.colour : "#000000";
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
    if (world_.contains("goal") && world_["goal"].is_object()) {
      const json& g = world_["goal"];
      const double d = 2 * g.value("radius", 0.5);
      cylinders.push_back({{"pose", pose(g.value("x", 0.0), g.value("y", 0.0), 0.005, 0)},
                           {"size", {{"x", d}, {"y", d}, {"z", 0.01}}},
                           {"bottom_scale", 1.0},
                           {"top_scale", 1.0},
                           {"color", rgba("#8e24aa", 0.35)}});
    }
    entities.push_back({{"timestamp", stamp},
                        {"frame_id", "arena"},
                        {"id", "arena"},
                        {"lifetime", {{"sec", 0}, {"nsec", 0}}},
                        {"frame_locked", false},
                        {"metadata", json::array()},
                        {"cubes", cubes},
                        {"cylinders", cylinders},
                        {"spheres", spheres},
                        {"texts", json::array()}});
  }
  if (with_obstacles && world_.is_object()) {
    // Their own entity, sent again whenever a world event has changed them (it replaces the one before).
    json cubes = json::array(), cylinders = json::array();
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
                        {"metadata", json::array()},
                        {"cubes", cubes},
                        {"cylinders", cylinders},
                        {"spheres", json::array()},
                        {"texts", json::array()}});
  }
  json cylinders = json::array(), texts = json::array(), leds = json::array();
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
    const auto c = colours.find(r.state);
    const std::string colour = !r.alive ? "#bdbdbd" : c != colours.end() ? c->second : "#000000";
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
                      {"metadata", {{{"key", "tick"}, {"value", std::to_string(f.tick)}}}},
                      {"cubes", json::array()},
                      {"cylinders", cylinders},
                      {"spheres", leds},
                      {"texts", texts}});
  return {{"deletions", json::array()}, {"entities", entities}};
}

json Foxglove::poses(const dds::ObserveFrameData& f) const {
  json list = json::array();
  for (const auto& r : f.robots) list.push_back(pose(r.pose.x, r.pose.y, 0.0, r.pose.theta));
  return {{"timestamp", time_of(seconds(f.tick))}, {"frame_id", "arena"}, {"poses", list}};
}

json Foxglove::telemetry(const dds::ObserveFrameData& f) const {
  std::map<std::int32_t, std::string> names;
  for (const auto& s : f.states) names[s.value] = s.name;
  json list = json::array();
  for (const auto& r : f.robots) {
    const auto n = names.find(r.state);
    json robot = {{"id", r.id},
                  {"alive", r.alive},
                  {"state", r.state},
                  {"state_name", n != names.end() ? n->second : "state " + std::to_string(r.state)},
                  {"label", r.label},
                  {"parent", r.parent},
                  {"leader", r.leader},
                  {"net_force", r.net_force}};
    if (!recorded_) {
      robot["left_speed"] = r.left_speed;
      robot["right_speed"] = r.right_speed;
      robot["heard"] = r.heard;
    }
    list.push_back(std::move(robot));
  }
  return {{"timestamp", time_of(seconds(f.tick))}, {"tick", f.tick}, {"robots", list}};
}

std::vector<std::pair<std::uint64_t, std::string>> Foxglove::messages(const dds::ObserveFrameData& f,
                                                                      std::uint64_t only) {
  std::vector<std::pair<std::uint64_t, std::string>> out;
  std::string cached[4];
  const auto stamp = static_cast<std::uint64_t>(seconds(f.tick) * 1e9);
  const std::size_t events = events_up_to(world_, f.tick);  // the same for every subscription
  for (auto& [client, subs] : subscriptions_) {
    if (only != 0 && client != only) continue;
    for (auto& [id, sub] : subs) {
      std::string payload;
      if (sub.channel == kScene) {
        const bool arena = !sub.arena_sent && world_.is_object();
        const bool obstacles = world_.is_object() && (arena || events != sub.events_applied);
        payload = scene(f, arena, obstacles).dump();
        sub.arena_sent = sub.arena_sent || arena;
        if (obstacles) sub.events_applied = events;
      } else {
        std::string& c = cached[sub.channel];
        if (c.empty()) c = (sub.channel == kPoses ? poses(f) : telemetry(f)).dump();
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
