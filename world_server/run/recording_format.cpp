#include "world_server/run/recording_format.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <span>

#include "behaviour/descriptor_check.hpp"
#include "common/led_text.hpp"
#include "world_server/run/provenance.hpp"
#include "world_server/world/robot_groups.hpp"

namespace swarmform::world {

namespace {

using ojson = nlohmann::ordered_json;

ojson xy(Vec2 v) {
  return ojson::array({v.x, v.y});
}

ojson obstacle_json(const Obstacle& o) {
  ojson j;
  if (o.kind == Obstacle::Kind::Box) {
    j["kind"] = "box";
    j["name"] = o.name;
    j["centre"] = xy(o.centre);
    j["half_extents"] = xy(o.half_extents);
    j["yaw"] = o.yaw;
  } else {
    j["kind"] = "cylinder";
    j["name"] = o.name;
    j["centre"] = xy(o.centre);
    j["radius"] = o.radius;
  }
  if (!o.present) j["present"] = false;  // absent at tick 0 (world events)
  return j;
}

// The scenario's world events (world_events.hpp), by tick: what the pictures and the view replay.
ojson world_events_json(const std::vector<WorldEvent>& events, const std::vector<Obstacle>& obstacles) {
  ojson out = ojson::array();
  for (const WorldEvent& e : events) {
    ojson j;
    j["tick"] = e.tick;
    j["obstacle"] = e.obstacle;
    j["name"] = obstacles[e.obstacle].name;
    j["do"] = std::string(action_word(e.action));
    if (e.action == WorldEvent::Action::Move) {
      j["centre"] = xy(e.centre);
      j["yaw"] = e.yaw ? ojson(*e.yaw) : ojson(nullptr);
    }
    out.push_back(std::move(j));
  }
  return out;
}

// "#rrggbb", or null when the scenario gave a grey rather than a colour.
ojson colour_json(const std::optional<Rgb>& c) {
  if (!c) return nullptr;
  std::string text;
  append_rgb_hex(text, *c);
  return text;
}

// The floor as the ground sensors read it and pictures draw it: its grey (and colour), the image (the run
// folder's copy, kFloorImageFile, so that a copied run folder keeps it; where it came from; its pixel size),
// the regions in painting order.
ojson floor_json(const Floor& f) {
  ojson j;
  j["grey"] = f.grey;
  j["colour"] = colour_json(f.colour);
  if (f.image) {
    std::error_code ec;
    const std::filesystem::path abs = std::filesystem::absolute(f.image->file, ec);
    j["image"] = {{"file", kFloorImageFile},
                  {"source", ec ? f.image->file : abs.lexically_normal().string()},
                  {"width", f.image->width},
                  {"height", f.image->height}};
  } else {
    j["image"] = nullptr;
  }
  ojson regions = ojson::array();
  for (const FloorRegion& r : f.regions) {
    ojson o;
    if (r.kind == FloorRegion::Kind::Circle) {
      o["kind"] = "circle";
      o["centre"] = xy(r.centre);
      o["radius"] = r.radius;
    } else {
      o["kind"] = "rectangle";
      o["centre"] = xy(r.centre);
      o["half_extents"] = xy(r.half_extents);
      o["yaw"] = r.yaw;
    }
    o["grey"] = r.grey;
    o["colour"] = colour_json(r.colour);
    regions.push_back(std::move(o));
  }
  j["regions"] = std::move(regions);
  return j;
}

ojson deaths_json(const std::vector<DeathRecord>& records) {
  ojson list = ojson::array();
  for (const auto& d : records) list.push_back({{"id", d.id}, {"tick", d.tick}});
  return list;
}

// The live robots' states by the behaviour's names, and the mean of each of its telemetry columns over the
// live robots that reported them: what a run of any behaviour ended with (the report's "Behaviour" group).
// With robot groups, of one group's robots by its own behaviour's names.
void behaviour_at_end(const GroupView& g, const std::vector<RobotTruth>& all, ojson& j) {
  const behaviour::Descriptor* d = g.behaviour;
  if (d == nullptr) return;
  const std::span<const RobotTruth> robots(all.data() + g.first_id,
                                           std::min(g.count, all.size() - g.first_id));
  // The behaviour's parameters as the run had them (the scenario's, a --param's, or the default), so that a
  // sweep's rows and an --expect can name them (params.NAME).
  ojson params = ojson::object();
  for (const auto& p : d->params) {
    const auto it = g.mission->params.find(std::string(p.name));
    params[std::string(p.name)] = it != g.mission->params.end() ? it->second : p.default_value;
  }
  j["params"] = std::move(params);
  ojson states = ojson::object();
  for (const auto& st : d->states) states[std::string(st.name)] = 0;
  for (const RobotTruth& r : robots) {
    if (!r.alive) continue;
    std::string name = "state " + std::to_string(r.telemetry.state);
    for (const auto& st : d->states) {
      if (st.value == r.telemetry.state) name = std::string(st.name);
    }
    states[name] = states.value(name, 0) + 1;
  }
  j["states_at_end"] = std::move(states);
  if (d->telemetry.empty()) return;
  ojson means = ojson::object();
  for (std::size_t k = 0; k < d->telemetry.size(); ++k) {
    double sum = 0.0;
    std::size_t n = 0;
    for (const RobotTruth& r : robots) {
      if (!r.alive || r.telemetry.extra.size() != d->telemetry.size()) continue;
      sum += r.telemetry.extra[k];
      ++n;
    }
    means[std::string(d->telemetry[k].name)] = n > 0 ? ojson(sum / static_cast<double>(n)) : ojson(nullptr);
  }
  j["telemetry_mean_at_end"] = std::move(means);
}

// summary.json's `groups`: each group's behaviour, ids, verdict and ending states, by group name.
ojson groups_summary(const Scenario& scenario, const std::vector<const ExperimentVerdict*>& verdicts,
                     const std::vector<RobotTruth>& robots) {
  ojson out = ojson::object();
  for (std::size_t k = 0; k < scenario.groups.size() && k < verdicts.size(); ++k) {
    const GroupView g = group_view(scenario, k);
    const ExperimentVerdict& v = *verdicts[k];
    ojson j;
    j["behaviour"] = g.mission->behaviour;
    j["first_id"] = g.first_id;
    j["count"] = g.count;
    j["outcome"] = v.outcome;
    j["success"] = v.success ? ojson(*v.success) : ojson(nullptr);
    j["behaviour_metrics"] = v.metrics;
    for (const auto& [key, value] : v.fields.items()) j[key] = value;
    if (!v.error.empty()) j["experiment_error"] = v.error;
    behaviour_at_end(g, robots, j);
    out[std::string(g.name)] = std::move(j);
  }
  return out;
}

}  // namespace

ojson describe_behaviour(const Scenario& scenario) {
  return describe_behaviour(scenario, 0);
}

ojson describe_behaviour(const Scenario& scenario, std::size_t group) {
  ojson j;
  const GroupView g = group_view(scenario, group);
  const behaviour::Descriptor* d = g.behaviour;
  const Mission& mission = *g.mission;
  j["name"] = mission.behaviour;
  j["plugin"] = mission.plugin.empty() ? ojson(nullptr) : ojson(mission.plugin);
  j["descriptor"] = mission.descriptor.empty() ? ojson(nullptr) : ojson(mission.descriptor);
  if (d == nullptr) return j;
  j["summary"] = std::string(d->summary);
  j["needs_shape"] = d->needs_shape;
  j["needs_goal"] = d->needs_goal;
  const behaviour::ShapeRules& rules = d->shape_rules;
  j["shape_rules"] = {
      {"anchor", rules.anchor == behaviour::ShapeAnchor::NearestOrigin ? "nearest_origin" : "unknown"},
      {"heading_param",
       rules.heading_param.empty() ? ojson(nullptr) : ojson(std::string(rules.heading_param))},
      {"motion_state",
       rules.motion_state == behaviour::ShapeRules::kNoState ? ojson(nullptr) : ojson(rules.motion_state)}};
  ojson params = ojson::array();
  for (const auto& p : d->params) {
    auto it = mission.params.find(std::string(p.name));
    params.push_back({{"name", std::string(p.name)},
                      {"value", it != mission.params.end() ? it->second : p.default_value},
                      {"default", p.default_value},
                      {"min", p.min_value},
                      {"max", p.max_value},
                      {"doc", std::string(p.doc)}});
  }
  j["params"] = std::move(params);
  ojson states = ojson::array();
  for (const auto& st : d->states) {
    states.push_back(
        {{"value", st.value}, {"name", std::string(st.name)}, {"colour", std::string(st.colour)}});
  }
  j["states"] = std::move(states);
  ojson telemetry = ojson::array();
  for (const auto& t : d->telemetry) {
    telemetry.push_back({{"name", std::string(t.name)}, {"doc", std::string(t.doc)}});
  }
  j["telemetry"] = std::move(telemetry);
  ojson sensors = ojson::array();
  const std::string names = behaviour::sensor_names(d->sensors);
  for (std::size_t at = 0; at < names.size();) {
    const std::size_t end = std::min(names.find(", ", at), names.size());
    sensors.push_back(names.substr(at, end - at));
    at = end + 2;
  }
  j["sensors"] = std::move(sensors);
  const behaviour::ExperimentSpec& e = d->experiment;
  if (e.make == nullptr) {
    j["experiment"] = nullptr;
  } else {
    ojson metrics = ojson::array();
    for (const auto& m : e.metrics)
      metrics.push_back({{"name", std::string(m.name)}, {"doc", std::string(m.doc)}});
    ojson summary = ojson::array();
    for (const auto& f : e.summary) {
      summary.push_back({{"key", std::string(f.key)},
                         {"kind", std::string(behaviour::summary_kind_name(f.kind))},
                         {"doc", std::string(f.doc)}});
    }
    ojson outcomes = ojson::array();
    for (std::string_view o : e.outcomes) outcomes.push_back(std::string(o));
    j["experiment"] = {{"metrics", std::move(metrics)},
                       {"summary", std::move(summary)},
                       {"outcomes", std::move(outcomes)},
                       {"success", std::string(e.success)}};
  }
  return j;
}

ojson describe_groups(const Scenario& scenario) {
  if (scenario.groups.empty()) return nullptr;
  ojson list = ojson::array();
  for (std::size_t k = 0; k < scenario.groups.size(); ++k) {
    const RobotGroup& g = scenario.groups[k];
    list.push_back({{"name", g.name},
                    {"first_id", g.first_id},
                    {"count", g.count},
                    {"behaviour_descriptor", describe_behaviour(scenario, k)}});
  }
  return list;
}

ojson describe_world(const Scenario& scenario, const std::string& mode) {
  const Mission& m = scenario.mission;
  ojson j;
  j["format"] = "swarmform-recording";
  j["version"] = kRecordingVersion;
  j["scenario"] = scenario.source;
  j["seed"] = scenario.seed;
  j["mode"] = mode;
  j["tick_rate"] = scenario.tick_rate;
  j["robots"] = scenario.robots.size();
  j["arena"] = {{"centre", xy(scenario.arena_centre)},
                {"width", scenario.arena_width},
                {"height", scenario.arena_height},
                {"walls", scenario.walls},
                {"wall_thickness", scenario.wall_thickness}};
  ojson obstacles = ojson::array();
  for (const auto& o : scenario.obstacles) obstacles.push_back(obstacle_json(o));
  j["obstacles"] = std::move(obstacles);
  if (!scenario.world_events.empty())
    j["world_events"] = world_events_json(scenario.world_events, scenario.obstacles);
  j["goal"] =
      m.has_goal ? ojson{{"x", m.goal.x}, {"y", m.goal.y}, {"radius", m.goal_radius}} : ojson(nullptr);
  if (!scenario.goal_events.empty()) {  // where the goal moves, by tick (goal_events.hpp)
    ojson moves = ojson::array();
    for (const GoalEvent& e : scenario.goal_events) {
      moves.push_back({{"tick", e.tick}, {"x", e.goal.at.x}, {"y", e.goal.at.y}, {"radius", e.goal.radius}});
    }
    j["goal_moves"] = std::move(moves);
  }
  j["grid_spacing"] = m.grid_spacing;
  j["comm_range"] = scenario.comm_range;
  // The radio and the sensors' noise (docs/scenario-format.md): mean_burst null is independent loss.
  const ojson mean_burst =
      scenario.packet_loss_mean_burst > 0.0 ? ojson(scenario.packet_loss_mean_burst) : ojson(nullptr);
  j["medium"] = {{"packet_loss", {{"rate", scenario.packet_loss}, {"mean_burst", mean_burst}}},
                 {"range_noise_sd", scenario.range_noise_sd},
                 {"bearing_noise_sd", scenario.bearing_noise_sd},
                 {"ultrasonic_noise_sd", scenario.ultrasonic_noise_sd},
                 {"occlusion", scenario.occlusion}};
  // The optional sensors' world (docs/scenario-format.md): what the ground and light sensors read, the
  // batteries.
  j["floor"] = floor_json(scenario.floor);
  ojson lights = ojson::array();
  for (const LightSource& l : scenario.lights) {
    lights.push_back({{"position", xy(l.position)}, {"height", l.height}, {"intensity", l.intensity}});
  }
  j["lights"] = std::move(lights);
  if (scenario.battery) {
    const BatterySpec& b = *scenario.battery;
    j["battery"] = {{"capacity", b.capacity}, {"idle", b.idle}, {"moving", b.moving}, {"start", b.start}};
  } else {
    j["battery"] = nullptr;
  }
  j["shape"] = {{"rows", m.shape.rows}, {"cols", m.shape.cols}, {"cells", m.shape.cells}};
  j["robot_radius"] = kRobotRadius;
  j["shape_file"] = scenario.shape_file;
  j["behaviour"] = m.behaviour;
  j["behaviour_descriptor"] = describe_behaviour(scenario);  // the first group's, with groups
  if (!scenario.groups.empty()) j["groups"] = describe_groups(scenario);
  j["max_speed"] = m.max_speed;
  j["max_ticks"] = scenario.max_ticks;
  ojson kills = ojson::array();
  for (const auto& k : scenario.kills) kills.push_back({{"id", k.id}, {"tick", k.tick}});
  j["kills"] = std::move(kills);
  ojson faults = ojson::array();  // every other scheduled fault, as written (docs/scenario-format.md, Faults)
  for (const auto& f : scenario.faults) faults.push_back(f.text);
  j["faults"] = std::move(faults);
  return j;
}

ojson make_summary(const SummaryInputs& in) {
  const Metrics& m = *in.metrics;
  std::size_t alive = 0;
  for (const auto& r : *in.robots) alive += r.alive ? 1 : 0;
  const bool timed = in.wall_seconds > 0.0 && std::isfinite(in.wall_seconds);
  const double tps = timed ? static_cast<double>(in.ticks) / in.wall_seconds : 0.0;

  ojson j;
  j["format"] = "swarmform-summary";
  j["version"] = kRecordingVersion;
  j["scenario"] = in.scenario->source;
  j["shape_file"] = in.scenario->shape_file;
  j["behaviour"] = in.scenario->mission.behaviour;
  j["robots"] = in.robots->size();
  j["labels"] = std::count_if(in.scenario->mission.shape.cells.begin(),
                              in.scenario->mission.shape.cells.end(), [](int c) { return c >= 0; });
  j["seed"] = in.scenario->seed;
  j["mode"] = in.mode;
  j["ticks"] = in.ticks;
  j["wall_seconds"] = in.wall_seconds;
  j["ticks_per_second"] = timed ? ojson(tps) : ojson(nullptr);
  j["robot_ticks_per_second"] = timed ? ojson(tps * static_cast<double>(in.robots->size())) : ojson(nullptr);
  const bool steady =
      in.steady.seconds > 0.0 && std::isfinite(in.steady.seconds) && in.ticks > in.steady.from_tick;
  j["steady_from_tick"] = in.steady.from_tick;
  j["steady_ticks_per_second"] =
      steady ? ojson(static_cast<double>(in.ticks - in.steady.from_tick) / in.steady.seconds)
             : ojson(nullptr);
  j["alive_at_end"] = alive;
  j["deaths"] = deaths_json(m.deaths);
  j["rejoins"] = deaths_json(m.rejoins);
  j["collisions_robot_robot"] = m.collisions_robot_robot;
  j["collisions_robot_obstacle"] = m.collisions_robot_obstacle;
  j["leader_changes"] = m.leader_changes;
  j["fragmentations"] = m.fragmentations;
  j["graph_rejoins"] = m.graph_rejoins;
  j["max_components"] = m.max_components;
  const ExperimentVerdict none;
  const ExperimentVerdict& verdict = in.verdict != nullptr ? *in.verdict : none;
  // The experiment's own keys (the paper's formation and goal ticks, shape errors, stuck robots...), its
  // series last (summary_text).
  for (const auto& [key, value] : verdict.fields.items()) j[key] = value;
  j["outcome"] = verdict.outcome;
  j["success"] = verdict.success ? ojson(*verdict.success) : ojson(nullptr);
  j["behaviour_metrics"] = verdict.metrics;
  if (!verdict.error.empty()) j["experiment_error"] = verdict.error;
  j["silent_robots"] = m.silent_robots;
  j["command_verdicts"] = in.command_verdicts;
  behaviour_at_end(group_view(*in.scenario, 0), *in.robots, j);  // the first group's, with groups
  if (in.group_verdicts != nullptr)
    j["groups"] = groups_summary(*in.scenario, *in.group_verdicts, *in.robots);
  j["trajectory_sha256"] = in.trajectory_sha256.empty() ? ojson(nullptr) : ojson(in.trajectory_sha256);
  j["end_reason"] = in.end_reason;
  j["provenance"] = in.provenance;
  if (in.extra.is_object()) {
    for (const auto& [key, value] : in.extra.items()) j[key] = value;
  }
  for (const auto& [key, value] : verdict.series.items()) j[key] = value;
  return j;
}

ojson summary_template(const Scenario& scenario, const std::string& mode) {
  // Every robot dead: states_at_end lists the declared states, each 0, and no undeclared one.
  std::vector<RobotTruth> robots(scenario.robots.size());
  for (std::size_t k = 0; k < robots.size(); ++k) {
    robots[k].id = static_cast<RobotId>(k);
    robots[k].alive = false;
  }
  const Metrics metrics;
  const std::size_t groups = std::max<std::size_t>(scenario.groups.size(), 1);
  std::vector<ExperimentVerdict> verdicts;
  for (std::size_t k = 0; k < groups; ++k)
    verdicts.push_back(declared_verdict(group_view(scenario, k).behaviour));
  std::vector<const ExperimentVerdict*> group_verdicts;
  for (const ExperimentVerdict& v : verdicts) group_verdicts.push_back(&v);
  SummaryInputs in;
  in.scenario = &scenario;
  in.mode = mode;
  in.robots = &robots;
  in.metrics = &metrics;
  in.verdict = &verdicts.front();
  if (!scenario.groups.empty()) in.group_verdicts = &group_verdicts;
  in.provenance = provenance(scenario);
  return make_summary(in);
}

ojson check_info(const Scenario& scenario) {
  const std::string mode(to_string(scenario.mode));
  ojson j = {{"robots", scenario.robots.size()},
             {"labels", scenario.mission.shape.label_count()},
             {"mode", mode},
             {"max_ticks", scenario.max_ticks},
             {"seed", scenario.seed},
             {"behaviour_descriptor", describe_behaviour(scenario)}};
  // Each robot group's behaviour, for the launcher's check of --expect 'groups.NAME.KEY' before the run.
  if (!scenario.groups.empty()) j["groups"] = describe_groups(scenario);
  // Every key the run's summary.json will have, from the code that writes it.
  j["summary_template"] = summary_template(scenario, mode);
  return j;
}

ojson summary_outcome(const ojson& summary) {
  ojson out = ojson::object();
  ojson cut = ojson::object();
  ojson left_out = ojson::array();
  for (const auto& [key, value] : summary.items()) {
    if (is_series(value)) {
      left_out.push_back(key);
      continue;
    }
    if (value.is_array() && value.size() > kOutcomeListEntries) {
      cut[key] = value.size();
      out[key] = ojson(value.begin(), value.begin() + static_cast<std::ptrdiff_t>(kOutcomeListEntries));
    } else {
      out[key] = value;
    }
  }
  out["summary_cut"] = {{"why", "the disk was full: the whole summary did not fit the room reserved for it"},
                        {"left_out", std::move(left_out)},
                        {"lists_cut_to_" + std::to_string(kOutcomeListEntries) + "_entries", cut}};
  return out;
}

std::string summary_text(const ojson& summary) {
  ojson head = ojson::object();
  std::vector<std::pair<std::string, std::string>> series;
  for (const auto& [key, value] : summary.items()) {
    if (is_series(value)) {
      series.emplace_back(key, value.dump());
    } else {
      head[key] = value;
    }
  }
  if (series.empty() || head.empty()) return summary.dump(2) + "\n";
  std::string text = head.dump(2);  // ends with "\n}"
  text.resize(text.size() - 2);
  for (const auto& [key, line] : series) {
    text.append(",\n  ");
    text.append(ojson(key).dump());
    text.append(": ");
    text.append(line);
  }
  text.append("\n}\n");
  return text;
}

bool is_series(const ojson& value) {
  if (!value.is_array() || value.empty()) return false;
  return std::all_of(value.begin(), value.end(),
                     [](const ojson& p) { return p.is_array() && p.size() == 2; });
}

}  // namespace swarmform::world
