// Analytic 2-D geometry shared by the sensors, the medium and robot placement: rays and segments against
// circles (robots, cylinders) and oriented boxes (walls, boxes). Header-only: these run tens of thousands of
// times a tick and must inline. Bullet is not used here on purpose: its ray casts cost ~5 us each and ignore
// a body that contains the ray's start; these cost ~20 ns.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "common/types.hpp"
#include "world_server/world/scenario.hpp"

namespace swarmform::world {

inline constexpr double kNoHit = std::numeric_limits<double>::infinity();
// The height of walls and obstacles (their Bullet bodies, and what the light sensors' occlusion test sees):
// far taller than a robot.
inline constexpr double kStaticHeight = 0.5;  // m

// Wraps an angle to (-pi, pi] (the convention of common/types.hpp). Angles a few turns out (sums and
// differences of wrapped angles) take the cheap path.
inline double wrap_angle(double a) {
  constexpr double kPi = std::numbers::pi;
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  if (a > -kPi && a <= kPi) return a;
  if (a > -4.0 * kPi && a <= 4.0 * kPi) {
    while (a > kPi) a -= kTwoPi;
    while (a <= -kPi) a += kTwoPi;
    return a;
  }
  a = std::remainder(a, kTwoPi);  // in [-pi, pi]
  return a <= -kPi ? a + kTwoPi : a;
}

// atan2(y, x) in [-pi, pi] to within 1e-13 rad, about three times cheaper than libm's (the medium calls it
// once per delivered message copy, tens of thousands of times a tick). Reduction: to the first octant
// (t = min/max in [0, 1]), then, past tan(pi/12), atan(t) = pi/6 + atan((t*sqrt3 - 1)/(t + sqrt3)), folded
// into one division; then the Taylor series of atan to t^19 on [0, tan(pi/12)] (next term < 1e-13).
// Same inputs, same bits on every machine (no libm in it). atan2(0, 0) returns 0.
inline double fast_atan2(double y, double x) {
  constexpr double kPi = std::numbers::pi;
  constexpr double kSqrt3 = 1.7320508075688772;
  constexpr double kTanPi12 = 0.2679491924311227;
  const double ax = std::abs(x), ay = std::abs(y);
  const bool steep = ay > ax;
  double num = steep ? ax : ay;
  double den = steep ? ay : ax;
  if (den == 0.0) return 0.0;
  double base = 0.0;
  if (num > kTanPi12 * den) {
    const double n2 = num * kSqrt3 - den;
    den = num + den * kSqrt3;
    num = n2;
    base = kPi / 6.0;
  }
  const double t = num / den;
  const double t2 = t * t;
  // t - t^3/3 + t^5/5 - ... - t^19/19, Horner in t^2.
  double p = -1.0 / 19.0;
  p = p * t2 + 1.0 / 17.0;
  p = p * t2 - 1.0 / 15.0;
  p = p * t2 + 1.0 / 13.0;
  p = p * t2 - 1.0 / 11.0;
  p = p * t2 + 1.0 / 9.0;
  p = p * t2 - 1.0 / 7.0;
  p = p * t2 + 1.0 / 5.0;
  p = p * t2 - 1.0 / 3.0;
  p = p * t2 + 1.0;
  double a = base + t * p;
  if (steep) a = kPi / 2.0 - a;
  if (x < 0.0) a = kPi - a;
  return std::signbit(y) ? -a : a;
}

// Distance along the ray o + t*d (d a unit vector, t >= 0) to the circle (c, r); kNoHit if it misses.
// A start inside the circle returns 0 (the ray starts in contact).
inline double ray_circle(double ox, double oy, double dx, double dy, double cx, double cy, double r) {
  const double mx = ox - cx;
  const double my = oy - cy;
  const double b = mx * dx + my * dy;
  const double c = mx * mx + my * my - r * r;
  if (c <= 0.0) return 0.0;
  if (b > 0.0) return kNoHit;  // outside and pointing away
  const double disc = b * b - c;
  if (disc < 0.0) return kNoHit;
  return -b - std::sqrt(disc);
}

// A box or a cylinder in a form cheap to test against: the box's axes are precomputed.
struct StaticShape {
  bool is_box = true;
  double cx = 0.0, cy = 0.0;
  double cos_yaw = 1.0, sin_yaw = 0.0;  // box frame
  double hx = 0.0, hy = 0.0;            // box half extents
  double r = 0.0;                       // cylinder radius
  double bound = 0.0;                   // radius of a circle around (cx, cy) that holds the whole shape
};

inline StaticShape make_static_shape(const Obstacle& o) {
  StaticShape s;
  s.cx = o.centre.x;
  s.cy = o.centre.y;
  if (o.kind == Obstacle::Kind::Box) {
    s.is_box = true;
    s.cos_yaw = std::cos(o.yaw);
    s.sin_yaw = std::sin(o.yaw);
    s.hx = o.half_extents.x;
    s.hy = o.half_extents.y;
    s.bound = std::hypot(s.hx, s.hy);
  } else {
    s.is_box = false;
    s.r = o.radius;
    s.bound = o.radius;
  }
  return s;
}

// Slab test in the box frame. Distance along o + t*d (unit d) to the box; 0 if o is inside; kNoHit if none.
inline double ray_box(double ox, double oy, double dx, double dy, const StaticShape& b) {
  // Into the box frame (rotate by -yaw).
  const double px = ox - b.cx;
  const double py = oy - b.cy;
  const double lx = b.cos_yaw * px + b.sin_yaw * py;
  const double ly = -b.sin_yaw * px + b.cos_yaw * py;
  const double ldx = b.cos_yaw * dx + b.sin_yaw * dy;
  const double ldy = -b.sin_yaw * dx + b.cos_yaw * dy;
  double t_min = 0.0;
  double t_max = kNoHit;
  const double o[2] = {lx, ly};
  const double d[2] = {ldx, ldy};
  const double h[2] = {b.hx, b.hy};
  for (int i = 0; i < 2; ++i) {
    if (std::abs(d[i]) < 1e-15) {
      if (o[i] < -h[i] || o[i] > h[i]) return kNoHit;
      continue;
    }
    const double inv = 1.0 / d[i];
    double t1 = (-h[i] - o[i]) * inv;
    double t2 = (h[i] - o[i]) * inv;
    if (t1 > t2) std::swap(t1, t2);
    t_min = std::max(t_min, t1);
    t_max = std::min(t_max, t2);
    if (t_min > t_max) return kNoHit;
  }
  return t_min;
}

inline double ray_static(double ox, double oy, double dx, double dy, const StaticShape& s) {
  return s.is_box ? ray_box(ox, oy, dx, dy, s) : ray_circle(ox, oy, dx, dy, s.cx, s.cy, s.r);
}

// True when the segment a->b crosses (or touches) the shape: used for the medium's line-of-sight test.
inline bool segment_blocked(double ax, double ay, double bx, double by, const StaticShape& s) {
  const double dx = bx - ax;
  const double dy = by - ay;
  const double len = std::hypot(dx, dy);
  if (len <= 0.0) return false;
  // Cheap reject: the segment's distance to the shape's bounding circle.
  const double t = std::clamp(((s.cx - ax) * dx + (s.cy - ay) * dy) / (len * len), 0.0, 1.0);
  const double qx = ax + t * dx - s.cx;
  const double qy = ay + t * dy - s.cy;
  if (qx * qx + qy * qy > s.bound * s.bound) return false;
  return ray_static(ax, ay, dx / len, dy / len, s) <= len;
}

// Distance from point p to the shape's surface (negative or 0 when inside): for placing robots clear of it.
inline double point_clearance(double px, double py, const StaticShape& s) {
  if (!s.is_box) return std::hypot(px - s.cx, py - s.cy) - s.r;
  const double rx = px - s.cx;
  const double ry = py - s.cy;
  const double lx = std::abs(s.cos_yaw * rx + s.sin_yaw * ry) - s.hx;
  const double ly = std::abs(-s.sin_yaw * rx + s.cos_yaw * ry) - s.hy;
  const double outside = std::hypot(std::max(lx, 0.0), std::max(ly, 0.0));
  return outside > 0.0 ? outside : std::max(lx, ly);
}

// The static bodies of a scenario: its obstacles (every one, present at tick 0 or not), then (when walls are
// on) the four walls as boxes whose inner faces are the arena's edges. The physics adds a body for each, in
// this order (world_events.hpp).
std::vector<Obstacle> static_obstacles(const Scenario& scenario);
// What the sensors, the medium and the placement see: the present ones of `obstacles` (the scenario's as they
// stand), then the walls.
std::vector<Obstacle> present_statics(const Scenario& scenario, const std::vector<Obstacle>& obstacles);

}  // namespace swarmform::world
