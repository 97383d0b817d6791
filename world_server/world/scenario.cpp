// The scenario loader: YAML (format in docs/scenario-format.md) -> an immutable, fully checked Scenario.
// Order: parse and check every field; load the shape; apply the command-line overrides; resolve the robots'
// initial poses (listed, or random from the seed); check what depends on the robot count (kills).
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
#include "world_server/world/yaml_fields.hpp"

namespace swarmform::world {
namespace {

namespace fs = std::filesystem;
using yaml::MapReader;
using yaml::Source;

constexpr double kMaxLength = 10000.0;  // m: any length beyond this is a typo
constexpr double kMaxSpeedLimit = 2.0;  // m/s: physics is verified tunnel-free well beyond this (3 m/s)
constexpr std::int64_t kMaxRobots = 100000;
constexpr double kMaxMeanBurst = 1e6;  // ticks: a burst longer than any run is a typo

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

// A coordinate of the arena (a centre, a pose): within +-kMaxLength, like every length. A farther one is a
// typo, and would leave the physics no precision (doubles near 1e300 are 1e284 apart).
double coordinate(const Source& src, const YAML::Node& n, const std::string& path) {
  return yaml::check_range(src, n, path, yaml::to_number(src, n, path), -kMaxLength, kMaxLength);
}
Vec2 point(const Source& src, const YAML::Node& n, const std::string& path) {
  const Vec2 v = yaml::to_vec2(src, n, path);
  coordinate(src, n[0], path + "[0]");
  coordinate(src, n[1], path + "[1]");
  return v;
}

Mode parse_mode(const Source& src, const YAML::Node& n, const std::string& path) {
  const std::string s = yaml::to_string(src, n, path);
  if (s == "lockstep") return Mode::Lockstep;
  if (s == "realtime") return Mode::Realtime;
  yaml::fail(src, n, path, "expected lockstep or realtime, got '" + s + "'");
}

void parse_arena(const Source& src, MapReader& top, Scenario& s) {
  auto node = top.get("arena");
  if (!node) return;
  MapReader m(src, *node, "arena");
  if (auto c = m.get("centre")) s.arena_centre = point(src, *c, m.field("centre"));
  s.arena_width = m.positive("width", s.arena_width, kMaxLength);
  s.arena_height = m.positive("height", s.arena_height, kMaxLength);
  s.walls = m.boolean("walls", s.walls);
  s.wall_thickness = m.positive("wall_thickness", s.wall_thickness, 10.0);
  m.finish({"centre", "width", "height", "walls", "wall_thickness"});
}

// A box's or a rectangle's required `size: [width along x, depth along y]`, as half extents.
Vec2 half_size(const Source& src, const YAML::Node& node, const std::string& path, MapReader& m) {
  auto size = m.get("size");
  if (!size) yaml::fail(src, node, path, "missing 'size' ([width along x, depth along y], m)");
  const Vec2 sz = yaml::to_vec2(src, *size, m.field("size"));
  yaml::check_positive(src, *size, m.field("size") + "[0]", sz.x, kMaxLength);
  yaml::check_positive(src, *size, m.field("size") + "[1]", sz.y, kMaxLength);
  return Vec2{sz.x / 2.0, sz.y / 2.0};
}

Obstacle parse_obstacle(const Source& src, const YAML::Node& node, const std::string& path) {
  MapReader m(src, node, path);
  Obstacle o;
  auto type = m.get("type");
  if (!type) yaml::fail(src, node, path, "missing 'type' (box or cylinder)");
  const std::string t = yaml::to_string(src, *type, m.field("type"));
  if (auto name = m.get("name")) o.name = yaml::to_string(src, *name, m.field("name"));
  auto centre = m.get("centre");
  if (!centre) yaml::fail(src, node, path, "missing 'centre' ([x, y], m)");
  o.centre = point(src, *centre, m.field("centre"));
  if (t == "box") {
    o.kind = Obstacle::Kind::Box;
    o.half_extents = half_size(src, node, path, m);
    o.yaw = m.number("yaw", 0.0, -2.0 * std::numbers::pi, 2.0 * std::numbers::pi);
    o.present = m.boolean("present", true);
    m.finish({"type", "name", "centre", "size", "yaw", "present"});
  } else if (t == "cylinder") {
    o.kind = Obstacle::Kind::Cylinder;
    auto radius = m.get("radius");
    if (!radius) yaml::fail(src, node, path, "missing 'radius' (m)");
    o.radius = yaml::check_positive(src, *radius, m.field("radius"),
                                    yaml::to_number(src, *radius, m.field("radius")), kMaxLength);
    o.present = m.boolean("present", true);
    m.finish({"type", "name", "centre", "radius", "present"});
  } else {
    yaml::fail(src, *type, m.field("type"), "expected box or cylinder, got '" + t + "'");
  }
  return o;
}

void parse_obstacles(const Source& src, MapReader& top, Scenario& s) {
  auto node = top.get("obstacles");
  if (!node) return;
  if (node->IsNull()) return;  // `obstacles:` with nothing after it: none
  if (!node->IsSequence()) yaml::fail(src, *node, "obstacles", "expected a list of obstacles");
  for (std::size_t i = 0; i < node->size(); ++i) {
    s.obstacles.push_back(parse_obstacle(src, (*node)[i], "obstacles[" + std::to_string(i) + "]"));
  }
}

struct RobotsSection {
  std::optional<std::size_t> count;
  std::optional<PlacementRegion> region;
  std::vector<Pose2D> poses;  // listed
  std::vector<YAML::Node> pose_nodes;
  YAML::Node node;
};

// `robots:` (or a group's `robots:`, whose fields are named under `prefix`).
RobotsSection parse_robots_node(const Source& src, const YAML::Node& node, const std::string& prefix) {
  RobotsSection r;
  r.node = node;
  MapReader m(src, node, prefix);
  if (auto c = m.get("count")) {
    const std::int64_t n = yaml::to_integer(src, *c, prefix + ".count");
    if (n < 1 || n > kMaxRobots) {
      yaml::fail(src, *c, prefix + ".count", "must be in [1, " + std::to_string(kMaxRobots) + "]");
    }
    r.count = static_cast<std::size_t>(n);
  }
  if (auto reg = m.get("region")) {
    MapReader rm(src, *reg, prefix + ".region");
    PlacementRegion pr;
    auto c = rm.get("centre");
    if (c) pr.centre = point(src, *c, rm.field("centre"));
    pr.width = rm.positive("width", 0.0, kMaxLength);
    pr.height = rm.positive("height", 0.0, kMaxLength);
    if (!rm.has("width") || !rm.has("height")) {
      yaml::fail(src, *reg, prefix + ".region", "needs centre, width and height");
    }
    rm.finish({"centre", "width", "height"});
    r.region = pr;
  }
  if (auto poses = m.get("poses")) {
    if (r.count || r.region) {
      yaml::fail(src, *poses, prefix + ".poses",
                 "give either count/region (random placement) or poses, not both");
    }
    if (!poses->IsSequence() || poses->size() == 0) {
      yaml::fail(src, *poses, prefix + ".poses", "expected a non-empty list of [x, y, theta]");
    }
    for (std::size_t i = 0; i < poses->size(); ++i) {
      const YAML::Node p = (*poses)[i];
      const std::string path = prefix + ".poses[" + std::to_string(i) + "]";
      if (!p.IsSequence() || (p.size() != 2 && p.size() != 3)) {
        yaml::fail(src, p, path, "expected [x, y] or [x, y, theta] (m, m, rad)");
      }
      Pose2D pose{coordinate(src, p[0], path + "[0]"), coordinate(src, p[1], path + "[1]"), 0.0};
      if (p.size() == 3) {
        pose.theta = yaml::check_range(src, p[2], path + "[2]", yaml::to_number(src, p[2], path + "[2]"),
                                       -2.0 * std::numbers::pi, 2.0 * std::numbers::pi);
      }
      r.poses.push_back(pose);
      r.pose_nodes.push_back(p);
    }
  }
  m.finish({"count", "region", "poses"});
  return r;
}

RobotsSection parse_robots(const Source& src, MapReader& top) {
  auto node = top.get("robots");
  if (!node) return {};
  return parse_robots_node(src, *node, "robots");
}

// A grey level: `grey: 0..1` or `colour: [r, g, b]` (0..255 each, made grey as ARGoS does), not both; the
// colour, when given, into `colour` (for pictures).
double parse_grey(const Source& src, MapReader& m, double fallback, std::optional<Rgb>& colour) {
  const bool has_grey = m.has("grey"), has_colour = m.has("colour");
  if (has_grey && has_colour) yaml::fail(src, m.node(), m.path(), "give 'grey' or 'colour', not both");
  if (has_colour) {
    auto c = *m.get("colour");
    if (!c.IsSequence() || c.size() != 3)
      yaml::fail(src, c, m.field("colour"), "expected [r, g, b], each an integer 0..255");
    std::array<std::uint8_t, 3> rgb{};
    for (std::size_t k = 0; k < 3; ++k) {
      const std::string path = m.field("colour") + "[" + std::to_string(k) + "]";
      const std::int64_t v = yaml::to_integer(src, c[k], path);
      if (v < 0 || v > 255)
        yaml::fail(src, c[k], path, "expected an integer 0..255, got " + std::to_string(v));
      rgb[k] = static_cast<std::uint8_t>(v);
    }
    colour = Rgb{rgb[0], rgb[1], rgb[2]};
    return grey_of(rgb[0], rgb[1], rgb[2]);
  }
  return m.number("grey", fallback, 0.0, 1.0);
}

FloorRegion parse_floor_region(const Source& src, const YAML::Node& node, const std::string& path) {
  MapReader m(src, node, path);
  FloorRegion r;
  auto type = m.get("type");
  if (!type) yaml::fail(src, node, path, "missing 'type' (circle or rectangle)");
  const std::string t = yaml::to_string(src, *type, m.field("type"));
  auto centre = m.get("centre");
  if (!centre) yaml::fail(src, node, path, "missing 'centre' ([x, y], m)");
  r.centre = point(src, *centre, m.field("centre"));
  if (!m.has("grey") && !m.has("colour")) yaml::fail(src, node, path, "missing 'grey' (0..1) or 'colour'");
  r.grey = parse_grey(src, m, 0.0, r.colour);
  if (t == "circle") {
    r.kind = FloorRegion::Kind::Circle;
    auto radius = m.get("radius");
    if (!radius) yaml::fail(src, node, path, "missing 'radius' (m)");
    r.radius = yaml::check_positive(src, *radius, m.field("radius"),
                                    yaml::to_number(src, *radius, m.field("radius")), kMaxLength);
    m.finish({"type", "centre", "radius", "grey", "colour"});
  } else if (t == "rectangle") {
    r.kind = FloorRegion::Kind::Rectangle;
    r.half_extents = half_size(src, node, path, m);
    r.yaw = m.number("yaw", 0.0, -2.0 * std::numbers::pi, 2.0 * std::numbers::pi);
    m.finish({"type", "centre", "size", "yaw", "grey", "colour"});
  } else {
    yaml::fail(src, *type, m.field("type"), "expected circle or rectangle, got '" + t + "'");
  }
  return r;
}

// floor: {grey, colour, image, regions}. The image is read relative to the scenario's folder and must have
// the arena's proportions (square pixels, within 1 %): it is stretched over the arena's rectangle.
void parse_floor(const Source& src, MapReader& top, const fs::path& base, Scenario& s) {
  auto node = top.get("floor");
  if (!node) return;
  MapReader m(src, *node, "floor");
  s.floor.grey = parse_grey(src, m, s.floor.grey, s.floor.colour);
  if (auto img = m.get("image")) {
    const std::string name = yaml::to_string(src, *img, m.field("image"));
    const fs::path file = fs::path(name).is_absolute() ? fs::path(name) : base / name;
    FloorImage image;
    try {
      image = load_floor_image(file.string());
    } catch (const std::runtime_error& e) {
      yaml::fail(src, *img, m.field("image"), file.string() + ": " + e.what());
    }
    const double px = s.arena_width / image.width, py = s.arena_height / image.height;
    if (std::abs(px / py - 1.0) > 0.01) {
      std::ostringstream what;
      what << file.string() << " is " << image.width << " x " << image.height << " pixels, but the arena is "
           << s.arena_width << " x " << s.arena_height
           << " m: the image is stretched over the arena, so it must have the arena's proportions (square "
              "pixels)";
      yaml::fail(src, *img, m.field("image"), what.str());
    }
    s.floor.image = std::make_shared<const FloorImage>(std::move(image));
  }
  if (auto regions = m.get("regions")) {
    if (!regions->IsSequence()) yaml::fail(src, *regions, m.field("regions"), "expected a list of regions");
    for (std::size_t i = 0; i < regions->size(); ++i)
      s.floor.regions.push_back(
          parse_floor_region(src, (*regions)[i], m.field("regions") + "[" + std::to_string(i) + "]"));
  }
  m.finish({"grey", "colour", "image", "regions"});
}

void parse_noise(const Source& src, MapReader& top, Scenario& s) {
  auto node = top.get("noise");
  if (!node) return;
  MapReader m(src, *node, "noise");
  s.range_noise_sd = m.number("range", s.range_noise_sd, 0.0, 10.0);
  s.bearing_noise_sd = m.number("bearing", s.bearing_noise_sd, 0.0, std::numbers::pi);
  s.ultrasonic_noise_sd = m.number("ultrasonic", s.ultrasonic_noise_sd, 0.0, 2.0);
  s.proximity_noise = m.number("proximity", s.proximity_noise, 0.0, 1.0);
  s.ground_noise = m.number("ground", s.ground_noise, 0.0, 1.0);
  s.light_noise = m.number("light", s.light_noise, 0.0, 1.0);
  s.lidar_noise = m.number("lidar", s.lidar_noise, 0.0, 1.0);
  m.finish({"range", "bearing", "ultrasonic", "proximity", "ground", "light", "lidar"});
}

// battery: {capacity: J, idle: W, moving: J/m, start: fraction}; capacity required.
void parse_battery(const Source& src, MapReader& top, Scenario& s) {
  auto node = top.get("battery");
  if (!node) return;
  MapReader m(src, *node, "battery");
  if (!m.has("capacity")) yaml::fail(src, *node, "battery", "missing 'capacity' (J)");
  BatterySpec b;
  b.capacity = m.positive("capacity", 1.0, 1e9);
  b.idle = m.number("idle", 0.0, 0.0, 1e6);
  b.moving = m.number("moving", 0.0, 0.0, 1e6);
  b.start = m.positive("start", 1.0, 1.0);
  m.finish({"capacity", "idle", "moving", "start"});
  s.battery = b;
}

// lidar: {rays: N, fov: rad, min_range: m, max_range: m}; every field optional (ARGoS's fan, lidar.hpp).
void parse_lidar(const Source& src, MapReader& top, Scenario& s) {
  auto node = top.get("lidar");
  if (!node) return;
  MapReader m(src, *node, "lidar");
  LidarSpec& l = s.lidar;
  l.rays = static_cast<std::uint32_t>(m.integer("rays", l.rays, 1, 10000));
  l.fov = m.positive("fov", l.fov, 2.0 * std::numbers::pi);
  l.min_range = m.number("min_range", l.min_range, 0.0, kMaxLength);
  l.max_range = m.positive("max_range", l.max_range, kMaxLength);
  if (l.min_range >= l.max_range) {
    const char* key = m.has("max_range") ? "max_range" : "min_range";
    std::ostringstream what;
    what << "min_range (" << l.min_range << " m) must be below max_range (" << l.max_range << " m)";
    yaml::fail(src, *m.get(key), m.field(key), what.str());
  }
  m.finish({"rays", "fov", "min_range", "max_range"});
}

// lights: [{position: [x, y], height: H, intensity: I}], every field required.
void parse_lights(const Source& src, MapReader& top, Scenario& s) {
  auto node = top.get("lights");
  if (!node || node->IsNull()) return;
  if (!node->IsSequence()) yaml::fail(src, *node, "lights", "expected a list of light sources");
  for (std::size_t i = 0; i < node->size(); ++i) {
    const std::string path = "lights[" + std::to_string(i) + "]";
    const YAML::Node& n = (*node)[i];
    MapReader m(src, n, path);
    LightSource l;
    for (const char* key : {"position", "height", "intensity"}) {
      if (!m.has(key)) yaml::fail(src, n, path, std::string("missing '") + key + "'");
    }
    l.position = point(src, *m.get("position"), m.field("position"));
    l.height = m.number("height", 0.0, 0.0, kMaxLength);
    l.intensity = m.positive("intensity", 1.0, 1e6);
    m.finish({"position", "height", "intensity"});
    s.lights.push_back(l);
  }
}

// packet_loss: RATE (each copy lost independently) or {rate: RATE, mean_burst: B} (bursts of B ticks on
// average per directed link, burst_loss.hpp).
void parse_packet_loss(const Source& src, MapReader& top, Scenario& s) {
  auto node = top.get("packet_loss");
  if (!node) return;
  auto rate_of = [&](const YAML::Node& n, const std::string& path) {
    const double p = yaml::to_number(src, n, path);
    if (p < 0.0 || p >= 1.0) yaml::fail(src, n, path, "must be in [0, 1)");
    return p;
  };
  if (!node->IsMap()) {
    s.packet_loss = rate_of(*node, "packet_loss");
    return;
  }
  MapReader m(src, *node, "packet_loss");
  auto rate = m.get("rate");
  auto burst = m.get("mean_burst");
  m.finish({"rate", "mean_burst"});
  if (!rate || !burst) {
    yaml::fail(src, *node, "packet_loss",
               "needs rate and mean_burst ({rate: 0.2, mean_burst: 5}: bursts of 5 ticks on average); for "
               "independent loss give a number (packet_loss: 0.2)");
  }
  s.packet_loss = rate_of(*rate, m.field("rate"));
  const double b = yaml::to_number(src, *burst, m.field("mean_burst"));
  const double lo = BurstLoss::min_mean_burst(s.packet_loss);
  if (!(b >= lo) || b > kMaxMeanBurst) {
    std::ostringstream why;
    why << "must be in [" << lo << ", " << kMaxMeanBurst << "] ticks, got " << b
        << " (the least, 1 / (1 - rate), "
        << "is the mean burst of independent loss at rate " << s.packet_loss
        << "; for independent loss give a number: packet_loss: " << s.packet_loss << ")";
    yaml::fail(src, *burst, m.field("mean_burst"), why.str());
  }
  s.packet_loss_mean_burst = b;
}

void parse_kills(const Source& src, MapReader& top, std::vector<Kill>& kills,
                 std::vector<YAML::Node>& nodes) {
  auto node = top.get("kills");
  if (!node || node->IsNull()) return;
  if (!node->IsSequence()) yaml::fail(src, *node, "kills", "expected a list of {id, tick}");
  for (std::size_t i = 0; i < node->size(); ++i) {
    const std::string path = "kills[" + std::to_string(i) + "]";
    MapReader m(src, (*node)[i], path);
    if (!m.has("id") || !m.has("tick")) yaml::fail(src, (*node)[i], path, "needs id and tick");
    Kill k;
    k.id = static_cast<RobotId>(m.integer("id", 0, 0, kMaxRobots - 1));
    k.tick = static_cast<Tick>(m.integer("tick", 0, 0, 1000000000));
    m.finish({"id", "tick"});
    kills.push_back(k);
    nodes.push_back((*node)[i]);
  }
}

// `faults:` a list of fault texts (faults.hpp). Kill faults join `kills` (one kill machinery); the others
// are kept with their nodes, to be checked once the robot count is known.
void parse_faults(const Source& src, MapReader& top, std::vector<Fault>& faults,
                  std::vector<YAML::Node>& fault_nodes, std::vector<std::string>& fault_paths,
                  std::vector<Kill>& kills, std::vector<YAML::Node>& kill_nodes,
                  std::vector<std::string>& kill_paths) {
  auto node = top.get("faults");
  if (!node || node->IsNull()) return;
  if (!node->IsSequence()) {
    yaml::fail(src, *node, "faults", "expected a list of faults, e.g. [stall:3@200+30, loss:all@400+20]");
  }
  for (std::size_t i = 0; i < node->size(); ++i) {
    const std::string path = "faults[" + std::to_string(i) + "]";
    const YAML::Node n = (*node)[i];
    if (!n.IsScalar()) yaml::fail(src, n, path, "expected a fault text KIND:TARGET@TICK[+TICKS][=VALUE]");
    Fault f;
    try {
      f = parse_fault(n.Scalar());
    } catch (const FaultSyntaxError& e) {
      yaml::fail(src, n, path, "'" + n.Scalar() + "': " + e.what());
    }
    if (f.kind == FaultKind::Kill) {
      kills.push_back(Kill{*f.robot, f.tick});
      kill_nodes.push_back(n);
      kill_paths.push_back(path);
    } else {
      faults.push_back(std::move(f));
      fault_nodes.push_back(n);
      fault_paths.push_back(path);
    }
  }
}

int parse_goal(const Source& src, MapReader& top, Mission& mission) {
  auto node = top.get("goal");
  if (!node) return 0;
  MapReader m(src, *node, "goal");
  mission.goal.x = m.number("x", mission.goal.x, -kMaxLength, kMaxLength);
  mission.goal.y = m.number("y", mission.goal.y, -kMaxLength, kMaxLength);
  mission.goal_radius = m.positive("radius", mission.goal_radius, kMaxLength);
  m.finish({"x", "y", "radius"});
  return yaml::line_of(*node);
}

// A plug-in's (or descriptor file's) path as the scenario gives it: as is when absolute, else the first of
// the scenario's folder and the registry's folders (--plugin-dir, SWARMFORM_PLUGIN_PATH) that holds it. Not
// found: InputError naming every folder searched and how to add one. The registry then refuses a plug-in
// outside its folders. `key`: "plugin" or "descriptor".
std::string resolve_plugin(const Source& src, const YAML::Node& at, const std::string& given,
                           const fs::path& base, const std::vector<fs::path>& folders,
                           const std::string& key = "plugin", const std::string& prefix = "behaviour") {
  std::error_code ec;
  const fs::path g(given);
  const std::string path = prefix + "." + key;
  const std::string what = key == "plugin" ? "plug-in '" + given + "'" : "descriptor file '" + given + "'";
  if (g.is_absolute()) {
    if (fs::exists(g, ec)) return g.string();
    yaml::fail(src, at, path, what + ": no such file");
  }
  std::vector<fs::path> searched{fs::weakly_canonical(fs::absolute(base), ec)};
  for (const fs::path& f : folders) {
    if (std::find(searched.begin(), searched.end(), f) == searched.end()) searched.push_back(f);
  }
  std::string list;
  for (const fs::path& f : searched) {
    if (fs::exists(f / g, ec)) return (f / g).string();
    list += (list.empty() ? "" : ", ") + f.string();
  }
  yaml::fail(src, at, path,
             what + " not found in the folders searched (" + list +
                 "): the scenario's folder, each --plugin-dir DIR and " + behaviour::kPluginPathVariable +
                 "; give the folder that holds it with --plugin-dir DIR");
}

const behaviour::Descriptor& named_behaviour(const Source& src, const YAML::Node* at, const std::string& name,
                                             behaviour::Registry& registry,
                                             const std::string& prefix = "behaviour") {
  if (const behaviour::Descriptor* d = registry.find(name)) return *d;
  const std::string why = "unknown behaviour '" + name + "' (built in: " + registry.names() +
                          "; a plug-in is named by its library: behaviour: {plugin: path/libx.so})";
  if (at) yaml::fail(src, *at, prefix, why);
  throw InputError(at ? src.file : "command line", 0, (at ? "" : "--behaviour: ") + why);
}

// A behaviour as chosen in the file: its descriptor and, in `mission`, its name, plug-in or descriptor file
// and parameters.
struct BehaviourChoice {
  const behaviour::Descriptor* descriptor = nullptr;
  std::optional<YAML::Node> params_node;
  std::string params_path;
};

// behaviour: NAME | {name: NAME, params: {...}} | {plugin: PATH, params: {...}} |
// {descriptor: PATH, params: {...}} (docs/scenario-format.md), at `node` (absent: the default, the paper's);
// its fields named under `prefix` ("behaviour", or a group's "groups[1].behaviour").
BehaviourChoice choose_behaviour(const Source& src, const std::optional<YAML::Node>& node,
                                 const fs::path& base, behaviour::Registry& registry,
                                 const std::string& prefix, Mission& mission) {
  BehaviourChoice c;
  const behaviour::Descriptor*& d = c.descriptor;
  if (node && node->IsMap()) {
    MapReader m(src, *node, prefix);
    auto name = m.get("name");
    auto plugin = m.get("plugin");
    auto described = m.get("descriptor");
    if ((name ? 1 : 0) + (plugin ? 1 : 0) + (described ? 1 : 0) > 1) {
      yaml::fail(src, *node, prefix,
                 "give one of name (a built-in), plugin (a library) or descriptor (a JSON file), not two");
    }
    if (described) {
      const std::string given = yaml::to_string(src, *described, prefix + ".descriptor");
      const std::string path =
          resolve_plugin(src, *described, given, base, registry.folders(), "descriptor", prefix);
      try {
        d = &registry.load_descriptor(path);
      } catch (const InputError& e) {
        yaml::fail(src, *described, prefix + ".descriptor", e.what());
      }
      mission.descriptor = fs::canonical(path).string();
    } else if (plugin) {
      const std::string given = yaml::to_string(src, *plugin, prefix + ".plugin");
      const std::string path =
          resolve_plugin(src, *plugin, given, base, registry.folders(), "plugin", prefix);
      try {
        d = &registry.load_plugin(path);
      } catch (const behaviour::PluginError& e) {
        yaml::fail(src, *plugin, prefix + ".plugin", e.what());
      }
      mission.plugin = fs::canonical(path).string();
    } else if (name) {
      d = &named_behaviour(src, &*name, yaml::to_string(src, *name, prefix + ".name"), registry, prefix);
    } else {
      yaml::fail(src, *node, prefix,
                 "expected name: (a built-in), plugin: (a shared library) or descriptor: (a JSON file)");
    }
    c.params_node = m.get("params");
    c.params_path = prefix + ".params";
    m.finish({"name", "plugin", "descriptor", "params"});
  } else if (node) {
    d = &named_behaviour(src, &*node, yaml::to_string(src, *node, prefix), registry, prefix);
  } else {
    d = &named_behaviour(src, nullptr, mission.behaviour, registry);  // the default: the paper's
  }
  return c;
}

// The file's parameters of the chosen behaviour, each checked against its own table at its line.
void set_params(const Source& src, const BehaviourChoice& c, bool behaviour_overridden, Mission& mission) {
  const behaviour::Descriptor& d = *c.descriptor;
  mission.behaviour = std::string(d.name);
  if (!c.params_node || c.params_node->IsNull()) return;
  const YAML::Node& params_node = *c.params_node;
  if (!params_node.IsMap()) yaml::fail(src, params_node, c.params_path, "expected a map of name: value");
  for (const auto& kv : params_node) {
    const std::string name = kv.first.Scalar();
    const std::string path = c.params_path + "." + name;
    // A --behaviour override runs another behaviour than the file's: the file's parameters that it does not
    // have belong to the file's behaviour and are left out (those it has are checked and kept).
    if (behaviour_overridden && !behaviour::find_param(d, name)) continue;
    if (!behaviour::find_param(d, name))
      yaml::fail(src, kv.first, path, behaviour::check_param(d, name, 0.0));
    const double value = yaml::to_number(src, kv.second, path);
    const std::string why = behaviour::check_param(d, name, value);
    if (!why.empty()) yaml::fail(src, kv.second, path, why);
    mission.params[name] = value;
  }
}

// One --param over the file's value, checked against the behaviour's table.
void apply_param(const ParamOverride& p, const std::string& name, const behaviour::Descriptor& d,
                 Mission& mission) {
  try {
    behaviour::check_params(d, {{name, p.value}});
  } catch (const InputError& e) {
    std::string why = e.what();
    if (const std::string prefix = e.file() + ": "; why.rfind(prefix, 0) == 0) why.erase(0, prefix.size());
    throw InputError("command line", 0, "--param " + p.text + ": " + why);
  }
  mission.params[name] = p.value;
}

// The top level's behaviour (and the older `controller:` section for the parameters). Every parameter is
// checked against the behaviour's own table, with the line it is on.
void parse_behaviour(const Source& src, MapReader& top, const ScenarioOverrides& ov, const fs::path& base,
                     behaviour::Registry& registry, Scenario& s) {
  BehaviourChoice c = choose_behaviour(src, top.get("behaviour"), base, registry, "behaviour", s.mission);
  if (auto ctl = top.get("controller")) {
    if (c.params_node)
      yaml::fail(src, *ctl, "controller", "the parameters are already given in behaviour.params");
    c.params_node = ctl;
    c.params_path = "controller";
  }
  if (ov.behaviour) {
    c.descriptor = &named_behaviour(src, nullptr, *ov.behaviour, registry);
    s.mission.plugin.clear();
    s.mission.descriptor.clear();
  }
  s.behaviour = c.descriptor;
  set_params(src, c, ov.behaviour.has_value(), s.mission);
  // --param: over the file's values, here, so that every check after this one (the shape's fit reads
  // shape_heading) sees the values the run will have.
  for (const ParamOverride& p : ov.params) {
    if (p.name.find('.') != std::string::npos) {
      throw InputError("command line", 0,
                       "--param " + p.text +
                           ": GROUP.NAME names a robot group, and this scenario has no "
                           "groups: (give NAME=VALUE)");
    }
    apply_param(p, p.name, *s.behaviour, s.mission);
  }
}

bool inside_arena(const Scenario& s, Vec2 p) {
  return std::abs(p.x - s.arena_centre.x) <= s.arena_width / 2.0 &&
         std::abs(p.y - s.arena_centre.y) <= s.arena_height / 2.0;
}

// Robot poses: listed (checked), or random in the given or default region (clipped to the arena).
// Where a group's robots are placed: `prefix` names its fields ("robots", "groups[1].robots"); `group` its
// index (its own stream of the seed); `default_count` the count when the file gives none (0: none). The poses
// are appended to s.robots (ids go on from the robots placed before).
void resolve_robots(const Source& src, const RobotsSection& r, const ScenarioOverrides& ov, Scenario& s,
                    const std::string& prefix = "robots", std::size_t group = 0,
                    std::optional<std::size_t> default_count = std::nullopt) {
  const std::size_t first = s.robots.size();
  if (!r.poses.empty()) {
    if (ov.robots && *ov.robots != r.poses.size()) {
      throw InputError(src.file, yaml::line_of(r.node),
                       "robots: --robots " + std::to_string(*ov.robots) + " conflicts with the " +
                           std::to_string(r.poses.size()) + " poses listed here");
    }
    std::vector<Pose2D> all = s.robots;
    all.insert(all.end(), r.poses.begin(), r.poses.end());
    for (std::size_t k = 0; k < r.poses.size(); ++k) {
      const std::string why = check_listed_pose(all, first + k, s);
      if (!why.empty()) yaml::fail(src, r.pose_nodes[k], prefix + ".poses[" + std::to_string(k) + "]", why);
    }
    s.robots = std::move(all);
    return;
  }
  const std::size_t n = ov.robots       ? *ov.robots
                        : r.count       ? *r.count
                        : default_count ? *default_count
                                        : static_cast<std::size_t>(s.mission.shape.label_count());
  if (n < 1 && (s.shape_file.empty() || default_count)) {
    throw InputError(src.file, yaml::line_of(r.node),
                     prefix + ": give " + prefix + ".count or " + prefix + ".poses (behaviour '" +
                         (default_count ? s.groups[group].mission.behaviour : s.mission.behaviour) +
                         "' has no shape to count the robots from)");
  }
  if (n < 1) throw InputError(src.file, yaml::line_of(r.node), "robots: need at least one robot");
  PlacementRegion region = r.region ? *r.region : default_region(n);
  if (!r.region && s.walls) {
    // Clip the default square to the arena's interior.
    const double x_lo =
        std::max(region.centre.x - region.width / 2.0, s.arena_centre.x - s.arena_width / 2.0);
    const double x_hi =
        std::min(region.centre.x + region.width / 2.0, s.arena_centre.x + s.arena_width / 2.0);
    const double y_lo =
        std::max(region.centre.y - region.height / 2.0, s.arena_centre.y - s.arena_height / 2.0);
    const double y_hi =
        std::min(region.centre.y + region.height / 2.0, s.arena_centre.y + s.arena_height / 2.0);
    region = PlacementRegion{Vec2{(x_lo + x_hi) / 2.0, (y_lo + y_hi) / 2.0}, std::max(x_hi - x_lo, 0.0),
                             std::max(y_hi - y_lo, 0.0)};
  }
  auto poses = place_randomly(n, region, s, s.seed, s.robots, group);
  if (!poses) {
    std::ostringstream why;
    why << prefix << ": cannot place " << n << " robots in the region " << region.width << " x "
        << region.height << " m centred at (" << region.centre.x << ", " << region.centre.y << ") at least "
        << kMinSeparation << " m apart and clear of obstacles"
        << (first > 0 ? " and of the robots placed before them" : "") << "; give a larger " << prefix
        << ".region";
    throw InputError(src.file, yaml::line_of(r.node), why.str());
  }
  s.robots.insert(s.robots.end(), poses->begin(), poses->end());
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

// One item of `groups:` as read: its name, behaviour and robots (placed once the shape and goal are known).
struct GroupSection {
  RobotsSection robots;
  YAML::Node node;
};

bool lower_case_name(const std::string& n) {
  if (n.empty() || !(n[0] >= 'a' && n[0] <= 'z')) return false;
  return std::all_of(n.begin(), n.end(),
                     [](char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_'; });
}

// `groups:` (docs/scenario-format.md "Groups"): instead of the top level's robots: and behaviour:. Fills
// s.groups (names, behaviours, parameters) and makes the first group's behaviour and parameters the
// scenario's own; the robots are placed later (resolve_groups).
std::vector<GroupSection> parse_groups(const Source& src, const YAML::Node& node, MapReader& top,
                                       const RobotsSection& top_robots, const ScenarioOverrides& ov,
                                       const fs::path& base, behaviour::Registry& registry, Scenario& s) {
  if (top.has("robots")) {
    yaml::fail(src, top_robots.node, "robots",
               "give groups: or a top-level robots:, not both (each group has its own robots:)");
  }
  for (const char* key : {"behaviour", "controller"}) {
    if (auto n = top.get(key)) {
      yaml::fail(src, *n, key,
                 std::string("give groups: or a top-level ") + key +
                     ":, not both (each group has its own "
                     "behaviour:, its parameters in behaviour.params)");
    }
  }
  if (ov.behaviour) {
    throw InputError("command line", 0,
                     "--behaviour: the scenario has groups:, each naming its own behaviour; change them in "
                     "the file");
  }
  if (ov.robots) {
    throw InputError("command line", 0,
                     "--robots: the scenario has groups:, each with its own robots.count; change them in the "
                     "file (or --set 'groups=...')");
  }
  if (!node.IsSequence() || node.size() == 0) {
    yaml::fail(src, node, "groups", "expected a non-empty list of {name, behaviour, robots}");
  }
  std::vector<GroupSection> sections;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const YAML::Node item = node[i];
    const std::string path = "groups[" + std::to_string(i) + "]";
    MapReader m(src, item, path);
    RobotGroup g;
    auto name = m.get("name");
    if (!name) yaml::fail(src, item, path, "missing 'name' (lower_case, unique)");
    g.name = yaml::to_string(src, *name, path + ".name");
    if (!lower_case_name(g.name)) {
      yaml::fail(src, *name, path + ".name",
                 "'" + g.name + "' is not lower_case (a-z first, then a-z, 0-9 or _)");
    }
    for (const RobotGroup& other : s.groups) {
      if (other.name == g.name) yaml::fail(src, *name, path + ".name", "'" + g.name + "' is given twice");
    }
    auto behaviour_node = m.get("behaviour");
    if (!behaviour_node) yaml::fail(src, item, path, "missing 'behaviour' (as the top level's behaviour:)");
    auto robots_node = m.get("robots");
    if (!robots_node) yaml::fail(src, item, path, "missing 'robots' ({count, region} or {poses})");
    m.finish({"name", "behaviour", "robots"});
    const BehaviourChoice c =
        choose_behaviour(src, behaviour_node, base, registry, path + ".behaviour", g.mission);
    g.behaviour = c.descriptor;
    set_params(src, c, false, g.mission);
    s.groups.push_back(std::move(g));
    sections.push_back({parse_robots_node(src, *robots_node, path + ".robots"), item});
  }
  // --param NAME=V is the first group's, --param GROUP.NAME=V that group's.
  for (const ParamOverride& p : ov.params) {
    const auto dot = p.name.find('.');
    RobotGroup* into = &s.groups.front();
    std::string name = p.name;
    if (dot != std::string::npos) {
      const std::string group = p.name.substr(0, dot);
      name = p.name.substr(dot + 1);
      into = nullptr;
      std::string known;
      for (RobotGroup& g : s.groups) {
        if (g.name == group) into = &g;
        known += (known.empty() ? "" : ", ") + g.name;
      }
      if (into == nullptr) {
        throw InputError("command line", 0,
                         "--param " + p.text + ": no robot group '" + group + "' (groups: " + known + ")");
      }
    }
    apply_param(p, name, *into->behaviour, into->mission);
  }
  const RobotGroup& first = s.groups.front();
  s.behaviour = first.behaviour;
  s.mission.behaviour = first.mission.behaviour;
  s.mission.plugin = first.mission.plugin;
  s.mission.descriptor = first.mission.descriptor;
  s.mission.params = first.mission.params;
  return sections;
}

// Whether any of the run's behaviours forms a shape / goes somewhere (every group's, or the one).
bool any_needs_shape(const Scenario& s) {
  for (std::size_t k = 0; k < group_count(s); ++k) {
    if (group_view(s, k).behaviour->needs_shape) return true;
  }
  return false;
}
bool any_needs_goal(const Scenario& s) {
  for (std::size_t k = 0; k < group_count(s); ++k) {
    if (group_view(s, k).behaviour->needs_goal) return true;
  }
  return false;
}

// Places every group's robots in group order (ids contiguous), each group's mission the scenario's run-wide
// fields with its own behaviour and parameters.
void resolve_groups(const Source& src, const std::vector<GroupSection>& sections, const ScenarioOverrides& ov,
                    Scenario& s) {
  for (std::size_t k = 0; k < sections.size(); ++k) {
    RobotGroup& g = s.groups[k];
    Mission own = std::move(g.mission);
    g.mission = s.mission;
    g.mission.behaviour = std::move(own.behaviour);
    g.mission.plugin = std::move(own.plugin);
    g.mission.descriptor = std::move(own.descriptor);
    g.mission.params = std::move(own.params);
    g.first_id = static_cast<RobotId>(s.robots.size());
    const std::optional<std::size_t> count =
        g.behaviour->needs_shape ? static_cast<std::size_t>(s.mission.shape.label_count()) : 0;
    resolve_robots(src, sections[k].robots, ov, s, "groups[" + std::to_string(k) + "].robots", k, count);
    g.count = s.robots.size() - g.first_id;
    if (s.robots.size() > static_cast<std::size_t>(kMaxRobots)) {
      throw InputError(src.file, yaml::line_of(sections[k].node),
                       "groups: " + std::to_string(s.robots.size()) + " robots in all, more than " +
                           std::to_string(kMaxRobots));
    }
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
