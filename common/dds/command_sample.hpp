// A sample of sf_command in plain types, as the world's CommandReader takes it: a claim, a tick's command or
// a bare liveliness sign, with who wrote it (the identity, docs/wire.md "Writer binding") and when.
#pragma once

#include <cstdint>

#include "common/dds/identity.hpp"
#include "common/types.hpp"

namespace swarmform::dds {

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

}  // namespace swarmform::dds
