// Bursty packet loss: a two-state Gilbert-Elliott chain per directed link (sender -> receiver). In the Good
// state a copy gets through, in the Bad state it is lost; the chain steps once a tick. Its two parameters are
// the long-run loss rate pi and the mean burst length B (ticks in Bad, geometric):
//   P(Bad -> Good) = 1 / B,   P(Good -> Bad) = pi / (B (1 - pi)),
// so B = 1 / (1 - pi) is memoryless (independent loss at rate pi) and larger B clusters the losses.
//
// A link's state is only looked at when a copy travels over it, and a link may be silent for many ticks (out
// of range, a silent sender, a loss fault). The state is therefore advanced lazily, by the chain's k-step
// transition in closed form (P(Bad at t+k | Bad at t) = pi + (1 - pi) l^k, | Good: pi (1 - l^k), with
// l = 1 - 1/(B (1 - pi))), which has the same law as stepping it every tick. A link first seen starts from
// the stationary law (Bad with probability pi).
//
// Each draw is a hash of (seed, tick, sender, receiver) through splitmix64, not a step of a shared stream: a
// link's losses depend on nothing but its own history, whatever the other links, the order in which the
// receivers are visited or the worker count, so the in-process and the multi-process runs lose the same
// copies.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "common/types.hpp"

namespace swarmform::world {

class BurstLoss {
 public:
  // rate in [0, 1), mean_burst >= 1 / (1 - rate) (checked by the scenario loader: valid_mean_burst).
  BurstLoss(double rate, double mean_burst, std::uint64_t seed);

  // True when the copy from `sender` to `receiver` at `tick` is lost. Ticks of one link must not decrease.
  bool lost(Tick tick, RobotId sender, RobotId receiver);

  // The smallest mean burst the model accepts at `rate`: that of independent loss, 1 / (1 - rate). Below it
  // the losses would be anti-correlated (a loss makes the next tick's less likely), which no radio does.
  static double min_mean_burst(double rate) { return 1.0 / (1.0 - rate); }

 private:
  struct LinkState {
    Tick tick = 0;  // when `bad` was last drawn
    bool bad = false;
  };
  double uniform(Tick tick, RobotId sender, RobotId receiver) const;
  double bad_after(bool bad, Tick steps) const;  // P(Bad `steps` ticks later | bad now)

  double rate_;
  double lambda_;  // the chain's second eigenvalue, 1 - P(Bad -> Good) - P(Good -> Bad), in [0, 1)
  std::uint64_t key_;
  std::vector<std::unordered_map<RobotId, LinkState>> links_;  // [receiver][sender]
};

}  // namespace swarmform::world
