#include "common/dds/agent_inbox.hpp"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <iostream>
#include <iterator>
#include <span>
#include <unordered_map>
#include <utility>

#include "common/dds/internal/endpoint_kit.hpp"
#include "common/dds/internal/idl.hpp"
#include "common/dds/internal/optional_sensors.hpp"
#include "common/dds/internal/perception_goal.hpp"
#include "common/dds/internal/topics.hpp"
#include "common/dds/matching.hpp"
#include "common/dds/qos.hpp"
#include "common/dds/readings_blob.hpp"
#include "common/dds/refusal_log.hpp"
#include "common/dds/wire_version.hpp"

namespace swarmform::dds {

using internal::Loan;
using internal::make_condition;
using internal::make_partitioned;
using internal::nonce_text;
using internal::pace_of;
using internal::str;
using internal::version_text;

namespace {
constexpr std::int32_t kInboxDepth = 16;  // AgentInbox's history per instance (see its constructor)
}  // namespace

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
      std::string bad = internal::optional_sensors_problem(s);
      if (bad.empty()) bad = internal::goal_problem(s);
      if (bad.empty()) {
        bad = decode_readings(std::span<const std::uint8_t>(s.readings._buffer, s.readings._length),
                              staged.perception.messages);
      }
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
      internal::take_optional_sensors(s, p);
      internal::take_goal(s, p);
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

}  // namespace swarmform::dds
