#include "world_server/world/burst_loss.hpp"

#include <cmath>

#include "common/splitmix64.hpp"
#include "world_server/world/rng.hpp"

namespace swarmform::world {

BurstLoss::BurstLoss(double rate, double mean_burst, std::uint64_t seed)
    : rate_(rate),
      lambda_(1.0 - 1.0 / (mean_burst * (1.0 - rate))),
      key_(splitmix64(seed ^ splitmix64(kSaltBurstLoss))) {}

double BurstLoss::uniform(Tick tick, RobotId sender, RobotId receiver) const {
  const std::uint64_t link = (static_cast<std::uint64_t>(sender) << 32) | receiver;
  const std::uint64_t h = splitmix64(splitmix64(key_ ^ splitmix64(tick)) ^ link);
  return static_cast<double>(h >> 11) * 0x1.0p-53;
}

double BurstLoss::bad_after(bool bad, Tick steps) const {
  const double decay = std::pow(lambda_, static_cast<double>(steps));
  return bad ? rate_ + (1.0 - rate_) * decay : rate_ * (1.0 - decay);
}

bool BurstLoss::lost(Tick tick, RobotId sender, RobotId receiver) {
  if (rate_ <= 0.0) return false;
  if (links_.size() <= receiver) links_.resize(static_cast<std::size_t>(receiver) + 1);
  const double u = uniform(tick, sender, receiver);
  auto [it, first] = links_[receiver].try_emplace(sender);
  LinkState& link = it->second;
  if (first) {
    link.bad = u < rate_;
  } else if (tick > link.tick) {
    link.bad = u < bad_after(link.bad, tick - link.tick);
  }
  link.tick = tick;
  return link.bad;
}

}  // namespace swarmform::world
