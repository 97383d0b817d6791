#include "world_server/mass_loss.hpp"

#include <algorithm>
#include <utility>

namespace swarmform::server {

std::optional<MassLoss::Group> MassLoss::died(RobotId id, Tick tick, dds_time_t lost_at,
                                              bool process_present) {
  std::optional<Group> closed;
  // A suspected loss is recorded late with the time it was noticed: it may be earlier than the group's first.
  if (open_ && (lost_at > open_->first + kWindow || lost_at < open_->first - kWindow)) closed = finish();
  if (!open_) open_ = Group{tick, lost_at, lost_at, {}, 0};
  open_->first = std::min(open_->first, lost_at);
  open_->last = std::max(open_->last, lost_at);
  open_->robots.push_back(id);
  if (process_present) ++open_->processes_present;
  return closed;
}

std::optional<MassLoss::Group> MassLoss::close(dds_time_t now) {
  if (!open_ || now - open_->first <= kWindow + kLate) return std::nullopt;
  return finish();
}

std::optional<MassLoss::Group> MassLoss::finish() {
  Group g = std::move(*open_);
  open_.reset();
  if (g.robots.size() < 2) return std::nullopt;
  closed_.push_back(g);
  return g;
}

}  // namespace swarmform::server
