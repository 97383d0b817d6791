// The controller's plane geometry: every operation on Vec2 the controller uses, and the angle wrap, in one
// place, each written one way.
//
// Named functions, not operators: most of the controller (the Ready and motion phases) already reads this
// way, a long force law stays readable as nested calls where mixed `k * a + b` would hide which operand is
// the vector, and swarmform::Vec2 (common/types.hpp) gets no operators that only code inside this namespace
// sees. Each function is one fixed floating-point expression: the trajectories are bit-exact, so a rewrite of
// one (hypot for sqrt, k * a.x for a.x * k on a product of three) is a change of behaviour, not a tidy-up.
#pragma once

#include <cmath>
#include <numbers>

#include "common/types.hpp"

namespace swarmform::controller {

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
// The vector of length `r` at angle `angle` (rad); vpolar(1.0, a) is the unit vector.
inline Vec2 vpolar(double r, double angle) {
  return {r * std::cos(angle), r * std::sin(angle)};
}
inline Vec2 vrotate(Vec2 a, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * a.x - s * a.y, s * a.x + c * a.y};
}
// `a` with its length capped at `limit` (direction kept); a zero or non-finite length leaves it as it is.
inline Vec2 vclamp(Vec2 a, double limit) {
  const double n = vnorm(a);
  return n > limit && n > 0.0 ? vscale(a, limit / n) : a;
}

// Wraps an angle to (-pi, pi] (the convention of common/types.hpp), bit-identical to std::remainder(a, 2 pi)
// moved off -pi; a non-finite angle gives 0. Fast paths, because std::remainder costs ~100 instructions and
// was 7% of an in-process tick at N=1000: for |a| <= pi it returns a; for pi < |a| < 2.5 pi it takes exactly
// one 2 pi off, and that subtraction is exact in floating point there (Sterbenz). Sums of two wrapped angles
// land there.
inline double wrap_angle(double a) {
  constexpr double kPi = std::numbers::pi;
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  if (a > -kPi && a <= kPi) return a;
  if (a > kPi && a < 2.5 * kPi) {
    a -= kTwoPi;
  } else if (a < -kPi && a > -2.5 * kPi) {
    a += kTwoPi;
    if (a == 0.0) a = -0.0;  // remainder keeps the sign of a: wrap(-2 pi) is -0
  } else {
    if (!std::isfinite(a)) return 0.0;
    a = std::remainder(a, kTwoPi);  // [-pi, pi]
  }
  if (a <= -kPi) a += kTwoPi;
  return a;
}

}  // namespace swarmform::controller
