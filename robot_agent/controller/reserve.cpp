#include "robot_agent/controller/reserve.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "robot_agent/controller/allotment.hpp"
#include "robot_agent/controller/motion_phase.hpp"
#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller {

namespace {

// Calls f(id, label) for every barrier entry, in id order: the namespace's own run of the key-sorted table,
// not a pass over every entry (a reserve asks every tick, vacant_labels).
template <class F>
void for_each_barrier_entry(const Stigmergy& stigmergy, F&& f) {
  for (const auto& e : stigmergy.in_namespace_from(stig::Ns::Barrier, 0))
    f(static_cast<RobotId>(stig::index_of(e.key)), e.value);
}

bool in_motion_phases(RobotState s) {
  return s == RobotState::Ready || s == RobotState::Motion || s == RobotState::Arrived;
}

}  // namespace

bool marked_dead_in_motion(const Stigmergy& stigmergy, RobotId id) {
  return stigmergy.get(stig::key(stig::Ns::Parents, id)) == motion::kDeadMark;
}

bool shape_in_motion(const Stigmergy& stigmergy) {
  return stigmergy.get(stig::key(stig::Ns::Leader, 0)).has_value();
}

std::vector<std::pair<RobotId, int>> motion_member_extras(const Stigmergy& stigmergy,
                                                          const std::map<RobotId, int>& at_ready) {
  std::vector<std::pair<RobotId, int>> extras;
  for_each_barrier_entry(stigmergy, [&](RobotId id, std::int64_t label) {
    if (label < 0 || at_ready.count(id) != 0 || marked_dead_in_motion(stigmergy, id)) return;
    const auto holder = label_status(stigmergy, static_cast<int>(label));
    if (holder.kind != LabelStatus::Kind::Held || holder.holder != id) return;
    for (const auto& [member, member_label] : at_ready) {
      if (member_label == label && !marked_dead_in_motion(stigmergy, member)) return;
    }
    extras.emplace_back(id, static_cast<int>(label));
  });
  std::sort(extras.begin(), extras.end());
  return extras;
}

std::map<RobotId, int> motion_members(const std::map<RobotId, int>& at_ready,
                                      const std::vector<std::pair<RobotId, int>>& extras) {
  std::map<RobotId, int> members = at_ready;
  for (const auto& [id, label] : extras) members[id] = label;
  return members;
}

std::map<RobotId, int> motion_members(const Stigmergy& stigmergy, const std::map<RobotId, int>& at_ready) {
  return motion_members(at_ready, motion_member_extras(stigmergy, at_ready));
}

std::vector<int> vacant_labels(const Stigmergy& stigmergy, int label_count, const LabelTicks& holder_since,
                               Tick now, int label_timeout) {
  // Per label: whether one of its barrier entries is alive.
  std::vector<char> live(static_cast<std::size_t>(label_count), 0);
  for_each_barrier_entry(stigmergy, [&](RobotId id, std::int64_t label) {
    if (label < 0 || label >= label_count) return;
    if (!marked_dead_in_motion(stigmergy, id)) live[static_cast<std::size_t>(label)] = 1;
  });
  std::vector<int> out;
  for (int l = 0; l < label_count; ++l) {
    // A label nobody entered was abandoned when the barrier passed (barrier.hpp): vacant as a dead member's
    // is.
    if (live[static_cast<std::size_t>(l)]) continue;
    const auto status = label_status(stigmergy, l);
    bool claimed = status.kind == LabelStatus::Kind::Held;
    if (claimed) {
      // Its holder's barrier entry names it: a member marked dead (a live one would have made it live).
      const bool a_dead_member = stigmergy.get(stig::key(stig::Ns::Barrier, status.holder)) == l;
      const auto since = holder_since.find(l);
      const bool silent = !since || now >= *since + static_cast<Tick>(label_timeout);
      claimed = !a_dead_member && !silent;
    }
    if (!claimed) out.push_back(l);
  }
  return out;
}

std::optional<RobotId> live_member_of(const Stigmergy& stigmergy, int label, RobotId self) {
  std::optional<RobotId> member;
  for_each_barrier_entry(stigmergy, [&](RobotId id, std::int64_t entry_label) {
    if (!member && entry_label == label && id != self && !marked_dead_in_motion(stigmergy, id)) member = id;
  });
  return member;
}

std::optional<Vec2> moving_origin(const NeighbourTable& neighbours, const Pose2D& self,
                                  const ShapeTable& table, double shape_heading) {
  Vec2 sum;
  int count = 0;
  for (const auto& [id, n] : neighbours.all()) {
    if (!neighbours.fresh(n) || !in_motion_phases(n.message.state) || n.message.label < 0 ||
        n.message.label >= table.size())
      continue;
    const Vec2 at = vadd(Vec2{self.x, self.y}, vpolar(n.range, n.azimuth));
    sum = vadd(sum, vsub(at, table.place(n.message.label, {}, shape_heading)));
    ++count;
  }
  if (count == 0) return std::nullopt;
  return vscale(sum, 1.0 / static_cast<double>(count));
}

Vec2 trailing_point(Vec2 centre, double radius, Vec2 goal, Vec2 self, double spacing) {
  const double keep = radius + 1.5 * spacing;
  Vec2 away = vsub(centre, goal);                       // behind the shape, seen from the goal
  if (vnorm(away) < radius) away = vsub(self, centre);  // at the goal: stay on its own side
  if (vnorm(away) < 1e-9) away = {-1.0, 0.0};
  return vadd(centre, vscale(away, keep / vnorm(away)));
}

}  // namespace swarmform::controller
