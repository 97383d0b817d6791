// What discovery tells an endpoint about the other side: whether a writer has matched a reader, and which
// participant a matched remote writer belongs to.
#pragma once

#include <dds/dds.h>

#include <array>
#include <cstdint>
#include <optional>

#include "common/dds/identity.hpp"

namespace swarmform::dds {

// True once `writer` has matched at least one reader (before that, what it writes goes to nobody).
bool writer_matched(dds_entity_t writer);

// A matched remote writer's GUID and its participant's, as Cyclone's discovery gives them: who a sample came
// from, whatever the sample says of itself.
struct RemoteWriter {
  std::array<std::uint8_t, 16> guid{};
  ParticipantKey participant{};
};
std::optional<RemoteWriter> remote_writer(dds_entity_t reader, dds_instance_handle_t writer);

// The participant of the remote writer `writer` matched by `reader` (nullopt when it is not matched).
std::optional<ParticipantKey> writer_participant(dds_entity_t reader, dds_instance_handle_t writer);

}  // namespace swarmform::dds
