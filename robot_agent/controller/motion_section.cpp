#include "robot_agent/controller/motion_section.hpp"

#include <bit>
#include <cmath>
#include <cstring>

namespace swarmform::controller::motion {

namespace {

constexpr std::uint8_t kVersion = 1;
constexpr std::size_t kSize = 22;

void put_u32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
std::uint32_t get_u32(std::span<const std::uint8_t> b, std::size_t at) {
  std::uint32_t v = 0;
  for (std::size_t i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(b[at + i]) << (8 * i);
  return v;
}
void put_f32(std::vector<std::uint8_t>& out, double v) {
  put_u32(out, std::bit_cast<std::uint32_t>(static_cast<float>(v)));
}
double get_f32(std::span<const std::uint8_t> b, std::size_t at) {
  return static_cast<double>(std::bit_cast<float>(get_u32(b, at)));
}

}  // namespace

std::vector<std::uint8_t> encode_motion_section(const MotionSection& s) {
  std::vector<std::uint8_t> out;
  out.reserve(kSize);
  out.push_back(kVersion);
  out.push_back(
      static_cast<std::uint8_t>((s.leader ? 1 : 0) | (s.arrived ? 2 : 0) | (s.wall_following ? 4 : 0)));
  put_u32(out, static_cast<std::uint32_t>(s.parent));
  put_f32(out, s.net_force);
  put_f32(out, s.velocity.x);
  put_f32(out, s.velocity.y);
  put_f32(out, s.strain);
  return out;
}

std::optional<MotionSection> decode_motion_section(std::span<const std::uint8_t> b) {
  if (b.size() != kSize || b[0] != kVersion || (b[1] & ~7u) != 0) return std::nullopt;
  MotionSection s;
  s.leader = (b[1] & 1) != 0;
  s.arrived = (b[1] & 2) != 0;
  s.wall_following = (b[1] & 4) != 0;
  s.parent = static_cast<std::int32_t>(get_u32(b, 2));
  s.net_force = get_f32(b, 6);
  s.velocity = {get_f32(b, 10), get_f32(b, 14)};
  s.strain = get_f32(b, 18);
  if (!std::isfinite(s.net_force) || !std::isfinite(s.velocity.x) || !std::isfinite(s.velocity.y) ||
      !std::isfinite(s.strain))
    return std::nullopt;
  return s;
}

}  // namespace swarmform::controller::motion
