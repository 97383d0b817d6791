// The world judges an agent's liveliness against its own progress (docs/wire.md
// "Liveliness, stalls and deaths"). When the world itself was not running (SIGSTOP, swap, a loaded host),
// Cyclone finds every agent's 500 ms lease expired as soon as it resumes, although the agents kept asserting
// it all along: their datagrams wait in the socket. So a writer lost within kSuspectWindow of awake time
// after the world's own stall, or of a sample refused as abuse (a flood), is only suspected; it becomes a
// death if it stays lost for kGrace of awake time, and was never dead if its liveliness comes back before or
// a sample of its comes in (the agent's next command or ALIVE sample). The grace outlasts the command
// reader's budget window: the samples an agent kept sending through a 4 s stall of the world (~30 ALIVE
// samples and claims) arrive at once, over its budget (common/dds/receive_budget.hpp), and the rest of that
// window drops them unread; a grace of one lease ran out first and buried a live agent (CI, 2026-12-06).
// Otherwise a loss is a death at once (a SIGKILL is seen in ~0.5 s). A writer that went away (deleted with
// its participant, or forgotten when its participant's lease ran out) is suspected the same way (a forgotten
// one comes back under a new handle), but nothing clears it any more: samples it wrote before it went may
// still be taken after its going was seen (they reach the world by another socket and thread than discovery),
// and once they cleared the suspicion of 566 agents that had exited while the world stalled among 1024: the
// world kept them alive to the end.
#pragma once

#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

#include "common/dds/identity.hpp"
#include "common/dds/qos.hpp"
#include "common/dds/receive_budget.hpp"
#include "common/own_clock.hpp"

namespace swarmform::server {

class StallGuard {
 public:
  // The server's loop wakes at least this often (its waits are capped to it), so that a longer gap is its
  // own stall.
  static constexpr dds_duration_t kProbe = DDS_MSECS(100);
  static constexpr dds_duration_t kMaxGap = DDS_MSECS(250);
  static constexpr dds_duration_t kSuspectWindow = 2 * dds::kLivelinessLease;
  // A budget window (at most a wall-clock second, and awake time runs no faster than the wall clock) and a
  // lease: the agent's next assertion after its dropped burst comes in a window that admits it.
  static constexpr dds_duration_t kGrace = dds::ReceiveBudget::kSecond + dds::kLivelinessLease;

  StallGuard() : clock_(kMaxGap) {}

  // First thing at every wake-up of the server's loop.
  void observe(dds_time_t now) { clock_.observe(now); }
  dds_time_t awake() const { return clock_.awake(); }
  // When the loop must wake next at the latest, from `now`, to keep observing.
  dds_time_t probe(dds_time_t now) const { return now + kProbe; }

  // A sample was refused as abuse (a flood): honest agents' datagrams, their liveliness among them, may wait
  // behind the flood's in the world's socket as they do through its own stall (a realtime flood on 2 cores
  // let 5 agents' leases lapse at once, ~2 runs in 15), so a loss within kSuspectWindow of it is only
  // suspected too.
  void flooded() {
    flooded_ = true;
    last_flood_ = clock_.awake();
  }
  // A writer lost its liveliness (`gone`: went away): true if this is only a suspicion (the world stalled,
  // or was flooded, lately), false if it is a death now.
  bool suspect(dds::PublicationHandle writer, bool gone = false);
  // Its liveliness came back, or a sample of it came in: true if it was a suspect that had not gone away
  // (then it never died).
  bool clear(dds::PublicationHandle writer);
  bool suspected(dds::PublicationHandle writer) const { return suspects_.count(writer) != 0; }
  // Suspects lost for kGrace of awake time: they are deaths now (removed from the suspects).
  void expired(std::vector<dds::PublicationHandle>& out);
  // The awake time an expired suspect's loss was noticed, once (for MassLoss: when it went, not when the
  // grace ran out); nullopt for a writer that did not expire from suspicion.
  std::optional<dds_time_t> take_lost_at(dds::PublicationHandle writer);
  // The world recorded `writer`'s owner dead. If it was suspected lately, it is one of the losses that were
  // deaths, and a sample that cleared it did not hold: an agent that exits while the world is stopped is
  // often heard again (its last samples wait in the socket) before its going is seen, and counting that as
  // a comeback made the end-of-run line say 9 came back where 6 of the 9 were recorded dead.
  void died(dds::PublicationHandle writer);

  std::uint64_t own_stalls() const { return clock_.stalls(); }
  double own_stalled_seconds() const { return static_cast<double>(clock_.stalled_total()) * 1e-9; }
  // Lost writers that came back within the grace and were not recorded dead afterwards.
  std::uint64_t suspicions_cleared() const { return cleared_; }
  // Lost writers, suspected lately, that were recorded dead (after the grace, or after going away).
  std::uint64_t suspects_died() const { return died_; }

 private:
  OwnClock clock_;
  struct Suspect {
    dds_time_t since = 0;  // awake time of the loss
    bool gone = false;
  };
  std::unordered_map<dds::PublicationHandle, Suspect> suspects_;
  std::unordered_map<dds::PublicationHandle, dds_time_t> expired_lost_at_;  // until take_lost_at
  // Writers suspected within kRecent of awake time (cleared or not): the awake time of their last
  // suspicion and how often a sample or their liveliness cleared them. A death of one of them is a loss of
  // the stall (died); older ones are forgotten (a death long after is another story).
  struct Lately {
    dds_time_t since = 0;
    std::uint64_t clears = 0;
  };
  static constexpr dds_duration_t kRecent = kSuspectWindow + kGrace;
  std::unordered_map<dds::PublicationHandle, Lately> lately_;
  std::uint64_t cleared_ = 0;
  std::uint64_t died_ = 0;
  bool flooded_ = false;
  dds_time_t last_flood_ = 0;  // awake time of the last refused sample
};

}  // namespace swarmform::server
