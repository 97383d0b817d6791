// sf_world_state: every robot's pose, state and label each tick, best effort, for anyone on the domain who
// watches (the world writes it; the test programs read its header to follow the run).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "common/dds/entity.hpp"
#include "common/dds/participant.hpp"
#include "common/types.hpp"

namespace swarmform::dds {

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
