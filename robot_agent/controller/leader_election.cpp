#include "robot_agent/controller/leader_election.hpp"

#include <cmath>

#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller::motion {

namespace {

constexpr double kTieTolerance = 1e-3;  // m along the heading

std::optional<RobotId> best_of(const std::vector<LeaderCandidate>& candidates,
                               const std::vector<Vec2>& places, Vec2 forward, bool boundary_only) {
  std::optional<RobotId> best;
  double best_forward = 0.0;
  for (const auto& c : candidates) {
    if (!c.alive || c.label < 0 || static_cast<std::size_t>(c.label) >= places.size()) continue;
    if (boundary_only && !c.role.any()) continue;
    const double f = vdot(places[static_cast<std::size_t>(c.label)], forward);
    const bool better = !best || f > best_forward + kTieTolerance ||
                        (std::abs(f - best_forward) <= kTieTolerance && c.id < *best);
    if (better) {
      best = c.id;
      best_forward = f;
    }
  }
  return best;
}

}  // namespace

std::optional<RobotId> elect_leader(const std::vector<LeaderCandidate>& candidates,
                                    const std::vector<Vec2>& places, double heading) {
  const Vec2 forward = vpolar(1.0, heading);
  if (auto leader = best_of(candidates, places, forward, true)) return leader;
  return best_of(candidates, places, forward, false);
}

}  // namespace swarmform::controller::motion
