// The run's generic metrics, computed from the truth for every behaviour (docs/recording-format.md). Updated
// once per tick by RunSession. What is particular to a behaviour (the paper's formation and goal ticks, shape
// errors...) is its experiment's (behaviour/experiment.hpp), never the world's.
#pragma once

#include <cstdint>
#include <vector>

#include "common/types.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::world {

// A live robot whose commands carried no message for this many ticks (or that never broadcast, from this
// tick on) is silent: nobody hears it (experiment::RobotTruth::silent; summary silent_robots).
inline constexpr Tick kSilentTicks = 50;
inline bool is_silent(const RobotTruth& r, Tick tick) {
  return r.alive &&
         (r.last_broadcast_tick ? tick >= *r.last_broadcast_tick + kSilentTicks : tick >= kSilentTicks);
}

struct DeathRecord {
  RobotId id = 0;
  Tick tick = 0;
};

struct Metrics {
  std::uint32_t collisions_robot_robot = 0;     // contact onsets
  std::uint32_t collisions_robot_obstacle = 0;  // contact onsets (walls, obstacles, dead bodies)
  std::vector<RobotId> silent_robots;           // live at the end but silent (kSilentTicks)
  std::vector<DeathRecord> deaths;
  std::vector<DeathRecord> rejoins;
  std::uint32_t leader_changes = 0;  // times the robot reporting leader=true changed (first one not counted)
  // The communication graph of the live robots (edges: true distance <= the fragment range), watched from
  // the tick the behaviour's experiment says it stood formed (experiment::Formation) on.
  std::uint32_t fragmentations = 0;  // times it went from one component to several
  std::uint32_t graph_rejoins = 0;   // times it went from several components back to one
  std::uint32_t max_components = 0;  // the most components seen at once (1 = never split)
};

}  // namespace swarmform::world
