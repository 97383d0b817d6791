// The one translation unit that includes the idlc-generated header: conversions between the IDL samples and
// the plain types, and the endpoints that carry them. Writes point the IDL sequences straight into the plain
// structs' storage (Cyclone serialises during dds_write), except a packet's readings, packed into one reused
// blob first (readings_blob.hpp); takes use loans and copy into reused plain structs, so the hot path
// allocates nothing once the reused buffers are warm.
#include "common/dds/wire.hpp"

#include "common/dds/observe_wire.hpp"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <deque>
#include <iostream>
#include <map>
#include <mutex>
#include <optional>
#include <span>
#include <stdexcept>
#include <unordered_map>
#include <utility>

#include "common/dds/qos.hpp"
#include "common/dds/readings_blob.hpp"
#include "common/dds/refusal_log.hpp"
#include "common/input_error.hpp"
#include "common/mission_check.hpp"
#include "swarmform.h"

namespace swarmform::dds {

static_assert(kWireVersion == sfdds_WIRE_VERSION,
              "kWireVersion (wire.hpp) must equal the IDL's WIRE_VERSION");

// Topics are created on first use: under DDS Security a participant may create only the topics its
// permissions name (an agent's name no sf_world_state), so each process makes just the ones its endpoints
// use.
struct Participant::Topics {
  dds_entity_t mission() const { return get(mission_, kMission); }
  dds_entity_t sensor() const { return get(sensor_, kSensor); }
  dds_entity_t command() const { return get(command_, kCommand); }
  dds_entity_t world_state() const { return get(world_state_, kWorldState); }
  dds_entity_t observe() const { return get(observe_, kObserve); }  // issue 21: observe_wire.hpp
  dds_entity_t control() const { return get(control_, kControl); }
  void reset() {
    std::lock_guard lock(mutex_);
    mission_.reset();
    sensor_.reset();
    command_.reset();
    world_state_.reset();
    observe_.reset();
    control_.reset();
  }

  dds_entity_t participant = 0;

 private:
  enum Which { kMission, kSensor, kCommand, kWorldState, kObserve, kControl };
  dds_entity_t get(Entity& slot, Which which) const;
  mutable std::mutex mutex_;
  mutable Entity mission_, sensor_, command_, world_state_, observe_, control_;
};

struct Participant::Impl {
  Entity domain;
  Entity participant;
  Topics topics;
  bool secure = false;
};

namespace {

constexpr const char* kMissionTopic = "sf_mission";
constexpr const char* kSensorTopic = "sf_sensor";
constexpr const char* kCommandTopic = "sf_command";
constexpr const char* kWorldStateTopic = "sf_world_state";
constexpr const char* kObserveTopic = "sf_observe";
constexpr const char* kControlTopic = "sf_control";

constexpr std::uint32_t kTakeBatch = 64;
constexpr std::int32_t kInboxDepth = 16;  // AgentInbox's history per instance (see its constructor)

Entity make_topic(dds_entity_t participant, const dds_topic_descriptor_t* desc, const char* name) {
  const dds_entity_t topic = dds_create_topic(participant, desc, name, nullptr, nullptr);
  if (topic == DDS_RETCODE_NOT_ALLOWED_BY_SECURITY) {
    throw DdsError(std::string("dds_create_topic(") + name + "): not allowed by this identity's permissions",
                   topic);
  }
  return Entity(topic, "dds_create_topic");
}

// A publisher or subscriber whose only partition is `partition`.
Entity make_partitioned(dds_entity_t participant, const std::string& partition, bool publisher) {
  Qos qos;
  dds_qset_partition1(qos.get(), partition.c_str());
  if (publisher) return Entity(dds_create_publisher(participant, qos.get(), nullptr), "dds_create_publisher");
  return Entity(dds_create_subscriber(participant, qos.get(), nullptr), "dds_create_subscriber");
}

Pace pace_of(bool realtime) {
  return realtime ? Pace::Realtime : Pace::Lockstep;
}

Entity make_writer(dds_entity_t parent, dds_entity_t topic, Channel channel, Pace pace = Pace::Lockstep) {
  Qos qos = make_qos(channel, pace);
  return Entity(dds_create_writer(parent, topic, qos.get(), nullptr), "dds_create_writer");
}

Entity make_reader(dds_entity_t parent, dds_entity_t topic, Channel channel,
                   const dds_listener_t* listener = nullptr, Pace pace = Pace::Lockstep) {
  Qos qos = make_qos(channel, pace);
  return Entity(dds_create_reader(parent, topic, qos.get(), listener), "dds_create_reader");
}

// Registers the instance of `key` with `writer` for the writer's lifetime. Cyclone keeps an instance in its
// key map only while something holds it: an unregistered instance whose sample has left the writer's history
// (at once for best effort, on acknowledgement for reliable) is removed after the write, and its memory goes
// to the domain's gc thread through a request. So each write allocated, hashed and freed the instance, and
// queued work for a thread whose wake-ups preempted the world's in its publish phase (perf: 173 of its
// preemptions in a 256-agent run, BENCHMARKS.md). A registered instance stays, so a write finds it in place.
void keep_instance(dds_entity_t writer, const void* key) {
  dds_instance_handle_t handle = 0;
  check(dds_register_instance(writer, &handle, key), "dds_register_instance");
}

Entity make_condition(dds_entity_t reader) {
  return Entity(dds_create_readcondition(reader, DDS_ANY_STATE), "dds_create_readcondition");
}

// Returns the loan of `n` samples taken into `ptrs` when it goes out of scope.
class Loan {
 public:
  Loan(dds_entity_t reader, void** ptrs, int n) : reader_(reader), ptrs_(ptrs), n_(n) {}
  ~Loan() {
    if (n_ > 0) (void)dds_return_loan(reader_, ptrs_, n_);  // cannot fail for a loan we hold
  }
  Loan(const Loan&) = delete;
  Loan& operator=(const Loan&) = delete;

 private:
  dds_entity_t reader_;
  void** ptrs_;
  int n_;
};

template <typename T>
dds_sequence_octet octets(const std::vector<T>& v) {
  static_assert(sizeof(T) == 1);
  dds_sequence_octet s{};
  s._length = s._maximum = static_cast<std::uint32_t>(v.size());
  s._buffer = const_cast<std::uint8_t*>(reinterpret_cast<const std::uint8_t*>(v.data()));
  s._release = false;
  return s;
}

void assign_octets(std::vector<std::uint8_t>& out, const dds_sequence_octet& s) {
  out.assign(s._buffer, s._buffer + s._length);
}

std::string str(const char* s) {
  return s != nullptr ? std::string(s) : std::string();
}

Entity make_guard(dds_entity_t participant) {
  return Entity(dds_create_guardcondition(participant), "dds_create_guardcondition");
}

// The participant of the remote writer `writer` matched by `reader` (nullopt when it is not matched).
std::optional<ParticipantKey> writer_participant(dds_entity_t reader, dds_instance_handle_t writer) {
  dds_builtintopic_endpoint_t* e = dds_get_matched_publication_data(reader, writer);
  if (e == nullptr) return std::nullopt;
  ParticipantKey key{};
  static_assert(sizeof(e->participant_key.v) == std::tuple_size_v<ParticipantKey>);
  std::memcpy(key.data(), e->participant_key.v, key.size());
  dds_builtintopic_free_endpoint(e);
  return key;
}

std::string version_text(std::uint16_t v) {
  return "wire version " + std::to_string(v) + ", this side speaks " + std::to_string(kWireVersion);
}

std::string nonce_text(std::uint64_t got, std::uint64_t want) {
  char b[96];
  std::snprintf(b, sizeof b, "run nonce %016llx, this side's run is %016llx",
                static_cast<unsigned long long>(got), static_cast<unsigned long long>(want));
  return b;
}

}  // namespace

std::string to_string(const ParticipantKey& key) {
  static const char* hex = "0123456789abcdef";
  std::string out;
  for (std::uint8_t b : key) {
    out += hex[b >> 4];
    out += hex[b & 15];
  }
  return out;
}

std::string robot_partition(RobotId id) {
  return "robot/" + std::to_string(id);
}

bool writer_matched(dds_entity_t writer) {
  dds_publication_matched_status_t st{};
  check(dds_get_publication_matched_status(writer, &st), "dds_get_publication_matched_status");
  return st.current_count > 0;
}

// ---- Participant
// -------------------------------------------------------------------------------------------

Participant::Participant(const DdsSettings& settings) : impl_(std::make_unique<Impl>()) {
  const std::string xml = cyclone_config_string(settings);
  const auto local_id = static_cast<dds_domainid_t>(local_domain_id(settings));  // a world face's own
  const dds_entity_t domain = dds_create_domain(local_id, xml.c_str());
  if (domain < 0) {
    // The usual cause is a port in use, or a user's configuration Cyclone refused: say which, rather than
    // Cyclone's bare "Error".
    std::string what = "dds_create_domain(domain " + std::to_string(settings.domain);
    if (settings.user) {
      what += "; the configuration of " + settings.user->source +
              " is merged on top of ours: Cyclone's messages above say what it refused; --print-dds-config "
              "shows both";
    }
    if (settings.role == Role::World) {
      what += "; is another world_server on this domain? its port " +
              std::to_string(face_discovery_port(settings.domain, settings.face)) + " may be taken";
    }
    throw DdsError(what + ")", domain);
  }
  impl_->domain = Entity(domain, "dds_create_domain");
  const dds_entity_t participant = dds_create_participant(local_id, nullptr, nullptr);
  if (participant < 0 && settings.security) {
    // Cyclone's security plugins say why on stderr (a certificate of another authority, an expired one,
    // permissions that name another subject or are not signed by the CA): name the files here.
    throw DdsError("dds_create_participant with DDS Security as '" + settings.security->identity +
                       "' (certificate " + settings.security->certificate + ", permissions " +
                       settings.security->permissions + ", governance " + settings.security->governance +
                       "; Cyclone's message above says what it refused)",
                   participant);
  }
  impl_->participant = Entity(participant, "dds_create_participant");
  const dds_entity_t p = impl_->participant.get();
  impl_->topics.participant = p;
  impl_->secure = settings.security.has_value();
}

dds_entity_t Participant::Topics::get(Entity& slot, Which which) const {
  std::lock_guard lock(mutex_);
  if (!slot) {
    switch (which) {
      case kMission:
        slot = make_topic(participant, &sfdds_Mission_desc, kMissionTopic);
        break;
      case kSensor:
        slot = make_topic(participant, &sfdds_SensorPacket_desc, kSensorTopic);
        break;
      case kCommand:
        slot = make_topic(participant, &sfdds_Command_desc, kCommandTopic);
        break;
      case kWorldState:
        slot = make_topic(participant, &sfdds_WorldState_desc, kWorldStateTopic);
        break;
      case kObserve:
        slot = make_topic(participant, &sfdds_ObserveFrame_desc, kObserveTopic);
        break;
      case kControl:
        slot = make_topic(participant, &sfdds_Control_desc, kControlTopic);
        break;
    }
  }
  return slot.get();
}

Participant::~Participant() {
  // Children before the participant, the participant before the domain.
  if (impl_) {
    impl_->topics.reset();
    impl_->participant.reset();
    impl_->domain.reset();
  }
}

dds_entity_t Participant::get() const {
  return impl_->participant.get();
}
const Participant::Topics& Participant::topics() const {
  return impl_->topics;
}
bool Participant::secure() const {
  return impl_->secure;
}

// ---- Waiter -----------------------------------------------------------------------------------------------

// The waitset belongs to the library, not to the participant: a world with several faces (each its own
// domain instance) waits for the readers of all of them on one waitset.
Waiter::Waiter(const Participant& participant)
    : waitset_(dds_create_waitset(DDS_CYCLONEDDS_HANDLE), "dds_create_waitset"),
      guard_(make_guard(participant.get())) {
  attach(guard_.get());
}

void Waiter::attach(dds_entity_t entity) {
  check(dds_waitset_attach(waitset_.get(), entity, entity), "dds_waitset_attach");
}

bool Waiter::wait_until(dds_time_t deadline) {
  // Counted samples are level-triggered, as a read condition is: while enough are pending, no sleep (and the
  // wake their listener may have sent is taken below, or it would cut the next sleep short).
  const dds_return_t n =
      enough_pending()
          ? 1
          : check(dds_waitset_wait_until(waitset_.get(), nullptr, 0, deadline), "dds_waitset_wait");
  // Reset the guard before the caller looks at what woke it: a wake() after this reset is never lost.
  bool triggered = false;
  check(dds_take_guardcondition(guard_.get(), &triggered), "dds_take_guardcondition");
  return n > 0;
}

void Waiter::wake() {
  check(dds_set_guardcondition(guard_.get(), true), "dds_set_guardcondition");
}

bool Waiter::enough_pending() const {
  // drained_at_ is a past value of arrivals_, so the difference never wraps.
  return arrivals_.load() - drained_at_.load() >= need_.load();
}

void Waiter::arrived() {
  arrivals_.fetch_add(1);
  // Checked after the count: either this sees the taker's latest need(), or the taker's own check before it
  // sleeps (wait_until) sees this sample. Sequentially consistent atomics, so one of the two does.
  if (enough_pending()) wake();
}

void Waiter::drained(std::uint64_t arrivals_before) {
  drained_at_.store(arrivals_before);
}

void Waiter::need(std::uint64_t samples) {
  need_.store(std::max<std::uint64_t>(samples, 1));
}

// ---- Mission ----------------------------------------------------------------------------------------------

MissionWriter::MissionWriter(const Participant& participant)
    : writer_(make_writer(participant.get(), participant.topics().mission(), Channel::Mission)) {}

void MissionWriter::publish(const MissionAnnouncement& a) {
  const Mission& m = a.mission;
  std::vector<sfdds_Param> params;
  params.reserve(m.params.size());
  for (const auto& [name, value] : m.params) {
    params.push_back(sfdds_Param{const_cast<char*>(name.c_str()), value});
  }
  std::vector<std::int32_t> cells(m.shape.cells.begin(), m.shape.cells.end());
  sfdds_Mission s{};
  s.wire_version = kWireVersion;
  s.run_nonce = a.run_nonce;
  s.robots = a.robots;
  s.behaviour = const_cast<char*>(m.behaviour.c_str());
  s.plugin = const_cast<char*>(m.plugin.c_str());
  s.rows = m.shape.rows;
  s.cols = m.shape.cols;
  s.cells._buffer = cells.data();
  s.cells._length = s.cells._maximum = static_cast<std::uint32_t>(cells.size());
  s.grid_spacing = m.grid_spacing;
  s.goal_x = m.goal.x;
  s.goal_y = m.goal.y;
  s.goal_radius = m.goal_radius;
  s.max_speed = m.max_speed;
  s.tick_rate = m.tick_rate;
  s.comm_range = m.comm_range;
  s.max_message_bytes = m.max_message_bytes;
  s.seed = m.seed;
  s.params._buffer = params.data();
  s.params._length = s.params._maximum = static_cast<std::uint32_t>(params.size());
  s.realtime = a.realtime;
  check(dds_write(writer_.get(), &s), "dds_write(mission)");
}

MissionReader::MissionReader(const Participant& participant)
    : reader_(make_reader(participant.get(), participant.topics().mission(), Channel::Mission)),
      condition_(make_condition(reader_.get())) {}

std::optional<MissionAnnouncement> MissionReader::take(std::optional<std::uint64_t> want_nonce,
                                                       RefusalLog& refusals) {
  void* ptrs[8] = {};
  dds_sample_info_t infos[8];
  const int n = check(dds_take(reader_.get(), ptrs, infos, 8, 8), "dds_take(mission)");
  Loan loan(reader_.get(), ptrs, n);
  std::optional<MissionAnnouncement> out;
  for (int i = 0; i < n; ++i) {
    if (!infos[i].valid_data) continue;
    const auto& s = *static_cast<const sfdds_Mission*>(ptrs[i]);
    const auto key = writer_participant(reader_.get(), infos[i].publication_handle);
    const std::string writer = "the world of participant " + (key ? to_string(*key) : std::string("?"));
    if (s.wire_version != kWireVersion) {
      refusals.refuse(infos[i].publication_handle, writer, "mission", version_text(s.wire_version),
                      dds_time());
      continue;
    }
    if (want_nonce && s.run_nonce != *want_nonce) {
      refusals.refuse(infos[i].publication_handle, writer, "mission",
                      "another run's (" + nonce_text(s.run_nonce, *want_nonce) + ")", dds_time());
      continue;
    }
    if (!key) continue;  // its writer is gone already: a world that left
    MissionAnnouncement a;
    a.world = *key;
    a.run_nonce = s.run_nonce;
    a.robots = s.robots;
    a.realtime = s.realtime;
    Mission& m = a.mission;
    m.behaviour = str(s.behaviour);
    m.plugin = str(s.plugin);
    m.shape.rows = s.rows;
    m.shape.cols = s.cols;
    m.shape.cells.assign(s.cells._buffer, s.cells._buffer + s.cells._length);
    m.grid_spacing = s.grid_spacing;
    m.goal = Vec2{s.goal_x, s.goal_y};
    m.goal_radius = s.goal_radius;
    m.max_speed = s.max_speed;
    m.tick_rate = s.tick_rate;
    m.comm_range = s.comm_range;
    m.max_message_bytes = s.max_message_bytes;
    m.seed = s.seed;
    for (std::uint32_t k = 0; k < s.params._length; ++k) {
      m.params[str(s.params._buffer[k].name)] = s.params._buffer[k].value;
    }
    check_mission(m,
                  "<mission>");  // common/mission_check.hpp: a malformed mission never reaches a controller
    out = std::move(a);
  }
  return out;
}

// ---- RobotChannels (world side) ---------------------------------------------------------------------------

namespace {
struct RobotChannel {
  Entity publisher, sensor;
};

sfdds_SensorPacket perception_key(RobotId id) {
  sfdds_SensorPacket key{};
  key.robot_id = id;
  key.lane = sfdds_LANE_PERCEPTION;
  key.note = const_cast<char*>("");
  return key;
}

RobotChannel make_robot_channel(const Participant& p, RobotId id, Pace pace) {
  RobotChannel c;
  c.publisher = make_partitioned(p.get(), robot_partition(id), true);
  c.sensor = make_writer(c.publisher.get(), p.topics().sensor(), Channel::Sensor, pace);
  const sfdds_SensorPacket key = perception_key(id);
  keep_instance(c.sensor.get(), &key);
  return c;
}
}  // namespace

struct RobotChannels::Impl {
  struct Owner {
    std::uint64_t claim_nonce = 0;
    std::uint32_t generation = 0;
  };
  std::vector<const Participant*> faces;  // robot K's channel is on faces[face(K)]
  Pace pace;
  std::uint64_t run_nonce = 0;
  std::vector<Owner> owners;
  std::vector<RobotChannel> robots;
  std::map<RobotId, RobotChannel> extra;  // claimants with an id outside the run (kMaxExtraChannels)
  std::deque<RobotId> extra_order;        // oldest first, for deleting
  std::vector<std::uint8_t> readings;     // the packed readings, reused for every packet
};

RobotChannels::RobotChannels(const Participant& participant, std::size_t robots, bool realtime)
    : RobotChannels(std::vector<const Participant*>{&participant}, robots, realtime) {}

RobotChannels::RobotChannels(std::vector<const Participant*> faces, std::size_t robots, bool realtime)
    : impl_(std::make_unique<Impl>(Impl{std::move(faces), pace_of(realtime), 0, {}, {}, {}, {}, {}})) {
  if (impl_->faces.empty()) throw std::invalid_argument("RobotChannels: no participant");
  impl_->owners.resize(robots);
  impl_->robots.reserve(robots);
  for (std::size_t i = 0; i < robots; ++i) {
    const auto id = static_cast<RobotId>(i);
    impl_->robots.push_back(make_robot_channel(*impl_->faces[face(id)], id, impl_->pace));
  }
}

std::uint32_t RobotChannels::face(RobotId id) const {
  return std::min<std::uint32_t>(face_of(id), static_cast<std::uint32_t>(impl_->faces.size() - 1));
}

RobotChannels::~RobotChannels() = default;

void RobotChannels::set_run_nonce(std::uint64_t run_nonce) {
  impl_->run_nonce = run_nonce;
}

void RobotChannels::set_owner(RobotId id, std::uint64_t claim_nonce, std::uint32_t generation) {
  impl_->owners.at(id) = Impl::Owner{claim_nonce, generation};
}

void RobotChannels::write_packet(RobotId id, PacketStatus status, const Perception& p) {
  encode_readings(p.messages, impl_->readings);
  sfdds_SensorPacket s{};
  s.robot_id = id;
  s.lane = sfdds_LANE_PERCEPTION;
  s.wire_version = kWireVersion;
  s.run_nonce = impl_->run_nonce;
  s.generation = impl_->owners.at(id).generation;
  s.claim_nonce = impl_->owners[id].claim_nonce;
  s.tick = p.tick;
  s.status = static_cast<std::uint8_t>(status);
  s.note = const_cast<char*>("");
  s.x = p.pose.x;
  s.y = p.pose.y;
  s.theta = p.pose.theta;
  std::copy(p.ultrasonic.begin(), p.ultrasonic.end(), s.ultrasonic);
  s.readings = octets(impl_->readings);
  check(dds_write(impl_->robots.at(id).sensor.get(), &s), "dds_write(sensor)");
}

void RobotChannels::reply_claim(const ClaimAnswer& a) {
  RobotChannel* c = nullptr;
  if (a.robot_id < impl_->robots.size()) {
    c = &impl_->robots[a.robot_id];
  } else {
    auto it = impl_->extra.find(a.robot_id);
    if (it == impl_->extra.end()) {
      // Each channel is a publisher and a writer with their discovery state: a claim storm over made-up ids
      // once left one behind per id (2,559 claims: +20 MB). The oldest goes; its claimant, if still there,
      // re-sends its claim and gets a channel again.
      while (impl_->extra.size() >= kMaxExtraChannels) {
        impl_->extra.erase(impl_->extra_order.front());
        impl_->extra_order.pop_front();
      }
      it = impl_->extra
               .emplace(a.robot_id,
                        make_robot_channel(*impl_->faces[face(a.robot_id)], a.robot_id, impl_->pace))
               .first;
      impl_->extra_order.push_back(a.robot_id);
    }
    c = &it->second;
  }
  sfdds_SensorPacket s{};
  s.robot_id = a.robot_id;
  s.lane = sfdds_LANE_CLAIM;
  s.wire_version = kWireVersion;
  s.run_nonce = impl_->run_nonce;
  s.status = a.accepted ? sfdds_CLAIM_ACCEPTED : sfdds_CLAIM_REFUSED;
  s.claim_nonce = a.nonce;
  s.note = const_cast<char*>(a.reason.c_str());
  check(dds_write(c->sensor.get(), &s), "dds_write(claim answer)");
}

std::size_t RobotChannels::extra_channels() const {
  return impl_->extra.size();
}

bool RobotChannels::reader_matched(RobotId id) const {
  return writer_matched(impl_->robots.at(id).sensor.get());
}

bool RobotChannels::holds_instance(RobotId id) const {
  const sfdds_SensorPacket key = perception_key(id);
  return dds_lookup_instance(impl_->robots.at(id).sensor.get(), &key) != DDS_HANDLE_NIL;
}

void RobotChannels::wait_for_acks(dds_duration_t timeout) {
  const dds_time_t deadline = dds_time() + timeout;
  for (const RobotChannel& c : impl_->robots) {
    const dds_duration_t left = std::max<dds_duration_t>(0, deadline - dds_time());
    // TIMEOUT is an answer, not a failure: a reader that died meanwhile never acknowledges.
    const dds_return_t rc = dds_wait_for_acks(c.sensor.get(), left);  // publishers: unsupported in 0.10
    if (rc != DDS_RETCODE_OK && rc != DDS_RETCODE_TIMEOUT) check(rc, "dds_wait_for_acks");
  }
}

// ---- AgentInbox (agent side) ------------------------------------------------------------------------------

struct AgentInbox::Impl {
  RobotId self = 0;
  Waiter* waiter = nullptr;
  std::atomic<std::uint32_t> alive{0};
  std::atomic<bool> seen{false};
  Entity subscriber, packets, packet_condition;
  // What poll() took and the callers have not asked for yet (swapped out: no allocation once warm).
  SensorSample staged;
  bool has_packet = false;
  std::optional<ClaimAnswer> reply;
  std::uint64_t foreign = 0;
  // The binding (docs/wire.md "Writer binding"): before bind() only the wire version is checked.
  std::optional<WorldBinding> world;
  std::unordered_map<dds_instance_handle_t, bool> writer_ok;  // per writer: of the bound participant?
  std::unique_ptr<RefusalLog> refusals = std::make_unique<RefusalLog>("swarmform dds", std::cerr);

  // Why the sample from `writer` is refused, or empty to take it.
  std::string refusal(const sfdds_SensorPacket& s, dds_instance_handle_t writer) {
    if (s.wire_version != kWireVersion) return version_text(s.wire_version);
    if (!world) return {};
    auto it = writer_ok.find(writer);
    if (it == writer_ok.end()) {
      if (writer_ok.size() >= 4096) writer_ok.clear();  // bounded: a writer forgotten is looked up again
      const auto key = writer_participant(packets.get(), writer);
      it = writer_ok.emplace(writer, key && *key == world->participant).first;
    }
    if (!it->second)
      return "not from the world whose mission this agent took (participant " +
             to_string(world->participant) + ")";
    if (s.run_nonce != world->run_nonce) return nonce_text(s.run_nonce, world->run_nonce);
    return {};
  }

  static void on_liveliness(dds_entity_t, const dds_liveliness_changed_status_t status, void* arg) {
    auto* self = static_cast<Impl*>(arg);
    self->alive.store(status.alive_count);
    if (status.alive_count > 0) self->seen.store(true);
    try {
      self->waiter->wake();
    } catch (const DdsError&) {
      // Only possible while tearing down; nobody is waiting then.
    }
  }

  // Takes everything available: the newest own perception into `staged`, the newest claim answer into
  // `reply`.
  void poll() {
    while (poll_batch() == 8) {
    }
  }
  int poll_batch() {
    void* ptrs[8] = {};
    dds_sample_info_t infos[8];
    const int n = check(dds_take(packets.get(), ptrs, infos, 8, 8), "dds_take(sensor)");
    Loan loan(packets.get(), ptrs, n);
    for (int i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      const auto& s = *static_cast<const sfdds_SensorPacket*>(ptrs[i]);
      if (const std::string why = refusal(s, infos[i].publication_handle); !why.empty()) {
        char writer[64];
        std::snprintf(writer, sizeof writer, "writer %016llx",
                      static_cast<unsigned long long>(infos[i].publication_handle));
        refusals->refuse(infos[i].publication_handle, writer,
                         s.lane == sfdds_LANE_CLAIM     ? "claim answer"
                         : s.status == sfdds_PACKET_END ? "END packet"
                                                        : "packet",
                         why, dds_time());
        continue;
      }
      if (s.robot_id != self) {
        ++foreign;
        continue;
      }
      if (s.lane == sfdds_LANE_CLAIM) {
        reply = ClaimAnswer{s.robot_id, s.claim_nonce, s.status == sfdds_CLAIM_ACCEPTED, str(s.note)};
        continue;
      }
      if (has_packet && s.tick < staged.perception.tick) continue;
      // Decoded first: a malformed blob leaves `staged` as it was, and the sample is dropped like a foreign
      // one (in lockstep the world's round deadline covers the missing command). Said on stderr, as it means
      // a writer that does not speak this format.
      const std::string bad = decode_readings(
          std::span<const std::uint8_t>(s.readings._buffer, s.readings._length), staged.perception.messages);
      if (!bad.empty()) {
        std::cerr << "swarmform dds: dropped the packet of robot " << s.robot_id << " tick " << s.tick << ": "
                  << bad << "\n";
        continue;
      }
      has_packet = true;
      staged.robot_id = s.robot_id;
      staged.status = s.status == sfdds_PACKET_END ? PacketStatus::End : PacketStatus::Run;
      staged.owner_nonce = s.claim_nonce;
      staged.generation = s.generation;
      Perception& p = staged.perception;
      p.tick = s.tick;
      p.pose = Pose2D{s.x, s.y, s.theta};
      std::copy(std::begin(s.ultrasonic), std::end(s.ultrasonic), p.ultrasonic.begin());
    }
    return n;
  }
};

AgentInbox::AgentInbox(const Participant& participant, RobotId self, Waiter& waiter, bool realtime)
    : impl_(std::make_unique<Impl>()) {
  impl_->self = self;
  impl_->waiter = &waiter;
  impl_->subscriber = make_partitioned(participant.get(), robot_partition(self), false);
  dds_listener_t* listener = dds_create_listener(impl_.get());
  dds_lset_liveliness_changed(listener, &Impl::on_liveliness);
  try {
    // Keep-last 1 per instance on the writer, but deeper here: the depth counts samples of every writer of
    // the instance, so another participant's forged samples, refused when taken, would otherwise push the
    // world's own perception out before it is taken (docs/wire.md "Writer binding").
    Qos qos = make_qos(Channel::Sensor, pace_of(realtime));
    dds_qset_history(qos.get(), DDS_HISTORY_KEEP_LAST, kInboxDepth);
    impl_->packets =
        Entity(dds_create_reader(impl_->subscriber.get(), participant.topics().sensor(), qos.get(), listener),
               "dds_create_reader(sensor)");
  } catch (...) {
    dds_delete_listener(listener);
    throw;
  }
  dds_delete_listener(listener);
  impl_->packet_condition = make_condition(impl_->packets.get());
}

AgentInbox::~AgentInbox() {
  // The reader (and its listener) goes before the state the listener touches.
  if (impl_) impl_->subscriber.reset();
}

dds_entity_t AgentInbox::packet_condition() const {
  return impl_->packet_condition.get();
}
void AgentInbox::bind(const WorldBinding& world, const std::string& who) {
  impl_->world = world;
  impl_->writer_ok.clear();
  impl_->refusals = std::make_unique<RefusalLog>(who, std::cerr);
}
std::uint64_t AgentInbox::refused() const {
  return impl_->refusals->total();
}
std::uint32_t AgentInbox::world_writers_alive() const {
  return impl_->alive.load();
}
bool AgentInbox::world_seen() const {
  return impl_->seen.load();
}

bool AgentInbox::take_packet(SensorSample& own, std::uint64_t& foreign) {
  impl_->poll();
  foreign += std::exchange(impl_->foreign, 0);
  if (!impl_->has_packet) return false;
  impl_->has_packet = false;
  std::swap(own, impl_->staged);
  return true;
}

std::optional<ClaimAnswer> AgentInbox::take_claim_reply() {
  impl_->poll();
  return std::exchange(impl_->reply, std::nullopt);
}

// ---- Commands ---------------------------------------------------------------------------------------------

struct CommandWriter::Impl {
  Entity publisher;  // secure: the robot's own partition
  Entity writer;
  std::uint64_t run_nonce = 0;
  std::uint16_t wire_version = kWireVersion;
  std::vector<char*> events;          // reused: points into the command's strings during dds_write
  dds_time_t alive_at = 0;            // the last write or assertion (each renews the liveliness lease)
  std::optional<RobotId> registered;  // the id whose instance is kept (keep_instance), from the first claim
};

CommandWriter::CommandWriter(const Participant& participant, bool realtime, std::optional<RobotId> robot)
    : impl_(std::make_unique<Impl>()) {
  dds_entity_t parent = participant.get();
  if (participant.secure() && !robot) {
    throw std::logic_error("CommandWriter on a secure participant needs its robot id");
  }
  if (robot) {
    impl_->publisher = make_partitioned(participant.get(), robot_partition(*robot), true);
    parent = impl_->publisher.get();
  }
  impl_->writer = make_writer(parent, participant.topics().command(), Channel::Command, pace_of(realtime));
}
CommandWriter::~CommandWriter() = default;
dds_entity_t CommandWriter::get() const {
  return impl_->writer.get();
}

namespace {
sfdds_Command command_key(RobotId id) {
  sfdds_Command key{};
  key.robot_id = id;
  return key;
}

// A command of `kind` for `id` stamped with the writer's run and version; its telemetry says nothing (no
// label, no parent) until a step fills it.
sfdds_Command stamped_command(RobotId id, std::uint8_t kind, std::uint64_t run_nonce,
                              std::uint16_t wire_version) {
  sfdds_Command s{};
  s.robot_id = id;
  s.wire_version = wire_version;
  s.run_nonce = run_nonce;
  s.kind = kind;
  s.label = -1;
  s.parent = -1;
  return s;
}
}  // namespace

void CommandWriter::set_stamp(std::uint64_t run_nonce, std::uint16_t wire_version) {
  impl_->run_nonce = run_nonce;
  impl_->wire_version = wire_version;
}

void CommandWriter::claim(RobotId id, std::uint64_t nonce, std::uint32_t pid) {
  if (impl_->registered != id) {
    const sfdds_Command key = command_key(id);
    keep_instance(impl_->writer.get(), &key);
    impl_->registered = id;
  }
  sfdds_Command s = stamped_command(id, sfdds_COMMAND_CLAIM, impl_->run_nonce, impl_->wire_version);
  s.nonce = nonce;
  s.pid = pid;
  check(dds_write(impl_->writer.get(), &s), "dds_write(claim)");
  impl_->alive_at = dds_time();
}

dds_time_t CommandWriter::keep_alive(dds_time_t now, bool by_sample) {
  if (now - impl_->alive_at >= kLivelinessAssertPeriod) {
    if (by_sample && impl_->registered) {
      const sfdds_Command s =
          stamped_command(*impl_->registered, sfdds_COMMAND_ALIVE, impl_->run_nonce, impl_->wire_version);
      check(dds_write(impl_->writer.get(), &s), "dds_write(alive)");
    } else {
      check(dds_assert_liveliness(impl_->writer.get()), "dds_assert_liveliness(command writer)");
    }
    impl_->alive_at = now;
  }
  return impl_->alive_at + kLivelinessAssertPeriod;
}

bool CommandWriter::holds_instance(RobotId id) const {
  const sfdds_Command key = command_key(id);
  return dds_lookup_instance(impl_->writer.get(), &key) != DDS_HANDLE_NIL;
}

void CommandWriter::step(RobotId id, Tick tick, const Command& c) {
  sfdds_Command s = stamped_command(id, sfdds_COMMAND_STEP, impl_->run_nonce, impl_->wire_version);
  s.tick = tick;
  s.left_speed = c.left_speed;
  s.right_speed = c.right_speed;
  s.message = octets(c.message);
  s.state = c.telemetry.state;
  s.label = c.telemetry.label;
  s.parent = c.telemetry.parent;
  s.leader = c.telemetry.leader;
  s.net_force = c.telemetry.net_force;
  auto& events = impl_->events;
  events.clear();
  for (const std::string& e : c.telemetry.events) events.push_back(const_cast<char*>(e.c_str()));
  s.events._buffer = events.data();
  s.events._length = s.events._maximum = static_cast<std::uint32_t>(events.size());
  s.extra._buffer = const_cast<double*>(c.telemetry.extra.data());
  s.extra._length = s.extra._maximum = static_cast<std::uint32_t>(c.telemetry.extra.size());
  check(dds_write(impl_->writer.get(), &s), "dds_write(command)");
  impl_->alive_at = dds_time();
}

struct CommandReader::Impl {
  Waiter* waiter = nullptr;
  std::mutex mutex;
  std::vector<LivelinessChange> changes;  // guarded by mutex
  dds_entity_t topic = 0;                 // with the id filter set on it (0: none)
  std::uint32_t accept_ids = 0;
  std::atomic<std::uint64_t> filtered{0};
  bool secure = false;
  std::uint32_t face = 0;  // stamped on every sample taken (CommandSample::face)
  Entity subscriber;       // secure: partition robot/* (every robot's own)
  Entity reader, condition;
  std::unordered_map<PublicationHandle, std::optional<RobotId>> authenticated;  // per writer, looked up once

  // Runs on Cyclone's receive thread for every sample, before the sample is stored: a sample for an id at or
  // above accept_ids never creates an instance in the reader (each costs ~0.9 KB for as long as its writer
  // lives: a flood over a million made-up ids once took the world to 890 MB).
  static bool accept(const void* sample, void* arg) {
    auto* self = static_cast<Impl*>(arg);
    if (static_cast<const sfdds_Command*>(sample)->robot_id < self->accept_ids) return true;
    self->filtered.fetch_add(1, std::memory_order_relaxed);
    return false;
  }

  static void on_data_available(dds_entity_t, void* arg) {
    try {
      static_cast<Impl*>(arg)->waiter->arrived();
    } catch (const DdsError&) {
      // Only possible while tearing down; nobody is waiting then.
    }
  }

  static void on_liveliness(dds_entity_t, const dds_liveliness_changed_status_t status, void* arg) {
    auto* self = static_cast<Impl*>(arg);
    // alive_count falls when a writer loses liveliness (not_alive rises) or goes away (deleted, unmatched),
    // and rises when a writer appears or its liveliness comes back; not_alive alone falls when a writer
    // that had lost its liveliness goes away.
    const int a = status.alive_count_change;
    const int na = status.not_alive_count_change;
    const bool alive = a > 0;
    const bool lapsed = a < 0 && na > 0;
    const bool gone = (a < 0 && na <= 0) || (a == 0 && na < 0);
    if (!alive && !lapsed && !gone) return;
    {
      std::lock_guard lock(self->mutex);
      self->changes.push_back(LivelinessChange{status.last_publication_handle, alive, gone});
    }
    try {
      self->waiter->wake();
    } catch (const DdsError&) {
      // Only possible while tearing down; nobody is waiting then.
    }
  }
};

CommandReader::CommandReader(const Participant& participant, Waiter& waiter, bool realtime,
                             std::uint32_t accept_ids, std::uint32_t face, bool count_arrivals)
    : impl_(std::make_unique<Impl>()) {
  impl_->waiter = &waiter;
  impl_->face = face;
  if (accept_ids > 0) {
    // Set before the reader exists (Cyclone's rule for topic filters); only the world reads this topic in
    // its participant.
    impl_->topic = participant.topics().command();
    impl_->accept_ids = accept_ids;
    dds_topic_filter filter{};
    filter.mode = DDS_TOPIC_FILTER_SAMPLE_ARG;
    filter.f.sample_arg = &Impl::accept;
    filter.arg = impl_.get();
    check(dds_set_topic_filter_extended(impl_->topic, &filter), "dds_set_topic_filter_extended(command)");
  }
  dds_entity_t parent = participant.get();
  if (participant.secure()) {
    // Every robot's commands come in its own partition (CommandWriter); a wildcard reads them all.
    impl_->secure = true;
    impl_->subscriber = make_partitioned(participant.get(), "robot/*", false);
    parent = impl_->subscriber.get();
  }
  dds_listener_t* listener = dds_create_listener(impl_.get());
  dds_lset_liveliness_changed(listener, &Impl::on_liveliness);
  // Set with the reader, so that no sample is ever stored uncounted (Cyclone calls it once per stored
  // sample).
  if (count_arrivals) dds_lset_data_available(listener, &Impl::on_data_available);
  try {
    impl_->reader =
        make_reader(parent, participant.topics().command(), Channel::Command, listener, pace_of(realtime));
  } catch (...) {
    dds_delete_listener(listener);
    throw;
  }
  dds_delete_listener(listener);
  impl_->condition = make_condition(impl_->reader.get());
}

CommandReader::~CommandReader() {
  if (impl_) {
    impl_->condition.reset();
    impl_->reader.reset();
    if (impl_->topic != 0) {  // the filter's argument dies with impl_
      dds_topic_filter none{};
      none.mode = DDS_TOPIC_FILTER_NONE;
      (void)dds_set_topic_filter_extended(impl_->topic, &none);
    }
  }
}

std::uint64_t CommandReader::filtered() const {
  return impl_->filtered.load(std::memory_order_relaxed);
}

std::optional<RobotId> CommandReader::authenticated_robot(PublicationHandle writer) {
  if (!impl_->secure) return std::nullopt;
  if (auto it = impl_->authenticated.find(writer); it != impl_->authenticated.end()) return it->second;
  dds_builtintopic_endpoint_t* e = dds_get_matched_publication_data(impl_->reader.get(), writer);
  if (e == nullptr) return std::nullopt;  // gone already: asked again if it writes again
  std::optional<RobotId> robot;
  std::uint32_t n = 0;
  char** names = nullptr;
  if (dds_qget_partition(e->qos, &n, &names) && n == 1) {
    const std::string name = names[0];
    const std::string prefix = "robot/";
    if (name.size() > prefix.size() && name.size() <= prefix.size() + 10 && name.rfind(prefix, 0) == 0 &&
        name.find_first_not_of("0123456789", prefix.size()) == std::string::npos) {
      const unsigned long long id = std::stoull(name.substr(prefix.size()));
      if (id <= 0xffffffffULL && robot_partition(static_cast<RobotId>(id)) == name) {
        robot = static_cast<RobotId>(id);
      }
    }
  }
  for (std::uint32_t i = 0; i < n; ++i) dds_free(names[i]);
  dds_free(names);
  dds_builtintopic_free_endpoint(e);
  // Bounded: one entry per matched writer, and only matched (authenticated, permitted) writers get here.
  impl_->authenticated.emplace(writer, robot);
  return robot;
}

bool CommandReader::matched(PublicationHandle writer) const {
  dds_builtintopic_endpoint_t* e = dds_get_matched_publication_data(impl_->reader.get(), writer);
  if (e == nullptr) return false;
  dds_builtintopic_free_endpoint(e);
  return true;
}

dds_entity_t CommandReader::condition() const {
  return impl_->condition.get();
}

void CommandReader::take_liveliness_changes(std::vector<LivelinessChange>& out) {
  std::lock_guard lock(impl_->mutex);
  out.insert(out.end(), impl_->changes.begin(), impl_->changes.end());
  impl_->changes.clear();
}

std::size_t CommandReader::take(std::vector<CommandSample>& buf, std::size_t max_samples, std::size_t first) {
  std::size_t count = first;
  max_samples += first;
  while (count < max_samples) {
    void* ptrs[kTakeBatch] = {};
    dds_sample_info_t infos[kTakeBatch];
    const auto batch = static_cast<std::uint32_t>(std::min<std::size_t>(kTakeBatch, max_samples - count));
    const int n = check(dds_take(impl_->reader.get(), ptrs, infos, batch, batch), "dds_take(command)");
    Loan loan(impl_->reader.get(), ptrs, n);
    for (int i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      const auto& s = *static_cast<const sfdds_Command*>(ptrs[i]);
      if (count == buf.size()) buf.emplace_back();
      CommandSample& c = buf[count++];
      c.wire_version = s.wire_version;
      c.run_nonce = s.run_nonce;
      c.robot_id = s.robot_id;
      c.kind = s.kind == sfdds_COMMAND_CLAIM   ? CommandKind::Claim
               : s.kind == sfdds_COMMAND_ALIVE ? CommandKind::Alive
                                               : CommandKind::Step;
      c.tick = s.tick;
      c.nonce = s.nonce;
      c.pid = s.pid;
      c.writer = infos[i].publication_handle;
      c.sent_at = infos[i].source_timestamp;
      c.face = impl_->face;
      c.command.left_speed = s.left_speed;
      c.command.right_speed = s.right_speed;
      assign_octets(c.command.message, s.message);
      Telemetry& t = c.command.telemetry;
      t.state = s.state;
      t.label = s.label;
      t.parent = s.parent;
      t.leader = s.leader;
      t.net_force = s.net_force;
      t.events.resize(s.events._length);
      for (std::uint32_t k = 0; k < s.events._length; ++k) t.events[k] = str(s.events._buffer[k]);
      t.extra.assign(s.extra._buffer, s.extra._buffer + s.extra._length);
    }
    if (n < static_cast<int>(batch)) break;
  }
  return count - first;
}

// ---- World state ------------------------------------------------------------------------------------------

struct WorldStateWriter::Impl {
  Entity writer;
  std::uint64_t run_nonce = 0;
  std::vector<sfdds_RobotPose> scratch;
};

WorldStateWriter::WorldStateWriter(const Participant& participant, std::uint64_t run_nonce)
    : impl_(std::make_unique<Impl>()) {
  impl_->run_nonce = run_nonce;
  impl_->writer = make_writer(participant.get(), participant.topics().world_state(), Channel::WorldState);
}
WorldStateWriter::~WorldStateWriter() = default;

void WorldStateWriter::publish(Tick tick, bool finished, std::uint32_t alive,
                               const std::vector<RobotPoseRow>& robots) {
  auto& scratch = impl_->scratch;
  scratch.resize(robots.size());
  for (std::size_t i = 0; i < robots.size(); ++i) {
    const RobotPoseRow& r = robots[i];
    scratch[i] = sfdds_RobotPose{r.id, r.pose.x, r.pose.y, r.pose.theta, r.alive, r.state, r.label};
  }
  sfdds_WorldState s{};
  s.wire_version = kWireVersion;
  s.run_nonce = impl_->run_nonce;
  s.tick = tick;
  s.finished = finished;
  s.alive = alive;
  s.robots._buffer = scratch.data();
  s.robots._length = s.robots._maximum = static_cast<std::uint32_t>(scratch.size());
  check(dds_write(impl_->writer.get(), &s), "dds_write(world state)");
}

WorldStateReader::WorldStateReader(const Participant& participant)
    : reader_(make_reader(participant.get(), participant.topics().world_state(), Channel::WorldState)),
      condition_(make_condition(reader_.get())) {}

std::optional<WorldStateHeader> WorldStateReader::take() {
  void* ptrs[4] = {};
  dds_sample_info_t infos[4];
  const int n = check(dds_take(reader_.get(), ptrs, infos, 4, 4), "dds_take(world state)");
  Loan loan(reader_.get(), ptrs, n);
  std::optional<WorldStateHeader> out;
  for (int i = 0; i < n; ++i) {
    if (!infos[i].valid_data) continue;
    const auto& s = *static_cast<const sfdds_WorldState*>(ptrs[i]);
    if (s.wire_version != kWireVersion) continue;
    out = WorldStateHeader{s.run_nonce, s.tick, s.finished, s.alive};
  }
  return out;
}

// ---- Observers (issue 21) ---------------------------------------------------------------------------------

struct ObserveWriter::Impl {
  Entity writer;
  std::uint64_t run_nonce = 0;
  std::vector<sfdds_ObservedRobot> robots;
  std::vector<sfdds_StateStyle> states;
  std::vector<char*> fields;
};

ObserveWriter::ObserveWriter(const Participant& participant, std::uint64_t run_nonce)
    : impl_(std::make_unique<Impl>()) {
  impl_->run_nonce = run_nonce;
  impl_->writer = make_writer(participant.get(), participant.topics().observe(), Channel::Observe);
}
ObserveWriter::~ObserveWriter() = default;

void ObserveWriter::publish(const ObserveFrameData& f) {
  auto& robots = impl_->robots;
  robots.resize(f.robots.size());
  for (std::size_t i = 0; i < f.robots.size(); ++i) {
    const ObservedRobotRow& r = f.robots[i];
    sfdds_ObservedRobot& o = robots[i];
    o = sfdds_ObservedRobot{};
    o.id = r.id;
    o.x = r.pose.x;
    o.y = r.pose.y;
    o.theta = r.pose.theta;
    o.alive = r.alive;
    o.state = r.state;
    o.label = r.label;
    o.parent = r.parent;
    o.leader = r.leader;
    o.net_force = r.net_force;
    for (std::size_t k = 0; k < kUltrasonicCount; ++k) o.ultrasonic[k] = r.ultrasonic[k];
    o.heard._buffer = const_cast<std::uint32_t*>(r.heard.data());
    o.heard._length = o.heard._maximum = static_cast<std::uint32_t>(r.heard.size());
    o.heard._release = false;
    o.left_speed = r.left_speed;
    o.right_speed = r.right_speed;
    o.message_bytes = r.message_bytes;
  }
  auto& states = impl_->states;
  states.resize(f.states.size());
  for (std::size_t i = 0; i < f.states.size(); ++i) {
    states[i] = sfdds_StateStyle{f.states[i].value, const_cast<char*>(f.states[i].name.c_str()),
                                 const_cast<char*>(f.states[i].colour.c_str())};
  }
  auto& fields = impl_->fields;
  fields.resize(f.telemetry_fields.size());
  for (std::size_t i = 0; i < f.telemetry_fields.size(); ++i)
    fields[i] = const_cast<char*>(f.telemetry_fields[i].c_str());
  sfdds_ObserveFrame s{};
  s.wire_version = kWireVersion;
  s.run_nonce = impl_->run_nonce;
  s.tick = f.tick;
  s.finished = f.finished;
  s.paused = f.paused;
  s.controllable = f.controllable;
  s.speed_cap = f.speed_cap;
  s.alive = f.alive;
  s.formation_tick = f.formation_tick;
  s.shape_error = f.shape_error;
  s.behaviour = const_cast<char*>(f.behaviour.c_str());
  s.states._buffer = states.data();
  s.states._length = s.states._maximum = static_cast<std::uint32_t>(states.size());
  s.telemetry_fields._buffer = fields.data();
  s.telemetry_fields._length = s.telemetry_fields._maximum = static_cast<std::uint32_t>(fields.size());
  s.robots._buffer = robots.data();
  s.robots._length = s.robots._maximum = static_cast<std::uint32_t>(robots.size());
  check(dds_write(impl_->writer.get(), &s), "dds_write(observe)");
}

ObserveReader::ObserveReader(const Participant& participant)
    : reader_(make_reader(participant.get(), participant.topics().observe(), Channel::Observe)),
      condition_(make_condition(reader_.get())) {}

bool ObserveReader::take(std::uint64_t run_nonce, ObserveFrameData& out) {
  void* ptrs[4] = {};
  dds_sample_info_t infos[4];
  const int n = check(dds_take(reader_.get(), ptrs, infos, 4, 4), "dds_take(observe)");
  Loan loan(reader_.get(), ptrs, n);
  const sfdds_ObserveFrame* newest = nullptr;
  for (int i = 0; i < n; ++i) {
    if (!infos[i].valid_data) continue;
    const auto& s = *static_cast<const sfdds_ObserveFrame*>(ptrs[i]);
    if (s.wire_version != kWireVersion || s.run_nonce != run_nonce) {
      ++refused_;
      continue;
    }
    newest = &s;
  }
  if (newest == nullptr) return false;
  const sfdds_ObserveFrame& s = *newest;
  out.run_nonce = s.run_nonce;
  out.tick = s.tick;
  out.finished = s.finished;
  out.paused = s.paused;
  out.controllable = s.controllable;
  out.speed_cap = s.speed_cap;
  out.alive = s.alive;
  out.formation_tick = s.formation_tick;
  out.shape_error = s.shape_error;
  out.behaviour = str(s.behaviour);
  out.states.resize(s.states._length);
  for (std::uint32_t i = 0; i < s.states._length; ++i) {
    const sfdds_StateStyle& st = s.states._buffer[i];
    out.states[i] = StateStyleRow{st.value, str(st.name), str(st.colour)};
  }
  out.telemetry_fields.resize(s.telemetry_fields._length);
  for (std::uint32_t i = 0; i < s.telemetry_fields._length; ++i) {
    out.telemetry_fields[i] = str(s.telemetry_fields._buffer[i]);
  }
  out.robots.resize(s.robots._length);
  for (std::uint32_t i = 0; i < s.robots._length; ++i) {
    const sfdds_ObservedRobot& o = s.robots._buffer[i];
    ObservedRobotRow& r = out.robots[i];
    r.id = o.id;
    r.pose = Pose2D{o.x, o.y, o.theta};
    r.alive = o.alive;
    r.state = o.state;
    r.label = o.label;
    r.parent = o.parent;
    r.leader = o.leader;
    r.net_force = o.net_force;
    for (std::size_t k = 0; k < kUltrasonicCount; ++k) r.ultrasonic[k] = o.ultrasonic[k];
    r.heard.assign(o.heard._buffer, o.heard._buffer + o.heard._length);
    r.left_speed = o.left_speed;
    r.right_speed = o.right_speed;
    r.message_bytes = o.message_bytes;
  }
  return true;
}

ControlWriter::ControlWriter(const Participant& participant)
    : writer_(make_writer(participant.get(), participant.topics().control(), Channel::Control)) {}

void ControlWriter::send(const ControlSample& c) {
  sfdds_Control s{};
  s.wire_version = c.wire_version;
  s.run_nonce = c.run_nonce;
  s.token = c.token;
  s.seq = c.seq;
  s.kind = c.kind;
  s.count = c.count;
  s.value = c.value;
  check(dds_write(writer_.get(), &s), "dds_write(control)");
}

bool ControlWriter::matched() const {
  return writer_matched(writer_.get());
}

ControlReader::ControlReader(const Participant& participant)
    : reader_(make_reader(participant.get(), participant.topics().control(), Channel::Control)),
      condition_(make_condition(reader_.get())) {}

void ControlReader::take(std::vector<ControlSample>& out) {
  constexpr int kBatch = 64;
  void* ptrs[kBatch] = {};
  dds_sample_info_t infos[kBatch];
  const int n = check(dds_take(reader_.get(), ptrs, infos, kBatch, kBatch), "dds_take(control)");
  Loan loan(reader_.get(), ptrs, n);
  for (int i = 0; i < n; ++i) {
    if (!infos[i].valid_data) continue;
    const auto& s = *static_cast<const sfdds_Control*>(ptrs[i]);
    out.push_back(ControlSample{s.wire_version, s.run_nonce, s.token, s.seq, s.kind, s.count, s.value,
                                infos[i].publication_handle});
  }
}

bool ControlReader::writer_alive(PublicationHandle writer) const {
  dds_builtintopic_endpoint_t* e = dds_get_matched_publication_data(reader_.get(), writer);
  if (e == nullptr) return false;
  dds_builtintopic_free_endpoint(e);
  return true;
}

}  // namespace swarmform::dds
