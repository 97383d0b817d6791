#include "world_server/world/scenario_sections.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>
#include <span>
#include <sstream>

#include "common/input_error.hpp"
#include "world_server/world/burst_loss.hpp"

namespace swarmform::world::scenario_parts {

namespace fs = std::filesystem;
using yaml::MapReader;
using yaml::Source;

namespace {

constexpr double kMaxMeanBurst = 1e6;  // ticks: a burst longer than any run is a typo

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

}  // namespace

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

void parse_obstacles(const Source& src, MapReader& top, Scenario& s) {
  auto node = top.get("obstacles");
  if (!node) return;
  if (node->IsNull()) return;  // `obstacles:` with nothing after it: none
  if (!node->IsSequence()) yaml::fail(src, *node, "obstacles", "expected a list of obstacles");
  for (std::size_t i = 0; i < node->size(); ++i) {
    s.obstacles.push_back(parse_obstacle(src, (*node)[i], "obstacles[" + std::to_string(i) + "]"));
  }
}
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

bool inside_arena(const Scenario& s, Vec2 p) {
  return std::abs(p.x - s.arena_centre.x) <= s.arena_width / 2.0 &&
         std::abs(p.y - s.arena_centre.y) <= s.arena_height / 2.0;
}

// Robot poses: listed (checked), or random in the given or default region (clipped to the arena).
// Where a group's robots are placed: `prefix` names its fields ("robots", "groups[1].robots"); `group` its
// index (its own stream of the seed); `default_count` the count when the file gives none (0: none). The poses
// are appended to s.robots (ids go on from the robots placed before).
void resolve_robots(const Source& src, const RobotsSection& r, const ScenarioOverrides& ov, Scenario& s,
                    const std::string& prefix, std::size_t group, std::optional<std::size_t> default_count) {
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

}  // namespace swarmform::world::scenario_parts
