#include "robot_agent/dds_link.hpp"

#include <unistd.h>

#include <algorithm>
#include <iostream>
#include <random>

#include "common/dds/qos.hpp"
#include "common/process_state.hpp"

namespace swarmform::agent {

namespace {

// See next_packet and claim in the header.
constexpr dds_duration_t kReclaimPeriod = DDS_SECS(1);
// The longest a silent world's re-claims are apart (next_packet).
constexpr dds_duration_t kSilentReclaimCap = DDS_SECS(30);
// How often a silent world's process (LinkOptions::world_pid) is looked at.
constexpr dds_duration_t kWorldProcessRecheck = DDS_MSECS(100);
constexpr dds_duration_t kPreRunReclaimPeriod = DDS_SECS(5);
constexpr dds_duration_t kQuietAfter = DDS_SECS(2);

dds_time_t after(double seconds) {
  return dds_time() + static_cast<dds_duration_t>(seconds * 1e9);
}

std::uint64_t fresh_nonce() {
  std::random_device rd;
  const std::uint64_t r = (static_cast<std::uint64_t>(rd()) << 32) ^ rd();
  return r ^ (static_cast<std::uint64_t>(getpid()) << 16) ^ static_cast<std::uint64_t>(dds_time());
}

}  // namespace

AgentLink::AgentLink(const dds::DdsSettings& settings, RobotId self, dds::SignalWatch& signals,
                     LinkOptions options)
    : self_(self),
      signals_(signals),
      options_(options),
      who_("robot_agent " + std::to_string(self)),
      mission_refusals_(who_, std::cerr),
      participant_(settings),
      waiter_(participant_),
      mission_(participant_) {
  waiter_.attach(mission_.condition());
  signals_.notify(&waiter_);
}

AgentLink::~AgentLink() {
  signals_.notify(nullptr);
}

WaitResult AgentLink::wait_mission(double timeout_s, dds::MissionAnnouncement& out) {
  const dds_time_t deadline = after(timeout_s);
  // As the claim's answer (below): past timeout_s only while the world's process is there.
  const dds_time_t patient_until = options_.world_pid ? after(claim_wait_s(timeout_s)) : deadline;
  for (;;) {
    if (auto m = mission_.take(options_.run_nonce, mission_refusals_)) {
      dds::take_own_group(*m, self_);  // in a mixed swarm, this robot's group's behaviour and parameters
      out = std::move(*m);
      if (!inbox_) {
        // Bound to the world whose mission this is (docs/wire.md "Writer binding"): from now on packets,
        // END and claim answers are taken from its participant and run only.
        mission_taken_ = out;
        inbox_.emplace(participant_, self_, waiter_, out.realtime);
        inbox_->bind(dds::WorldBinding{out.world, out.run_nonce}, who_);
        waiter_.attach(inbox_->packet_condition());
        // Secure: in its own partition robot/K, the only one its permissions let it write (docs/security.md).
        commands_.emplace(participant_, out.realtime,
                          participant_.secure() ? std::optional<RobotId>(self_) : std::nullopt);
        commands_->set_stamp(out.run_nonce);
      }
      return WaitResult::Ok;
    }
    if (signals_.stop_requested()) return WaitResult::Stopped;
    const dds_time_t now = dds_time();
    if (const auto over = start_wait_over(now, deadline, patient_until)) return *over;
    waiter_.wait_until(std::min(now >= deadline ? now + kWorldProcessRecheck : deadline, patient_until));
  }
}

void AgentLink::send_claim(std::uint64_t nonce) {
  if (options_.claim_token && (!proof_ || proof_nonce_ != nonce)) {
    proof_ =
        dds::claim_proof(*options_.claim_token, mission_taken_.run_nonce, self_, nonce, commands_->guid());
    proof_nonce_ = nonce;
  }
  commands_->claim(self_, nonce, static_cast<std::uint32_t>(getpid()),
                   proof_ ? std::span<const std::uint8_t>(*proof_) : std::span<const std::uint8_t>());
}

WaitResult AgentLink::claim(double timeout_s, dds::ClaimAnswer& out) {
  const dds_time_t deadline = after(timeout_s);
  // With the world's pid the claim outlives timeout_s while that process is there (slow, not gone: 1024
  // agents starting on a busy host, or discovery on a loaded one), up to world_stall_limit_s; and ends as
  // soon as it is gone.
  const dds_time_t patient_until = options_.world_pid ? after(claim_wait_s(timeout_s)) : deadline;
  const std::uint64_t nonce = fresh_nonce();
  dds_time_t resend = 0;
  int attempts = 0;
  for (;;) {
    while (auto answer = inbox_->take_claim_reply()) {
      // A reply to an earlier attempt (ours or a previous agent's with this id) is not an answer to this one.
      if (answer->nonce == nonce) {
        out = std::move(*answer);
        claim_nonce_ = nonce;
        claimed_at_ = dds_time();
        return WaitResult::Ok;
      }
    }
    (void)mission_.take(options_.run_nonce, mission_refusals_);  // a republished mission is not news here
    if (signals_.stop_requested()) return WaitResult::Stopped;
    const dds_time_t now = dds_time();
    if (const auto over = start_wait_over(now, deadline, patient_until)) return *over;
    if (now >= resend) {
      // Re-sent: a claim written before the world matched our writer is lost, and so is an answer written
      // before the world matched our reader (both volatile). The first answers come quickly, the endpoints
      // were just made; then the world may be busy (see the header).
      send_claim(nonce);
      // 0.1 s four times, then 0.5, 1, 2, 2, ... s.
      resend = now + (++attempts < 5 ? DDS_MSECS(100) : DDS_MSECS(250) << std::min(attempts - 4, 3));
    }
    const dds_time_t look = now >= deadline ? now + kWorldProcessRecheck : deadline;
    waiter_.wait_until(std::min({look, patient_until, resend, commands_->keep_alive(now)}));
  }
}

std::optional<WaitResult> AgentLink::start_wait_over(dds_time_t now, dds_time_t deadline,
                                                     dds_time_t patient_until) {
  if (now < deadline) return std::nullopt;
  if (now >= patient_until) return WaitResult::Timeout;
  if (process_state(*options_.world_pid) == ProcessState::Gone) {
    world_process_gone_ = true;
    return WaitResult::WorldGone;
  }
  return std::nullopt;
}

double AgentLink::claim_wait_s(double timeout_s) const {
  return options_.world_pid ? std::max(timeout_s, options_.world_stall_limit_s) : timeout_s;
}

std::uint64_t AgentLink::refused_samples() const {
  return mission_refusals_.total() + (inbox_ ? inbox_->refused() : 0);
}

WaitResult AgentLink::next_packet(double idle_timeout_s, dds::SensorSample& out) {
  dds_time_t idle_deadline = after(idle_timeout_s);
  // Quiet: waiting for the run (see the header). Not in the first seconds after the claim: an agent that
  // joins a running world (a rejoin) gets its first packet within a round and is judged meanwhile.
  const auto quiet = [this](dds_time_t now) { return packets_ == 0 && now - claimed_at_ >= kQuietAfter; };
  // While the world is silent (its writers not alive) every sample written waits in its socket, or in this
  // writer's history if the link is cut, and reaches it in one burst when it is back, where more than a
  // writer's receive budget (24 a tick or second, common/dds/receive_budget.hpp) drops the rest, this round's
  // command among them: a world stopped 12 s met 27 samples of each agent and waited for commands it had
  // dropped. So the re-claims back off while it is silent (1, 2, 4, ... s, at most 30 s apart: 14 in 300 s),
  // and the keep-alive is no sample then (below).
  int silent_reclaims = 0;
  const auto reclaim_period = [&](dds_time_t now) {
    if (silent_reclaims > 0)
      return std::min<dds_duration_t>(kReclaimPeriod << (silent_reclaims - 1), kSilentReclaimCap);
    return quiet(now) ? kPreRunReclaimPeriod : kReclaimPeriod;
  };
  dds_time_t reclaim = dds_time() + reclaim_period(dds_time());
  bool reclaim_refused = false;
  // Realtime: a packet every tick; none for 3 ticks (at least a reclaim period) means the world took us for
  // dead.
  const double tick_s = mission_taken_.mission.tick_rate > 0 ? 1.0 / mission_taken_.mission.tick_rate : 0.1;
  const dds_duration_t starved_after =
      std::max(kReclaimPeriod, static_cast<dds_duration_t>(3 * tick_s * 1e9));
  dds_time_t world_silent_since = DDS_NEVER;  // in awake time (clock_)
  const auto silence_limit = static_cast<dds_duration_t>(world_silence_limit_s(idle_timeout_s) * 1e9);
  for (;;) {
    clock_.observe(dds_time());
    if (inbox_->take_packet(out, foreign_)) {
      ++packets_;
      last_packet_at_ = dds_time();
      return WaitResult::Ok;
    }
    (void)mission_.take(options_.run_nonce, mission_refusals_);
    if (auto answer = inbox_->take_claim_reply();
        answer && answer->nonce == claim_nonce_ && !answer->accepted) {
      // Another agent took the id over while we were lost: stop claiming it (the world says why once).
      reclaim_refused = true;
    }
    if (signals_.stop_requested()) return WaitResult::Stopped;
    const std::uint32_t alive = inbox_->world_writers_alive();
    const dds_time_t now = dds_time();
    if (alive > 0) {
      idle_deadline = now + static_cast<dds_duration_t>(idle_timeout_s * 1e9);
      world_silent_since = DDS_NEVER;
    } else {
      if (inbox_->world_seen() && options_.world_pid &&
          process_state(*options_.world_pid) == ProcessState::Gone) {
        // Once more round the loop first: a last packet (the END) may still wait in the reader.
        if (world_process_gone_) return WaitResult::WorldGone;
        world_process_gone_ = true;
        continue;
      }
      if (inbox_->world_seen()) {
        // Gone only if it stays silent for world_timeout_s of this agent's own awake time: an agent that was
        // itself stalled past the world's writer lease (2 s) finds that lease expired when it resumes, until
        // the world's next liveliness message comes in (within its lease); a world that is stalled itself
        // (SIGSTOP, swap) comes back.
        if (world_silent_since == DDS_NEVER) world_silent_since = clock_.awake();
        if (clock_.awake() - world_silent_since >= silence_limit) return WaitResult::WorldGone;
      } else if (now >= idle_deadline) {
        return WaitResult::Timeout;
      }
    }
    // Re-claims before the first packet, while the world's writers are not alive, and in realtime (a packet
    // every tick) when none came for a reclaim period (see the header).
    const bool starved = mission_taken_.realtime && packets_ > 0 && now - last_packet_at_ >= starved_after;
    const bool reclaiming =
        !reclaim_refused && (packets_ == 0 || (alive == 0 && inbox_->world_seen()) || starved);
    silent_reclaims = alive == 0 && inbox_->world_seen() ? std::max(silent_reclaims, 1) : 0;
    if (reclaiming && now >= reclaim) {
      send_claim(claim_nonce_);
      reclaim = now + reclaim_period(now);
      if (silent_reclaims > 0) silent_reclaims = std::min(silent_reclaims + 1, 16);
    }
    // Wake at least once a second to re-check the world's liveliness against the idle deadline, and to keep
    // our own alive while the world sends nothing (a slow lockstep round; not while quiet).
    // No packet for a lease: the world may have taken us for dead meanwhile (its own stall, a cut link,
    // ours), and only a sample brings a lost writer back (CommandWriter::keep_alive), so the keep-alive is
    // one. An assertion otherwise: nothing is lost, and it costs the world no sample to take. Not while the
    // world's writers are not alive: the world cannot take it then, and a backlog of them would cost this
    // round's command (above); the first keep-alive once they are back is a sample.
    const bool by_sample = alive > 0 && packets_ > 0 && now - last_packet_at_ >= dds::kLivelinessLease;
    const dds_time_t assert_at = quiet(now) ? DDS_NEVER : commands_->keep_alive(now, by_sample);
    dds_time_t wake = std::min({now + DDS_SECS(1), reclaiming ? reclaim : DDS_NEVER, assert_at});
    if (!inbox_->world_seen()) wake = std::min(wake, idle_deadline);
    if (alive == 0 && options_.world_pid) wake = std::min(wake, now + kWorldProcessRecheck);
    waiter_.wait_until(wake);
  }
}

double AgentLink::world_silence_limit_s(double idle_timeout_s) const {
  // Before its first packet an agent waits for a world that is still admitting the others: with 1024 agents
  // on 2 cores the world's writers missed their 2 s lease again and again during its start-up, and the
  // agents admitted first gave up after 10 s, so the run never started. Then only the agent's own --timeout.
  const double limit =
      packets_ == 0 ? std::max(options_.world_timeout_s, idle_timeout_s) : options_.world_timeout_s;
  return options_.world_pid ? std::max(limit, options_.world_stall_limit_s) : limit;
}

void AgentLink::keep_alive() {
  if (commands_) (void)commands_->keep_alive(dds_time());
}

void AgentLink::send(Tick tick, const Command& command) {
  commands_->step(self_, tick, command);
}

}  // namespace swarmform::agent
