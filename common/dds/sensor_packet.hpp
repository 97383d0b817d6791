// A SensorPacket (sf_sensor) in plain types. Each robot's packets travel in its own partition robot/K on two
// key lanes: its perceptions (PacketStatus, SensorSample) and the answers to claims for its id (ClaimAnswer).
// Written by RobotChannels (world), taken by AgentInbox (agent).
#pragma once

#include <cstdint>
#include <string>

#include "common/types.hpp"

namespace swarmform::dds {

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

struct SensorSample {
  RobotId robot_id = 0;  // as it came on the wire (an agent counts any that is not its own)
  PacketStatus status = PacketStatus::Run;
  std::uint64_t owner_nonce = 0;  // the claim nonce of the id's owner, as the world knows it
  std::uint32_t generation = 0;   // the robot's generation (raised at each revival after a death)
  Perception perception;
};

}  // namespace swarmform::dds
