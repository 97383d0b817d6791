// The agent's side of the DDS wire, as four verbs main() reads top to bottom: wait for the mission, claim the
// id, take the next own packet, send the command. Every wait blocks on one waitset (no polling sleeps) and
// ends on data, a signal, the world going away, or a deadline.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <optional>
#include <string>

#include "common/dds/agent_inbox.hpp"
#include "common/dds/command_writer.hpp"
#include "common/dds/mission_endpoints.hpp"
#include "common/dds/participant.hpp"
#include "common/dds/refusal_log.hpp"
#include "common/dds/signal_watch.hpp"
#include "common/dds/waiter.hpp"
#include "common/own_clock.hpp"

namespace swarmform::agent {

enum class WaitResult {
  Ok,
  Timeout,    // the deadline passed
  Stopped,    // SIGINT/SIGTERM
  WorldGone,  // the world's packet writer was alive and is no more
};

struct LinkOptions {
  // Take only the mission of this run (the launcher's --run-nonce); any first mission when empty.
  std::optional<std::uint64_t> run_nonce;
  // How long, in this agent's own awake time, the world's writers may stay not alive before the world is
  // taken for gone (docs/wire.md: a stalled or swapped world is not a dead one).
  double world_timeout_s = 10.0;
  // The world's process on this host (--world-pid; swarm run gives it): the world is gone as soon as that
  // process is, and while it is there (stopped, starved: slow, not dead) its silence is waited out for up to
  // world_stall_limit_s instead of world_timeout_s. A lockstep world starved for seconds (1024 agents on 2
  // cores) or stopped past world_timeout_s otherwise lost the agents that timed it out first.
  std::optional<pid_t> world_pid;
  double world_stall_limit_s = 300.0;
  // This robot's token from whoever started the run (SWARMFORM_CLAIM_TOKEN): every claim carries the proof
  // it gives (common/dds/claim_proof.hpp). Without one the world takes the claim only where it needs none.
  std::optional<dds::ClaimToken> claim_token;
};

class AgentLink {
 public:
  AgentLink(const dds::DdsSettings& settings, RobotId self, dds::SignalWatch& signals, LinkOptions options);
  ~AgentLink();
  AgentLink(const AgentLink&) = delete;
  AgentLink& operator=(const AgentLink&) = delete;

  // Also creates the endpoints of the per-tick topics: their QoS follows the mission's pace (realtime: best
  // effort), so they cannot exist before it. claim(), next_packet() and send() need a mission first.
  // With LinkOptions::world_pid, as claim(): past `timeout_s` while that process is there.
  WaitResult wait_mission(double timeout_s, dds::MissionAnnouncement& out);
  // Sends a claim until the world answers this attempt or `timeout_s` passes: again after 0.1 s four times
  // (the first are lost while the world matches our writer), then at doubling intervals up to 2 s (a world
  // busy admitting 1024 agents answers late, and a claim a second more only adds to its queue).
  // With LinkOptions::world_pid it waits on past `timeout_s` while that process is there, up to
  // claim_wait_s, and says WorldGone (world_process_gone) as soon as it is not.
  WaitResult claim(double timeout_s, dds::ClaimAnswer& out);
  // The waits before the run (mission, claim answer) at `now`: Timeout past `patient_until`, WorldGone once
  // past `deadline` (timeout_s) if the world's process is gone, else nullopt (wait on).
  std::optional<WaitResult> start_wait_over(dds_time_t now, dds_time_t deadline, dds_time_t patient_until);
  // The longest claim() waits for an answer, and wait_mission() for the mission (s).
  double claim_wait_s(double timeout_s) const;
  // The next packet of this robot. While the world is alive this waits as long as it takes (the world may be
  // waiting for other agents); `idle_timeout_s` bounds the wait only while no world writer is alive.
  // From 2 s after its claim until the first packet it is quiet: the world does not judge its liveliness
  // before the run (a lapse then is not a loss, world_server/server.cpp), so it asserts nothing, and it
  // re-sends the accepted claim only every kPreRunReclaimPeriod (5 s), for a world that forgot its
  // participant (DDS dropped it after its lease): 1024 agents waiting for the run each woke ~10 times a
  // second for assertions, claims and their answers, ~2 cores in all, and the run never started
  // (bench/scale/README.md). In its first 2 s it asserts and re-claims as after the first packet: an agent
  // joining a running world is judged at once, and its first packet comes within a round. After the first
  // packet it re-sends the claim every second (kReclaimPeriod) while the world's writers are not alive, and
  // in realtime when no packet came for a reclaim period (a network path lost and back, docs/multi-host.md; a
  // cut shorter than the world's 2 s writer lease leaves those writers alive here): the world took this agent
  // for dead and sends it nothing, and in realtime (best effort) Cyclone 0.10.2 drops the writer's liveliness
  // heartbeats ("no-reliable-readers") before they revive it, so only a sample does. The world answers a
  // claim it already holds as a repeat, and takes a lost owner's claim back. WorldGone only after the world's
  // writers have stayed not alive for world_timeout_s of this agent's own awake time (OwnClock): an agent
  // stalled past their 2 s lease finds it expired when it resumes, until the world's next liveliness message
  // arrives, and a world stalled for seconds is not a dead one. Before the first packet the world may stay
  // silent for max(world_timeout_s, idle_timeout_s) (world_silence_limit_s).
  WaitResult next_packet(double idle_timeout_s, dds::SensorSample& out);
  // How long the world may stay silent now before next_packet says WorldGone (s of this agent's time).
  double world_silence_limit_s(double idle_timeout_s) const;
  // next_packet said WorldGone because the world's process (LinkOptions::world_pid) is gone.
  bool world_process_gone() const { return world_process_gone_; }
  void send(Tick tick, const Command& command);
  // Renews this agent's liveliness if it is due (cheap otherwise): for a caller that is busy for longer than
  // the lease without sending, e.g. waiting on an --exec behaviour that is slow but not dead.
  void keep_alive();

  std::uint64_t packets() const { return packets_; }
  std::uint64_t foreign_packets() const { return foreign_; }
  std::uint64_t refused_samples() const;
  std::uint64_t claim_nonce() const { return claim_nonce_; }
  const dds::MissionAnnouncement& mission() const { return mission_taken_; }

 private:
  RobotId self_;
  dds::SignalWatch& signals_;
  LinkOptions options_;
  std::string who_;
  dds::RefusalLog mission_refusals_;
  dds::MissionAnnouncement mission_taken_;
  dds_time_t last_packet_at_ = 0;    // when next_packet last returned one
  OwnClock clock_{DDS_MSECS(1500)};  // the loop wakes at least every second
  dds::Participant participant_;
  dds::Waiter waiter_;
  dds::MissionReader mission_;
  std::optional<dds::AgentInbox> inbox_;        // made by wait_mission
  std::optional<dds::CommandWriter> commands_;  // made by wait_mission
  bool world_process_gone_ = false;
  std::uint64_t packets_ = 0;
  std::uint64_t foreign_ = 0;
  std::uint64_t claim_nonce_ = 0;  // of the accepted claim, re-sent before the first packet
  dds_time_t claimed_at_ = 0;      // when the world accepted it
  std::uint64_t proof_nonce_ = 0;  // the claim nonce proof_ is for
  std::optional<dds::ClaimProof> proof_;

  // Writes the claim of attempt `nonce`, with its proof when this agent has a token.
  void send_claim(std::uint64_t nonce);
};

}  // namespace swarmform::agent
