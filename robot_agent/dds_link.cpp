#include "robot_agent/dds_link.hpp"

#include <unistd.h>

#include <algorithm>
#include <random>

namespace swarmform::agent {

namespace {

constexpr dds_duration_t kReclaimPeriod = DDS_SECS(1);  // see next_packet in the header
// How long the world's writers must stay not alive before the agent takes the world for gone (see
// next_packet in the header): a dead world is noticed within its writer lease (2 s) + this.
constexpr dds_duration_t kWorldGoneGrace = DDS_SECS(3);

dds_time_t after(double seconds) {
  return dds_time() + static_cast<dds_duration_t>(seconds * 1e9);
}

std::uint64_t fresh_nonce() {
  std::random_device rd;
  const std::uint64_t r = (static_cast<std::uint64_t>(rd()) << 32) ^ rd();
  return r ^ (static_cast<std::uint64_t>(getpid()) << 16) ^ static_cast<std::uint64_t>(dds_time());
}

}  // namespace

AgentLink::AgentLink(const dds::DdsSettings& settings, RobotId self, dds::SignalWatch& signals)
    : self_(self), signals_(signals), participant_(settings), waiter_(participant_), mission_(participant_) {
  waiter_.attach(mission_.condition());
  signals_.notify(&waiter_);
}

AgentLink::~AgentLink() {
  signals_.notify(nullptr);
}

WaitResult AgentLink::wait_mission(double timeout_s, dds::MissionAnnouncement& out) {
  const dds_time_t deadline = after(timeout_s);
  for (;;) {
    if (auto m = mission_.take()) {
      out = std::move(*m);
      if (!inbox_) {
        inbox_.emplace(participant_, self_, waiter_, out.realtime);
        waiter_.attach(inbox_->packet_condition());
        commands_.emplace(participant_, out.realtime);
      }
      return WaitResult::Ok;
    }
    if (signals_.stop_requested()) return WaitResult::Stopped;
    if (dds_time() >= deadline) return WaitResult::Timeout;
    waiter_.wait_until(deadline);
  }
}

WaitResult AgentLink::claim(double timeout_s, dds::ClaimAnswer& out) {
  const dds_time_t deadline = after(timeout_s);
  const std::uint64_t nonce = fresh_nonce();
  dds_time_t resend = 0;
  int attempts = 0;
  for (;;) {
    while (auto answer = inbox_->take_claim_reply()) {
      // A reply to an earlier attempt (ours or a previous agent's with this id) is not an answer to this one.
      if (answer->nonce == nonce) {
        out = std::move(*answer);
        claim_nonce_ = nonce;
        return WaitResult::Ok;
      }
    }
    (void)mission_.take();  // a republished mission is not news here
    if (signals_.stop_requested()) return WaitResult::Stopped;
    const dds_time_t now = dds_time();
    if (now >= deadline) return WaitResult::Timeout;
    if (now >= resend) {
      // Re-sent every 0.5 s: a claim written before the world matched our writer is lost, and so is an answer
      // written before the world matched our reader (both volatile).
      commands_->claim(self_, nonce, static_cast<std::uint32_t>(getpid()));
      // The first answers come quickly: the endpoints were just made, and an answer written before the world
      // matched them is lost (best effort or volatile); then every 0.5 s.
      resend = now + (++attempts < 5 ? DDS_MSECS(100) : DDS_MSECS(500));
    }
    waiter_.wait_until(std::min({deadline, resend, commands_->keep_alive(now)}));
  }
}

WaitResult AgentLink::next_packet(double idle_timeout_s, dds::SensorSample& out) {
  dds_time_t idle_deadline = after(idle_timeout_s);
  dds_time_t reclaim = packets_ == 0 ? dds_time() + kReclaimPeriod : DDS_NEVER;
  dds_time_t world_silent_since = DDS_NEVER;
  for (;;) {
    if (inbox_->take_packet(out, foreign_)) {
      ++packets_;
      return WaitResult::Ok;
    }
    (void)mission_.take();
    if (auto answer = inbox_->take_claim_reply();
        answer && answer->nonce == claim_nonce_ && !answer->accepted) {
      // Another agent took the id over while we were lost: stop claiming it (the world says why once).
      reclaim = DDS_NEVER;
    }
    if (signals_.stop_requested()) return WaitResult::Stopped;
    const std::uint32_t alive = inbox_->world_writers_alive();
    const dds_time_t now = dds_time();
    if (alive > 0) {
      idle_deadline = now + static_cast<dds_duration_t>(idle_timeout_s * 1e9);
      world_silent_since = DDS_NEVER;
    } else {
      if (inbox_->world_seen()) {
        // Gone only if it stays silent for kWorldGoneGrace: an agent that was itself stalled past the world's
        // writer lease (2 s) finds that lease expired when it resumes, until the world's next liveliness
        // message comes in (within its lease).
        if (world_silent_since == DDS_NEVER) world_silent_since = now;
        if (now - world_silent_since >= kWorldGoneGrace) return WaitResult::WorldGone;
      }
      if (now >= idle_deadline) return WaitResult::Timeout;
    }
    if (now >= reclaim) {  // before the first packet only (see the header)
      commands_->claim(self_, claim_nonce_, static_cast<std::uint32_t>(getpid()));
      reclaim = now + kReclaimPeriod;
    }
    // Wake at least once a second to re-check the world's liveliness against the idle deadline, and to keep
    // our own alive while the world sends nothing (before the run, or a slow lockstep round).
    const dds_time_t gone_check =
        world_silent_since == DDS_NEVER ? DDS_NEVER : world_silent_since + kWorldGoneGrace;
    waiter_.wait_until(
        std::min({idle_deadline, now + DDS_SECS(1), reclaim, gone_check, commands_->keep_alive(now)}));
  }
}

void AgentLink::send(Tick tick, const Command& command) {
  commands_->step(self_, tick, command);
}

}  // namespace swarmform::agent
