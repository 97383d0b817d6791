// nlohmann::json with exceptions off for parsing (a bad line is the behaviour's error, said in one
// sentence, not a parser's exception text). Doubles are written with round-trip precision, so a behaviour
// sees exactly the perception the world sent.
#include "robot_agent/exec/line_protocol.hpp"

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <utility>

namespace swarmform::agent {

namespace {

using nlohmann::json;

json parse_object(const std::string& line, const char* what) {
  json j = json::parse(line, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) {
    const bool non_finite =
        line.find("NaN") != std::string::npos || line.find("Infinity") != std::string::npos;
    throw ProtocolError(non_finite
                            ? std::string("wrote a non-finite number (NaN or Infinity) as its ") + what
                            : std::string("wrote a line that is not JSON where its ") + what + " was due");
  }
  if (!j.is_object()) throw ProtocolError(std::string("wrote JSON that is not an object as its ") + what);
  return j;
}

std::string type_of(const json& j) {
  const auto it = j.find("type");
  return it != j.end() && it->is_string() ? it->get<std::string>() : std::string();
}

double finite_number(const json& j, const char* key, const char* what) {
  const auto it = j.find(key);
  if (it == j.end()) throw ProtocolError(std::string(what) + " has no \"" + key + "\"");
  if (!it->is_number()) throw ProtocolError(std::string(what) + "'s \"" + key + "\" is not a number");
  const double v = it->get<double>();
  if (!std::isfinite(v)) throw ProtocolError(std::string(what) + "'s \"" + key + "\" is not finite");
  return v;
}

}  // namespace

std::string encode_hello(const Mission& mission, RobotId self) {
  json params = json::object();
  for (const auto& [name, value] : mission.params) params[name] = value;
  json shape = json::array();
  for (int r = 0; r < mission.shape.rows; ++r) {
    json row = json::array();
    for (int c = 0; c < mission.shape.cols; ++c) row.push_back(mission.shape.at(r, c));
    shape.push_back(std::move(row));
  }
  const json hello = {
      {"type", "hello"},
      {"protocol", kProtocolVersion},
      {"robot", self},
      {"behaviour", mission.behaviour},
      {"params", std::move(params)},
      {"seed", mission.seed},
      {"tick_rate", mission.tick_rate},
      {"max_speed", mission.max_speed},
      {"comm_range", mission.comm_range},
      {"max_message_bytes", mission.max_message_bytes},
      {"goal", mission.has_goal
                   ? json{{"x", mission.goal.x}, {"y", mission.goal.y}, {"radius", mission.goal_radius}}
                   : json(nullptr)},
      {"grid_spacing", mission.grid_spacing},
      {"shape", std::move(shape)},
  };
  return hello.dump();
}

std::string parse_hello_reply(const std::string& line) {
  const json j = parse_object(line, "hello");
  if (type_of(j) != "hello") {
    throw ProtocolError("answered the hello with a line whose \"type\" is not \"hello\"");
  }
  const auto p = j.find("protocol");
  if (p == j.end() || !p->is_number_integer())
    throw ProtocolError("said hello without an integer \"protocol\"");
  if (p->get<long long>() != kProtocolVersion) {
    throw ProtocolError("speaks protocol " + std::to_string(p->get<long long>()) + ", this agent speaks " +
                        std::to_string(kProtocolVersion));
  }
  const auto name = j.find("name");
  return name != j.end() && name->is_string() ? name->get<std::string>() : std::string();
}

std::string encode_perception(const Perception& perception) {
  json messages = json::array();
  for (const RabReading& m : perception.messages) {
    messages.push_back(
        {{"sender", m.sender}, {"range", m.range}, {"bearing", m.bearing}, {"data", to_hex(m.data)}});
  }
  json out = {
      {"type", "perception"},
      {"tick", perception.tick},
      {"pose", {{"x", perception.pose.x}, {"y", perception.pose.y}, {"theta", perception.pose.theta}}},
      {"ultrasonic", perception.ultrasonic},
      {"messages", std::move(messages)},
  };
  // The goal as it stands this tick (it moves by world events), when the run has one.
  if (perception.goal) {
    out["goal"] = {
        {"x", perception.goal->at.x}, {"y", perception.goal->at.y}, {"radius", perception.goal->radius}};
  }
  // The optional sensors only when equipped (the behaviour declared them): absent otherwise.
  if (perception.proximity) out["proximity"] = *perception.proximity;
  if (perception.light) out["light"] = *perception.light;
  if (perception.ground) out["ground"] = *perception.ground;
  if (perception.battery) out["battery"] = *perception.battery;
  if (!perception.lidar.empty()) {
    json rays = json::array();
    for (const LidarRay& r : perception.lidar) rays.push_back(json::array({r.angle, r.range}));
    out["lidar"] = std::move(rays);
  }
  return out.dump();
}

Command parse_command(const std::string& line, Tick tick, std::size_t max_message_bytes) {
  const json j = parse_object(line, "command");
  if (type_of(j) != "command") throw ProtocolError("wrote a line whose \"type\" is not \"command\"");
  const auto t = j.find("tick");
  if (t == j.end() || !t->is_number_unsigned() || t->get<Tick>() != tick) {
    throw ProtocolError("answered the perception of tick " + std::to_string(tick) +
                        " with a command whose \"tick\" is " +
                        (t == j.end() ? std::string("missing") : t->dump()));
  }
  Command c;
  c.left_speed = finite_number(j, "left", "the command");
  c.right_speed = finite_number(j, "right", "the command");
  if (const auto m = j.find("message"); m != j.end()) {
    if (!m->is_string()) throw ProtocolError("the command's \"message\" is not a hex string");
    const auto& hex = m->get_ref<const std::string&>();
    if (hex.size() % 2 != 0) throw ProtocolError("the command's \"message\" has an odd number of hex digits");
    if (hex.size() / 2 > max_message_bytes) {
      throw ProtocolError("the command's \"message\" has " + std::to_string(hex.size() / 2) +
                          " bytes, over the mission's max_message_bytes " +
                          std::to_string(max_message_bytes));
    }
    auto bytes = from_hex(hex);
    if (!bytes) throw ProtocolError("the command's \"message\" is not hex");
    c.message = std::move(*bytes);
  }
  if (const auto s = j.find("state"); s != j.end()) {
    if (!s->is_number_integer() || s->get<long long>() < 0 ||
        s->get<long long>() > std::numeric_limits<std::int32_t>::max()) {
      throw ProtocolError("the command's \"state\" is not a non-negative integer");
    }
    c.telemetry.state = static_cast<std::int32_t>(s->get<long long>());
  }
  if (const auto x = j.find("telemetry"); x != j.end()) {
    // The behaviour's descriptor's telemetry columns, in order (the world checks the count against them).
    if (!x->is_array() || x->size() > kMaxTelemetry) {
      throw ProtocolError("the command's \"telemetry\" is not a list of at most " +
                          std::to_string(kMaxTelemetry) + " numbers");
    }
    for (const json& v : *x) {
      if (!v.is_number())
        throw ProtocolError("the command's \"telemetry\" holds something other than a number");
      c.telemetry.extra.push_back(v.get<double>());
    }
  }
  if (const auto e = j.find("events"); e != j.end()) {
    if (!e->is_array() || e->size() > kMaxEvents) {
      throw ProtocolError("the command's \"events\" is not a list of at most " + std::to_string(kMaxEvents) +
                          " strings");
    }
    for (const json& ev : *e) {
      if (!ev.is_string() || ev.get_ref<const std::string&>().empty() ||
          ev.get_ref<const std::string&>().size() > kMaxEventBytes ||
          ev.get_ref<const std::string&>().find('\n') != std::string::npos) {
        throw ProtocolError("the command's \"events\" holds something other than a one-line string of 1.." +
                            std::to_string(kMaxEventBytes) + " bytes");
      }
      c.telemetry.events.push_back(ev.get<std::string>());
    }
  }
  return c;
}

}  // namespace swarmform::agent
