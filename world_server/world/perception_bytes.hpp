// One definition of "the same perception", for run digests and determinism tests: every field the world
// computes for a robot (pose, ultrasonic ranges, each reading with its bytes, then the optional sensors that
// are equipped: a perception without them gives the bytes it always gave), fed in a fixed order to
// `put(const void* bytes, std::size_t count)`. Not the goal: it is the scenario's at the tick (goal_at), the
// same for every robot, and a run whose goal moves differs in its trajectory where a robot acts on it.
#pragma once

#include <cstddef>

#include "common/types.hpp"

namespace swarmform::world {

template <class Put>
void put_perception_bytes(const Perception& p, Put&& put) {
  put(&p.pose, sizeof p.pose);
  put(p.ultrasonic.data(), sizeof(double) * p.ultrasonic.size());
  for (const RabReading& m : p.messages) {
    put(&m.sender, sizeof m.sender);
    put(&m.range, sizeof m.range);
    put(&m.bearing, sizeof m.bearing);
    put(m.data.data(), m.data.size());
  }
  if (p.proximity) put(p.proximity->data(), sizeof(double) * p.proximity->size());
  if (p.light) put(p.light->data(), sizeof(double) * p.light->size());
  if (p.ground) put(p.ground->data(), sizeof(double) * p.ground->size());
  if (p.battery) put(&*p.battery, sizeof(double));
  for (const LidarRay& r : p.lidar) {
    put(&r.angle, sizeof r.angle);
    put(&r.range, sizeof r.range);
  }
}

}  // namespace swarmform::world
