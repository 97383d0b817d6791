// The DDS wire of swarmform, in plain types: the participant with its topics, the typed endpoints of each
// side and a waiter. This header and its .cpp are the only place that knows the IDL (idl/swarmform.idl); the
// world, the agents, the bench and the test programs see Perception, Command and Mission (common/).
//
// Who writes what (SPEC section 3):
//   world:  MissionWriter (durable), RobotChannels (per robot: a publisher in partition "robot/K" holding the
//           SensorPacket writer and the ClaimReply writer), CommandReader (claims and commands, with the
//           liveliness of every agent's writer), WorldStateWriter (viewers).
//   agent:  MissionReader, AgentInbox (a subscriber in partition "robot/K": its SensorPackets and
//   ClaimReplies
//           only, so no process receives another robot's packets), CommandWriter.
// Identity is the writer: an agent claims an id with a CLAIM sample on the command topic, and the world binds
// the id to that sample's publication handle; later commands from any other writer are not the owner's.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/dds/cyclone_config.hpp"
#include "common/dds/entity.hpp"
#include "common/mission.hpp"
#include "common/types.hpp"

namespace swarmform::dds {

using PublicationHandle = std::uint64_t;  // dds_instance_handle_t of a remote writer, as a reader sees it

// The wire-protocol version every sample carries (idl/swarmform.idl WIRE_VERSION; docs/wire.md says when to
// bump it). wire.cpp checks the two are equal at compile time.
inline constexpr std::uint16_t kWireVersion = 5;

// A participant's GUID (its key in DDS discovery), as 16 bytes.
using ParticipantKey = std::array<std::uint8_t, 16>;
std::string to_string(const ParticipantKey& key);  // hex

// The world an agent listens to (docs/wire.md "Writer binding"): the participant that wrote the mission it
// took, and that mission's run.
struct WorldBinding {
  ParticipantKey participant{};
  std::uint64_t run_nonce = 0;
};

std::string robot_partition(RobotId id);  // "robot/<id>"
// True once `writer` has matched at least one reader (before that, what it writes goes to nobody).
bool writer_matched(dds_entity_t writer);

// The domain (created from cyclone_config_xml), the participant and its topics (made on first use).
class Participant {
 public:
  explicit Participant(const DdsSettings& settings);
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  dds_entity_t get() const;
  struct Topics;
  const Topics& topics() const;
  // Made with DDS Security (DdsSettings::security): commands then travel in their robot's partition
  // (CommandWriter, CommandReader), where the access control lets only that robot's identity write.
  bool secure() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// A waitset with a guard condition: the one place a thread blocks, woken by data on an attached condition or
// by wake() from another thread (a signal watcher, a DDS listener). No polling sleeps.
//
// Counted arrivals, for readers that do not attach a read condition (CommandReader with count_arrivals): the
// reader's listener calls arrived() for every sample it stores, and the waiter wakes once the samples that
// came in since the taker's last drain reach what it said it needs (need(k); 1 by default: every arrival
// wakes, as a read condition would). A lockstep world waiting for k commands so sleeps until k samples are
// there, not once per sample (BENCHMARKS.md, P1). The count can only err early: a sample that is not an
// awaited command (an ALIVE, a forged copy, one the reader replaced) wakes it before its k are in, and it
// takes, finds fewer, and says what it still needs; a sample counted during a take that then took it stays
// in the count until the next drain (one early wake at most).
class Waiter {
 public:
  explicit Waiter(const Participant& participant);
  void attach(dds_entity_t condition_or_entity);
  // Blocks until something triggered, enough counted samples are pending, or `deadline` (dds_time_t,
  // absolute) passed; false on timeout. Returns at once while enough counted samples are pending.
  bool wait_until(dds_time_t deadline);
  // Thread-safe.
  void wake();

  // Thread-safe (a reader's listener): one more sample stored.
  void arrived();
  // The taker, before a take: the count to pass to drained() once that take emptied the readers.
  std::uint64_t arrivals() const { return arrivals_.load(); }
  // The taker: the readers were emptied by a take that began at `arrivals_before` (arrivals()).
  void drained(std::uint64_t arrivals_before);
  // The taker: wake once `samples` (at least 1) counted samples are pending.
  void need(std::uint64_t samples);

 private:
  bool enough_pending() const;

  Entity waitset_;
  Entity guard_;
  std::atomic<std::uint64_t> arrivals_{0};
  std::atomic<std::uint64_t> drained_at_{0};  // arrivals_ when the readers were last known empty (or before)
  std::atomic<std::uint64_t> need_{1};
};

// ---- the mission
// -------------------------------------------------------------------------------------------

struct MissionAnnouncement {
  Mission mission;
  std::uint32_t robots = 0;     // robots in the run (ids 0..robots-1)
  std::uint64_t run_nonce = 0;  // random per run (the launcher's --run-nonce, or the world's own draw)
  bool realtime = false;   // the pace of sf_sensor / sf_command (qos.hpp): an agent creates them after this
  ParticipantKey world{};  // reader side: the participant of the writer it came from
};

class MissionWriter {
 public:
  explicit MissionWriter(const Participant& participant);
  void publish(const MissionAnnouncement& announcement);

 private:
  Entity writer_;
};

class RefusalLog;

class MissionReader {
 public:
  explicit MissionReader(const Participant& participant);
  dds_entity_t condition() const { return condition_.get(); }
  // A mission of this wire version (and of run `want_nonce`, when given), if one arrived; the newest if
  // several. Others are refused through `refusals` (said once a second per writer). Throws InputError
  // ("<mission>: what") if an acceptable one is malformed.
  std::optional<MissionAnnouncement> take(std::optional<std::uint64_t> want_nonce, RefusalLog& refusals);

 private:
  Entity reader_;
  Entity condition_;
};

// ---- per-robot packets and claim replies
// -------------------------------------------------------------------

enum class PacketStatus : std::uint8_t {
  Run = 0,  // a perception for its tick
  End = 1,  // the run is over: the agent exits 0
};

struct ClaimAnswer {
  RobotId robot_id = 0;
  std::uint64_t nonce = 0;
  bool accepted = false;
  std::string reason;
};

inline constexpr std::size_t kMaxExtraChannels = 8;

// World side: for each robot a publisher in partition robot/K with its SensorPacket writer.
class RobotChannels {
 public:
  RobotChannels(const Participant& participant, std::size_t robots, bool realtime = false);
  // The world's faces (docs/wire.md "Faces"): robot K's channel is made on faces[face(K)], the participant
  // its agent peers with. One face: every channel on it.
  RobotChannels(std::vector<const Participant*> faces, std::size_t robots, bool realtime = false);
  ~RobotChannels();
  RobotChannels(const RobotChannels&) = delete;
  RobotChannels& operator=(const RobotChannels&) = delete;

  // Every sample written from now on carries this run's nonce (docs/wire.md "Run nonce").
  void set_run_nonce(std::uint64_t run_nonce);
  // Robot `id`'s owner (its claim attempt's nonce) and generation (raised at each revival), stamped on its
  // perceptions: an agent learns from them that it lost its id, or that it must start afresh.
  void set_owner(RobotId id, std::uint64_t claim_nonce, std::uint32_t generation);
  // No allocation after the first ticks (scratch buffers are reused; sequences point into the perception).
  void write_packet(RobotId id, PacketStatus status, const Perception& perception);
  // Answers a claim in the claimant's partition, on the packets' claim lane (a channel is made on demand for
  // an id outside the run; at most kMaxExtraChannels are kept, the oldest deleted first, so claims for
  // made-up ids cannot grow the world). Volatile: an answer to a reader not matched yet is lost, and the
  // agent's re-sent claim gets it again.
  void reply_claim(const ClaimAnswer& answer);
  // Waits until every packet written so far is acknowledged by its matched readers, up to `timeout`.
  void wait_for_acks(dds_duration_t timeout);
  // True once robot `id`'s packet writer has matched a reader (its agent's, in partition robot/K); before
  // that a packet is written to nobody and lost.
  bool reader_matched(RobotId id) const;
  // True while Cyclone's key map holds robot `id`'s perception instance (kept registered, so that a write
  // finds it in place rather than creating and freeing it; wire.cpp keep_instance). For tests.
  bool holds_instance(RobotId id) const;
  // Channels held for ids outside the run (<= kMaxExtraChannels). For tests.
  std::size_t extra_channels() const;
  // The face robot `id`'s channel is on: face_of(id), or the last face when there are fewer.
  std::uint32_t face(RobotId id) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

struct SensorSample {
  RobotId robot_id = 0;  // as it came on the wire (an agent counts any that is not its own)
  PacketStatus status = PacketStatus::Run;
  std::uint64_t owner_nonce = 0;  // the claim nonce of the id's owner, as the world knows it
  std::uint32_t generation = 0;   // the robot's generation (raised at each revival after a death)
  Perception perception;
};

// Agent side: a subscriber in partition robot/K with a SensorPacket reader (perceptions and claim answers).
// The liveliness of the world's packet writer is followed by a listener (world_alive), which wakes `waiter`.
class AgentInbox {
 public:
  AgentInbox(const Participant& participant, RobotId self, Waiter& waiter, bool realtime = false);
  ~AgentInbox();
  AgentInbox(const AgentInbox&) = delete;
  AgentInbox& operator=(const AgentInbox&) = delete;

  dds_entity_t packet_condition() const;
  // From now on only samples of `world`'s participant and run are taken; the others are refused (counted,
  // said once a second per writer on stderr as "<who>: refused ..."). Before, only the wire version is
  // checked.
  void bind(const WorldBinding& world, const std::string& who);
  std::uint64_t refused() const;
  // Takes every packet available: `own` receives the newest of robot `self` (true if there was one);
  // `foreign` is increased by the number of packets for any other robot (never expected).
  bool take_packet(SensorSample& own, std::uint64_t& foreign);
  std::optional<ClaimAnswer> take_claim_reply();
  // Writers of this robot's packets alive now, and whether one was ever seen (the world came and went).
  std::uint32_t world_writers_alive() const;
  bool world_seen() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// ---- commands ---------------------------------------------------------------------------------------------

enum class CommandKind : std::uint8_t {
  Step = 0,   // the command of `tick`
  Claim = 1,  // this writer claims robot_id; `nonce` identifies the attempt
  Alive = 2,  // nothing but the writer's liveliness (CommandWriter::keep_alive)
};

struct CommandSample {
  std::uint16_t wire_version = 0;
  std::uint64_t run_nonce = 0;
  RobotId robot_id = 0;
  CommandKind kind = CommandKind::Step;
  Tick tick = 0;
  std::uint64_t nonce = 0;
  std::uint32_t pid = 0;
  Command command;
  PublicationHandle writer = 0;  // who sent it (the identity)
  std::uint32_t face = 0;        // the world face whose reader took it (its CommandReader's `face`)
  std::int64_t sent_at = 0;      // the writer's source timestamp (ns, dds_time() on the sender's host)
};

class CommandWriter {
 public:
  // `robot`: put the writer in robot K's partition robot/K, where a secure world reads commands (required on
  // a secure participant: robot K's permissions let it write only there, docs/security.md). Without it the
  // writer is in the default partition, where a world without security reads them (it binds ids to writers).
  explicit CommandWriter(const Participant& participant, bool realtime = false,
                         std::optional<RobotId> robot = std::nullopt);
  ~CommandWriter();
  CommandWriter(const CommandWriter&) = delete;
  CommandWriter& operator=(const CommandWriter&) = delete;
  // Every sample written from now on carries this run's nonce and wire version (a test may forge another
  // version; an agent never does).
  void set_stamp(std::uint64_t run_nonce, std::uint16_t wire_version = kWireVersion);
  void claim(RobotId id, std::uint64_t nonce, std::uint32_t pid);
  void step(RobotId id, Tick tick, const Command& command);
  dds_entity_t get() const;
  // Asserts the writer's liveliness if nothing was written or asserted for kLivelinessAssertPeriod (its
  // liveliness is MANUAL_BY_TOPIC: a writer idle for its lease is taken for dead). Returns when it is next
  // due: an idle agent wakes by then. `by_sample`: write an ALIVE sample of the claimed id instead, for a
  // writer the world may have taken for dead already (a world's own stall, a cut link): an assertion renews
  // a lease that has not run out, but Cyclone 0.10.2 brings a lost writer back only on a sample.
  dds_time_t keep_alive(dds_time_t now, bool by_sample = false);
  // True while Cyclone's key map holds robot `id`'s command instance (kept from the first claim, as
  // RobotChannels::holds_instance). For tests.
  bool holds_instance(RobotId id) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

inline constexpr std::size_t kMaxCommandTake = 1024;

// World side. A listener follows the liveliness of every command writer and wakes `waiter` when one is lost.
class CommandReader {
 public:
  // `accept_ids` > 0: samples (claims and commands) for ids at or above it are dropped before the reader
  // stores them (a topic filter; counted by filtered()), so no writer can make the reader hold an instance
  // per made-up id. The world passes its robot count plus kMaxExtraChannels (near misses still get their
  // "no robot K in this run" answer).
  // `face`: stamped on every sample it takes (CommandSample::face), for a world with several faces.
  // `count_arrivals`: every sample stored is counted on `waiter` (Waiter::arrived), for a taker that does not
  // attach condition() and wakes on the counts instead; the taker then reports its drains (Waiter::drained).
  CommandReader(const Participant& participant, Waiter& waiter, bool realtime = false,
                std::uint32_t accept_ids = 0, std::uint32_t face = 0, bool count_arrivals = false);
  ~CommandReader();
  CommandReader(const CommandReader&) = delete;
  CommandReader& operator=(const CommandReader&) = delete;

  dds_entity_t condition() const;
  // Takes what is available, at most `max_samples`, into buf[0..n) (grown as needed, elements reused: no
  // allocation once warm). The cap bounds the buffer under a flood; what is left is taken by the next call
  // (the reader's condition stays triggered).
  // `first`: fill from buf[first] on (buf holds at least `first` elements), to gather several readers'
  // samples in one buffer; returns how many were taken.
  std::size_t take(std::vector<CommandSample>& buf, std::size_t max_samples = kMaxCommandTake,
                   std::size_t first = 0);
  // Liveliness changes of command writers since the last call, in the order they happened (appended to
  // `out`): alive = false when a writer lost liveliness or went away, true when one appeared or came back;
  // gone = the writer went away (deleted, or its participant's lease ran out), not only its liveliness.
  struct LivelinessChange {
    PublicationHandle writer = 0;
    bool alive = false;
    bool gone = false;
  };
  void take_liveliness_changes(std::vector<LivelinessChange>& out);
  // Samples dropped by the `accept_ids` filter so far (thread-safe).
  std::uint64_t filtered() const;
  // On a secure participant (the reader then reads partition robot/*): the robot whose partition `writer`
  // writes in, when it writes in exactly one partition robot/K. DDS Security let that writer match only if
  // its participant's certificate and permissions are robot K's, so this is the writer's authenticated robot
  // id. Looked up once per writer. nullopt: not secure, unknown writer, or any other partition set.
  std::optional<RobotId> authenticated_robot(PublicationHandle writer);
  // Whether `writer` is still matched: false once it went away (its participant deleted or forgotten). Its
  // samples taken after that are stale: a writer's data and its going reach the reader by different threads.
  bool matched(PublicationHandle writer) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// ---- observers --------------------------------------------------------------------------------------------

struct RobotPoseRow {
  RobotId id = 0;
  Pose2D pose;
  bool alive = true;
  std::int32_t state = 0;
  std::int32_t label = -1;
};

class WorldStateWriter {
 public:
  explicit WorldStateWriter(const Participant& participant, std::uint64_t run_nonce = 0);
  ~WorldStateWriter();
  WorldStateWriter(const WorldStateWriter&) = delete;
  WorldStateWriter& operator=(const WorldStateWriter&) = delete;
  void publish(Tick tick, bool finished, std::uint32_t alive, const std::vector<RobotPoseRow>& robots);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

struct WorldStateHeader {
  std::uint64_t run_nonce = 0;
  Tick tick = 0;
  bool finished = false;
  std::uint32_t alive = 0;
};

class WorldStateReader {
 public:
  explicit WorldStateReader(const Participant& participant);
  dds_entity_t condition() const { return condition_.get(); }
  std::optional<WorldStateHeader> take();  // the newest of this wire version

 private:
  Entity reader_;
  Entity condition_;
};

}  // namespace swarmform::dds
