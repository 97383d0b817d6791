// A participant's topics, each created on first use: under DDS Security a participant may create only the
// topics its permissions name (an agent's name no sf_world_state), so each process makes just the ones its
// endpoints use. Private to common/dds: the endpoint files ask Participant::topics() for theirs.
#pragma once

#include <mutex>

#include "common/dds/entity.hpp"
#include "common/dds/participant.hpp"

namespace swarmform::dds {

struct Participant::Topics {
  dds_entity_t mission() const { return get(mission_, kMission); }
  dds_entity_t sensor() const { return get(sensor_, kSensor); }
  dds_entity_t command() const { return get(command_, kCommand); }
  dds_entity_t world_state() const { return get(world_state_, kWorldState); }
  dds_entity_t observe() const { return get(observe_, kObserve); }  // observe_wire.hpp
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
  dds_entity_t get(Entity& slot, Which which) const;  // participant.cpp
  mutable std::mutex mutex_;
  mutable Entity mission_, sensor_, command_, world_state_, observe_, control_;
};

}  // namespace swarmform::dds
