// The scenario loader: YAML (format in docs/scenario-format.md) -> an immutable, fully checked Scenario.
// Order: parse and check every field; load the shape; apply the command-line overrides; resolve the robots'
// initial poses (listed, or random from the seed); check what depends on the robot count (kills). The parts it
// puts together: the world's and the robots' sections (scenario_sections.cpp), the behaviour and its
// parameters (scenario_behaviour.cpp), a mixed swarm's groups (scenario_groups.cpp).
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <numbers>
#include <span>
#include <sstream>

#include "behaviour/params.hpp"
#include "common/input_error.hpp"
#include "common/shape.hpp"
#include "world_server/world/burst_loss.hpp"
#include "world_server/world/placement.hpp"
#include "world_server/world/robot_groups.hpp"
#include "world_server/world/scenario.hpp"
#include "world_server/world/scenario_behaviour.hpp"
#include "world_server/world/scenario_groups.hpp"
#include "world_server/world/scenario_sections.hpp"
#include "world_server/world/yaml_fields.hpp"

namespace swarmform::world {
namespace {

namespace fs = std::filesystem;
using yaml::MapReader;
using yaml::Source;

using namespace scenario_parts;  // the parts the loader puts together
                                 // (scenario_sections/behaviour/groups.hpp)

constexpr double kMaxSpeedLimit = 2.0;  // m/s: physics is verified tunnel-free well beyond this (3 m/s)

// The folder to resolve relative paths against: the scenario file's, or the working directory.
fs::path base_folder(const std::string& origin) {
  std::error_code ec;
  fs::path p = fs::absolute(fs::path(origin), ec);
  if (ec) return fs::current_path();
  fs::path dir = p.parent_path();
  return fs::is_directory(dir, ec) ? dir : fs::current_path();
}

// The repository root: the first folder upwards from `from` that holds shapes/.
std::optional<fs::path> repo_root_from(fs::path from) {
  std::error_code ec;
  for (fs::path p = fs::absolute(from, ec); !p.empty(); p = p.parent_path()) {
    if (fs::is_directory(p / "shapes", ec)) return p;
    if (p == p.parent_path()) break;
  }
  return std::nullopt;
}

// A shape path: as given when absolute; else under each of `folders`, then under the repository's shapes/
// (and the repository root itself, for paths written as shapes/x.txt).
std::string resolve_shape(const std::string& given, const std::vector<fs::path>& folders,
                          std::vector<std::string>& tried) {
  std::error_code ec;
  const fs::path g(given);
  auto ok = [&](const fs::path& p) {
    tried.push_back(p.string());
    return fs::is_regular_file(p, ec);
  };
  if (g.is_absolute()) return ok(g) ? g.string() : std::string();
  for (const fs::path& f : folders) {
    if (ok(f / g)) return (f / g).lexically_normal().string();
  }
  for (const fs::path& f : folders) {
    if (auto root = repo_root_from(f)) {
      if (ok(*root / "shapes" / g)) return (*root / "shapes" / g).lexically_normal().string();
      if (ok(*root / g)) return (*root / g).lexically_normal().string();
    }
  }
  return {};
}

// The shape must fit inside the walls from where it forms (docs/scenario-format.md, "The shape must fit").
// Checked for a behaviour whose descriptor says where its label 0 stands (ShapeRules::anchor); every other
// label L stands at label 0 + R(heading - pi/2) * offset(L) (ShapeRules::heading_param). For NearestOrigin
// the robots' start poses are known here (listed, or drawn from the seed), so label 0 is taken at the robot
// nearest the origin and, should it die and another be elected, at every robot less than one grid spacing
// farther from the origin than it; every place must then lie inside the walls less a body radius.
// With groups: each group whose behaviour forms the shape, from its own robots' start.
void check_shape_fits(const Source& src, const Scenario& s, int shape_line, bool shape_from_command_line,
                      const GroupView& group) {
  if (!s.walls || !group.behaviour->needs_shape) return;
  const behaviour::ShapeRules& rules = group.behaviour->shape_rules;
  if (rules.anchor != behaviour::ShapeAnchor::NearestOrigin) return;
  const ShapeMatrix& shape = s.mission.shape;
  const auto [r0, c0] = shape.cell_of(0);
  if (r0 < 0) return;
  const double heading = behaviour::shape_heading(*group.mission, *group.behaviour);
  const std::span<const Pose2D> robots(s.robots.data() + group.first_id, group.count);
  const std::string heading_name = rules.heading_param.empty() ? "heading" : std::string(rules.heading_param);
  const double rot = heading - std::numbers::pi / 2.0;
  const double cr = std::cos(rot);
  const double sr = std::sin(rot);
  const double g = s.mission.grid_spacing;
  // Rotated offsets from label 0: their extent along x and y, and which label reaches each end.
  double lo_x = 0.0, hi_x = 0.0, lo_y = 0.0, hi_y = 0.0;
  int l_lo_x = 0, l_hi_x = 0, l_lo_y = 0, l_hi_y = 0;
  for (int row = 0; row < shape.rows; ++row) {
    for (int col = 0; col < shape.cols; ++col) {
      const int label = shape.at(row, col);
      if (label < 0) continue;
      const double ox = g * (col - c0);
      const double oy = -g * (row - r0);
      const double x = cr * ox - sr * oy;
      const double y = sr * ox + cr * oy;
      if (x < lo_x) {
        lo_x = x;
        l_lo_x = label;
      }
      if (x > hi_x) {
        hi_x = x;
        l_hi_x = label;
      }
      if (y < lo_y) {
        lo_y = y;
        l_lo_y = label;
      }
      if (y > hi_y) {
        hi_y = y;
        l_hi_y = label;
      }
    }
  }
  const double margin = kRobotRadius;
  const double wx_lo = s.arena_centre.x - s.arena_width / 2.0 + margin;
  const double wx_hi = s.arena_centre.x + s.arena_width / 2.0 - margin;
  const double wy_lo = s.arena_centre.y - s.arena_height / 2.0 + margin;
  const double wy_hi = s.arena_centre.y + s.arena_height / 2.0 - margin;
  // Label 0's possible places: the robot nearest the origin, and those within a grid spacing of its distance.
  double nearest = std::numeric_limits<double>::infinity();
  for (const Pose2D& p : robots) nearest = std::min(nearest, std::hypot(p.x, p.y));
  std::vector<Vec2> origins;
  for (const Pose2D& p : robots) {
    if (std::hypot(p.x, p.y) <= nearest + g) origins.push_back({p.x, p.y});
  }
  std::stable_sort(origins.begin(), origins.end(),
                   [](Vec2 a, Vec2 b) { return std::hypot(a.x, a.y) < std::hypot(b.x, b.y); });
  for (const Vec2& o : origins) {
    int label = -1;
    if (o.x + lo_x < wx_lo)
      label = l_lo_x;
    else if (o.x + hi_x > wx_hi)
      label = l_hi_x;
    else if (o.y + lo_y < wy_lo)
      label = l_lo_y;
    else if (o.y + hi_y > wy_hi)
      label = l_hi_y;
    if (label < 0) continue;
    const auto [row, col] = shape.cell_of(label);
    const double ox = g * (col - c0);
    const double oy = -g * (row - r0);
    std::ostringstream what;
    what << "shape: " << fs::path(s.shape_file).filename().string()
         << (shape_from_command_line ? " (--shape)" : "") << " (" << shape.rows << " x " << shape.cols << ", "
         << shape.label_count() << " labels, grid_spacing " << g << " m, " << heading_name << " " << heading
         << ") cannot fit inside the walls from where it forms: with label 0 at (" << o.x << ", " << o.y
         << ")"
         << (std::hypot(o.x, o.y) == nearest
                 ? ", where the robot nearest the origin starts,"
                 : ", where a robot starts that would be elected should the nearest one die,")
         << " label " << label << "'s place (" << o.x + cr * ox - sr * oy << ", " << o.y + sr * ox + cr * oy
         << ") lies outside the walls' interior x in [" << wx_lo << ", " << wx_hi << "], y in [" << wy_lo
         << ", " << wy_hi
         << "] (less a body radius); give a larger arena, a smaller shape or grid_spacing, or a start "
         << "region (robots.region)" << (rules.heading_param.empty() ? "" : " and " + heading_name)
         << " that leave the shape room";
    throw InputError(src.file, shape_line, what.str());
  }
}
Scenario parse(const YAML::Node& root, const std::string& origin, const ScenarioOverrides& ov,
               behaviour::Registry& registry) {
  const Source src{origin};
  Scenario s;
  s.source = origin;
  if (root.IsNull()) throw InputError(origin, 0, "the scenario is empty (it needs at least `shape: <file>`)");
  MapReader top(src, root, "");

  parse_arena(src, top, s);
  parse_obstacles(src, top, s);
  const RobotsSection robots = parse_robots(src, top);
  s.comm_range = top.positive("comm_range", s.comm_range, kMaxLength);
  parse_noise(src, top, s);
  parse_lights(src, top, s);
  parse_battery(src, top, s);
  parse_lidar(src, top, s);
  parse_packet_loss(src, top, s);
  s.occlusion = top.boolean("occlusion", s.occlusion);
  if (auto n = top.get("mode")) s.mode = parse_mode(src, *n, "mode");
  s.tick_rate = top.positive("tick_rate", s.tick_rate, 1000.0);
  s.substeps = static_cast<int>(top.integer("substeps", s.substeps, 1, 1000));
  s.lockstep_deadline_s = top.positive("lockstep_deadline", s.lockstep_deadline_s, 3600.0);
  if (auto n = top.get("seed")) s.seed = yaml::to_unsigned(src, *n, "seed");
  s.max_ticks =
      static_cast<Tick>(top.integer("max_ticks", static_cast<std::int64_t>(s.max_ticks), 1, 1000000000));
  std::vector<YAML::Node> kill_nodes;
  parse_kills(src, top, s.kills, kill_nodes);
  std::vector<std::string> kill_paths;
  for (std::size_t i = 0; i < kill_nodes.size(); ++i)
    kill_paths.push_back("kills[" + std::to_string(i) + "]");
  std::vector<YAML::Node> fault_nodes;
  std::vector<std::string> fault_paths;
  parse_faults(src, top, s.faults, fault_nodes, fault_paths, s.kills, kill_nodes, kill_paths);
  parse_world_events(src, top, s);
  const int goal_line = parse_goal(src, top, s.mission);
  s.mission.grid_spacing = top.positive("grid_spacing", s.mission.grid_spacing, 100.0);
  s.mission.max_speed = top.positive("max_speed", s.mission.max_speed, kMaxSpeedLimit);
  s.mission.max_message_bytes =
      static_cast<std::uint32_t>(top.integer("max_message_bytes", s.mission.max_message_bytes, 1, 65536));
  const fs::path base = base_folder(origin);
  parse_floor(src, top, base, s);
  std::vector<GroupSection> group_sections;
  if (auto groups = top.get("groups")) {
    group_sections = parse_groups(src, *groups, top, robots, ov, base, registry, s);
  } else {
    parse_behaviour(src, top, ov, base, registry, s);
  }
  auto shape_node = top.get("shape");
  if (auto d = top.get("description")) yaml::to_string(src, *d, "description");  // for people; not used
  top.finish({"description",  "arena",
              "obstacles",    "robots",
              "comm_range",   "noise",
              "packet_loss",  "occlusion",
              "mode",         "tick_rate",
              "substeps",     "lockstep_deadline",
              "seed",         "max_ticks",
              "kills",        "faults",
              "goal",         "shape",
              "grid_spacing", "max_speed",
              "behaviour",    "max_message_bytes",
              "controller",   "floor",
              "lights",       "battery",
              "lidar",        "events",
              "groups"});

  // Overrides (before placement, so --robots and --seed take effect).
  if (ov.seed) s.seed = *ov.seed;
  if (ov.mode) s.mode = *ov.mode;
  const Tick file_max_ticks = s.max_ticks;
  if (ov.max_ticks) {
    if (*ov.max_ticks < 1) throw InputError("command line", 0, "--max-ticks must be >= 1");
    s.max_ticks = *ov.max_ticks;
  }
  if (ov.robots && (*ov.robots < 1 || *ov.robots > static_cast<std::size_t>(kMaxRobots))) {
    throw InputError("command line", 0, "--robots must be in [1, " + std::to_string(kMaxRobots) + "]");
  }

  // The shape: the override's path (from the working directory first), else the file's `shape`; required only
  // by a behaviour that needs one.
  std::vector<std::string> tried;
  if (ov.shape_file) {
    s.shape_file = resolve_shape(*ov.shape_file, {fs::current_path(), base}, tried);
    if (s.shape_file.empty()) {
      std::string list;
      for (const auto& t : tried) list += (list.empty() ? "" : ", ") + t;
      throw InputError("command line", 0,
                       "--shape: file '" + *ov.shape_file + "' not found (looked at " + list + ")");
    }
  } else if (shape_node) {
    const std::string given = yaml::to_string(src, *shape_node, "shape");
    s.shape_file = resolve_shape(given, {base}, tried);
    if (s.shape_file.empty()) {
      std::string list;
      for (const auto& t : tried) list += (list.empty() ? "" : ", ") + t;
      yaml::fail(src, *shape_node, "shape", "file '" + given + "' not found (looked at " + list + ")");
    }
  } else if (any_needs_shape(s)) {
    throw InputError(origin, 0,
                     "shape: missing (behaviour '" + s.mission.behaviour +
                         "' forms a shape: give the shape file, e.g. shape: triangle.txt)");
  }
  if (!s.shape_file.empty()) s.mission.shape = load_shape_file(s.shape_file);

  // No goal: a behaviour that goes somewhere is told the default one (checked below); any other is told there
  // is none rather than a point it would take for one.
  if (goal_line == 0 && !any_needs_goal(s)) {
    s.mission.has_goal = false;
    s.mission.goal = Vec2{0.0, 0.0};
    s.mission.goal_radius = 0.0;
  }
  // Goal inside the walls (else the formation can never get there), for a behaviour that goes to one.
  if (any_needs_goal(s) && s.walls && !inside_arena(s, s.mission.goal)) {
    std::ostringstream what;
    what << "goal: (" << s.mission.goal.x << ", " << s.mission.goal.y << ")"
         << (goal_line == 0 ? " (the default)" : "") << " lies outside the arena's walls";
    throw InputError(origin, goal_line, what.str());
  }

  check_goal_events(origin, s);

  // What the robots are told (before the groups copy the run-wide fields).
  s.mission.tick_rate = s.tick_rate;
  s.mission.comm_range = s.comm_range;
  s.mission.seed = s.seed;
  if (group_sections.empty()) {
    resolve_robots(src, robots, ov, s);
  } else {
    resolve_groups(src, group_sections, ov, s);
  }
  for (std::size_t k = 0; k < group_count(s); ++k) {
    check_shape_fits(src, s, shape_node && !ov.shape_file ? yaml::line_of(*shape_node) : 0,
                     ov.shape_file.has_value(), group_view(s, k));
  }

  s.kills.insert(s.kills.end(), ov.kills.begin(), ov.kills.end());
  // --fault texts: kills join the kills (after --kill's), the others the faults.
  std::vector<std::string> flag_kill_texts;
  std::vector<std::string> flag_fault_texts;
  for (const std::string& text : ov.faults) {
    Fault f;
    try {
      f = parse_fault(text);
    } catch (const FaultSyntaxError& e) {
      throw InputError("command line", 0, "--fault '" + text + "': " + e.what());
    }
    if (f.kind == FaultKind::Kill) {
      s.kills.push_back(Kill{*f.robot, f.tick});
      flag_kill_texts.push_back(text);
    } else {
      s.faults.push_back(std::move(f));
      flag_fault_texts.push_back(text);
    }
  }
  const std::size_t flag_kills_from = s.kills.size() - flag_kill_texts.size();
  const std::size_t file_kills = kill_nodes.size();
  for (std::size_t i = 0; i < s.kills.size(); ++i) {
    // A kill after the last tick would never happen. The file's own kills are held to the file's max_ticks
    // only: a --max-ticks that cuts the run short leaves them out on purpose (a probe, a short test run).
    const Tick last = i < file_kills ? file_max_ticks : s.max_ticks;
    const bool too_late = s.kills[i].tick > last;
    if (s.kills[i].id < s.robots.size() && !too_late) continue;
    const std::string what =
        too_late
            ? "kill at tick " + std::to_string(s.kills[i].tick) + ", after the run's last tick (max_ticks " +
                  std::to_string(last) +
                  "): it would never happen; give a tick <= max_ticks or a larger max_ticks (--max-ticks)"
            : "kill of robot " + std::to_string(s.kills[i].id) + ", but there are only " +
                  std::to_string(s.robots.size()) + " robots";
    // The file's kills, then its kill faults: kill_nodes holds their nodes in this order.
    if (i < kill_nodes.size()) yaml::fail(src, kill_nodes[i], kill_paths[i], what);
    if (i >= flag_kills_from) {
      throw InputError("command line", 0, "--fault '" + flag_kill_texts[i - flag_kills_from] + "': " + what);
    }
    throw InputError("command line", 0, "--kill: " + what);
  }
  FaultContext context{s.robots.size(), s.comm_range, {}};
  for (const Kill& k : s.kills) context.kills.emplace_back(k.id, k.tick);
  const std::size_t flag_faults_from = s.faults.size() - flag_fault_texts.size();
  for (std::size_t i = 0; i < s.faults.size(); ++i) {
    std::string what = check_fault(s.faults, i, context);
    const Tick last = i < flag_faults_from ? file_max_ticks : s.max_ticks;
    if (what.empty() && s.faults[i].tick > last) {
      what = "it starts at tick " + std::to_string(s.faults[i].tick) +
             ", after the run's last tick (max_ticks " + std::to_string(last) +
             "): it would never happen; give a tick <= max_ticks or a larger max_ticks (--max-ticks)";
    }
    if (what.empty()) continue;
    if (i < flag_faults_from)
      yaml::fail(src, fault_nodes[i], fault_paths[i], "'" + s.faults[i].text + "': " + what);
    throw InputError("command line", 0, "--fault '" + s.faults[i].text + "': " + what);
  }

  return s;
}

}  // namespace

std::string_view to_string(Mode m) {
  return m == Mode::Lockstep ? "lockstep" : "realtime";
}

Scenario parse_scenario_text(const std::string& yaml_text, const std::string& origin,
                             const ScenarioOverrides& overrides, behaviour::Registry& behaviours) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::ParserException& e) {
    throw InputError(origin, e.mark.is_null() ? 0 : e.mark.line + 1, "YAML syntax: " + e.msg);
  }
  apply_field_overrides(root, overrides.fields);
  try {
    return parse(root, origin, overrides, behaviours);
  } catch (const YAML::Exception& e) {  // anything yaml-cpp throws that our checks did not foresee
    throw InputError(origin, e.mark.is_null() ? 0 : e.mark.line + 1, e.msg);
  } catch (const InputError& e) {
    // An error in a field the command line set is the flag's, not the file line's.
    if (e.file() != origin || overrides.fields.empty()) throw;
    std::string what = e.what();
    const std::string prefix = e.line() > 0 ? origin + ":" + std::to_string(e.line()) + ": " : origin + ": ";
    if (what.compare(0, prefix.size(), prefix) == 0) what = what.substr(prefix.size());
    const FieldOverride* f = override_of_error(overrides.fields, what);
    if (f == nullptr) throw;
    throw InputError("command line", 0, "--set '" + f->text + "': " + what);
  }
}

Scenario load_scenario(const std::string& path, const ScenarioOverrides& overrides,
                       behaviour::Registry& behaviours) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "cannot open the scenario file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(path, 0, "cannot read the scenario file");
  return parse_scenario_text(text.str(), path, overrides, behaviours);
}

}  // namespace swarmform::world
