#include "world_server/mass_loss.hpp"

#include <utility>

namespace swarmform::server {

std::optional<MassLoss::Group> MassLoss::died(RobotId id, Tick tick, dds_time_t now, bool process_present) {
  std::optional<Group> closed;
  if (open_ && now - open_->first > kWindow) closed = finish();
  if (!open_) open_ = Group{tick, now, now, {}, 0};
  open_->last = now;
  open_->robots.push_back(id);
  if (process_present) ++open_->processes_present;
  return closed;
}

std::optional<MassLoss::Group> MassLoss::close(dds_time_t now) {
  if (!open_ || now - open_->first <= kWindow) return std::nullopt;
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
