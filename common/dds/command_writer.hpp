// The agent's side of sf_command: one writer for its claims, its commands and, when it has nothing to write,
// its liveliness (MANUAL_BY_TOPIC, qos.hpp: a SIGKILLed agent is seen dead within the lease).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>

#include "common/dds/claim_proof.hpp"
#include "common/dds/participant.hpp"
#include "common/dds/wire_version.hpp"
#include "common/types.hpp"

namespace swarmform::dds {

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
  // `proof`: the claim's proof (claim_proof.hpp), empty for an agent started without a token; it travels in
  // the claim's `message`.
  void claim(RobotId id, std::uint64_t nonce, std::uint32_t pid, std::span<const std::uint8_t> proof = {});
  // This writer's GUID: what a claim proof is bound to.
  WriterGuid guid() const;
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

}  // namespace swarmform::dds
