// Is a command sample of this run and this wire? (docs/wire.md "Wire version", "Run nonce".) A sample of
// another version or another run's nonce is refused before anything else looks at it.
#pragma once

#include <cstdint>
#include <string>

#include "common/dds/command_sample.hpp"

namespace swarmform::server {

// Why `s` is refused (empty: it is this run's).
std::string wire_refusal(const dds::CommandSample& s, std::uint64_t run_nonce);

// "writer 0123abcd (pid P)": a command writer for messages.
std::string writer_text(const dds::CommandSample& s);

}  // namespace swarmform::server
