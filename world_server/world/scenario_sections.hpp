// The scenario file's sections that describe the world and its robots (docs/scenario-format.md), each read
// and checked at its line: parts of the loader (scenario.cpp puts them together), not an API of their own.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "world_server/world/placement.hpp"
#include "world_server/world/scenario.hpp"
#include "world_server/world/yaml_fields.hpp"

namespace swarmform::world::scenario_parts {

inline constexpr double kMaxLength = 10000.0;  // m: any length beyond this is a typo
inline constexpr std::int64_t kMaxRobots = 100000;

// A coordinate of the arena (a centre, a pose): within +-kMaxLength, like every length.
double coordinate(const yaml::Source& src, const YAML::Node& n, const std::string& path);
Vec2 point(const yaml::Source& src, const YAML::Node& n, const std::string& path);
Mode parse_mode(const yaml::Source& src, const YAML::Node& n, const std::string& path);
void parse_arena(const yaml::Source& src, yaml::MapReader& top, Scenario& s);
void parse_obstacles(const yaml::Source& src, yaml::MapReader& top, Scenario& s);

struct RobotsSection {
  std::optional<std::size_t> count;
  std::optional<PlacementRegion> region;
  std::vector<Pose2D> poses;  // listed
  std::vector<YAML::Node> pose_nodes;
  YAML::Node node;
};

// `robots:` (or a group's `robots:`, whose fields are named under `prefix`).
RobotsSection parse_robots_node(const yaml::Source& src, const YAML::Node& node, const std::string& prefix);
RobotsSection parse_robots(const yaml::Source& src, yaml::MapReader& top);
// floor: {grey, colour, image, regions}, the image read relative to `base`.
void parse_floor(const yaml::Source& src, yaml::MapReader& top, const std::filesystem::path& base,
                 Scenario& s);
void parse_noise(const yaml::Source& src, yaml::MapReader& top, Scenario& s);
void parse_battery(const yaml::Source& src, yaml::MapReader& top, Scenario& s);
void parse_lidar(const yaml::Source& src, yaml::MapReader& top, Scenario& s);
void parse_lights(const yaml::Source& src, yaml::MapReader& top, Scenario& s);
void parse_packet_loss(const yaml::Source& src, yaml::MapReader& top, Scenario& s);
void parse_kills(const yaml::Source& src, yaml::MapReader& top, std::vector<Kill>& kills,
                 std::vector<YAML::Node>& nodes);
// `faults:` a list of fault texts (faults.hpp). Kill faults join `kills`; the others are kept with their
// nodes, to be checked once the robot count is known.
void parse_faults(const yaml::Source& src, yaml::MapReader& top, std::vector<Fault>& faults,
                  std::vector<YAML::Node>& fault_nodes, std::vector<std::string>& fault_paths,
                  std::vector<Kill>& kills, std::vector<YAML::Node>& kill_nodes,
                  std::vector<std::string>& kill_paths);
// goal: {x, y, radius} into `mission`; its line (0: none given).
int parse_goal(const yaml::Source& src, yaml::MapReader& top, Mission& mission);

bool inside_arena(const Scenario& s, Vec2 p);
// Robot poses: listed (checked), or random in the given or default region (clipped to the arena), appended
// to s.robots. `prefix` names the fields ("robots", "groups[1].robots"); `group` the group's index (its own
// stream of the seed); `default_count` the count when the file gives none.
void resolve_robots(const yaml::Source& src, const RobotsSection& r, const ScenarioOverrides& ov, Scenario& s,
                    const std::string& prefix = "robots", std::size_t group = 0,
                    std::optional<std::size_t> default_count = std::nullopt);

}  // namespace swarmform::world::scenario_parts
