#include "world_server/run/provenance.hpp"

#include "swarmform_build_info.hpp"
#include "world_server/run/sha256.hpp"

namespace swarmform::world {

namespace {

using ojson = nlohmann::ordered_json;

ojson xy(Vec2 v) {
  return ojson::array({v.x, v.y});
}

// Every field of the loaded scenario but its source path, in a fixed order.
ojson canonical(const Scenario& s) {
  ojson j;
  j["arena"] = {{"centre", xy(s.arena_centre)},
                {"width", s.arena_width},
                {"height", s.arena_height},
                {"walls", s.walls},
                {"wall_thickness", s.wall_thickness}};
  ojson obstacles = ojson::array();
  for (const Obstacle& o : s.obstacles) {
    obstacles.push_back({{"kind", o.kind == Obstacle::Kind::Box ? "box" : "cylinder"},
                         {"name", o.name},
                         {"centre", xy(o.centre)},
                         {"half_extents", xy(o.half_extents)},
                         {"yaw", o.yaw},
                         {"radius", o.radius}});
    if (!o.present) obstacles.back()["present"] = false;
  }
  j["obstacles"] = std::move(obstacles);
  if (!s.world_events.empty()) {  // only then: the hash of a scenario without any stays as it was
    ojson events = ojson::array();
    for (const WorldEvent& e : s.world_events) {
      events.push_back({{"tick", e.tick},
                        {"obstacle", e.obstacle},
                        {"do", std::string(action_word(e.action))},
                        {"centre", xy(e.centre)},
                        {"yaw", e.yaw ? ojson(*e.yaw) : ojson(nullptr)}});
    }
    j["world_events"] = std::move(events);
  }
  if (!s.goal_events.empty()) {  // only then, as the world events above
    ojson moves = ojson::array();
    for (const GoalEvent& e : s.goal_events) {
      moves.push_back({{"tick", e.tick}, {"goal", xy(e.goal.at)}, {"radius", e.goal.radius}});
    }
    j["goal_moves"] = std::move(moves);
  }
  ojson robots = ojson::array();
  for (const Pose2D& p : s.robots) robots.push_back(ojson::array({p.x, p.y, p.theta}));
  j["robots"] = std::move(robots);
  j["medium"] = {{"comm_range", s.comm_range},
                 {"range_noise_sd", s.range_noise_sd},
                 {"bearing_noise_sd", s.bearing_noise_sd},
                 {"ultrasonic_noise_sd", s.ultrasonic_noise_sd},
                 {"packet_loss", s.packet_loss},
                 {"occlusion", s.occlusion}};
  // Only when bursty, so that every scenario of independent loss keeps the hash it had before bursts.
  if (s.packet_loss_mean_burst > 0.0) j["medium"]["packet_loss_mean_burst"] = s.packet_loss_mean_burst;
  j["time"] = {
      {"mode", std::string(to_string(s.mode))},       {"tick_rate", s.tick_rate}, {"substeps", s.substeps},
      {"lockstep_deadline_s", s.lockstep_deadline_s}, {"seed", s.seed},           {"max_ticks", s.max_ticks}};
  ojson kills = ojson::array();
  for (const Kill& k : s.kills) kills.push_back(ojson::array({k.id, k.tick}));
  j["kills"] = std::move(kills);
  const Mission& m = s.mission;
  j["mission"] = {{"behaviour", m.behaviour},
                  {"shape", {{"rows", m.shape.rows}, {"cols", m.shape.cols}, {"cells", m.shape.cells}}},
                  {"grid_spacing", m.grid_spacing},
                  {"goal", m.has_goal ? xy(m.goal) : ojson(nullptr)},
                  {"goal_radius", m.goal_radius},
                  {"max_speed", m.max_speed},
                  {"tick_rate", m.tick_rate},
                  {"comm_range", m.comm_range},
                  {"max_message_bytes", m.max_message_bytes},
                  {"seed", m.seed},
                  {"params", m.params}};
  return j;
}

}  // namespace

std::string scenario_sha256(const Scenario& scenario) {
  return sha256_hex(canonical(scenario).dump());
}

ojson provenance(const Scenario& scenario) {
  return {{"product", "swarmform"},
          {"version", SWARMFORM_VERSION},
          {"git_commit", SWARMFORM_GIT_COMMIT},
          {"build_type", SWARMFORM_BUILD_TYPE},
          {"scenario_sha256", scenario_sha256(scenario)}};
}

}  // namespace swarmform::world
