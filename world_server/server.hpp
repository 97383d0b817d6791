// The DDS world server's run: connect the agents, then tick in lockstep or realtime until the run is complete
// or a signal comes, then announce the end. The tick order is World's (world.hpp); this file decides only
// when a tick happens and which commands go into it:
//
//   round t:  scheduled kills and faults -> publish SensorPacket(t) to every live robot -> collect Command(t)
//             (lockstep: every live owner's, until the deadline; realtime: whatever came within the period)
//             -> apply in id order -> World::step -> RunSession::record_tick (after the next round's
//             packets when that round's start changes nothing it records, record_can_follow_packets)
//
// Claims, deaths (liveliness lost) and spoofed commands are handled whenever the server wakes, in any phase.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "common/dds/refusal_log.hpp"
#include "common/dds/signal_watch.hpp"
#include "world_server/agent_registry.hpp"
#include "world_server/dds_bridge.hpp"
#include "world_server/input_guard.hpp"
#include "world_server/late_commands.hpp"
#include "world_server/process_faults.hpp"
#include "world_server/run/end_reason.hpp"
#include "world_server/run/fault_schedule.hpp"
#include "world_server/run/run_session.hpp"
#include "world_server/run/telemetry_check.hpp"
#include "world_server/stall_guard.hpp"
#include "world_server/viewer_control.hpp"
#include "world_server/world/scenario.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::server {

// How long the world waits for every agent when --connect-timeout is not given: 30 s, plus 25 ms an agent
// (1024 agents: 55.6 s). Start-up grows with N (each agent starts a DDS participant and discovers the world
// on a shared machine), so a fixed wait is either too short at 2048 or needlessly long at 4; the launcher
// (scripts/swarmform/launcher.py connect_timeout) mirrors this formula.
inline constexpr double kConnectTimeoutBaseS = 30.0;
inline constexpr double kConnectTimeoutPerAgentS = 0.025;
inline double default_connect_timeout(std::size_t robots) {
  return kConnectTimeoutBaseS + kConnectTimeoutPerAgentS * static_cast<double>(robots);
}

struct ServerOptions {
  std::string run_dir;
  Tick record_every = 1;                // robots.csv rows every K-th tick (world::RunOptions::record_every)
  dds::DdsSettings dds;                 // role World
  double connect_timeout_s = 60.0;      // every agent must have claimed its id by then
  std::map<RobotId, pid_t> agent_pids;  // for --kill and stalls: the world SIGKILLs / SIGSTOPs these
  Tick warmup_ticks = 100;              // left out of summary.json's steady_ticks_per_second
  std::uint64_t run_nonce = 0;          // this run's (docs/wire.md); 0: drawn at random
  // --agent-pids FILE: {"id": pid} JSON the launcher writes after starting the agents (after the world);
  // read when a --kill is due for an id not in agent_pids.
  std::string agent_pids_file;
  // Issue 21: the run's viewer (viewer_control.hpp). A token != 0 makes the observer endpoints; the viewer
  // presents the same token. start_paused: lockstep holds tick 0 until the viewer says go.
  std::uint64_t viewer_token = 0;
  bool start_paused = false;
};

// Exit codes of a run (main.cpp documents them all; scripts/README.md too).
inline constexpr int kExitOk = 0;           // completed, max_ticks or interrupted: summary.json written
inline constexpr int kExitWorldFailed = 1;  // the world could not go on (a DDS failure, an internal error)
inline constexpr int kExitAgentsMissing = 3;
inline constexpr int kExitRecordingFailed = 5;  // a write of the run directory failed (disk full, ...)

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
  void run_lockstep();
  void run_realtime();

  // One round's start: kills due now, packets out, the set of robots whose command is awaited; then the
  // previous tick's record if end_round left it pending.
  void begin_round();
  // Applies the commands of this round (id order), steps the world and records the new tick, at once or,
  // when the next round's start changes nothing it records, after that round's packets (record_pending_);
  // true when the run is complete (then always recorded at once).
  bool end_round();
  // The session's record of the new tick with the WorldState and progress lines.
  void record_round();
  // Whether the next round's start changes nothing the record reads and records nothing itself (no kill,
  // fault edge or pending restart due, no viewer): its record may then wait until its packets are out.
  bool record_can_follow_packets() const;
  // Takes what DDS has: claims, commands, lost writers. `running`: the world is ticking (deaths and rejoins
  // act on the world).
  void pump(bool running);
  void on_claim(const dds::CommandSample& s, bool running);
  void on_command(const dds::CommandSample& s);
  void on_lost(dds::PublicationHandle writer, bool running, bool gone);
  bool judged(dds::PublicationHandle writer) const;  // judged_ of the robot `writer` owns
  void on_regained(dds::PublicationHandle writer, bool running);
  // A lost owner that is a death now (after StallGuard's judgement).
  void on_dead(dds::PublicationHandle writer, bool running);
  // Brings a dead robot back for its (same or new) owner: a rejoin, its generation raised so that the agent
  // starts its controller afresh.
  void revive(RobotId id);
  // Waits until `deadline` at the latest, waking at least every StallGuard::kProbe.
  void wait_a_while(dds_time_t deadline);
  std::optional<pid_t> agent_pid(RobotId id);
  void announce_end();
  void progress(bool force);
  // Lockstep: holds the next round while the viewer paused the run or its speed cap says wait (pumping DDS
  // meanwhile: deaths and claims are still handled). False when a stop was asked.
  bool wait_for_viewer();
  bool stopping() const;
  // run() without its failure handling: a RecordingError or another exception out of it ends in fail().
  int run_inner();
  // Ends a run that failed with `what` for `reason`: the agents are told, the summary written if it can be,
  // one line on stderr. Returns `code`.
  int fail(world::EndReason reason, const std::string& what, int code);
  // Issue 18 point 4: the budget check and throttled report of one sample (input_guard.hpp).
  bool admit(const dds::CommandSample& s, bool running);
  // Counts `what` from s's writer; when it is to be logged now (once a second per writer and kind), records
  // event `kind` with `detail` (plus the count it stands for), and prints it on stderr with `to_stderr`.
  void report(const dds::CommandSample& s, Abuse what, const std::string& kind, const std::string& detail,
              bool to_stderr);
  // Issue 18 point 3: an owner's telemetry checked before the world takes it (telemetry_check.hpp).
  void check_telemetry_of(RobotId id);
  void note_input_dropped();

  const world::Scenario& scenario_;
  ServerOptions options_;
  dds::SignalWatch& signals_;
  world::World world_;
  world::RunSession session_;
  AgentRegistry registry_;
  WorldLink link_;
  StallGuard stalls_;
  dds::RefusalLog refusals_;
  std::vector<std::uint32_t> generation_;   // per robot: raised at each revival
  std::vector<std::uint64_t> owner_nonce_;  // per robot: the claim nonce of its owner
  std::vector<dds::PublicationHandle> expired_;

  // Per robot, reused every tick.
  std::vector<Command> latest_;        // the newest command taken
  std::vector<Tick> latest_tick_;      // its tick
  std::vector<std::uint8_t> fresh_;    // taken since the last apply
  std::vector<std::uint8_t> waiting_;  // lockstep: command for this round still awaited
  // Lockstep: missed a deadline and has not answered since, so rounds do not wait for it (it still gets
  // its packets). Without this one silent agent would cost every round the whole deadline.
  std::vector<std::uint8_t> unresponsive_;
  // A packet went to the robot's current owner since its claim: only then is the owner's liveliness judged
  // (pump). Before, a lapse is not a loss: the agent is quiet until its first packet (docs/wire.md).
  std::vector<std::uint8_t> judged_;
  // Owners whose first packet went out while their liveliness was lapsed (all quiet agents at the start):
  // writer -> the awake time by which a sample or their liveliness must come back, or they are dead (an
  // agent killed before the run is otherwise seen only when its participant's lease runs out).
  std::unordered_map<dds::PublicationHandle, dds_time_t> first_answer_due_;
  static constexpr dds_duration_t kFirstAnswerGrace = DDS_SECS(2);
  std::vector<dds::PublicationHandle> latest_writer_;  // the writer of latest_ (its owner's)
  InputGuard guard_;
  world::TelemetryLimits telemetry_limits_;
  std::uint64_t telemetry_fields_dropped_ = 0;
  std::uint64_t telemetry_events_dropped_ = 0;
  std::size_t waiting_count_ = 0;
  std::vector<dds::CommandSample> samples_;
  std::vector<dds::CommandReader::LivelinessChange> liveliness_;
  // Liveliness lapses before an owner's first packet: counted, not losses.
  std::uint64_t unjudged_lapses_ = 0;
  // Claims and commands taken after their writer went away: ignored, counted.
  std::uint64_t stale_samples_ = 0;
  std::vector<dds::RobotPoseRow> rows_;

  dds_time_t start_ = 0;
  dds_time_t steady_start_ = 0;  // the end of tick options_.warmup_ticks; 0 until then
  dds_time_t last_progress_ = 0;
  Tick last_progress_tick_ = 0;
  dds_time_t last_state_ = 0;
  bool record_pending_ = false;  // end_round left the new tick's record to the next begin_round
  std::uint64_t missed_ticks_ = 0;
  // Realtime: when this round started and each robot's packet went out, and where a missed command's time
  // went.
  dds_time_t round_start_ = 0;
  std::vector<dds_time_t> written_at_;
  LateCommands late_;
  world::FaultSchedule schedule_;          // scheduled kills and faults (run/fault_schedule.hpp)
  ProcessFaults faults_;                   // what they do to the agents' processes (process_faults.hpp)
  std::unique_ptr<ViewerControl> viewer_;  // null without --viewer-token

  // Where a round's wall time goes (printed on stderr at the end; issue 6 P1's first question).
  struct Profile {
    dds_duration_t publish = 0;  // kills + SensorPackets out
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
