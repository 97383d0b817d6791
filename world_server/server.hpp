// The DDS world server's run: connect the agents, then round after round until the run is complete or a
// signal comes, then announce the end. Server::run_rounds lists a round's stages in order (README.md "A
// round"); World::step is the step stage's own table of contents (world.hpp).
//
// Claims, deaths (liveliness lost) and spoofed commands are handled whenever the server wakes, in any stage.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "common/dds/qos.hpp"
#include "common/dds/refusal_log.hpp"
#include "common/dds/signal_watch.hpp"
#include "common/exit_codes.hpp"
#include "world_server/agent_registry.hpp"
#include "world_server/dds_bridge.hpp"
#include "world_server/input_guard.hpp"
#include "world_server/late_commands.hpp"
#include "world_server/mass_loss.hpp"
#include "world_server/process_faults.hpp"
#include "world_server/robot_slot.hpp"
#include "world_server/run/end_reason.hpp"
#include "world_server/run/fault_schedule.hpp"
#include "world_server/run/run_session.hpp"
#include "world_server/run/telemetry_check.hpp"
#include "world_server/stall_guard.hpp"
#include "world_server/status_channel.hpp"
#include "world_server/stragglers.hpp"
#include "world_server/viewer_control.hpp"
#include "world_server/world/scenario.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::server {

// How long the world's start-up may stand still (no claim, no matched reader) when --connect-timeout is not
// given: 30 s, plus 25 ms an agent (1024 agents: 55.6 s). Start-up grows with N (each agent starts a DDS
// participant and discovers the world on a shared machine), so a fixed wait is either too short at 2048 or
// needlessly long at 4; the launcher (scripts/swarmform/launcher.py connect_timeout) mirrors this formula.
inline constexpr double kConnectTimeoutBaseS = 30.0;
inline constexpr double kConnectTimeoutPerAgentS = 0.025;
inline double default_connect_timeout(std::size_t robots) {
  return kConnectTimeoutBaseS + kConnectTimeoutPerAgentS * static_cast<double>(robots);
}

struct ServerOptions {
  std::string run_dir;
  Tick record_every = 1;                // robots.csv rows every K-th tick (world::RunOptions::record_every)
  dds::DdsSettings dds;                 // role World
  double connect_timeout_s = 60.0;      // the start-up ends when no agent connected for this long
  std::map<RobotId, pid_t> agent_pids;  // for --kill and stalls: the world SIGKILLs / SIGSTOPs these
  Tick warmup_ticks = 100;              // left out of summary.json's steady_ticks_per_second
  std::uint64_t run_nonce = 0;          // this run's (docs/wire.md); 0: drawn at random
  // --agent-pids FILE: {"id": pid} JSON the launcher writes after starting the agents (after the world);
  // read when a --kill is due for an id not in agent_pids.
  std::string agent_pids_file;
  // The run's viewer (viewer_control.hpp). A token != 0 makes the observer endpoints; the viewer
  // presents the same token. start_paused: lockstep holds tick 0 until the viewer says go.
  std::uint64_t viewer_token = 0;
  bool start_paused = false;
  // Who may take a robot's id (docs/wire.md "Claim proofs"): the run's secret, from which every agent the
  // launcher starts has its id's token (none: no claim is issued, so an owned id goes to nobody else), and
  // --open-rejoin (anyone may take a dead owner's id).
  std::optional<dds::RunSecret> run_secret;
  bool open_rejoin = false;
  // --status-fd: where the JSON status lines go (status_channel.hpp); -1: none.
  int status_fd = -1;
};

// Exit codes of a run: common/exit_codes.json holds them all (and their meanings).
using exit_codes::kExitAgentsMissing;
using exit_codes::kExitAgentsStalled;
using exit_codes::kExitOk;
using exit_codes::kExitRecordingFailed;
inline constexpr int kExitWorldFailed = exit_codes::kExitFailed;  // the world could not go on

class Server {
 public:
  Server(const world::Scenario& scenario, ServerOptions options, dds::SignalWatch& signals);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  int run();

 private:
  bool connect_agents();
  std::vector<RobotId> unmatched_robots() const;  // robots whose packet writer has matched no reader yet

  // ---- the round: run_rounds lists the stages in order; each is one function below ----
  void run_rounds();
  // Lockstep with a viewer: holds the next round while the viewer paused the run or its speed cap says wait
  // (pumping DDS meanwhile: deaths and claims are still handled). False when a stop was asked.
  bool hold_for_viewer();
  void begin_publish();     // the round's clock: round_start_ and the publish stage's profile
  void kills_and_faults();  // the scheduled kills and faults due now (run/fault_schedule.hpp)
  // SensorPacket(t) to every live, connected, not held robot, each robot's perception made just before its
  // packet (World::defer_perceptions); who this round awaits.
  void publish_packets();
  void offer_viewer_frame();  // the viewer's frame, while the agents compute
  void end_publish();
  // The previous tick's record, when record_or_defer left it until this round's packets were out.
  void record_deferred_tick();
  // Command(t): lockstep waits for every awaited command until the deadline, realtime takes whatever comes
  // until the period is over. False when a stop was asked (the round in flight is then not stepped).
  bool collect();
  bool collect_lockstep();
  // The awaited robots' packets again (collect_lockstep, kRoundRewrite).
  void rewrite_round();
  bool collect_realtime();
  void apply_commands();  // this round's commands, in id order
  void step_world();      // World::step
  // The new tick's record now, or, when the next round's start changes nothing it records, after that
  // round's packets (record_pending_). True when the run is complete (then always recorded at once).
  bool record_or_defer();
  // The session's record of the new tick, then the observers': WorldState (<= 20 Hz) and progress (1 Hz).
  void record_tick();
  void publish_observers();
  // Whether the next round's start changes nothing the record reads and records nothing itself (no kill,
  // fault edge or pending restart due, no viewer): its record may then wait until its packets are out.
  bool record_can_follow_packets() const;
  // The viewer's frame with each robot's last command (viewer_control.hpp).
  void offer_frame(dds_time_t now, bool finished);

  // Takes what DDS has: claims, commands, lost writers. `running`: the world is ticking (deaths and rejoins
  // act on the world).
  void pump(bool running);
  void on_claim(const dds::CommandSample& s, bool running);
  void on_command(const dds::CommandSample& s);
  void on_lost(dds::PublicationHandle writer, bool running, bool gone);
  // Lockstep: `writer`'s owner lost its liveliness but its process is there: a straggler (stragglers.hpp).
  bool straggles(dds::PublicationHandle writer, bool running);
  // Stragglers whose process went are deaths now.
  void check_stragglers();
  bool judged(dds::PublicationHandle writer) const;  // judged_ of the robot `writer` owns
  void on_regained(dds::PublicationHandle writer, bool running);
  // A lost owner that is a death now (after StallGuard's judgement); `why` for its death_detected event
  // (default: its liveliness was lost).
  void on_dead(dds::PublicationHandle writer, bool running, const char* why = nullptr);
  // Brings a dead robot back for its (same or new) owner: a rejoin, its generation raised so that the agent
  // starts its controller afresh.
  void revive(RobotId id);
  // The robots whose commands the round still awaits, for a line ("robots 1, 3, 5").
  std::string awaited_text() const;
  // Waits until `deadline` at the latest, waking at least every StallGuard::kProbe.
  void wait_a_while(dds_time_t deadline);
  std::optional<pid_t> agent_pid(RobotId id);
  void announce_end();
  // Whether robot `id`'s agent gets the END: its owner, or a lost owner whose process may still be there.
  bool may_hear_the_end(RobotId id);
  void progress(bool force);
  bool stopping() const;
  // run() without its failure handling: a RecordingError or another exception out of it ends in fail().
  int run_inner();
  // Ends a run that failed with `what` for `reason`: the agents are told, the summary written if it can be,
  // one line on stderr. Returns `code`.
  int fail(world::EndReason reason, const std::string& what, int code);
  // The budget check and throttled report of one sample (input_guard.hpp).
  bool admit(const dds::CommandSample& s, bool running);
  // Counts `what` from s's writer; when it is to be logged now (once a second per writer and kind), records
  // event `kind` with `detail` (plus the count it stands for), and prints it on stderr with `to_stderr`.
  // The samples the command readers dropped over their writers' budgets (dds::ReceiveBudget), reported as
  // commands over the limit: counted, an event a second a writer.
  void report_budget_drops();
  void report(const dds::CommandSample& s, Abuse what, const std::string& kind, const std::string& detail,
              bool to_stderr);
  // An owner's telemetry checked before the world takes it (telemetry_check.hpp).
  void check_telemetry_of(RobotId id);
  // The summary's fields of the world_server alone: input_dropped and mass_losses.
  void note_summary_fields();
  void note_input_dropped();
  // One `mass_loss` event and stdout line for a group of robots lost together (mass_loss.hpp).
  void report_mass_loss(const MassLoss::Group& g);

  const world::Scenario& scenario_;
  ServerOptions options_;
  dds::SignalWatch& signals_;
  world::World world_;
  world::RunSession session_;
  AgentRegistry registry_;
  WorldLink link_;
  StallGuard stalls_;
  Stragglers stragglers_;
  MassLoss mass_;
  dds::RefusalLog refusals_;
  std::vector<dds::PublicationHandle> expired_;
  std::vector<RobotSlot> robots_;  // by id
  // Owners whose first packet went out while their liveliness was lapsed (all quiet agents at the start):
  // writer -> the awake time by which a sample or their liveliness must come back, or they are dead (an
  // agent killed before the run is otherwise seen only when its participant's lease runs out).
  std::unordered_map<dds::PublicationHandle, dds_time_t> first_answer_due_;
  static constexpr dds_duration_t kFirstAnswerGrace = DDS_SECS(2);
  // A round waiting this long says on stderr whom it waits for, and again at each further period.
  static constexpr dds_duration_t kWaitReport = DDS_SECS(5);
  // A lockstep round still waiting this long (wall time) writes the awaited robots' packets again, and again
  // at each further period (rewrite_round): two of the world's writer leases; at most half the scenario's
  // lockstep_deadline, so that a lost packet is written again before the wait ends the run.
  static constexpr dds_duration_t kRoundRewrite = 2 * dds::kWorldLivelinessLease;
  std::uint64_t rounds_rewritten_ = 0;
  std::uint64_t packets_rewritten_ = 0;
  InputGuard guard_;
  std::vector<world::TelemetryLimits> telemetry_limits_;  // a robot group's each (one without groups)
  std::uint64_t telemetry_fields_dropped_ = 0;
  std::uint64_t telemetry_events_dropped_ = 0;
  std::size_t waiting_count_ = 0;
  std::vector<dds::CommandSample> samples_;
  std::vector<dds::CommandReader::LivelinessChange> liveliness_;
  std::vector<dds::ReceiveBudget::Drops> budget_drops_;
  // Liveliness lapses before an owner's first packet: counted, not losses.
  std::uint64_t unjudged_lapses_ = 0;
  // Lockstep waited lockstep_deadline for a round's commands: the run ends (agents_stalled), saying this.
  bool stalled_out_ = false;
  std::string stalled_what_;
  // Claims and commands taken after their writer went away: ignored, counted.
  std::uint64_t stale_samples_ = 0;
  std::vector<dds::RobotPoseRow> rows_;
  std::vector<behaviour::KnownColumns> known_;  // by robot id: where each reports its label

  dds_time_t start_ = 0;
  dds_time_t steady_start_ = 0;  // the end of tick options_.warmup_ticks; 0 until then
  dds_time_t last_progress_ = 0;
  Tick last_progress_tick_ = 0;
  dds_time_t last_state_ = 0;
  bool record_pending_ = false;  // record_or_defer left the new tick's record to the next round
  std::uint64_t missed_ticks_ = 0;
  dds_time_t round_start_ = 0;             // when this round began
  dds_time_t round_due_ = 0;               // realtime: when this round's period is over
  LateCommands late_;                      // realtime: where a missed command's time went
  world::FaultSchedule schedule_;          // scheduled kills and faults (run/fault_schedule.hpp)
  StatusChannel status_;                   // the JSON status lines (status_channel.hpp)
  ProcessFaults faults_;                   // what they do to the agents' processes (process_faults.hpp)
  std::unique_ptr<ViewerControl> viewer_;  // null without --viewer-token

  // Where a round's wall time goes (printed on stderr at the end; what P1 asks first, BENCHMARKS.md).
  struct Profile {
    // Where the stage being timed began: the wall clock, and the publish stage's thread clock.
    dds_time_t stage_start = 0;
    dds_duration_t cpu_at_start = 0;
    std::uint64_t preempted_at_start = 0;
    dds_duration_t publish = 0;  // kills and faults + SensorPackets out + the viewer's frame
    // Of the publish phase: the main thread's CPU time and how often it was preempted. At N = 256 in
    // realtime the phase took ~30 ms of wall time a round with ~5 ms on the CPU: the rest is waiting for a
    // CPU among the agents it wakes (BENCHMARKS.md, P2).
    dds_duration_t publish_cpu = 0;
    std::uint64_t publish_preempted = 0;
    dds_duration_t collect = 0;  // waiting for and taking the commands
    dds_duration_t step = 0;     // apply + World::step
    dds_duration_t record = 0;   // RunSession::record_tick + world state + progress
    std::uint64_t rounds = 0;
    // What the rounds carried, so that the bare DDS round (bench/bare_round) can carry the same bytes.
    std::uint64_t packets = 0;
    std::uint64_t packet_messages = 0;       // neighbours' messages in those packets
    std::uint64_t packet_message_bytes = 0;  // their payload bytes
    std::uint64_t commands = 0;              // this round's commands taken
    std::uint64_t command_message_bytes = 0;
  } profile_;
};

}  // namespace swarmform::server
