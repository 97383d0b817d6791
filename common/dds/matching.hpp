// What discovery tells an endpoint about the other side: whether a writer has matched a reader, and which
// participant a matched remote writer belongs to.
#pragma once

#include <dds/dds.h>

#include <optional>

#include "common/dds/identity.hpp"

namespace swarmform::dds {

// True once `writer` has matched at least one reader (before that, what it writes goes to nobody).
bool writer_matched(dds_entity_t writer);

// The participant of the remote writer `writer` matched by `reader` (nullopt when it is not matched).
std::optional<ParticipantKey> writer_participant(dds_entity_t reader, dds_instance_handle_t writer);

}  // namespace swarmform::dds
