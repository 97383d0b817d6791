#include "robot_agent/controller/boundary_episode.hpp"

#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller::motion {

namespace {
// The parent stands on one side when its direction is this far off the desired motion's line (x |to_parent|).
constexpr double kParentSide = 0.2;
}  // namespace

int BoundaryEpisode::tie_break(std::uint64_t seed, RobotId self) {
  return ((seed * 0x9E3779B97F4A7C15ull) >> 7 ^ self) & 1 ? 1 : -1;
}

void BoundaryEpisode::start(const EpisodeInputs& in, Vec2 echo, int tie, const BoundaryFollowParams& params,
                            std::vector<std::string>& events) {
  Vec2 prefer = in.desired;
  if (vnorm(in.to_parent) > 1e-6) {
    const Vec2 d_hat = vscale(in.desired, 1.0 / vnorm(in.desired));
    const Vec2 across = vsub(in.to_parent, vscale(d_hat, vdot(in.to_parent, d_hat)));
    if (vnorm(across) > kParentSide * vnorm(in.to_parent)) prefer = vadd(in.desired, across);
  }
  const double gap = vnorm(vsub(in.place, in.position));
  if (side_ != 0 && gap > gap_ - params.keep) {
    follower_.start(side_, in.tick, since_, turns_);
  } else {
    follower_.start(BoundaryFollower::choose_side(in.position, echo, prefer, tie), in.tick);
    gap_ = gap;
  }
  hit_place_ = in.place;
  hit_gap_ = gap;
  events.push_back("boundary_follow_start " + std::to_string(follower_.side()));
}

std::optional<Vec2> BoundaryEpisode::follow(const EpisodeInputs& in, const std::optional<Vec2>& echo,
                                            EchoMemory& trace, double arrival_tolerance,
                                            const BoundaryFollowParams& params,
                                            std::vector<std::string>& events) {
  const bool same_place = in.place_still && about(in.place, params.keep);
  const bool may_leave = !same_place || vnorm(vsub(in.place, in.position)) < hit_gap_ - arrival_tolerance;
  const auto across =
      echo ? trace.across(in.position, *echo, in.tick, 2.0 * params.keep, kTraceTicks) : std::nullopt;
  Vec2 v;
  const bool following =
      follower_.update(echo, in.position, in.desired, in.tick, params, v, may_leave, across);
  side_ = follower_.side();
  since_ = follower_.since();
  turns_ = follower_.turns();
  if (following) return v;
  events.push_back("boundary_follow_end");
  return std::nullopt;
}

}  // namespace swarmform::controller::motion
