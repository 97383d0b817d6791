// Is a command sample of this run and this wire? (docs/wire.md "Wire version", "Run nonce".) A sample of
// another version or another run's nonce is refused before anything else looks at it.
#pragma once

#include <cstdint>
#include <string>

#include <optional>

#include "common/dds/command_sample.hpp"
#include "common/dds/matching.hpp"

namespace swarmform::server {

// Why `s` is refused (empty: it is this run's).
std::string wire_refusal(const dds::CommandSample& s, std::uint64_t run_nonce);

// "writer 0123abcd (pid P)": a command writer for messages.
std::string writer_text(const dds::CommandSample& s);

// "pid P (participant <GUID>)": a claimant for messages. The pid is only what the sample says; the
// participant GUID is what DDS discovery knows of its writer ("participant unknown" once it is gone).
std::string claimant_text(const dds::CommandSample& s, const std::optional<dds::RemoteWriter>& remote);

}  // namespace swarmform::server
