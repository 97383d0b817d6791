// The label timeout a shape needs (allotment.hpp, dead holders; barrier.hpp, abandoned labels).
//
// Every holder in Moving or Reached re-puts its labels entry every label_timeout / 3 ticks (the heartbeat),
// and each new version floods the whole swarm: every robot forwards it in Stigmergy::kResendCount messages.
// With L holders that is 3 L kResendCount / label_timeout entries a tick in every robot's messages, against
// the entries a message carries. When they do not fit, heartbeats queue, arrive later than label_timeout,
// and live robots' labels are freed, offered and fought over (a 20 x 20 block with the default 40 ticks: ~50
// false frees per 100 ticks, never formed). So the timeout a robot uses is the largest of:
//   - the configured `label_timeout`;
//   - 3 x ceil(2 kResendCount L / entries): the heartbeats take at most half of every message, the other
//     half left for the changes that drive the formation (labels taken, barrier entries);
//   - 3 x the shape's diameter in radio hops (its bounding box's diagonal / comm_range, rounded up): a
//     heartbeat, one hop a tick at best, crosses the shape within one heartbeat period.
// Every robot derives it from the same shape and mission, so all agree. Shapes of up to ~50 labels keep the
// default 40 ticks (shapes/: at most 30 labels); a 10 x 10 block gets 75, 20 x 20 300, 32 x 32 768.
#pragma once

#include <cstddef>

#include "common/shape.hpp"

namespace swarmform::controller {

// `entries_per_message`: stigmergy entries one message carries (>= 1).
int scaled_label_timeout(int configured, int label_count, std::size_t entries_per_message, int diameter_hops);

// The shape's bounding box diagonal in radio hops: ceil(hypot(rows - 1, cols - 1) x spacing / comm_range),
// at least 1 (a non-positive or non-finite comm_range counts as one hop).
int shape_diameter_hops(const ShapeMatrix& shape, double spacing, double comm_range);

// Stigmergy entries in a formation-phase message under the world's byte limit (message.hpp): at most
// kMaxEntriesPerMessage, at least 1.
std::size_t formation_entries_per_message(std::size_t max_message_bytes);

}  // namespace swarmform::controller
