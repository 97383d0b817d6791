// The range-and-bearing medium, after ARGoS: the medium decides WHO hears whom (spatial
// grid, range test on the true centre distance, optional line of sight, per-copy loss), and to_receiver_frame
// decides WHAT is perceived (range and bearing in the receiver's frame, with noise). Messages given to
// deliver() are those of tick t; they land in the perceptions of tick t+1, only of live robots, never of the
// sender itself, never from a dead sender. All randomness comes from one seeded stream, drawn in a fixed
// order (receivers by id, then senders in the grid's order), so a run replays exactly, whatever the worker
// count (the geometry runs on the worker pool, the draws on the calling thread). Bursty loss draws instead
// from a hash of the link and the tick (burst_loss.hpp); each deliver() is one tick's round.
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "common/types.hpp"
#include "world_server/world/burst_loss.hpp"
#include "world_server/world/geometry.hpp"
#include "world_server/world/rng.hpp"
#include "world_server/world/spatial_grid.hpp"

namespace swarmform::world {

struct MediumParams {
  double comm_range = 3.0;        // m
  double range_noise_sd = 0.0;    // m
  double bearing_noise_sd = 0.0;  // rad
  double packet_loss = 0.0;       // per copy: the long-run loss rate
  double loss_mean_burst = 0.0;   // ticks: > 0, losses come in bursts of this mean length per directed
                                  // link (burst_loss.hpp); 0, each copy is lost independently
  bool occlusion = false;         // static bodies (obstacles, walls) block; robots never do
};

struct RangeBearing {
  double range = 0.0;    // m, centre to centre
  double bearing = 0.0;  // rad, in the receiver's frame, CCW from its heading, (-pi, pi]
};

// The bearing of the offset (dx, dy) = sender - receiver (arena frame) in the frame of a receiver heading
// `theta`: one atan2, no sin/cos of the heading.
inline double bearing_in_frame(double dx, double dy, double theta) {
  return wrap_angle(fast_atan2(dy, dx) - theta);
}

// The sender's position as the receiver perceives it (no noise).
inline RangeBearing to_receiver_frame(const Pose2D& sender, const Pose2D& receiver) {
  const double dx = sender.x - receiver.x;
  const double dy = sender.y - receiver.y;
  return RangeBearing{std::sqrt(dx * dx + dy * dy), bearing_in_frame(dx, dy, receiver.theta)};
}

// One robot's outgoing message of this tick.
struct Outbox {
  bool has_message = false;
  std::vector<std::uint8_t> data;
};

// Scheduled radio faults of one tick (faults.hpp: loss and range), per robot. A silent robot's messages are
// lost and it hears none; a pair hears each other only within the smaller of their two ranges.
struct MediumFaults {
  bool any = false;           // false: the rest is not read
  std::vector<char> silent;   // 1: every copy to and from this robot is lost
  std::vector<double> range;  // m: this robot's cut range (comm_range when not cut)
};

class Medium {
 public:
  Medium(const MediumParams& params, const std::vector<Obstacle>& statics, std::uint64_t seed);

  // Fills perceptions[i].messages for every robot (cleared first; dead receivers get none). `grid` holds
  // `poses`. Reuses the perceptions' buffers. With `with_bytes` false only sender, range and bearing are
  // written and each reading's `data` is left as it was: the caller fills it later with fill_bytes (the
  // World does, when a perception is read: copying every message's bytes into every receiver's inbox at once
  // streams tens of MB a tick through memory at N = 1000, which the controllers then read back cold).
  // `faults` (may be null): this tick's loss bursts and range cuts.
  void deliver(const std::vector<Pose2D>& poses, const std::vector<char>& alive,
               const std::vector<Outbox>& outboxes, const SpatialGrid& grid,
               std::vector<Perception>& perceptions, bool with_bytes = true,
               const MediumFaults* faults = nullptr);

  // Copies into each reading of `inbox` its sender's bytes from `outboxes` (those given to deliver()).
  static void fill_bytes(std::vector<RabReading>& inbox, const std::vector<Outbox>& outboxes) {
    for (RabReading& m : inbox) {
      const std::vector<std::uint8_t>& bytes = outboxes[m.sender].data;
      m.data.assign(bytes.begin(), bytes.end());  // within the buffer's capacity once warm: a memcpy
    }
  }

  // Resizes `inbox` to `n` readings without freeing or allocating buffers where it can: readings past `n`
  // are parked in `spare` (with their data buffers), and new ones are taken from `spare` first.
  static void resize_reusing(std::vector<RabReading>& inbox, std::size_t n, std::vector<RabReading>& spare) {
    while (inbox.size() > n) {
      spare.push_back(std::move(inbox.back()));
      inbox.pop_back();
    }
    while (inbox.size() < n) {
      if (spare.empty()) {
        inbox.emplace_back();
      } else {
        inbox.push_back(std::move(spare.back()));
        spare.pop_back();
      }
    }
  }

  // True when the straight line between a and b crosses a static body (used when occlusion is on).
  bool occluded(const Pose2D& a, const Pose2D& b) const;

  const MediumParams& params() const { return params_; }

  // True when deliver() draws random numbers (loss or noise): then inboxes must be filled by deliver(), in
  // receiver order. Otherwise one receiver's inbox can be filled alone by gather(), at any time before the
  // poses, grid or outboxes change, with the same readings deliver() gives it.
  bool random() const {
    return params_.packet_loss > 0.0 || params_.range_noise_sd > 0.0 || params_.bearing_noise_sd > 0.0;
  }

  // Receiver r's noiseless inbox (pass 1 of deliver), readings reused from `inbox` and `spare`; touches
  // nothing else, so several threads may gather different inboxes at once.
  void gather(std::size_t r, const std::vector<Pose2D>& poses, const std::vector<char>& alive,
              const std::vector<Outbox>& outboxes, const SpatialGrid& grid, std::vector<RabReading>& inbox,
              std::vector<RabReading>& spare, bool with_bytes, const MediumFaults* faults) const;

  // The obstacles it sees from now on (present_statics: world events moved, added or removed some).
  void set_statics(const std::vector<Obstacle>& statics);

 private:
  MediumParams params_;
  std::vector<StaticShape> statics_;
  Rng rng_;
  std::optional<BurstLoss> burst_;              // when loss_mean_burst > 0
  Tick round_ = 0;                              // deliver() calls so far: the tick, for the burst chains
  std::vector<std::vector<RabReading>> spare_;  // per receiver: readings kept for reuse (no churn)
};

}  // namespace swarmform::world
