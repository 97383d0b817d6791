// Initial robot poses: random in a region from the seed (never overlapping, clear of obstacles and walls,
// communication graph connected at the start), and the checks a listed set of poses must pass.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/types.hpp"
#include "world_server/world/scenario.hpp"

namespace swarmform::world {

struct PlacementRegion {
  Vec2 centre;
  double width = 0.0;   // m along x
  double height = 0.0;  // m along y
};

inline constexpr double kMinSeparation = 0.4;  // m between random robots' centres (5.7 body radii)
inline constexpr double kLinkFraction = 0.6;   // each random robot within this * comm_range of an earlier one
inline constexpr double kObstacleClearance = 0.1;  // m free between a random robot's body and any static body

// The default region for n robots: a square centred on the origin (the paper's robots know their place
// from the origin, and the seed robot is the one closest to it), about 0.6 m^2 per robot.
PlacementRegion default_region(std::size_t n);

// Random placement: robot k (k >= 1) is drawn within kLinkFraction*comm_range of a uniformly chosen earlier
// robot, inside the region, at least kMinSeparation from every placed robot and kObstacleClearance clear of
// every static body; headings uniform. So the graph is connected by construction. Returns nullopt when the
// region cannot hold them (after many tries), for the caller to report. `others`: robots placed already (a
// robot group's, docs/scenario-format.md "Groups"), kept kMinSeparation from too; `stream`: the group's
// index, so that each group draws from its own stream of the seed (0: the stream of a scenario without
// groups).
std::optional<std::vector<Pose2D>> place_randomly(std::size_t n, const PlacementRegion& region,
                                                  const Scenario& scenario, std::uint64_t seed,
                                                  const std::vector<Pose2D>& others = {},
                                                  std::uint64_t stream = 0);

// What is wrong with listed pose k among poses[0..k) (overlap with another body, inside an obstacle or wall,
// outside the arena), or empty when it is fine.
std::string check_listed_pose(const std::vector<Pose2D>& poses, std::size_t k, const Scenario& scenario);

}  // namespace swarmform::world
