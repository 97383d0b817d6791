#include "robot_agent/controller/label_timeout.hpp"

#include <algorithm>
#include <cmath>

#include "robot_agent/controller/message.hpp"
#include "robot_agent/controller/stigmergy.hpp"

namespace swarmform::controller {

int scaled_label_timeout(int configured, int label_count, std::size_t entries_per_message,
                         int diameter_hops) {
  const long long entries = static_cast<long long>(std::max<std::size_t>(entries_per_message, 1));
  const long long load = 2LL * Stigmergy::kResendCount * std::max(label_count, 0);
  const long long period = std::max((load + entries - 1) / entries, static_cast<long long>(diameter_hops));
  const long long needed = 3 * period;
  constexpr long long kMax = 1'000'000;  // the parameter's own upper bound
  return static_cast<int>(std::min(kMax, std::max(static_cast<long long>(configured), needed)));
}

int shape_diameter_hops(const ShapeMatrix& shape, double spacing, double comm_range) {
  if (!(comm_range > 0.0) || !std::isfinite(comm_range)) return 1;
  const double diagonal = std::hypot(std::max(shape.rows - 1, 0), std::max(shape.cols - 1, 0)) * spacing;
  const double hops = std::ceil(diagonal / comm_range);
  if (!std::isfinite(hops)) return 1;
  return static_cast<int>(std::clamp(hops, 1.0, 1e6));
}

std::size_t formation_entries_per_message(std::size_t max_message_bytes) {
  constexpr std::size_t kEntryBytes = 20;  // one stigmergy entry on the wire (message.hpp)
  const std::size_t fixed = kMessageFixedBytes + 2 * kMaxFreeLabels;
  const std::size_t fit = max_message_bytes > fixed ? (max_message_bytes - fixed) / kEntryBytes : 0;
  return std::clamp<std::size_t>(fit, 1, kMaxEntriesPerMessage);
}

}  // namespace swarmform::controller
