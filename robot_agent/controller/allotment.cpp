#include "robot_agent/controller/allotment.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <tuple>

#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller {

void LabelTicks::set(int label, Tick tick) {
  if (label < 0) return;
  const auto i = static_cast<std::size_t>(label);
  if (i >= ticks_.size()) ticks_.resize(i + 1, kNone);
  ticks_[i] = tick;
}

LabelStatus label_status(const Stigmergy& stigmergy, int label) {
  LabelStatus s;
  if (label < 0) return s;
  const auto value = stigmergy.get(stig::key(stig::Ns::Labels, static_cast<std::uint32_t>(label)));
  if (!value) return s;
  if (*value >= 0) {
    s.kind = LabelStatus::Kind::Held;
    s.holder = static_cast<RobotId>(*value);
  } else if (*value <= kLabelFreedBase) {
    s.kind = LabelStatus::Kind::Freed;
    s.freed_at = static_cast<Tick>(kLabelFreedBase - *value);
  }
  return s;
}

void put_label_holder(Stigmergy& stigmergy, int label, RobotId holder) {
  stigmergy.put(stig::key(stig::Ns::Labels, static_cast<std::uint32_t>(label)),
                static_cast<std::int64_t>(holder));
}

void put_label_freed(Stigmergy& stigmergy, int label, Tick now) {
  stigmergy.put(stig::key(stig::Ns::Labels, static_cast<std::uint32_t>(label)),
                kLabelFreedBase - static_cast<std::int64_t>(now));
}

void SeedElection::update(RobotId self, double own_distance, const NeighbourTable& neighbours, Tick now,
                          int max_age) {
  // Distances travel as f32 on the wire: compare what the others will see.
  RobotId best = self;
  double best_d = static_cast<double>(static_cast<float>(own_distance));
  int best_age = 0;
  for (const auto& [id, n] : neighbours.all()) {
    // Only what was heard this tick: a stale report would keep a minimum alive after its source moved on.
    if (n.last_heard != now) continue;
    const auto& m = n.message;
    if (m.state != RobotState::Searching) continue;
    if (m.seed_candidate == self) continue;  // our own minimum coming back: we report it at age 0
    const int age = static_cast<int>(m.seed_age) + 1;
    if (age > max_age) continue;  // aged out: its source has not been heard of for too long
    const double d = m.seed_distance;
    if (std::tie(d, m.seed_candidate) < std::tie(best_d, best)) {
      best = m.seed_candidate;
      best_d = d;
      best_age = age;
    } else if (m.seed_candidate == best && best != self) {
      best_age = std::min(best_age, age);
    }
  }
  if (!started_ || best != candidate_) {
    started_ = true;
    candidate_ = best;
    since_ = now;
  }
  distance_ = best_d;
  age_ = static_cast<std::uint8_t>(std::min(best_age, 255));
}

bool SeedElection::settled(Tick now, int settle_ticks) const {
  return started_ && now >= since_ + static_cast<Tick>(settle_ticks);
}

namespace {

// Whether a neighbour reports holding `label` right now. Asked only for the few grid labels the stigmergy
// does not give to a holder: a scan of the neighbours for each, not a set of their labels built (and sorted,
// or allocated node by node) for every message.
bool heard_holding(const NeighbourTable& neighbours, int label) {
  return std::any_of(neighbours.all().begin(), neighbours.all().end(),
                     [label](const auto& entry) { return entry.second.message.label == label; });
}

// A label held by a robot other than `self` whose entry this robot has seen change: that tick, and the
// holder.
struct OtherHolder {
  RobotId holder = 0;
  Tick since = 0;
};
std::optional<OtherHolder> held_by_other(const Stigmergy& stigmergy, int label,
                                         const LabelTicks& entry_changed, RobotId self) {
  const auto status = label_status(stigmergy, label);
  if (status.kind != LabelStatus::Kind::Held || status.holder == self) return std::nullopt;
  const auto changed = entry_changed.find(label);
  if (!changed) return std::nullopt;  // not tracked yet
  return OtherHolder{status.holder, *changed};
}

}  // namespace

std::vector<int> watched_labels(const ShapeTable& table, int own_label, const Stigmergy& stigmergy) {
  std::vector<int> out;
  if (own_label < 0 || own_label >= table.size()) return out;
  std::vector<int> through{own_label};  // labels whose grid is watched: our own, then the freed ones reached
  std::vector<bool> seen(static_cast<std::size_t>(table.size()), false);
  seen[static_cast<std::size_t>(own_label)] = true;
  for (std::size_t i = 0; i < through.size(); ++i) {
    for (const auto& nb : table.neighbours(through[i])) {
      if (seen[static_cast<std::size_t>(nb.label)]) continue;
      seen[static_cast<std::size_t>(nb.label)] = true;
      out.push_back(nb.label);
      if (label_status(stigmergy, nb.label).kind == LabelStatus::Kind::Freed) through.push_back(nb.label);
    }
  }
  return out;
}

std::vector<int> free_grid_labels(const ShapeTable& table, int label, const Stigmergy& stigmergy,
                                  const NeighbourTable& neighbours) {
  std::vector<int> out;
  for (const auto& nb : table.neighbours(label)) {
    if (label_status(stigmergy, nb.label).kind == LabelStatus::Kind::Held) continue;
    if (heard_holding(neighbours, nb.label)) continue;
    out.push_back(nb.label);
  }
  return out;
}

std::vector<LabelOffer> collect_offers(const ShapeTable& table, double shape_heading,
                                       const NeighbourTable& neighbours, const Stigmergy& stigmergy) {
  std::map<int, LabelOffer> by_label;
  for (const auto& [id, n] : neighbours.all()) {
    const auto& m = n.message;
    if (m.label < 0 || !m.has_origin) continue;
    for (int label : m.free_labels) {
      if (label < 0 || label >= table.size()) continue;
      if (by_label.contains(label)) continue;  // std::map iterates ids in order: the lowest advertiser wins
      if (label_status(stigmergy, label).kind == LabelStatus::Kind::Held) continue;
      if (heard_holding(neighbours, label)) continue;
      by_label[label] = {label, id, m.label, m.origin, table.place(label, m.origin, shape_heading)};
    }
  }
  std::vector<LabelOffer> out;
  for (auto& [label, offer] : by_label) out.push_back(offer);
  return out;
}

std::optional<LabelOffer> choose_offer(const std::vector<LabelOffer>& offers,
                                       const std::vector<Searcher>& searchers, RobotId self) {
  struct Pair {
    double distance;
    RobotId id;
    int label;
    std::size_t offer;
  };
  std::vector<Pair> pairs;
  for (std::size_t o = 0; o < offers.size(); ++o) {
    for (const auto& s : searchers) {
      pairs.push_back({vnorm(vsub(offers[o].place, s.position)), s.id, offers[o].label, o});
    }
  }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) {
    return std::tie(a.distance, a.id, a.label) < std::tie(b.distance, b.id, b.label);
  });
  std::set<RobotId> matched_robots;
  std::set<int> matched_labels;
  for (const auto& p : pairs) {
    if (matched_robots.contains(p.id) || matched_labels.contains(p.label)) continue;
    if (p.id == self) return offers[p.offer];
    matched_robots.insert(p.id);
    matched_labels.insert(p.label);
  }
  return std::nullopt;
}

std::vector<int> labels_to_free(const ShapeTable& table, int own_label, const Stigmergy& stigmergy,
                                const NeighbourTable& neighbours, const LabelTicks& entry_changed,
                                RobotId self, Tick now, int label_timeout) {
  std::vector<int> out;
  for (const int l : watched_labels(table, own_label, stigmergy)) {
    const auto other = held_by_other(stigmergy, l, entry_changed, self);
    if (!other) continue;
    // Beyond a freed label only a holder that never stood at its place: one in the barrier is counted by it
    // (nothing waits for its label), and it may be alive out of everyone's radio range, its heartbeat unable
    // to cross the freed labels (the cross's long arm beyond two dead robots).
    if (!table.are_neighbours(own_label, l) &&
        stigmergy.get(stig::key(stig::Ns::Barrier, other->holder)) == static_cast<std::int64_t>(l))
      continue;
    Tick quiet_since = other->since;
    if (const auto heard = neighbours.last_heard(other->holder)) quiet_since = std::max(quiet_since, *heard);
    if (now >= quiet_since + static_cast<Tick>(label_timeout)) out.push_back(l);
  }
  return out;
}

Tick earliest_label_free(const ShapeTable& table, int own_label, const Stigmergy& stigmergy,
                         const LabelTicks& entry_changed, RobotId self, int label_timeout) {
  Tick earliest = std::numeric_limits<Tick>::max();
  for (const int l : watched_labels(table, own_label, stigmergy)) {
    if (const auto other = held_by_other(stigmergy, l, entry_changed, self))
      earliest = std::min(earliest, other->since + static_cast<Tick>(label_timeout));
  }
  return earliest;
}

std::vector<int> labels_left_untaken(const ShapeTable& table, int own_label, const Stigmergy& stigmergy,
                                     const NeighbourTable& neighbours, Tick reached_at, Tick now,
                                     int label_timeout) {
  std::vector<int> out;
  if (now < reached_at + static_cast<Tick>(label_timeout)) return out;
  for (const int l : watched_labels(table, own_label, stigmergy)) {
    if (label_status(stigmergy, l).kind == LabelStatus::Kind::Unclaimed && !heard_holding(neighbours, l))
      out.push_back(l);
  }
  return out;
}

}  // namespace swarmform::controller
