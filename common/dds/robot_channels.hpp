// The world's side of sf_sensor: for each robot a publisher in partition robot/K, on the face its agent
// peers with, holding its SensorPacket writer: its perceptions, and the answers to claims for its id.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "common/dds/participant.hpp"
#include "common/dds/sensor_packet.hpp"
#include "common/types.hpp"

namespace swarmform::dds {

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
  // finds it in place rather than creating and freeing it: keep_instance, internal/endpoint_kit.hpp). For
  // tests.
  bool holds_instance(RobotId id) const;
  // Channels held for ids outside the run (<= kMaxExtraChannels). For tests.
  std::size_t extra_channels() const;
  // The face robot `id`'s channel is on: face_of(id), or the last face when there are fewer.
  std::uint32_t face(RobotId id) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace swarmform::dds
