#include "viewer/frame_json.hpp"

#include <cmath>
#include <string>

#include "behaviour/descriptor.hpp"
#include "common/led_text.hpp"
#include "common/sensor_readings.hpp"

namespace swarmform::viewer {

namespace {

// Rounded to 0.1 mm / 1 mrad: the page draws pixels; 17 digits would triple the bytes on the socket.
double r4(double v) {
  return std::isfinite(v) ? std::round(v * 1e4) / 1e4 : 0.0;
}

}  // namespace

void add_readings(std::uint32_t equipped, const std::vector<double>& readings, nlohmann::json& robot) {
  if (sensor_readings_count(equipped) != readings.size()) return;  // the wire and the replay check it first
  std::size_t at = 0;
  for (const SensorReadingsLayout& s : kSensorReadings) {
    if ((equipped & s.bit) == 0) continue;
    const double* v = readings.data() + at;
    at += s.count;
    if (s.bit == behaviour::kLidar) {
      robot[s.name] = {{"rays", static_cast<std::uint32_t>(v[0])},
                       {"nearest_angle", r4(v[1])},
                       {"nearest_range", r4(v[2])}};
    } else if (s.count == 1) {
      robot[s.name] = r4(v[0]);
    } else {
      nlohmann::json list = nlohmann::json::array();
      for (std::size_t k = 0; k < s.count; ++k) list.push_back(r4(v[k]));
      robot[s.name] = std::move(list);
    }
  }
}

nlohmann::json leds_json(const std::array<Rgb, kLedCount>& leds) {
  if (leds_off(leds)) return nullptr;
  nlohmann::json out = nlohmann::json::array();
  for (const Rgb& c : leds) {
    std::string text;
    append_rgb_hex(text, c);
    out.push_back(std::move(text));
  }
  return out;
}

nlohmann::json frame_json(const dds::ObserveFrameData& f) {
  nlohmann::json states = nlohmann::json::array();
  for (const auto& s : f.states)
    states.push_back({{"value", s.value}, {"name", s.name}, {"colour", s.colour}});
  nlohmann::json robots = nlohmann::json::array();
  for (const auto& r : f.robots) {
    nlohmann::json us = nlohmann::json::array();
    for (double u : r.ultrasonic) us.push_back(r4(u));
    nlohmann::json robot = {{"id", r.id},
                            {"x", r4(r.pose.x)},
                            {"y", r4(r.pose.y)},
                            {"theta", r4(r.pose.theta)},
                            {"alive", r.alive},
                            {"state", r.state},
                            {"label", r.label},
                            {"parent", r.parent},
                            {"leader", r.leader},
                            {"net_force", r4(r.net_force)},
                            {"ultrasonic", us},
                            {"heard", r.heard},
                            {"left_speed", r4(r.left_speed)},
                            {"right_speed", r4(r.right_speed)},
                            {"message_bytes", r.message_bytes}};
    if (nlohmann::json leds = leds_json(r.leds); !leds.is_null()) robot["leds"] = std::move(leds);
    // Its behaviour's own columns by name, as a replay's robot has them (a name the frame already gives the
    // robot is not overwritten; a value the world could not take as finite is left out).
    const auto& names = f.columns_of(r.id);
    for (std::size_t k = 0; k < names.size() && k < r.extra.size(); ++k) {
      if (std::isfinite(r.extra[k]) && !robot.contains(names[k])) robot[names[k]] = r.extra[k];
    }
    add_readings(r.equipped, r.readings, robot);
    robots.push_back(std::move(robot));
  }
  return {{"type", "frame"},
          {"tick", f.tick},
          {"sent_ms", f.sent_at / 1000000},  // the world's write time, ms since the epoch (the page's lag)
          {"finished", f.finished},
          {"paused", f.paused},
          {"controllable", f.controllable},
          {"speed_cap", f.speed_cap},
          {"alive", f.alive},
          {"formation_tick", f.formation_tick},
          {"shape_error", f.shape_error},
          {"behaviour", f.behaviour},
          {"states", states},
          {"telemetry_fields", f.telemetry_fields},
          {"robots", robots}};
}

}  // namespace swarmform::viewer
