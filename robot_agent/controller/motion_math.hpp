// Small plane-geometry helpers for the Ready and motion phases (boundary, leader, parent tree, forces).
// Named functions, not operators, and in their own namespace, so they never collide with helpers another
// phase defines for swarmform::Vec2.
#pragma once

#include <cmath>
#include <numbers>

#include "common/types.hpp"

namespace swarmform::controller::motion {

inline Vec2 vadd(Vec2 a, Vec2 b) {
  return {a.x + b.x, a.y + b.y};
}
inline Vec2 vsub(Vec2 a, Vec2 b) {
  return {a.x - b.x, a.y - b.y};
}
inline Vec2 vscale(Vec2 a, double k) {
  return {a.x * k, a.y * k};
}
inline double vdot(Vec2 a, Vec2 b) {
  return a.x * b.x + a.y * b.y;
}
inline double vnorm(Vec2 a) {
  return std::hypot(a.x, a.y);
}
inline Vec2 vpolar(double r, double angle) {
  return {r * std::cos(angle), r * std::sin(angle)};
}
inline Vec2 vrotate(Vec2 a, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * a.x - s * a.y, s * a.x + c * a.y};
}
// |a| capped at `limit` (direction kept).
inline Vec2 vclamp(Vec2 a, double limit) {
  const double n = vnorm(a);
  return n > limit && n > 0.0 ? vscale(a, limit / n) : a;
}

// Wraps to (-pi, pi].
inline double wrap_angle(double a) {
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  a = std::fmod(a, kTwoPi);
  if (a <= -std::numbers::pi) a += kTwoPi;
  if (a > std::numbers::pi) a -= kTwoPi;
  return a;
}

}  // namespace swarmform::controller::motion
