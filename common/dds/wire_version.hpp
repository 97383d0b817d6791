// The wire-protocol version every sample carries (idl/swarmform.idl WIRE_VERSION; docs/wire.md says when to
// bump it). internal/idl.hpp checks the two are equal at compile time.
#pragma once

#include <cstdint>

namespace swarmform::dds {

inline constexpr std::uint16_t kWireVersion = 14;

}  // namespace swarmform::dds
