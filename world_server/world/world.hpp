// The world: Bullet physics, the sensors and the range-and-bearing medium for N Khepera IV robots. No DDS.
// The tick order is written once, in World::step (act, physics, medium, sense), after ARGoS:
//
//   perception(i) for tick t  --> controllers --> apply_command(i, cmd of tick t) --> step() --> tick t+1
//
// A message in the command of tick t is delivered, range-filtered, in the perceptions of tick t+1.
// Same scenario, same commands => bit-identical states (single-threaded Bullet, bodies added in a fixed
// order).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/types.hpp"
#include "world_server/world/scenario.hpp"

namespace swarmform::world {

// The truth about one robot, for the recorder and metrics (never shown to a controller).
struct RobotTruth {
  RobotId id = 0;
  Pose2D pose;
  bool alive = true;
  Telemetry telemetry;                // what its controller last reported
  std::array<Rgb, kLedCount> leds{};  // its LEDs as last commanded (off after a rebirth)
  // The tick at which `telemetry` was applied (apply_command before the step to telemetry_tick + 1). The
  // recorder writes telemetry.events only when they are new (telemetry_tick + 1 == the recorded tick): a
  // robot whose command did not come keeps its old telemetry, whose events must not be logged twice.
  Tick telemetry_tick = 0;
  // The last tick whose command carried a message (a broadcast), if any. The metrics leave out a live robot
  // that has said nothing for a while: nobody can hear it, so it cannot take part in a decentralised shape.
  std::optional<Tick> last_broadcast_tick;
  // Its battery's charge, 0..1 (1 when the scenario has no battery), and the tick it ran out, if it did
  // (from then on its wheels stay stopped; the recorder logs a battery_empty event at that tick).
  double battery = 1.0;
  std::optional<Tick> battery_empty_tick;
};

// What the world did with a command (anything but Ok is logged as an event by the caller's recorder).
enum class CommandVerdict {
  Ok,
  Clamped,            // a wheel speed over the limit was clamped to it
  RejectedNonFinite,  // NaN or infinity: the robot keeps still this tick
  MessageDropped,     // outgoing message over max_message_bytes: dropped, wheels applied
  DeadRobot,          // the robot is dead: ignored
  UnknownRobot,       // no such id: ignored
};
std::string_view to_string(CommandVerdict v);

// Contact onsets this tick (a pair counts once when it starts touching, not every tick it stays in contact).
struct ContactCounts {
  std::uint32_t robot_robot = 0;
  std::uint32_t robot_obstacle = 0;  // walls, obstacles and dead robots' bodies
};

class World {
 public:
  explicit World(const Scenario& scenario);
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  const Scenario& scenario() const;
  Tick tick() const;
  std::size_t robot_count() const;

  // The perception of robot `id` for the current tick (pose, ultrasonics, messages sent last tick).
  // The messages' bytes are copied in at the first call of a tick (see copy_perception for why), so calls
  // from several threads at once must be for different ids.
  const Perception& perception(RobotId id) const;

  // The optional sensors' readings of robot `id` for the current tick (Perception's proximity, light,
  // ground, lidar and battery: never deferred) in its perception, whose ultrasonics and messages may not be
  // read yet (defer_perceptions). Computes nothing: the recorder reads it without pulling deferred work onto
  // its thread or changing what a later perception() gives.
  const Perception& optional_sensors(RobotId id) const;

  // A caller's reusable copy of perceptions: its readings keep their byte buffers from robot to robot, so
  // a copy allocates nothing once warm and its bytes stay in this thread's cache for the controller. One per
  // thread.
  struct PerceptionCopy {
    Perception perception;
    std::vector<RabReading> spare;  // readings the last copy did not need, kept with their buffers
  };
  // Copies the perception of robot `id` (the same contents as perception(id)) into `copy` and returns it.
  // The world is not modified: several threads may copy at once (each into its own PerceptionCopy), as long
  // as none calls perception() meanwhile. The in-process harness steps its controllers on these copies: at
  // N = 1000 the messages' bytes (~73 neighbours x up to 528 bytes per robot) would otherwise be written
  // into every robot's perception, ~40 MB a tick, and read back from memory by the controllers.
  const Perception& copy_perception(RobotId id, PerceptionCopy& copy) const;

  // On: each robot's messages are gathered by the medium, and its ultrasonics read, when its perception is
  // first read (perception() or copy_perception(), on the reader's thread) instead of in step(), with the
  // same readings in the same order; off (the default) in step(), on the worker pool. The in-process
  // harness reads every perception from the pool: the inbox and the readings are written straight into the
  // reading core's copy, nothing of every robot written at the step and read back cold. world_server reads
  // them in its packet loop: robot i's are computed just before its packet goes, while the robots already
  // written compute, not in the step every agent waits for. Messages are not deferred on ticks where the
  // medium draws random numbers (loss, noise), nor ultrasonics with ultrasonic noise: those draws are made
  // in robot order in step(). Takes effect from the next step().
  void defer_perceptions(bool on);

  // The command of robot `id` for the current tick; checked and clamped here (world_server/world/README.md).
  // A robot with no command this tick keeps its last wheel speeds and says nothing.
  CommandVerdict apply_command(RobotId id, const Command& command);

  // Advances one tick: wheel speeds -> Bullet substeps -> the world events of the new tick
  // (world_events.hpp) -> medium -> sensors.
  void step();

  // A dead robot stops, says nothing, hears nothing, and stays as a body that others' sensors see.
  void kill(RobotId id);
  // Back to life as a fresh robot where its body stands (its controller is re-initialised by the caller).
  void revive(RobotId id);
  bool alive(RobotId id) const;

  const std::vector<RobotTruth>& robots() const;
  // Contacts that began during the last step.
  ContactCounts last_contacts() const;
  // The scenario's obstacles as they stand at the current tick (each one's `present` says whether it is).
  const std::vector<Obstacle>& obstacles() const;
  // The run's goal as it stands at the current tick (goal_events.hpp); nullopt when the run has none.
  const std::optional<Goal>& goal() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace swarmform::world
