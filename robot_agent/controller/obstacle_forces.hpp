// Obstacles (paper III.E): repulsion from the five ultrasonic readings, eq. (6)-(7), with the directions in
// which a neighbour stands left out (Algorithm 2), and the size discrimination that picks the strategy.
//
//   eq. (6)  F_obs = - sum_s m (1/r_s - 1/R) (cos a_s x + sin a_s y)     over unmasked sensors with r_s < R
//   eq. (7)  m ∝ |F_goal|
//
// Choices where the paper is loose:
// - The paper writes m / r_s along the sensor's direction; a repulsion points away from the echo, hence the
//   minus sign, and we subtract m / R so that the force starts from zero at the obstacle range R
//   (`obstacle_range`) instead of jumping to m / R when an echo enters it.
// - eq. (7): the leader uses m = m_obstacle |F_goal|. Followers do not know the goal, so they use
//   m = m_obstacle * v_cruise, the saturated |F_goal| every robot knows from the parameters (the same m the
//   leader has while cruising).
// - Algorithm 2: sensor s is masked when some neighbour j (range-and-bearing, body frame) satisfies
//   |bearing_j - a_s| < neighbour_mask_angle + atan(robot radius / range_j) (the neighbour's own angular
//   half-size) AND the echo is no nearer than that neighbour's near side, r_s >= range_j - 2 radius - slack.
//   An echo clearly nearer than the neighbour is something between us, so it stays.
// - Size discrimination by ultrasonic fusion: take the run of adjacent unmasked sensors whose echoes are
//   nearer than `fusion_range` and that holds the nearest echo. One sensor: SMALL. Three or more: LARGE (a
//   post never fills three cones 45 degrees apart). Two: SMALL only if their readings are within
//   kRoundRatio of each other (the near side of something round; a plane seen head-on by sensors at 0 and
//   45 degrees reads in the ratio 1 : 1.41) and their echo points lie closer than `small_obstacle_width`.
//   SMALL: the affected robot wall-follows around it; LARGE: eq. (6) repulsion, the perimeter gives way.
//   (The motion phase also latches LARGE for a while, so that a wall seen end-on for a tick is not taken
//   for a post.)
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <vector>

#include "common/types.hpp"
#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller::motion {

using UltrasonicArray = std::array<double, kUltrasonicCount>;
using SensorMask = std::array<bool, kUltrasonicCount>;  // true: left out (a neighbour stands there)

// A neighbour in the robot's own frame, as the range-and-bearing sensor gives it, or, not heard this tick,
// where it is estimated to stand; `uncertainty` (m) is how far off that estimate may be (0: heard now).
struct NeighbourBearing {
  double range = 0.0;    // m, centre to centre
  double bearing = 0.0;  // rad, body frame
  double uncertainty = 0.0;
};

// Algorithm 2's test for one sensor and one neighbour: the neighbour stands within the sensor's direction
// (the angle between `neighbour_angle` and `sensor_angle`, both in one frame, is below the mask angle plus
// the neighbour's own angular half-size) and its near side is no further than the reading, so the echo is
// that neighbour.
inline bool neighbour_explains_echo(double neighbour_angle, double sensor_angle, double reading, double range,
                                    double mask_angle, double slack) {
  // The range test first: it rejects most neighbours of a crowd before the angle is wrapped and the
  // arctangent taken (same verdict: both halves are pure).
  if (!(reading >= range - 2.0 * kRobotRadius - slack)) return false;
  const double off = wrap_angle(neighbour_angle - sensor_angle);
  const double half_size = std::atan2(kRobotRadius, std::max(range, kRobotRadius));
  return std::abs(off) < mask_angle + half_size;
}

// Algorithm 2's mask. `slack`: m of tolerance on the range consistency. A neighbour's `uncertainty` widens
// both tests by that much (the range by it, the angle by what it subtends at the neighbour's range).
SensorMask mask_neighbour_directions(const UltrasonicArray& readings,
                                     const std::vector<NeighbourBearing>& neighbours, double mask_angle,
                                     double slack);

enum class ObstacleSize { None, Small, Large };

inline constexpr double kRoundRatio = 1.15;

struct ObstacleSense {
  Vec2 force;  // eq. (6), arena frame (already rotated by the robot's heading)
  ObstacleSize size = ObstacleSize::None;
  double nearest = kUltrasonicMaxRange;  // m, nearest unmasked echo
  double nearest_bearing = 0.0;          // rad, body frame, of that echo's sensor
  int sensors_seeing = 0;                // unmasked sensors with an echo nearer than fusion_range
  int run_length = 0;                    // adjacent seeing sensors in the run that holds the nearest echo
};

struct ObstacleParams {
  double m = 0.0;                     // eq. (6)-(7) gain, m^2/s
  double obstacle_range = 0.6;        // R, m
  double fusion_range = 1.0;          // m, echoes used to judge the obstacle's size
  double small_obstacle_width = 0.5;  // m
};

// `theta`: the robot's heading in the arena frame (to rotate the force out of the body frame).
ObstacleSense sense_obstacles(const UltrasonicArray& readings, const SensorMask& mask, double theta,
                              const ObstacleParams& params);

// eq. (6) with a short memory. A differential-drive robot turns while it avoids, and its five cones sweep:
// an obstacle beside it is seen one tick and lost the next, and a force that comes and goes makes the robot
// dither on the spot. So the echoes of the last `max_age` ticks are kept as points in the arena frame, and
// eq. (6) sums, over eight 45-degree sectors around the robot, the nearest remembered echo of each sector
// (like eight sensors all round, each reading what was last seen there). Masked directions (Algorithm 2)
// are never remembered.
class EchoMemory {
 public:
  void add(const UltrasonicArray& readings, const SensorMask& mask, const Pose2D& pose, Tick tick,
           double max_range);
  Vec2 force(Vec2 position, Tick tick, double m, double obstacle_range, Tick max_age);
  // The nearest echo point of the last `max_age` ticks within `within` of `position` (centre to point).
  std::optional<Vec2> nearest(Vec2 position, Tick tick, double within, Tick max_age);
  // Where the nearest surface is, for boundary following: at the nearest echo's distance, in the mean
  // direction of the echoes within kSurfaceBand of that distance. A reading is placed on its sensor's axis,
  // so one echo alone can lie well off the surface: against a wall, every cone that sees it reads the minimum
  // range, and the nearest such point may lie beside the robot, along the wall (a leader then followed the
  // wall into the wall and stood there for good). Their mean direction is the wall's normal.
  std::optional<Vec2> surface(Vec2 position, Tick tick, double within, Tick max_age);
  // The far side of a passage: the distance from `position` to the nearest echo point of the last `max_age`
  // ticks within `within` that lies across the robot from `surface` (within 60 degrees of the direction from
  // `surface` through `position`); none when there is none. Boundary following keeps to the middle of a
  // passage narrower than its two keeps (wall_follow.hpp).
  std::optional<double> across(Vec2 position, Vec2 surface, Tick tick, double within, Tick max_age);
  // A gap ahead: echoes of the last `max_age` ticks within `obstacle_range` (of the robot's surface) on
  // both sides of the unit direction `d` (ahead of the robot's side-line), and none within `clearance` of
  // the way `obstacle_range` + a body radius along `d` (a robot centre driving straight there would come
  // no nearer to anything it saw).
  bool gap_ahead(Vec2 position, Vec2 d, double obstacle_range, double clearance, Tick tick, Tick max_age);
  // The echo points of the last `max_age` ticks (arena frame).
  std::vector<Vec2> points(Tick tick, Tick max_age);
  void clear() { echoes_.clear(); }

 private:
  struct Echo {
    Vec2 point;  // arena frame, on the obstacle's surface
    Tick tick;
  };
  std::vector<Echo> echoes_;
};

}  // namespace swarmform::controller::motion
