// A process's place on the wire: the Cyclone domain (created from cyclone_config_xml) and the participant in
// it, with its topics (made on first use, internal/topics.hpp). One domain per process (dds_create_domain
// fails for a second one): a process holds one Participant, a world one per face (docs/wire.md "Faces").
#pragma once

#include <memory>

#include "common/dds/cyclone_config.hpp"
#include "common/dds/entity.hpp"

namespace swarmform::dds {

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

}  // namespace swarmform::dds
