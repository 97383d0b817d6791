#include "world_server/late_commands.hpp"

#include <algorithm>
#include <cstdio>

namespace swarmform::server {

namespace {

double ms(std::int64_t ns) {
  return static_cast<double>(ns) / 1e6;
}

// "3.2 ms (median; max 41.0)" of one part over every late command.
std::string median_max(const std::vector<LateCommand>& late, double LateCommand::*part) {
  std::vector<double> v;
  v.reserve(late.size());
  for (const LateCommand& c : late) v.push_back(c.*part);
  std::sort(v.begin(), v.end());
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.1f ms (median; max %.1f)", v[v.size() / 2], v.back());
  return buf;
}

}  // namespace

void LateCommands::missed(RobotId id, Tick tick, std::int64_t round_start, std::int64_t written,
                          std::int64_t deadline) {
  if (id >= open_.size()) return;
  open_[id] = Open{true, tick, round_start, written, deadline};
}

std::optional<LateCommand> LateCommands::arrived(RobotId id, Tick tick, std::int64_t sent,
                                                 std::int64_t received) {
  if (id >= open_.size() || !open_[id].open || open_[id].tick != tick) return std::nullopt;
  Open& o = open_[id];
  o.open = false;
  LateCommand c;
  c.written_ms = ms(o.written - o.round_start);
  c.answered_ms = ms(sent - o.written);
  c.transit_ms = ms(received - sent);
  c.late_ms = ms(received - o.deadline);
  c.sent_late = sent > o.deadline;
  late_.push_back(c);
  return c;
}

std::string LateCommands::summary() const {
  if (late_.empty()) return "no late commands";
  const auto sent_late =
      std::count_if(late_.begin(), late_.end(), [](const LateCommand& c) { return c.sent_late; });
  return std::to_string(late_.size()) + " late commands (" + std::to_string(sent_late) +
         " sent after the deadline): packet written " + median_max(late_, &LateCommand::written_ms) +
         " into the round, answered " + median_max(late_, &LateCommand::answered_ms) + " after it, transit " +
         median_max(late_, &LateCommand::transit_ms) + ", received " +
         median_max(late_, &LateCommand::late_ms) + " after the deadline";
}

}  // namespace swarmform::server
