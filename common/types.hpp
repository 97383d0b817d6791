// The plain data that crosses between the world and a robot's controller, once per tick.
// No DDS, no Bullet: the world library fills these, the DDS adapters copy them to and from the IDL types, and
// the controller reads a Perception and returns a Command. Units: metres, radians, seconds, metres per
// second.
//
// Angle convention (as ARGoS's range-and-bearing sensor): a bearing is measured in the receiver's own frame,
// counter-clockwise from its heading (+x of the robot), wrapped to (-pi, pi]. Headings in the arena frame are
// counter-clockwise from the arena's +x axis.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace swarmform {

using RobotId = std::uint32_t;
using Tick = std::uint64_t;

struct Vec2 {
  double x = 0.0;  // m
  double y = 0.0;  // m
  friend bool operator==(const Vec2&, const Vec2&) = default;
};

struct Pose2D {
  double x = 0.0;      // m, arena frame
  double y = 0.0;      // m, arena frame
  double theta = 0.0;  // rad, heading, arena frame, (-pi, pi]
};

// The Khepera IV's five ultrasonic sensors, facing these directions in the robot frame (the front pi).
inline constexpr std::size_t kUltrasonicCount = 5;
inline constexpr std::array<double, kUltrasonicCount> kUltrasonicAngles = {
    -1.5707963267948966, -0.7853981633974483, 0.0, 0.7853981633974483, 1.5707963267948966};
inline constexpr double kUltrasonicMinRange = 0.25;  // m: readings are clamped up to this
inline constexpr double kUltrasonicMaxRange = 2.0;   // m: "nothing seen" reads exactly this

// Khepera IV geometry.
inline constexpr double kRobotRadius = 0.0704;   // m
inline constexpr double kRobotHeight = 0.053;    // m
inline constexpr double kWheelRadius = 0.021;    // m
inline constexpr double kWheelSpacing = 0.1054;  // m, distance between the two wheels
inline constexpr double kRobotMass = 0.4;        // kg

// One message heard this tick: what a neighbour sent last tick, as the range-and-bearing medium delivers it.
struct RabReading {
  RobotId sender = 0;              // the sender's id (as Buzz's `neighbors` keys them)
  double range = 0.0;              // m, centre to centre (with noise if the scenario sets it)
  double bearing = 0.0;            // rad, in the receiver's frame (see the convention above)
  std::vector<std::uint8_t> data;  // the sender's payload, opaque to the world
};

// The rest of ARGoS's Khepera IV (ilpincy/argos3-kheperaiv): sensors a behaviour reads only when its
// descriptor declares them (behaviour/descriptor.hpp Sensor), and the three RGB LEDs on top.
inline constexpr std::size_t kProximityCount = 8;  // infrared ring
inline constexpr std::size_t kLightCount = 8;      // light sensors on the same ring
inline constexpr std::size_t kGroundCount = 4;     // ground sensors underneath
inline constexpr std::size_t kLedCount = 3;
// The infrared ring's sensor k faces kProximityAngles[k] in the robot frame (counter-clockwise from the
// heading): 0, 45, ..., 180, -135, -90, -45 degrees (ARGoS kheperaiv_entity.cpp: a ring of 8 from angle 0).
// A reading is 0 (nothing within 0.12 m of the sensor) to 1 (a body closer than 0.04 m):
// world_server/world/proximity.hpp.
inline constexpr std::array<double, kProximityCount> kProximityAngles = {0.0,
                                                                         0.7853981633974483,
                                                                         1.5707963267948966,
                                                                         2.356194490192345,
                                                                         3.141592653589793,
                                                                         -2.356194490192345,
                                                                         -1.5707963267948966,
                                                                         -0.7853981633974483};

// One lidar ray: where it points and what it measured.
struct LidarRay {
  double angle = 0.0;  // rad, robot frame, counter-clockwise from the heading
  double range = 0.0;  // m
};

// A goal: a disc in the arena.
struct Goal {
  Vec2 at;              // m, arena frame
  double radius = 0.0;  // m
  friend bool operator==(const Goal&, const Goal&) = default;
};

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  friend bool operator==(const Rgb&, const Rgb&) = default;
};

// Everything a robot perceives in one tick. The controller gets nothing else. The optional sensors are empty
// (nullopt, no rays) when not equipped: the behaviour did not declare them, so the world computed nothing.
struct Perception {
  Tick tick = 0;
  Pose2D pose;                                        // positioning sensor, arena frame
  std::array<double, kUltrasonicCount> ultrasonic{};  // m, in [kUltrasonicMinRange, kUltrasonicMaxRange]
  std::vector<RabReading> messages;                   // heard this tick, any order
  std::optional<std::array<double, kProximityCount>> proximity;  // infrared ring (Sensor::Proximity)
  std::optional<std::array<double, kLightCount>> light;          // light ring (Sensor::Light)
  std::optional<std::array<double, kGroundCount>> ground;        // floor under the robot (Sensor::Ground)
  std::vector<LidarRay> lidar;                                   // (Sensor::Lidar)
  std::optional<double> battery;                                 // charge left, 0..1 (Sensor::Battery)
  // The run's goal as it stands this tick: the mission's until a world event moves it
  // (docs/scenario-format.md "World events"); nullopt when the run has none. Every robot is told, as the
  // mission tells every robot.
  std::optional<Goal> goal;
};

// What the controller reports about itself, for the recorder and the metrics only (never delivered to
// robots).
struct Telemetry {
  std::int32_t state = 0;  // the behaviour's state (its descriptor's `states`; the paper's: robot_state.hpp)
  // The behaviour's own telemetry columns (its descriptor's `telemetry`, in that order): recorded in
  // robots.csv. Empty or exactly as many values as the descriptor names. Columns named label, parent, leader
  // or net_force carry those quantities, which the world knows (behaviour/known_columns.hpp).
  std::vector<double> extra;
  // What happened in the controller this tick that the recorder should log, one event a string:
  // "<kind> <detail>", kind one word (e.g. "seed_elected", "label_taken 3", "label_lost 3 to 7",
  // "label_freed 3 holder 5", "label_abandoned 3", "barrier_passed 8/9"). Usually empty.
  std::vector<std::string> events;
};

// One tick's output of the controller.
struct Command {
  double left_speed = 0.0;            // m/s, linear speed of the left wheel's rim
  double right_speed = 0.0;           // m/s
  std::vector<std::uint8_t> message;  // broadcast to the neighbours in range next tick; empty = say nothing
  std::array<Rgb, kLedCount> leds{};  // the three RGB LEDs on top; all off unless set
  Telemetry telemetry;
};

}  // namespace swarmform
