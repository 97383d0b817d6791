#include "world_server/world/medium.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "world_server/world/parallel_for.hpp"

namespace swarmform::world {

Medium::Medium(const MediumParams& params, const std::vector<Obstacle>& statics, std::uint64_t seed)
    : params_(params), rng_(seed, kSaltMedium) {
  if (params.loss_mean_burst > 0.0) burst_.emplace(params.packet_loss, params.loss_mean_burst, seed);
  set_statics(statics);
}

bool Medium::occluded(const Pose2D& a, const Pose2D& b) const {
  for (const StaticShape& s : statics_) {
    if (segment_blocked(a.x, a.y, b.x, b.y, s)) return true;
  }
  return false;
}

// Receiver by receiver (each inbox is filled in one go, which keeps the writes local in memory); a sender is
// heard when it is alive, said something, is within range of the receiver (the test is symmetric) and, with
// occlusion on, in its line of sight. Two passes, so that the result does not depend on the worker count:
//   1. on the worker pool, each receiver's inbox gets every heard sender's noiseless reading (only its own
//      inbox and spare list are written);
//   2. on the calling thread, receivers by id and readings in the grid's order (a fixed function of the
//      positions), the loss and noise draws, in the same order as a single loop would draw them.
void Medium::deliver(const std::vector<Pose2D>& poses, const std::vector<char>& alive,
                     const std::vector<Outbox>& outboxes, const SpatialGrid& grid,
                     std::vector<Perception>& perceptions, bool with_bytes, const MediumFaults* faults) {
  if (faults != nullptr && !faults->any) faults = nullptr;
  const std::size_t n = poses.size();
  spare_.resize(n);
  const Tick round = ++round_;
  parallel::for_range(
      n,
      [&](std::size_t begin, std::size_t end, std::size_t) {
        for (std::size_t r = begin; r < end; ++r)
          gather(r, poses, alive, outboxes, grid, perceptions[r].messages, spare_[r], with_bytes, faults);
      },
      parallel::kMinRobotsPerWorker);
  if (!random()) return;
  for (std::size_t r = 0; r < n; ++r) {
    std::vector<RabReading>& inbox = perceptions[r].messages;
    std::size_t kept = 0;
    for (std::size_t k = 0; k < inbox.size(); ++k) {
      RabReading& m = inbox[k];
      const bool lost = burst_ ? burst_->lost(round, m.sender, static_cast<RobotId>(r))
                               : rng_.bernoulli(params_.packet_loss);
      if (lost) continue;
      m.range = std::max(0.0, m.range + rng_.gaussian(params_.range_noise_sd));
      m.bearing = wrap_angle(m.bearing + rng_.gaussian(params_.bearing_noise_sd));
      if (kept != k) std::swap(inbox[kept], m);  // swap: the lost reading's buffer stays for reuse
      ++kept;
    }
    resize_reusing(inbox, kept, spare_[r]);
  }
}

void Medium::gather(std::size_t r, const std::vector<Pose2D>& poses, const std::vector<char>& alive,
                    const std::vector<Outbox>& outboxes, const SpatialGrid& grid,
                    std::vector<RabReading>& inbox, std::vector<RabReading>& spare, bool with_bytes,
                    const MediumFaults* faults) const {
  if (faults != nullptr && !faults->any) faults = nullptr;
  std::size_t used = 0;
  if (alive[r] && (faults == nullptr || !faults->silent[r])) {
    const Pose2D& me = poses[r];
    const double reach =
        faults == nullptr ? params_.comm_range : std::min(params_.comm_range, faults->range[r]);
    // The grid hands over the sender's offset (sender - receiver), so the reading is to_receiver_frame's
    // without reading the sender's pose again.
    grid.for_each_near_offset(me.x, me.y, reach, [&](std::uint32_t s, double dx, double dy, double d2) {
      if (s == r || !alive[s] || !outboxes[s].has_message) return;
      if (faults != nullptr && (faults->silent[s] || d2 > faults->range[s] * faults->range[s])) {
        return;
      }
      if (params_.occlusion && occluded(poses[s], me)) return;
      // Reuse the receiver's earlier RabReading objects (and their data buffers)
      // where there are some.
      if (used == inbox.size()) resize_reusing(inbox, used + 1, spare);
      RabReading& m = inbox[used++];
      m.sender = s;
      m.range = std::sqrt(d2);
      m.bearing = bearing_in_frame(dx, dy, me.theta);
    });
  }
  resize_reusing(inbox, used, spare);
  if (with_bytes) fill_bytes(inbox, outboxes);
}

void Medium::set_statics(const std::vector<Obstacle>& statics) {
  statics_.clear();
  for (const Obstacle& o : statics) statics_.push_back(make_static_shape(o));
}

}  // namespace swarmform::world
