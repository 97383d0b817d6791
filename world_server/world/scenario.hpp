// The scenario: an immutable description of one run (arena, obstacles, robots, medium, mode, goal, shape,
// controller parameters), loaded from a YAML file in scenarios/ (format: docs/scenario-format.md) and then
// never changed. The mutable state lives in World.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "behaviour/descriptor.hpp"
#include "behaviour/registry.hpp"
#include "common/mission.hpp"
#include "common/types.hpp"
#include "world_server/world/battery.hpp"
#include "world_server/world/faults.hpp"
#include "world_server/world/field_overrides.hpp"
#include "world_server/world/floor.hpp"
#include "world_server/world/goal_events.hpp"
#include "world_server/world/lidar_spec.hpp"
#include "world_server/world/world_events.hpp"

namespace swarmform::world {

struct Obstacle {
  enum class Kind { Box, Cylinder };
  Kind kind = Kind::Box;
  std::string name;     // for the log and the pictures
  Vec2 centre;          // m
  double yaw = 0.0;     // rad (boxes)
  Vec2 half_extents;    // m (boxes): half width along the box's x, half depth along its y
  double radius = 0.0;  // m (cylinders)
  bool present = true;  // there at tick 0 (`present: false`: it starts absent); world events change it
};

// A light source for the light sensors (light.hpp).
struct LightSource {
  Vec2 position;           // m, arena frame
  double height = 0.0;     // m above the floor
  double intensity = 1.0;  // ARGoS's reference intensity: a reading is exp(-2 d / I) at d m
};

enum class Mode { Lockstep, Realtime };

// A robot group (`groups:`, docs/scenario-format.md "Groups"): robots first_id..first_id+count-1 run their
// own behaviour with their own parameters. The mission's run-wide fields (shape, goal, speed limit...) are
// the scenario's, the same in every group's.
struct RobotGroup {
  std::string name;  // lower_case, unique
  RobotId first_id = 0;
  std::size_t count = 0;
  Mission mission;                                   // what this group's robots are told
  const behaviour::Descriptor* behaviour = nullptr;  // never null in a loaded scenario
};

struct Kill {  // a scheduled fault: SIGKILL agent `id` (multi-process) or kill its robot (in-process) at
               // `tick`
  RobotId id = 0;
  Tick tick = 0;
};

struct Scenario {
  std::string source;  // path of the file it came from

  // Arena: a rectangle centred at `arena_centre`, walls on its four sides when `walls`.
  Vec2 arena_centre{4.0, 0.0};
  double arena_width = 20.0;   // m, along x
  double arena_height = 12.0;  // m, along y
  bool walls = true;
  double wall_thickness = 0.1;           // m
  std::vector<Obstacle> obstacles;       // as they stand at tick 0
  std::vector<WorldEvent> world_events;  // `events:` that act on obstacles, by tick (world_events.hpp)
  std::vector<GoalEvent> goal_events;    // `events:` that move the goal, by tick (goal_events.hpp)

  // Robots: ids 0..robots.size()-1, initial poses resolved (listed in the file, or random in a region from
  // the seed: never overlapping, communication graph connected).
  std::vector<Pose2D> robots;

  // Medium and sensors (docs/scenario-format.md).
  double comm_range = 3.0;              // m
  double range_noise_sd = 0.0;          // m, Gaussian noise on a received message's range
  double bearing_noise_sd = 0.0;        // rad, on its bearing
  double ultrasonic_noise_sd = 0.0;     // m, on each ultrasonic reading
  double proximity_noise = 0.0;         // in [0,1]: uniform +-this on each infrared reading (proximity.hpp)
  double ground_noise = 0.0;            // in [0,1]: uniform +-this on each ground reading (ground.hpp)
  double light_noise = 0.0;             // in [0,1]: uniform +-this on each light reading (light.hpp)
  double lidar_noise = 0.0;             // m, in [0,1]: uniform +-this on each lidar ray that hit (lidar.hpp)
  LidarSpec lidar;                      // the lidar's fan (lidar.hpp); ARGoS's by default
  std::vector<LightSource> lights;      // what the light sensors see (light.hpp)
  std::optional<BatterySpec> battery;   // none: the robots' batteries never run down (battery.hpp)
  Floor floor;                          // what the ground sensors read (floor.hpp); plain white by default
  double packet_loss = 0.0;             // probability in [0,1) that one copy of a message is lost
  double packet_loss_mean_burst = 0.0;  // ticks: > 0, the loss comes in bursts (Gilbert-Elliott, per
                                        // directed link); 0, independently per copy
  bool occlusion = false;               // obstacles block messages (line of sight)

  // Time.
  Mode mode = Mode::Lockstep;
  double tick_rate = 10.0;            // ticks per simulated (and, in realtime, wall) second
  int substeps = 10;                  // physics substeps per tick
  double lockstep_deadline_s = 30.0;  // lockstep waits this long for a live agent's command, then ends
  std::uint64_t seed = 1;
  Tick max_ticks = 3000;
  std::vector<Kill> kills;  // the file's `kills`, kill faults and --kill
  // Every other scheduled fault (faults.hpp), checked against the robots, the comm range and the kills.
  std::vector<Fault> faults;

  // What the robots are told (goal, shape, speed limit, the behaviour's name, plug-in and parameters...).
  // With groups: the first group's (robot_groups.hpp gives each robot its own).
  Mission mission;
  std::string shape_file;  // path the shape came from (for the log); empty when the scenario has no shape
  // The behaviour's descriptor (static data: a built-in's or a loaded plug-in's), resolved at load through
  // the registry given to load_scenario. Never null in a loaded scenario. With groups: the first group's.
  const behaviour::Descriptor* behaviour = nullptr;
  // The file's `groups:`, in id order (contiguous ids from 0); empty when it has none (every robot runs
  // `behaviour` with `mission`).
  std::vector<RobotGroup> groups;
};

// Command-line overrides, applied before random placement is resolved (so --robots and --seed take effect).
// `--param NAME=VALUE` (swarm_inprocess, what `swarm sweep --param` varies): a behaviour parameter over the
// file's.
struct ParamOverride {
  std::string text;  // as given, for messages
  std::string name;
  double value = 0.0;
};

struct ScenarioOverrides {
  std::optional<std::string> shape_file;
  std::optional<std::size_t> robots;
  std::optional<std::uint64_t> seed;
  std::optional<Mode> mode;
  std::optional<Tick> max_ticks;
  std::vector<Kill> kills;               // appended to the file's
  std::vector<std::string> faults;       // --fault texts (faults.hpp), appended to the file's
  std::optional<std::string> behaviour;  // a registered behaviour's name, instead of the file's
  // Set over the file's parameters before anything that uses them is checked (the shape's fit reads
  // shape_heading); each checked against the behaviour's table ("command line: --param TEXT: why").
  std::vector<ParamOverride> params;
  // --set KEY=VALUE (field_overrides.hpp): any field over the file's, checked as the file's are.
  std::vector<FieldOverride> fields;
};

// Loads and checks a scenario; throws InputError (file:line: what) on anything wrong. A relative shape path
// is resolved against the scenario file's folder, then against the repository's shapes/ folder. The
// behaviour is resolved through `behaviours` (a plug-in is loaded into it: relative paths against the
// scenario's folder, then each of the registry's plug-in folders) and its parameters are checked against its
// own table; `shape:` is required only when the behaviour needs one, the goal only checked when it needs one.
Scenario load_scenario(const std::string& path, const ScenarioOverrides& overrides,
                       behaviour::Registry& behaviours);
Scenario parse_scenario_text(const std::string& yaml_text, const std::string& origin,
                             const ScenarioOverrides& overrides, behaviour::Registry& behaviours);

std::string_view to_string(Mode m);

}  // namespace swarmform::world
