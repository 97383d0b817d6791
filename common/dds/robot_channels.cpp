#include "common/dds/robot_channels.hpp"

#include <algorithm>
#include <deque>
#include <map>
#include <stdexcept>
#include <utility>

#include "common/dds/cyclone_config.hpp"
#include "common/dds/identity.hpp"
#include "common/dds/internal/endpoint_kit.hpp"
#include "common/dds/internal/idl.hpp"
#include "common/dds/internal/optional_sensors.hpp"
#include "common/dds/internal/perception_goal.hpp"
#include "common/dds/internal/topics.hpp"
#include "common/dds/matching.hpp"
#include "common/dds/readings_blob.hpp"
#include "common/dds/wire_version.hpp"

namespace swarmform::dds {

using internal::keep_instance;
using internal::make_partitioned;
using internal::make_writer;
using internal::octets;
using internal::pace_of;

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
  std::vector<double> lidar;              // the packed lidar values, reused for every packet
};

RobotChannels::RobotChannels(const Participant& participant, std::size_t robots, bool realtime)
    : RobotChannels(std::vector<const Participant*>{&participant}, robots, realtime) {}

RobotChannels::RobotChannels(std::vector<const Participant*> faces, std::size_t robots, bool realtime)
    : impl_(std::make_unique<Impl>(Impl{std::move(faces), pace_of(realtime), 0, {}, {}, {}, {}, {}, {}})) {
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
  internal::put_optional_sensors(p, s, impl_->lidar);
  internal::put_goal(p, s);
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

}  // namespace swarmform::dds
