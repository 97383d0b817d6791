// The events of a run that are derived from the truth, tick by tick: state and label changes and leader
// elections (from what the controllers report), deaths and rejoins (from the alive flags, unless the front
// end reported them first), and the splitting and reuniting of the shape robots' communication graph. An
// event is one JSON object, written as one line of events.jsonl (docs/recording-format.md).
#pragma once

#include <algorithm>
#include <optional>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>
#include <span>

#include "behaviour/descriptor.hpp"
#include "behaviour/known_columns.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::world {

using Event = nlohmann::ordered_json;

// A robot is taken as the new leader once it has been the only live robot claiming it for this many ticks in
// a row: during an election several robots claim it for a tick or two, which is not a change of leader.
inline constexpr Tick kLeaderSettleTicks = 5;

// {"tick": tick, "kind": kind, "id": id}; more fields are added by the caller. id -1: no single robot.
Event make_event(Tick tick, std::string_view kind, std::int64_t id);

// The events a robot's controller reported itself (Telemetry::events, "<kind> <detail>"), as events of the
// recorded tick `tick`: kind the first word, `detail` the rest (empty if none), `source` "controller". Only
// telemetry applied just before this tick's step (RobotTruth::telemetry_tick + 1 == tick) counts: a robot
// whose command did not come keeps its old telemetry, and its events are not news. A first word that is one
// of the kinds derived here (state, label, leader, ...) becomes "controller_<word>" so that it can never be
// counted as one of them (e.g. in leader_changes).
std::vector<Event> controller_events(Tick tick, const std::vector<RobotTruth>& robots);

class EventDeriver {
 public:
  // `states`: the behaviour's (its descriptor's), which name a state event's values ("unknown" for others).
  EventDeriver(double comm_range, std::span<const behaviour::StateSpec> states)
      : comm_range_(comm_range), states_(states) {}
  // With robot groups: each robot's own behaviour's states, by id (a robot beyond the list: `states`).
  void set_robot_states(std::vector<std::span<const behaviour::StateSpec>> by_id) {
    robot_states_ = std::move(by_id);
  }
  // Where each robot's label and leader flag are (behaviour/known_columns.hpp), by id: a robot beyond the
  // list reports neither, so its label and leader events are never derived.
  void set_known_columns(std::vector<behaviour::KnownColumns> by_id) {
    known_ = std::move(by_id);
    labelled_run_ = std::any_of(known_.begin(), known_.end(), [](const auto& k) { return k.label >= 0; });
  }

  // Compares this tick's truth with what was seen before. The first call only sets the baseline. With
  // `track_graph` the shape robots' communication graph is checked and its component count is put in
  // `components` (0 when not tracked or no shape robot).
  std::vector<Event> observe(Tick tick, const std::vector<RobotTruth>& robots, bool track_graph,
                             std::size_t& components);

  // Deaths and rejoins the front end knows of; nullopt when this one is already known (no double counting).
  std::optional<Event> death(Tick tick, RobotId id);
  std::optional<Event> rejoin(Tick tick, RobotId id);

 private:
  struct Seen {
    bool alive = true;
    Telemetry telemetry;
  };
  void observe_leader(Tick tick, const std::vector<RobotTruth>& robots, std::vector<Event>& out);
  void observe_graph(Tick tick, const std::vector<RobotTruth>& robots, std::vector<Event>& out,
                     std::size_t& components);

  std::string state_name(std::int32_t s, std::size_t id) const;

  double comm_range_;
  std::span<const behaviour::StateSpec> states_;
  std::vector<std::span<const behaviour::StateSpec>> robot_states_;  // by id; empty: states_ for all
  std::vector<behaviour::KnownColumns> known_;                       // by id
  bool labelled_run_ =
      false;  // a behaviour of the run reports labels (the graph is then its labelled robots')
  behaviour::KnownColumns known_of(std::size_t id) const {
    return id < known_.size() ? known_[id] : behaviour::KnownColumns{};
  }
  std::vector<Seen> seen_;  // by id
  bool baseline_ = false;
  struct Candidate {
    RobotId id = 0;
    Tick since = 0;  // first tick of its run as the only claimant
  };
  std::optional<RobotId> leader_;       // the robot taken as leader now
  std::optional<RobotId> last_leader_;  // the last one there was (for "previous")
  std::optional<Candidate> candidate_;  // the only claimant, not yet settled
  std::size_t components_ = 0;          // of the last tracked tick
};

}  // namespace swarmform::world
