#include "robot_agent/controller/paper_controller.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "common/splitmix64.hpp"
#include "robot_agent/controller/collision_avoidance.hpp"
#include "robot_agent/controller/drive.hpp"
#include "robot_agent/controller/label_timeout.hpp"
#include "robot_agent/controller/paper_telemetry.hpp"
#include "robot_agent/controller/reserve.hpp"
#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller {

namespace {

Vec2 position(const Pose2D& p) {
  return {p.x, p.y};
}

bool in_shape_before_ready(RobotState s) {
  return s == RobotState::Moving || s == RobotState::Reached;
}

bool in_motion_phases(RobotState s) {
  return s == RobotState::Ready || s == RobotState::Motion || s == RobotState::Arrived;
}

// Searching robots keep this far from every place (grid spacings), spares (every label held) further: they
// leave the shape's area.
constexpr double kSearcherClearance = 0.5;
constexpr double kSpareClearance = 1.2;
// A searcher that has heard no offer for this long walks towards the nearest unheld place, up to this many
// grid spacings from it.
constexpr double kApproachDistance = 1.5;
// A Moving robot this near its place may drive backwards onto it (m); further away it faces where it goes.
constexpr double kReverseRange = 0.1;
// A Moving robot that has not come kProgress (m) nearer its place in kStuckTicks commits to one go-round
// side.
constexpr double kProgress = 0.05;
constexpr Tick kStuckTicks = 50;
constexpr Tick kSideTicks = 200;
// Stuck with a side committed: a detour this far (m) in a random direction, for at most this long.
constexpr double kDetourDistance = 1.0;
constexpr Tick kDetourTicks = 150;

// The shape's places as a spare sees them: their centroid and the one nearest to `pos`.
struct PlacesAround {
  Vec2 centroid;
  Vec2 nearest_place;
  double nearest = 1e18;  // m
};
PlacesAround places_around(const std::vector<Vec2>& places, Vec2 pos) {
  PlacesAround a;
  for (const auto& pl : places) {
    a.centroid = vadd(a.centroid, vscale(pl, 1.0 / static_cast<double>(places.size())));
    const double d = vnorm(vsub(pl, pos));
    if (d < a.nearest) {
      a.nearest = d;
      a.nearest_place = pl;
    }
  }
  return a;
}

// A spare leaves the shape's area at full speed: away from its centroid (from the nearest place when on it).
Vec2 leave_the_shape(Vec2 pos, const PlacesAround& a, double max_speed) {
  Vec2 away = vsub(pos, a.centroid);
  if (vnorm(away) < 1e-6) away = vsub(pos, a.nearest_place);
  return vscale(away, max_speed / std::max(vnorm(away), 1e-9));
}

}  // namespace

PaperController::PaperController(std::unique_ptr<MotionPhases> motion) : motion_(std::move(motion)) {}

void PaperController::init(const Mission& mission, RobotId self) {
  mission_ = mission;
  self_ = self;
  params_ = params_from_mission(mission);
  table_ = ShapeTable(mission.shape, params_.grid_spacing);
  // A large shape needs a longer label timeout, so that its holders' heartbeats fit the messages
  // (label_timeout.hpp).
  params_.label_timeout = scaled_label_timeout(
      params_.label_timeout, table_.size(), formation_entries_per_message(params_.max_message_bytes),
      shape_diameter_hops(mission.shape, params_.grid_spacing, params_.comm_range));
  if (!motion_) motion_ = make_motion_phases(params_);
  const auto places = table_.places({}, params_.shape_heading);
  Vec2 centroid;
  for (const auto& pl : places)
    centroid = vadd(centroid, vscale(pl, 1.0 / static_cast<double>(places.size())));
  shape_radius_ = 0.0;
  for (const auto& pl : places) shape_radius_ = std::max(shape_radius_, vnorm(vsub(pl, centroid)));
  reset();
}

void PaperController::reset() {
  rng_.seed(splitmix64(mission_.seed ^ static_cast<std::uint64_t>(self_)));
  state_ = RobotState::Searching;
  label_ = -1;
  parent_label_ = -1;
  has_origin_ = false;
  origin_ = {};
  tick_ = 0;
  backoff_until_ = 0;
  last_offer_tick_ = 0;
  blocked_ticks_ = 0;
  ready_tick_ = 0;
  holder_since_.clear();
  holder_version_.assign(static_cast<std::size_t>(table_.size()), -1);
  holders_cursor_ = {};
  free_stale_ = true;
  free_label_ = -1;
  free_from_ = 0;
  stale_claims_.clear();
  last_heartbeat_ = 0;
  last_member_heard_ = 0;
  reached_tick_ = 0;
  neighbours_ = NeighbourTable::learning_losses(params_.neighbour_timeout, params_.comm_range,
                                                params_.max_speed, params_.tick_rate);
  stigmergy_ = Stigmergy(self_);
  election_.reset();
  barrier_at_ready_ = {};
  barrier_watch_ = {};
  reserve_ = false;
  last_shape_heard_ = 0;
  members_stale_ = true;
  ctx_ = {};
  has_places_ = false;
  events_.clear();
  last_motion_ = {};
  if (!in_motion_phases(state_) && motion_) motion_ = make_motion_phases(params_);
}

Command PaperController::step(const Perception& p) {
  events_.clear();
  tick_ = p.tick;
  if (p.goal) {  // the goal as it stands this tick: the mission's until a world event moves it
    mission_.goal = p.goal->at;
    mission_.goal_radius = p.goal->radius;
    params_.goal = p.goal->at;
    params_.goal_radius = p.goal->radius;
  }

  // Hear: neighbour table, stigmergy entries, the shape's origin.
  neighbours_.update(p, self_, stigmergy_.digest());
  bool shape_heard_moving = false;
  for (const auto& [id, n] : neighbours_.all()) {
    if (n.last_heard != tick_) continue;
    shape_heard_moving = shape_heard_moving || in_motion_phases(n.message.state);
    // Same digest, same table: its entries would change nothing here (stigmergy.hpp). 0 is "no digest".
    const std::uint64_t digest = n.message.table_digest;
    if (digest == 0 || digest != stigmergy_.digest()) stigmergy_.merge_all(neighbours_.entries_heard(n));
    if (!has_origin_ && n.message.has_origin) {
      has_origin_ = true;
      origin_ = n.message.origin;
    }
  }
  track_holders();
  disown_stale_claims();

  // A spare that learns the shape is moving becomes a reserve (reserve.hpp): from then on its label 0's
  // place follows the shape, as estimated from the shape's robots it hears.
  if (state_ == RobotState::Searching && !reserve_ && (shape_heard_moving || shape_in_motion(stigmergy_))) {
    reserve_ = true;
    event("reserve");
  }
  if (reserve_ && !in_motion_phases(state_)) {
    if (const auto origin = moving_origin(neighbours_, p.pose, table_, params_.shape_heading)) {
      origin_ = *origin;
      has_origin_ = true;
      last_shape_heard_ = tick_;
    }
  }

  // Keep the label. (A reserve frees nobody's: members in motion no longer heartbeat their entries.)
  if (in_shape_before_ready(state_)) {
    keep_label();
    if (label_ >= 0 && !reserve_) free_dead_labels();
    if (label_ >= 0 && reserve_) {
      if (const auto member = live_member_of(stigmergy_, label_, self_)) {
        // Its labels entry names the member again, or the barrier would no longer count the member.
        put_label_holder(stigmergy_, label_, *member);
        lose_label("to live member " + std::to_string(*member));
      }
    }
  }

  // In the motion phases the labels entry settles who holds a label (reserve.hpp): a reserve that joined
  // and finds another robot named gives way (two reserves reached the same place, or the member marked dead
  // by mistake is back); a member of the barrier re-asserts its entry over a reserve's claim.
  if (in_motion_phases(state_) && label_ >= 0) {
    const auto s = label_status(stigmergy_, label_);
    if (s.kind == LabelStatus::Kind::Held && s.holder != self_) {
      if (reserve_) {
        lose_label("to " + std::to_string(s.holder) + " in motion");
        barrier_at_ready_ = {};
        members_stale_ = true;
        motion_ = make_motion_phases(params_);
      } else if (barrier_at_ready_.members.count(s.holder) == 0) {
        put_label_holder(stigmergy_, label_, self_);
      }
    }
  }

  // The state's behaviour.
  Vec2 velocity;
  std::optional<WheelSpeeds> wheels;
  // Searching and Moving robots face where they go, so that their ultrasonic sensors see it; a mover
  // within kReverseRange of its place may back onto it (small corrections need no half turn).
  may_reverse_ =
      !(state_ == RobotState::Idle || state_ == RobotState::Searching || state_ == RobotState::Moving);
  std::vector<std::uint8_t> motion_bytes;
  Telemetry telemetry;
  std::int32_t parent = -1;
  bool leader = false;
  double net_force = 0.0;
  switch (state_) {
    case RobotState::Idle:
    case RobotState::Searching:
      state_ = RobotState::Searching;
      velocity = reserve_ ? reserve_step(p) : searching_step(p);
      break;
    case RobotState::Moving:
      velocity = moving_step(p);
      break;
    case RobotState::Reached:
      wheels = reached_step(p);
      break;
    case RobotState::Ready:
    case RobotState::Motion:
    case RobotState::Arrived:
      break;
  }
  if (in_motion_phases(state_)) {
    last_motion_ = motion_->step(context(p));
    state_ = in_motion_phases(last_motion_.state) ? last_motion_.state : RobotState::Ready;
    velocity = last_motion_.velocity;
    wheels = last_motion_.wheels;
    motion_bytes = last_motion_.message;
    for (auto& e : last_motion_.events) events_.push_back(e);
    leader = last_motion_.leader;
    net_force = std::isfinite(last_motion_.net_force) ? last_motion_.net_force : 0.0;
    parent = last_motion_.parent;
  } else {
    parent = parent_id();
  }

  Command cmd;
  const WheelSpeeds w =
      clamp_wheels(wheels ? *wheels : drive_velocity(velocity, p.pose.theta, params_.max_speed, may_reverse_),
                   params_.max_speed);
  cmd.left_speed = w.left;
  cmd.right_speed = w.right;
  cmd.message = encode_message(compose_message(p, motion_bytes));
  telemetry.state = static_cast<std::int32_t>(state_);
  telemetry.extra = paper_telemetry(label_, parent, leader, net_force);
  telemetry.events = std::move(events_);
  events_.clear();
  cmd.telemetry = std::move(telemetry);
  return cmd;
}

// ---- Searching (paper III.C 'Searching') ----

Vec2 PaperController::searching_step(const Perception& p) {
  const Vec2 pos = position(p.pose);
  // The seed: closest to the arena origin by the flooded minimum, once it has settled. Re-election: when the
  // seed died with nobody of the shape left to offer label 0 again (free_seed_label), the searchers elect
  // the one closest to label 0's known place, which goes there.
  const auto seed_status = label_status(stigmergy_, 0).kind;
  const bool first_election = seed_status == LabelStatus::Kind::Unclaimed && !has_origin_;
  const bool re_election = seed_status == LabelStatus::Kind::Freed && has_origin_;
  election_.update(self_, re_election ? vnorm(vsub(pos, origin_)) : vnorm(pos), neighbours_, tick_,
                   params_.seed_settle);
  if ((first_election || re_election) && election_.candidate() == self_ &&
      election_.settled(tick_, params_.seed_settle)) {
    take_label(0, -1, re_election ? origin_ : pos, "seed_elected");
    return {};
  }
  free_seed_label();

  // Take a free label from the offers heard.
  const auto offers = collect_offers(table_, params_.shape_heading, neighbours_, stigmergy_);
  if (!offers.empty()) last_offer_tick_ = tick_;
  if (!offers.empty() && tick_ >= backoff_until_) {
    std::vector<Searcher> searchers;
    searchers.reserve(neighbours_.all().size() + 1);
    searchers.push_back({self_, pos});
    for (const auto& [id, n] : neighbours_.all()) {
      if (n.last_heard == tick_ && n.message.state == RobotState::Searching) {
        searchers.push_back({id, {n.message.pose.x, n.message.pose.y}});
      }
    }
    if (auto offer = choose_offer(offers, searchers, self_)) {
      take_label(offer->label, offer->advertiser_label, offer->origin, "label_taken");
      return {};
    }
  }

  // Keep clear of the shape's places; spares leave its area; a searcher with nothing to take walks towards
  // where labels are still open.
  Vec2 v;
  if (has_origin_) {
    const auto& places = this->places();
    // Labels held (label_status Held: an entry >= 0) of the shape's, counted by the stigmergy as it changes;
    // entries beyond the shape's labels (none unless a message lied) are taken off.
    std::size_t held = stigmergy_.non_negative_in(stig::Ns::Labels);
    if (table_.size() <= static_cast<int>(stig::kMaxIndex)) {
      for (const auto& e :
           stigmergy_.in_namespace_from(stig::Ns::Labels, static_cast<std::uint32_t>(table_.size()))) {
        if (e.value >= 0) --held;
      }
    }
    const bool spare = held == static_cast<std::size_t>(table_.size());
    const double s = params_.grid_spacing;
    const PlacesAround around = places_around(places, pos);
    const double nearest = around.nearest;
    if (spare && nearest < kSpareClearance * s) {
      v = leave_the_shape(pos, around, params_.max_speed);
    } else if (nearest < kSearcherClearance * s) {
      const Vec2 away = vsub(pos, around.nearest_place);
      v = vscale(away, params_.k_move * (kSearcherClearance * s - nearest) / std::max(vnorm(away), 1e-9));
    } else if (!spare && tick_ > last_offer_tick_ + static_cast<Tick>(params_.neighbour_timeout)) {
      double best = 1e18;
      Vec2 target;
      for (int l = 0; l < table_.size(); ++l) {
        if (label_status(stigmergy_, l).kind == LabelStatus::Kind::Held) continue;
        const double d = vnorm(vsub(places[static_cast<std::size_t>(l)], pos));
        if (d < best) {
          best = d;
          target = places[static_cast<std::size_t>(l)];
        }
      }
      if (best < 1e17 && best > kApproachDistance * s) {
        v = vclamp(
            vscale(vscale(vsub(target, pos), 1.0 / best), params_.k_move * (best - kApproachDistance * s)),
            params_.max_speed);
      }
    }
  }
  fresh_neighbour_positions();
  return avoid_collisions(vclamp(v, params_.max_speed), with_echoes(p, echo_range()), params_.k_collision,
                          params_.r_o, params_.max_speed);
}

// ---- The reserve: a spare once the shape moves (reserve.hpp) ----

Vec2 PaperController::reserve_step(const Perception& p) {
  const Vec2 pos = position(p.pose);
  const double s = params_.grid_spacing;
  const auto& places = this->places();
  // The nearest vacancy, unless a searching robot heard is nearer to it (ties: the lower id).
  int vacancy = -1;
  double vacancy_distance = 1e18;
  for (int l : vacant_labels(stigmergy_, table_.size(), holder_since_, tick_, params_.label_timeout)) {
    const double d = vnorm(vsub(places[static_cast<std::size_t>(l)], pos));
    if (d < vacancy_distance) {
      vacancy = l;
      vacancy_distance = d;
    }
  }
  if (vacancy >= 0 && has_origin_ && tick_ >= backoff_until_) {
    const Vec2 place = places[static_cast<std::size_t>(vacancy)];
    const bool nearest =
        std::none_of(neighbours_.all().begin(), neighbours_.all().end(), [&](const auto& entry) {
          const auto& [id, n] = entry;
          if (n.last_heard != tick_ || n.message.state != RobotState::Searching) return false;
          const double d = vnorm(vsub(Vec2{n.message.pose.x, n.message.pose.y}, place));
          return d < vacancy_distance || (d == vacancy_distance && id < self_);
        });
    if (nearest) {
      take_label(vacancy, -1, origin_, "reserve_takes");
      return {};
    }
  }

  // Trail the shape; out of the way of its places.
  Vec2 centre = mission_.goal;
  const PlacesAround around = places_around(places, pos);
  // Where the shape is now, as far as it is heard; a reserve that hears none of it makes for the goal.
  const bool shape_heard =
      has_origin_ && tick_ <= last_shape_heard_ + static_cast<Tick>(params_.neighbour_timeout);
  if (shape_heard) centre = around.centroid;
  Vec2 v;
  if (shape_heard && around.nearest < kSpareClearance * s) {
    v = leave_the_shape(pos, around, params_.max_speed);
  } else {
    // Unheard, it walks to the goal itself: where the shape is, or will be, within radio range.
    const Vec2 to =
        vsub(shape_heard ? trailing_point(centre, shape_radius_, mission_.goal, pos, s) : mission_.goal, pos);
    if (vnorm(to) > 0.5 * s) v = vclamp(vscale(to, params_.k_move), params_.max_speed);
  }
  fresh_neighbour_positions();
  return avoid_collisions(vclamp(v, params_.max_speed), with_echoes(p, echo_range()), params_.k_collision,
                          params_.r_o, params_.max_speed);
}

void PaperController::take_label(int label, int parent_label, Vec2 origin, const std::string& why) {
  label_ = label;
  parent_label_ = parent_label;
  origin_ = origin;
  has_origin_ = true;
  put_label_holder(stigmergy_, label, self_);
  last_heartbeat_ = tick_;
  state_ = RobotState::Moving;
  blocked_ticks_ = 0;
  best_distance_ = 1e18;
  progress_tick_ = tick_;
  go_round_side_ = 0;
  detour_.reset();
  event(why + " " + std::to_string(label) +
        (parent_label >= 0 ? " parent_label " + std::to_string(parent_label) : std::string()));
}

void PaperController::lose_label(const std::string& why) {
  event("label_lost " + std::to_string(label_) + " " + why);
  barrier_withdraw(stigmergy_, self_);
  label_ = -1;
  parent_label_ = -1;
  state_ = RobotState::Searching;
  // A short random back-off, so two losers do not collide again on the next offer.
  backoff_until_ = tick_ + 1 + std::uniform_int_distribution<Tick>(0, 10)(rng_);
}

// ---- Keeping the label: conflicts (paper III.C 'Moving') and dead holders ----

void PaperController::keep_label() {
  if (label_ < 0) return;
  const auto s = label_status(stigmergy_, label_);
  if (s.kind == LabelStatus::Kind::Held && s.holder != self_) {
    if (!keeps_label(self_, s.holder)) {
      lose_label("to " + std::to_string(s.holder));
      return;
    }
    put_label_holder(stigmergy_, label_, self_);  // the higher id re-asserts
  } else if (s.kind != LabelStatus::Kind::Held) {
    put_label_holder(stigmergy_, label_, self_);  // freed while alive (a false alarm): still here
    last_heartbeat_ = tick_;
  } else if (tick_ >= last_heartbeat_ + static_cast<Tick>(heartbeat_period())) {
    // The heartbeat: a fresh version of our entry floods the swarm, so robots out of radio range know we
    // are alive (allotment.hpp, dead holders).
    put_label_holder(stigmergy_, label_, self_);
    last_heartbeat_ = tick_;
  }
  for (const auto& [id, n] : neighbours_.all()) {
    if (n.last_heard == tick_ && n.message.label == label_ && in_shape_before_ready(n.message.state) &&
        !keeps_label(self_, id)) {
      lose_label("to " + std::to_string(id));
      return;
    }
  }
}

void PaperController::track_holders() {
  const auto track = [this](int l) {
    const auto* e = stigmergy_.entry(stig::key(stig::Ns::Labels, static_cast<std::uint32_t>(l)));
    if (!e) return;
    std::int64_t& seen = holder_version_[static_cast<std::size_t>(l)];
    if (seen != static_cast<std::int64_t>(e->version)) {
      seen = e->version;
      holder_since_.set(l, tick_);
      if (l != label_) {
        const auto s = label_status(stigmergy_, l);
        if (s.kind == LabelStatus::Kind::Held && s.holder == self_) stale_claims_.push_back(l);
      }
    }
  };
  // Only the label entries changed since the last call (the others' versions are the ones seen then): a
  // 1024-label shape made this a thousand lookups per robot per tick. The whole table when the change log
  // overflowed.
  std::span<const std::uint32_t> changed;
  if (!stigmergy_.changes_since(holders_cursor_, changed)) {
    for (int l = 0; l < table_.size(); ++l) track(l);
    free_stale_ = true;
    return;
  }
  const auto labels = static_cast<std::uint32_t>(stig::Ns::Labels);
  for (const std::uint32_t key : changed) {
    if (stig::ns_of(key) == labels && stig::index_of(key) < static_cast<std::uint32_t>(table_.size())) {
      const int l = static_cast<int>(stig::index_of(key));
      track(l);
      // Any change to an entry we watch (a holder, a freed mark, a conflict settled at the same version)
      // may change what free_dead_labels can free, and what it watches.
      if (!free_stale_ && std::find(free_watched_.begin(), free_watched_.end(), l) != free_watched_.end())
        free_stale_ = true;
    }
  }
}

// Only this robot knows which label it holds. An entry naming it as the holder of another label was written
// by an earlier run of its id (killed and restarted with a fresh controller, or a stalled agent taken for
// dead and started afresh) and heard back from the swarm: its neighbours hear the id alive, so they would
// never free that label (free_dead_labels), and the barrier would wait for a holder that is not coming. The
// robot frees it itself, and withdraws a barrier entry its earlier run left: the label is offered again (this
// robot may take it).
void PaperController::disown_stale_claims() {
  for (const int l : stale_claims_) {
    const auto s = label_status(stigmergy_, l);
    if (l == label_ || s.kind != LabelStatus::Kind::Held || s.holder != self_) continue;
    put_label_freed(stigmergy_, l, tick_);
    event("label_freed " + std::to_string(l) + " not mine (an earlier run of this id held it)");
  }
  stale_claims_.clear();
  if (label_ < 0) barrier_withdraw(stigmergy_, self_);
}

void PaperController::free_dead_labels() {
  // Before the earliest tick the rule could free anything its lookups (each a cache miss in a 1024-label
  // shape) are skipped; that tick is recomputed when an entry of the grid changed (track_holders) or the
  // label did.
  if (free_stale_ || free_label_ != label_) {
    free_stale_ = false;
    free_label_ = label_;
    free_from_ = earliest_label_free(table_, label_, stigmergy_, holder_since_, self_, params_.label_timeout);
    free_watched_ = watched_labels(table_, label_, stigmergy_);
  }
  const std::vector<int> dead = tick_ >= free_from_
                                    ? labels_to_free(table_, label_, stigmergy_, neighbours_, holder_since_,
                                                     self_, tick_, params_.label_timeout)
                                    : std::vector<int>{};
  for (int l : dead) {
    const auto holder = label_status(stigmergy_, l).holder;
    put_label_freed(stigmergy_, l, tick_);
    barrier_withdraw(stigmergy_, holder);
    event("label_freed " + std::to_string(l) + " holder " + std::to_string(holder));
  }
  // A label of our grid that nobody has taken while we stood at our place for label_timeout ticks: no
  // searcher is coming for it (one that hears an offer takes it within a few ticks). Marked freed, it is
  // still offered, and abandoned label_timeout ticks later if nobody takes it (barrier.hpp).
  if (state_ != RobotState::Reached) return;
  for (int l : labels_left_untaken(table_, label_, stigmergy_, neighbours_, reached_tick_, tick_,
                                   params_.label_timeout)) {
    put_label_freed(stigmergy_, l, tick_);
    event("label_freed " + std::to_string(l) + " untaken");
  }
}

void PaperController::free_seed_label() {
  // Label 0's holder died before any robot of the shape could notice (the seed alone in the shape): no
  // robot hears any member of the shape, and label 0's entry has been neither refreshed nor its holder
  // heard for label_timeout ticks. Freeing it starts the re-election above.
  for (const auto& [id, n] : neighbours_.all()) {
    if (n.message.label >= 0) last_member_heard_ = std::max(last_member_heard_, n.last_heard);
  }
  const auto status = label_status(stigmergy_, 0);
  if (status.kind != LabelStatus::Kind::Held || !has_origin_) return;
  const auto timeout = static_cast<Tick>(params_.label_timeout);
  if (tick_ < last_member_heard_ + timeout) return;
  Tick quiet_since = holder_since_.find(0).value_or(0);
  if (const auto heard = neighbours_.last_heard(status.holder)) quiet_since = std::max(quiet_since, *heard);
  if (tick_ < quiet_since + timeout) return;
  put_label_freed(stigmergy_, 0, tick_);
  barrier_withdraw(stigmergy_, status.holder);
  event("label_freed 0 holder " + std::to_string(status.holder));
}

// ---- Moving (paper III.C 'Moving', eq. 1) ----

Vec2 PaperController::moving_step(const Perception& p) {
  const Vec2 pos = position(p.pose);
  const Vec2 target = table_.place(label_, origin_, params_.shape_heading);
  const Vec2 error = vsub(target, pos);
  const double distance = vnorm(error);
  if (distance < params_.reach_tolerance) {
    state_ = RobotState::Reached;
    reached_tick_ = tick_;
    event("reached " + std::to_string(label_));
    return {};
  }

  // A place held by something that is not a robot we hear (a dead robot's body, a silent robot): stop short
  // of it, and after a while take the spot as reached. Collision avoidance keeps an unexplained echo at the
  // edge of its go-round zone at the nearest (collision_avoidance.hpp), so "in front of the place" is: an
  // echo that no heard neighbour explains (Algorithm 2's mask), within that zone, nearer than the place and
  // in its direction, with the place itself within that reach.
  const auto& neighbours = fresh_neighbour_positions();
  const double blocked_echo = params_.r_o + kAwarenessMargin - 2.0 * kRobotRadius + 0.02;
  const double place_azimuth = std::atan2(error.y, error.x);
  bool blocked = false;
  if (distance < blocked_echo + 3.0 * kRobotRadius) {
    for (const auto& e : unexplained_echoes(p.ultrasonic, p.pose.theta, neighbours, blocked_echo)) {
      const double echo = e.range - 2.0 * kRobotRadius;
      if (echo + kRobotRadius < distance && std::abs(wrap_angle(e.azimuth - place_azimuth)) < 0.4)
        blocked = true;
    }
  }
  if (blocked) {
    if (++blocked_ticks_ >= kBlockedPlaceTicks) {
      state_ = RobotState::Reached;
      reached_tick_ = tick_;
      event("reached " + std::to_string(label_) + " blocked_place");
    }
    return {};
  }
  blocked_ticks_ = 0;
  may_reverse_ = distance < kReverseRange;
  // No progress for kStuckTicks (a pocket between obstacles whose go-round sides alternate): go round the
  // echoes on one side; the other side if that side has brought no progress in kSideTicks (going round a
  // body first takes the robot further from its place).
  if (distance < best_distance_ - kProgress) {
    best_distance_ = distance;
    progress_tick_ = tick_;
  } else if (tick_ >= progress_tick_ + (go_round_side_ == 0 ? kStuckTicks : kSideTicks)) {
    // Stuck again with a side committed: a pocket whose way out is a detour (three obstacles round it). A
    // random back-off in space, deterministic per seed: kDetourDistance in a random direction, for at most
    // kDetourTicks, then the place again.
    if (go_round_side_ != 0) {
      const double a = std::uniform_real_distribution<double>(-std::numbers::pi, std::numbers::pi)(rng_);
      detour_ = vadd(position(p.pose), vpolar(kDetourDistance, a));
      detour_until_ = tick_ + kDetourTicks;
      event("detour " + std::to_string(label_));
    }
    go_round_side_ = go_round_side_ < 0 ? 1 : -1;
    best_distance_ = distance;
    progress_tick_ = tick_;
  }
  Vec2 heading_for = error;
  if (detour_) {
    const Vec2 to_detour = vsub(*detour_, position(p.pose));
    if (tick_ >= detour_until_ || vnorm(to_detour) < 0.15) {
      detour_.reset();
      best_distance_ = distance;
      progress_tick_ = tick_;
    } else {
      heading_for = to_detour;
    }
  }
  const Vec2 v = vclamp(vscale(heading_for, params_.k_move), params_.max_speed);
  // Echoes from nearer than the place (the echo point, a body radius beyond the reading): a body, a wall or
  // an obstacle on the way, not one standing just beyond the place.
  return avoid_collisions(v, with_echoes(p, std::min(echo_range(), distance - kRobotRadius)),
                          params_.k_collision, params_.r_o, params_.max_speed, go_round_side_);
}

double PaperController::echo_range() const {
  return params_.r_o + kAwarenessMargin + kBlendWidth - 2.0 * kRobotRadius;
}

const std::vector<NeighbourPosition>& PaperController::with_echoes(const Perception& p, double max_echo) {
  const auto echoes = unexplained_echoes(p.ultrasonic, p.pose.theta, positions_, max_echo);
  positions_.insert(positions_.end(), echoes.begin(), echoes.end());
  return positions_;
}

// ---- Reached and the barrier (paper III.C 'Reached', Algorithm 1) ----

std::optional<WheelSpeeds> PaperController::reached_step(const Perception& p) {
  const Vec2 pos = position(p.pose);
  const Vec2 error = vsub(table_.place(label_, origin_, params_.shape_heading), pos);
  WheelSpeeds wheels;
  const double heading_error = wrap_angle(params_.shape_heading - p.pose.theta);
  if (blocked_ticks_ < kBlockedPlaceTicks && vnorm(error) > 2.0 * params_.reach_tolerance) {
    // Pushed off its place: back to it without leaving the state.
    wheels = drive_velocity(vclamp(vscale(error, params_.k_move), params_.max_speed), p.pose.theta,
                            params_.max_speed);
  } else if (std::abs(heading_error) > params_.heading_tolerance) {
    wheels = turn_towards(params_.shape_heading, p.pose.theta, params_.max_speed);
  } else if (!barrier_contains(stigmergy_, self_) ||
             stigmergy_.get(stig::key(stig::Ns::Barrier, self_)) != label_) {
    barrier_enter(stigmergy_, self_, label_);
  }
  if (barrier_contains(stigmergy_, self_) && stigmergy_.get(stig::key(stig::Ns::Barrier, self_)) == label_) {
    // The full view only once it has passed with us in it (the watch says so without reading every label).
    if (barrier_watch_.passed_with(stigmergy_, self_, table_.size(), tick_, params_.label_timeout)) {
      const auto view = read_barrier(stigmergy_, table_.size(), tick_, params_.label_timeout);
      barrier_at_ready_ = view;
      members_stale_ = true;
      enter_ready();
      return WheelSpeeds{};
    }
  }
  return wheels;
}

void PaperController::enter_ready() {
  state_ = RobotState::Ready;
  ready_tick_ = tick_;
  for (int l : barrier_at_ready_.abandoned) event("label_abandoned " + std::to_string(l));
  event("barrier_passed " + std::to_string(barrier_at_ready_.count) + "/" + std::to_string(table_.size()));
}

const std::vector<Vec2>& PaperController::places() {
  if (!has_places_ || places_origin_.x != origin_.x || places_origin_.y != origin_.y) {
    places_ = table_.places(origin_, params_.shape_heading);
    places_origin_ = origin_;
    has_places_ = true;
    ++places_version_;
  }
  return places_;
}

const FormationContext& PaperController::context(const Perception& p) {
  FormationContext& ctx = ctx_;
  ctx.self = self_;
  ctx.tick = tick_;
  ctx.perception = &p;
  ctx.pose = p.pose;
  ctx.params = &params_;
  ctx.table = &table_;
  ctx.label = label_;
  ctx.origin = origin_;
  places();
  if (ctx.places_version != places_version_) {
    ctx.places = places_;
    ctx.places_version = places_version_;
  }
  ctx.common_heading = params_.shape_heading;
  ctx.neighbours = &neighbours_;
  ctx.stigmergy = const_cast<Stigmergy*>(&stigmergy_);
  if (members_inputs_.changed(stigmergy_) || members_stale_) {
    // The members are the barrier at Ready (changed only with members_stale_) plus a few extras: rebuilt only
    // when one of the two changed (a 1024-label shape's labels entries change every tick somewhere).
    auto extras = motion_member_extras(stigmergy_, barrier_at_ready_.members);
    if (members_stale_ || ctx.members_version == 0 || extras != member_extras_) {
      auto members = motion_members(barrier_at_ready_.members, extras);
      if (ctx.members_version == 0 || members != ctx.members) {
        ctx.members = std::move(members);
        ++ctx.members_version;
      }
      member_extras_ = std::move(extras);
    }
    members_stale_ = false;
  }
  if (ctx.abandoned_labels != barrier_at_ready_.abandoned) ctx.abandoned_labels = barrier_at_ready_.abandoned;
  ctx.ready_tick = ready_tick_;
  return ctx;
}

// ---- Helpers ----

const std::vector<NeighbourPosition>& PaperController::fresh_neighbour_positions() {
  positions_.clear();  // a member, reused: no allocation per step once it has grown (~73 in a crowd)
  for (const auto& [id, n] : neighbours_.all()) {
    if (n.last_heard == tick_) positions_.push_back({n.range, n.azimuth, right_of_way(id, n.message.state)});
  }
  return positions_;
}

RightOfWay PaperController::right_of_way(RobotId other, RobotState other_state) const {
  // The yield rule (collision_avoidance.hpp): a mover before a searcher; between movers the higher id. A
  // searcher (a spare) also gives way to the shape on its way to the goal (Motion): spares standing in the
  // shape's path held its leader for good (spares.yaml, seed 18).
  const bool they_move = other_state == RobotState::Moving;
  if (state_ == RobotState::Moving) {
    if (they_move) return other > self_ ? RightOfWay::Theirs : RightOfWay::Ours;
    if (other_state == RobotState::Searching) return RightOfWay::Ours;
  } else if (state_ == RobotState::Searching && (they_move || other_state == RobotState::Motion)) {
    return RightOfWay::Theirs;
  }
  return RightOfWay::Mutual;
}

std::int32_t PaperController::parent_id() const {
  if (parent_label_ < 0) return -1;
  const auto s = label_status(stigmergy_, parent_label_);
  return s.kind == LabelStatus::Kind::Held ? static_cast<std::int32_t>(s.holder) : -1;
}

RobotMessage PaperController::compose_message(const Perception& p, const std::vector<std::uint8_t>& motion) {
  RobotMessage m;
  m.sender = self_;
  m.state = state_;
  m.label = label_;
  m.pose = p.pose;
  m.has_origin = has_origin_;
  m.origin = origin_;
  m.seed_candidate = state_ == RobotState::Searching ? election_.candidate() : self_;
  m.seed_distance = state_ == RobotState::Searching ? election_.distance() : vnorm(position(p.pose));
  m.seed_age = state_ == RobotState::Searching ? election_.age() : 0;
  if (in_shape_before_ready(state_) && !reserve_)
    m.free_labels = free_grid_labels(table_, label_, stigmergy_, neighbours_);
  if (m.free_labels.size() > kMaxFreeLabels) m.free_labels.resize(kMaxFreeLabels);
  m.motion = motion;
  // What is left of the world's message limit goes to the stigmergy.
  const std::size_t fixed = kMessageFixedBytes + 2 * m.free_labels.size() + m.motion.size();
  const std::size_t budget = params_.max_message_bytes > fixed ? params_.max_message_bytes - fixed : 0;
  if (!neighbours_hold_our_table())
    m.entries = stigmergy_.outgoing(std::min(kMaxEntriesPerMessage, budget / 20));
  m.table_digest = stigmergy_.digest();
  return m;
}

bool PaperController::neighbours_hold_our_table() const {
  // Each neighbour that sent our digest holds every entry we hold (stigmergy.hpp), so entries sent now would
  // be skipped by all of them: the message goes without them (in the P3 field of BENCHMARKS.md, a message
  // of 371 bytes on average before, 122 after). Flooding on change is kept: a change here changes our digest,
  // so the next message carries it. A robot that hears us before we hear it is heard, with its own digest,
  // a tick later. A robot with no neighbour sends no entries.
  const std::uint64_t own = stigmergy_.digest();
  return std::all_of(neighbours_.all().begin(), neighbours_.all().end(),
                     [own](const auto& entry) { return entry.second.message.table_digest == own; });
}

}  // namespace swarmform::controller
