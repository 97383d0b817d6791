#include "world_server/world/medium.hpp"

#include <algorithm>
#include <cmath>

namespace swarmform::world {

RangeBearing to_receiver_frame(const Pose2D& sender, const Pose2D& receiver) {
  const double dx = sender.x - receiver.x;
  const double dy = sender.y - receiver.y;
  return RangeBearing{std::sqrt(dx * dx + dy * dy), wrap_angle(std::atan2(dy, dx) - receiver.theta)};
}

Medium::Medium(const MediumParams& params, const std::vector<Obstacle>& statics, std::uint64_t seed)
    : params_(params), rng_(seed, kSaltMedium) {
  for (const Obstacle& o : statics) statics_.push_back(make_static_shape(o));
}

bool Medium::occluded(const Pose2D& a, const Pose2D& b) const {
  for (const StaticShape& s : statics_) {
    if (segment_blocked(a.x, a.y, b.x, b.y, s)) return true;
  }
  return false;
}

void Medium::deliver(const std::vector<Pose2D>& poses, const std::vector<char>& alive,
                     const std::vector<Outbox>& outboxes, const SpatialGrid& grid,
                     std::vector<Perception>& perceptions) {
  const std::size_t n = poses.size();
  used_.assign(n, 0);
  for (std::size_t s = 0; s < n; ++s) {
    if (!alive[s] || !outboxes[s].has_message) continue;
    receivers_.clear();
    grid.for_each_near(poses[s].x, poses[s].y, params_.comm_range, [&](std::uint32_t r) {
      if (r != s && alive[r]) receivers_.push_back(r);
    });
    // The grid's order is a fixed function of the positions, so the draws below replay exactly.
    for (std::uint32_t r : receivers_) {
      if (params_.occlusion && occluded(poses[s], poses[r])) continue;
      if (rng_.bernoulli(params_.packet_loss)) continue;
      RangeBearing rb = to_receiver_frame(poses[s], poses[r]);
      rb.range = std::max(0.0, rb.range + rng_.gaussian(params_.range_noise_sd));
      rb.bearing = wrap_angle(rb.bearing + rng_.gaussian(params_.bearing_noise_sd));
      // Reuse the receiver's previous RabReading objects (and their data buffers) where there are some.
      std::vector<RabReading>& inbox = perceptions[r].messages;
      const std::size_t k = used_[r]++;
      if (k == inbox.size()) inbox.emplace_back();
      RabReading& m = inbox[k];
      m.sender = static_cast<RobotId>(s);
      m.range = rb.range;
      m.bearing = rb.bearing;
      m.data.assign(outboxes[s].data.begin(), outboxes[s].data.end());
    }
  }
  for (std::size_t r = 0; r < n; ++r) perceptions[r].messages.resize(used_[r]);
}

}  // namespace swarmform::world
