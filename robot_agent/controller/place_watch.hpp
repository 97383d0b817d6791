// An arrived follower's watch over its place (robot_agent/README.md, "an arrived robot pushed off its place
// moves back"). Arrival stops a follower where its parent, at rest, put its place; after that only a change
// of parent or the parent moving again (its section no longer says arrived) used to move it. But robots still
// on their way push through an arrived shape (eq. 1 makes an arrived robot give way too), and over a lossy
// radio more of them arrive late: an arrived robot pushed 0.7 m off its place stood there for good, beside
// its empty place, and its children with it. The watch keeps where its parent was heard over the last
// `window` ticks; their mean (noise averaged away, as the resting parent's place is while moving) minus the
// reference to the parent is where its place is now.
#pragma once

#include <cstddef>
#include <deque>
#include <optional>
#include <utility>

#include "common/types.hpp"

namespace swarmform::controller::motion {

class PlaceWatch {
 public:
  void reset() { heard_.clear(); }
  // The parent heard at `parent_position` (arena frame) at `tick`; readings older than `window` ticks go.
  void add(Tick tick, Vec2 parent_position, Tick window);
  // Where the readings put the place (their mean minus `reference`, the vector to the parent), once at least
  // `min_readings` are in the window.
  std::optional<Vec2> place(Vec2 reference, std::size_t min_readings) const;

 private:
  std::deque<std::pair<Tick, Vec2>> heard_;
};

}  // namespace swarmform::controller::motion
