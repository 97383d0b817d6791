// The motion phases' part of a robot's broadcast: the opaque `motion` bytes of RobotMessage (message.hpp).
// Little-endian, versioned, 22 bytes:
//   u8 version (1)   u8 flags (bit 0 leader, bit 1 arrived, bit 2 wall-following)
//   i32 parent id (-1 none)   f32 |F_net|   f32 vx   f32 vy  (the sender's desired velocity, arena frame)
//   f32 strain: the largest lag in the sender's subtree (its F_net towards the goal, and its
//       children's strains), passed up
//       the tree so that the leader learns how far behind the shape has fallen (motion_phase.hpp)
// decode_motion_section never trusts its input (nullopt on a wrong size, version or a non-finite number).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "common/types.hpp"

namespace swarmform::controller::motion {

struct MotionSection {
  bool leader = false;
  bool arrived = false;
  bool wall_following = false;
  std::int32_t parent = -1;
  double net_force = 0.0;  // |F_net|
  Vec2 velocity;           // m/s, arena frame
  double strain = 0.0;     // max lag over the sender's subtree (motion_phase.hpp)
};

std::vector<std::uint8_t> encode_motion_section(const MotionSection& s);
std::optional<MotionSection> decode_motion_section(std::span<const std::uint8_t> bytes);

}  // namespace swarmform::controller::motion
