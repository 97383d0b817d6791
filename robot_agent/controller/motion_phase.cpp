#include "robot_agent/controller/motion_phase.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "common/splitmix64.hpp"
#include "robot_agent/controller/boundary.hpp"
#include "robot_agent/controller/collision_avoidance.hpp"
#include "robot_agent/controller/formation_forces.hpp"
#include "robot_agent/controller/goal_force.hpp"
#include "robot_agent/controller/leader_election.hpp"
#include "robot_agent/controller/motion_math.hpp"
#include "robot_agent/controller/motion_section.hpp"
#include "robot_agent/controller/obstacle_forces.hpp"
#include "robot_agent/controller/parent_tree.hpp"

namespace swarmform::controller::motion {

namespace {

constexpr double kKeepUpStrain = 1.5;    // x the speed limit: the lag of a follower that keeps up
constexpr double kProgressShare = 0.25;  // of the way asked for
constexpr double kMinAsked = 0.05;       // m asked for over the window
constexpr Tick kPinnedTicks = 20;
constexpr Tick kTraceTicks = 60;
constexpr Tick kEchoMemoryTicks = 15;  // eq. (6)'s memory of echoes (obstacle_forces.hpp: EchoMemory)
constexpr double kRestingShare = 0.1;  // of the cruise: the smallest eq. (7) |F_goal|
constexpr double kResumeFactor = 2.0;  // x arrival_tolerance off its target: an arrived leader moves again
constexpr double kSlowest = 0.3;  // x the cruise: the leader never stops, so the gaps a held robot needs open
constexpr double kParentSide =
    0.2;  // the parent stands on one side when its direction is this far off the normal
// x the radio range: a member this near that is not heard is dead, not out of range (both death rules).
constexpr double kWellInsideRange = 0.8;

std::uint32_t boundary_key(RobotId id) {
  return stig::key(stig::Ns::Boundary, id);
}
std::uint32_t parents_key(RobotId id) {
  return stig::key(stig::Ns::Parents, id);
}
std::uint32_t leader_key() {
  return stig::key(stig::Ns::Leader, 0);
}

bool marked_dead(const Stigmergy& s, RobotId id) {
  return s.get(parents_key(id)) == kDeadMark;
}

// eq. (2)/(4): k_o r^2 (cos a, sin a) for the vector r (cos a, sin a).
Vec2 spring(double k_o, Vec2 to_parent) {
  return attractive_force(k_o, {vnorm(to_parent), std::atan2(to_parent.y, to_parent.x)});
}

std::optional<MotionSection> section_of(const Neighbour& n) {
  return decode_motion_section(n.message.motion);
}

// Which way round an obstacle in direction `o` (unit, arena frame) leads away from the neighbours: +1 turning
// left of `o`, -1 right, 0 when both sides are alike. Each neighbour within `reach` weighs by how much it
// stands on that side, nearer ones more.
int side_away_from_neighbours(const NeighbourTable& table, Vec2 o, double reach) {
  double left = 0.0, right = 0.0;
  const Vec2 t_left = vrotate(o, std::numbers::pi / 2);
  for (const auto& [id, n] : table.all()) {
    if (!table.fresh(n) || n.range > reach) continue;
    const double side = vdot(vpolar(1.0, n.azimuth), t_left) / std::max(n.range, 0.3);
    (side > 0 ? left : right) += std::abs(side);
  }
  constexpr double kAlike = 0.05;
  if (left + kAlike < right) return 1;
  if (right + kAlike < left) return -1;
  return 0;
}

// Motion always drives forwards, turning towards the desired velocity first: the ultrasonic sensors cover
// only the front half, so a robot must face where it goes (drive.hpp's reversing would make it blind).
WheelSpeeds forward_wheels(Vec2 v, double theta, double max_speed) {
  constexpr double kTurnGain = 2.0;  // 1/s
  const double speed = vnorm(v);
  if (speed < 1e-3) return {};
  const double error = wrap_angle(std::atan2(v.y, v.x) - theta);
  const double forward = speed * std::max(0.0, std::cos(error));
  const double omega = kTurnGain * error;
  return clamp_wheels({forward - omega * kWheelSpacing / 2, forward + omega * kWheelSpacing / 2}, max_speed);
}

}  // namespace

PaperMotion::PaperMotion(const FormationParams& params) : p_(motion_params(params)), seed_(params.seed) {}

void PaperMotion::on_ready(const FormationContext& ctx) {
  state_ = RobotState::Ready;
  ready_tick_ = ctx.ready_tick;
  started_ = true;
  boundary_written_ = false;
  leader_.reset();
  parent_.reset();
  references_.clear();
  ready_sums_.clear();
  parent_rest_ = {};
  resting_parent_.reset();
  last_position_.clear();
  last_velocity_.clear();
  large_until_ = 0;
  marked_dead_.clear();
  // Only at the shape's own barrier: a robot that joins a shape already on its way (a reserve, a robot back
  // from a restart) enters Ready where the members are not standing at their places, and no leader entry
  // exists before the shape's first one is written.
  unheard_members_checked_ = ctx.stigmergy->get(leader_key()).has_value();
  wall_.reset();
  echoes_.clear();
  slide_side_ = 0;
  net_force_ = 0.0;
  boundary_.reset();
  bug_side_ = 0;
  bug_turns_ = 0;
  approach_.reset();
  rng_.seed(splitmix64(splitmix64(seed_) ^ static_cast<std::uint64_t>(ctx.self)));
  trace_.clear();
  anchor_ = {ctx.pose.x, ctx.pose.y};
  anchor_tick_ = ctx.tick;
  asked_ = 0.0;
  has_live_centroid_ = false;
  choice_ = {};
}

MotionStep PaperMotion::step(const FormationContext& ctx) {
  // The hook promises on_ready before the first step; a caller that skips it (or enters Ready again, a new
  // ready_tick) still gets a clean Ready phase.
  if (!started_ || ctx.ready_tick != ready_tick_) on_ready(ctx);
  MotionStep out;
  for (const auto& [id, n] : ctx.neighbours->all()) {
    if (ctx.neighbours->fresh(n)) {
      last_position_[id] = vadd({ctx.pose.x, ctx.pose.y}, vpolar(n.range, n.azimuth));
      if (state_ == RobotState::Ready && ctx.members.count(id) != 0) {
        // eq. (2)'s r0: the mean of the readings while the neighbour stands (Reached or Ready); one that has
        // set off already counts where it is now, as the paper's record at the end of Ready has it.
        Sum& sum = ready_sums_[id];
        if (n.message.state != RobotState::Ready && n.message.state != RobotState::Reached) sum = {};
        sum.total = vadd(sum.total, vpolar(n.range, n.azimuth));
        ++sum.count;
      }
      const auto section = section_of(n);
      last_velocity_[id] = section ? section->velocity : Vec2{};
    }
  }
  children_strain_ = 0.0;
  for (const auto& [id, n] : ctx.neighbours->all()) {
    if (!ctx.neighbours->fresh(n)) continue;
    const auto section = section_of(n);
    if (section && section->parent == static_cast<std::int32_t>(ctx.self)) {
      children_strain_ = std::max(children_strain_, section->strain);
    }
  }
  judge_boundary(ctx);
  watch_for_the_dead(ctx);
  choose_leader_and_parent(ctx, out);

  Vec2 velocity;
  net_force_ = 0.0;
  lag_ = 0.0;
  if (state_ == RobotState::Ready) {
    if (ctx.tick >= ready_tick_ + static_cast<Tick>(p_.ready_timeout)) {
      record_references(ctx);
      state_ = RobotState::Motion;
      out.events.push_back("motion_started");
    }
  }
  if (state_ == RobotState::Arrived && should_resume(ctx)) {
    // Something changed after arrival (a death re-parented it, its parent moves again, or the live shape's
    // centroid moved the leader's target): back to Motion until it has arrived again.
    state_ = RobotState::Motion;
    out.events.push_back("motion_resumed");
  }
  if (state_ == RobotState::Motion) velocity = motion_velocity(ctx, out);

  // Collision avoidance, eq. (1), in every phase (also when the formation forces are zero).
  std::vector<NeighbourPosition> near;
  for (const auto& [id, n] : ctx.neighbours->all()) {
    if (ctx.neighbours->fresh(n)) near.push_back({n.range, n.azimuth});
  }
  velocity = avoid_collisions(velocity, near, p_.k_collision, p_.r_o, p_.max_speed);

  out.state = state_;
  out.velocity = vclamp(velocity, p_.max_speed);
  out.wheels = forward_wheels(out.velocity, ctx.pose.theta, p_.max_speed);
  out.parent = parent_ ? static_cast<std::int32_t>(*parent_) : -1;
  out.leader = leader_ == ctx.self;
  out.net_force = net_force_;
  MotionSection section;
  section.leader = out.leader;
  section.arrived = state_ == RobotState::Arrived;
  section.wall_following = wall_.active();
  section.parent = out.parent;
  section.net_force = net_force_;
  section.velocity = out.velocity;
  // A robot held by an obstacle (one seen within fusion_range lately, or going round one) asks the leader to
  // wait only once it has fallen about a grid spacing behind (a lag of ~2 k_o spacing^2, eq. 5 along the
  // link): slowing the shape does not free it (the paper's corner robot trails its neighbour along the box,
  // whatever the leader's pace), but the leader must not leave it behind either.
  const bool held =
      wall_.active() || boundary_.active() ||
      trace_.nearest({ctx.pose.x, ctx.pose.y}, ctx.tick, p_.fusion_range + kRobotRadius, kTraceTicks);
  const double held_allowance = 2.0 * p_.k_o * p_.spacing * p_.spacing;
  section.strain = std::max(held && lag_ < held_allowance ? 0.0 : lag_, children_strain_);
  out.message = encode_motion_section(section);
  return out;
}

// Boundary role (boundary.hpp) from the shape neighbours heard, once the neighbour table has filled.
void PaperMotion::judge_boundary(const FormationContext& ctx) {
  Stigmergy& st = *ctx.stigmergy;
  if (!boundary_written_ && ctx.tick >= ready_tick_ + static_cast<Tick>(p_.boundary_delay)) {
    std::vector<NeighbourAzimuth> around;
    for (const auto& [id, n] : ctx.neighbours->all()) {
      if (ctx.members.count(id) != 0) around.push_back({id, n.range, n.azimuth});
    }
    const BoundaryRole role =
        classify_boundary(around, ctx.common_heading, 1.5 * p_.spacing, p_.boundary_cone);
    st.put(boundary_key(ctx.self), encode_boundary_entry(ctx.label, role));
    boundary_written_ = true;
  }
}

// A member we heard since Ready, last heard well inside radio range, silent for neighbour_timeout: dead.
// A live robot marked dead by a mistaken neighbour rewrites its own entry (a newer version wins).
void PaperMotion::watch_for_the_dead(const FormationContext& ctx) {
  Stigmergy& st = *ctx.stigmergy;
  // The members with a last position (heard since Ready), in id order: the robots heard, not every member
  // of a shape of a thousand labels.
  for (const auto& [id, last] : last_position_) {
    if (id == ctx.self || ctx.members.count(id) == 0) continue;
    const auto heard = ctx.neighbours->last_heard(id);
    if (!heard || *heard < ready_tick_ || ctx.tick < *heard + static_cast<Tick>(p_.neighbour_timeout))
      continue;
    const auto pos = last_position_.find(id);
    const double last_range = vnorm(vsub(pos->second, {ctx.pose.x, ctx.pose.y}));
    if (last_range > kWellInsideRange * p_.comm_range) continue;  // it may simply have drifted out of range
    auto marked = marked_dead_.find(id);
    if (marked != marked_dead_.end() && marked->second == *heard) continue;  // once per silence
    marked_dead_[id] = *heard;
    if (!marked_dead(st, id)) st.put(parents_key(id), kDeadMark);
  }
  mark_members_unheard_since_ready(ctx);
  if (marked_dead(st, ctx.self))
    st.put(parents_key(ctx.self), parent_ ? static_cast<std::int64_t>(*parent_) : -1);
}

// The members never heard since Ready whose places lie well inside radio range of ours, judged once,
// neighbour_timeout ticks after the shape's own Ready (on_ready: not a late joiner's). The barrier passed
// with every member at its place, so a live one that near would have been heard by now: it is dead. It died
// at its place shortly before the barrier passed (its label not yet freed: the barrier counted its entry) and
// the rule above never applies to it (it was not heard since Ready); unmarked, its label would stay held for
// the whole run and no reserve would take it. The distance is the shape's own geometry (places), not where
// anyone stands now. A member heard since Ready is the rule above's; a live robot marked by mistake (all its
// messages lost) rewrites its own entry.
void PaperMotion::mark_members_unheard_since_ready(const FormationContext& ctx) {
  if (unheard_members_checked_ || ctx.tick < ready_tick_ + static_cast<Tick>(p_.neighbour_timeout)) return;
  unheard_members_checked_ = true;
  if (ctx.label < 0 || static_cast<std::size_t>(ctx.label) >= ctx.places.size()) return;
  Stigmergy& st = *ctx.stigmergy;
  const Vec2 mine = ctx.places[static_cast<std::size_t>(ctx.label)];
  for (const auto& [id, label] : ctx.members) {
    if (id == ctx.self || label < 0 || static_cast<std::size_t>(label) >= ctx.places.size()) continue;
    const auto heard = ctx.neighbours->last_heard(id);
    if (heard && *heard >= ready_tick_) continue;
    if (vnorm(vsub(ctx.places[static_cast<std::size_t>(label)], mine)) > kWellInsideRange * p_.comm_range)
      continue;
    if (!marked_dead(st, id)) st.put(parents_key(id), kDeadMark);
  }
}

void PaperMotion::choose_leader_and_parent(const FormationContext& ctx, MotionStep& out) {
  Stigmergy& st = *ctx.stigmergy;
  const bool stigmergy_changed = choice_inputs_.changed(st);  // read every tick: it follows the change log
  const bool same_inputs =
      choice_.valid && ctx.members_version != 0 && ctx.places_version != 0 && !stigmergy_changed &&
      choice_.members_version == ctx.members_version && choice_.places_version == ctx.places_version &&
      choice_.heading == ctx.common_heading && choice_.label == ctx.label && choice_.self == ctx.self;
  if (!same_inputs) read_leader_and_parent(ctx);
  const std::optional<RobotId> leader = choice_.leader;
  if (leader != leader_) {
    leader_ = leader;
    if (leader_ == ctx.self) {
      out.events.push_back("leader_elected " + std::to_string(ctx.self));
      st.put(leader_key(), ctx.self);
    }
  }
  if (!leader_) return;

  std::optional<RobotId> parent = choice_.parent;
  if (parent && parent != parent_) {
    // The shared parents table guards against a cycle while views of the stigmergy still differ.
    std::map<RobotId, RobotId> table;
    for (const auto& [index, e] : st.in_namespace(stig::Ns::Parents)) {
      if (e.value >= 0 && index != ctx.self) table[index] = static_cast<RobotId>(e.value);
    }
    if (would_close_cycle(table, ctx.self, *parent)) parent = parent_;
  }
  if (parent != parent_) {
    parent_ = parent;
    out.events.push_back("parent " + (parent_ ? std::to_string(*parent_) : std::string("none")));
    if (parent_) parent_reference_ = reference_to(ctx, *parent_);
  }
  const std::int64_t entry = parent_ ? static_cast<std::int64_t>(*parent_) : -1;
  if (st.get(parents_key(ctx.self)) != entry) st.put(parents_key(ctx.self), entry);
}

// What choose_leader_and_parent derives from every member: the leader elected, the tree's parent for our
// label, the live centroid. Reads only (the stigmergy, the members, the places).
void PaperMotion::read_leader_and_parent(const FormationContext& ctx) {
  const Stigmergy& st = *ctx.stigmergy;
  choice_.valid = true;
  choice_.members_version = ctx.members_version;
  choice_.places_version = ctx.places_version;
  choice_.heading = ctx.common_heading;
  choice_.label = ctx.label;
  choice_.self = ctx.self;
  // Candidates: the barrier's members, with the roles they shared, minus the dead. Members of this object,
  // reused: a 1024-label shape re-reads them often while its members learn of each other.
  std::vector<LeaderCandidate>& candidates = candidates_;
  std::vector<bool>& present = present_;
  std::vector<std::optional<RobotId>>& holder = holder_;  // label -> the first live id named (in id order)
  candidates.clear();
  present.assign(ctx.places.size(), false);
  holder.assign(ctx.places.size(), std::nullopt);
  for (const auto& [id, label] : ctx.members) {
    LeaderCandidate c;
    c.id = id;
    c.label = label;
    if (auto b = st.get(boundary_key(id))) c.role = decode_boundary_entry(*b).role;
    c.alive = !marked_dead(st, id);
    candidates.push_back(c);
    if (c.alive && label >= 0 && static_cast<std::size_t>(label) < present.size()) {
      present[static_cast<std::size_t>(label)] = true;
      if (!holder[static_cast<std::size_t>(label)]) holder[static_cast<std::size_t>(label)] = id;
    }
  }
  // The centroid of the places live members hold: where the goal puts the shape that is left.
  Vec2 sum;
  int held = 0;
  for (std::size_t label = 0; label < present.size(); ++label) {
    if (!present[label]) continue;
    sum = vadd(sum, ctx.places[label]);
    ++held;
  }
  has_live_centroid_ = held > 0;
  if (held > 0) live_centroid_ = vscale(sum, 1.0 / held);
  const auto leader = elect_leader(candidates, ctx.places, ctx.common_heading);
  choice_.leader = leader;
  choice_.parent.reset();
  if (leader && *leader != ctx.self) {
    const int root = ctx.members.count(*leader) ? ctx.members.at(*leader) : -1;
    // Only our own label's parent in the tree (ParentTreeCache::parent).
    const int parent_label = tree_cache_.parent(ctx.places, present, root, p_.spacing, p_.link_range,
                                                p_.comm_range, ctx.common_heading, ctx.label);
    if (parent_label >= 0 && static_cast<std::size_t>(parent_label) < holder.size())
      choice_.parent = holder[static_cast<std::size_t>(parent_label)];
  }
}

// Where the goal puts this robot's place: the goal plus the place's offset from the live shape's centroid.
Vec2 PaperMotion::own_target(const FormationContext& ctx) const {
  if (ctx.label < 0 || static_cast<std::size_t>(ctx.label) >= ctx.places.size() || !has_live_centroid_)
    return p_.goal;
  return vadd(p_.goal, vsub(ctx.places[static_cast<std::size_t>(ctx.label)], live_centroid_));
}

// The leader stops once its place is this close to its target, i.e. once the live shape's centroid (as the
// leader's own place puts it) is this close to the goal. The world judges arrival by the assigned robots'
// centroid within the goal's radius, not at its centre (docs/recording-format.md): carrying the shape on to
// the centre cost the paper's run 20 ticks. So: inside the radius by the leader's own arrival_tolerance and
// by the world's shape tolerance (0.1 grid spacing), by which the assigned centroid may differ from the
// leader's estimate. A goal too small for those margins: within arrival_tolerance of its centre, and never
// further than half its radius.
double PaperMotion::leader_stop_distance() const {
  constexpr double kShapeTolerance = 0.1;  // x spacing: the world's formation test
  const double inside = p_.goal_radius - p_.arrival_tolerance - kShapeTolerance * p_.spacing;
  return std::max(inside, std::min(p_.arrival_tolerance, 0.5 * p_.goal_radius));
}

// An arrived robot moves again when its target moved (the leader, or a robot that arrived alone: the live
// shape's centroid moved, a death), its parent changed, or its parent is no longer arrived. A robot that
// arrived alone (its piece cut off) follows again once it hears a parent: its own target is where the goal
// puts its place, but the leader's piece stops anywhere inside the goal's radius, up to
// leader_stop_distance() short of that, and the shape is whole only around the leader's place.
bool PaperMotion::should_resume(const FormationContext& ctx) const {
  const Vec2 position{ctx.pose.x, ctx.pose.y};
  if (leader_ == ctx.self) {
    return vnorm(vsub(own_target(ctx), position)) > leader_stop_distance() + p_.arrival_tolerance;
  }
  if (arrived_alone_ && parent_ && !parent_lost(ctx)) return true;
  if (!parent_ || arrived_alone_) {
    return vnorm(vsub(own_target(ctx), position)) > kResumeFactor * p_.arrival_tolerance;
  }
  if (parent_ != arrived_parent_) return true;
  const Neighbour* n = ctx.neighbours->find(*parent_);
  if (n == nullptr || !ctx.neighbours->fresh(*parent_)) return false;
  const auto section = section_of(*n);
  return section && !section->arrived;
}

// The parent is alive as far as the shared table says, but has not been heard for neighbour_timeout ticks.
bool PaperMotion::parent_lost(const FormationContext& ctx) const {
  if (!parent_) return false;
  const auto heard = ctx.neighbours->last_heard(*parent_);
  return !heard || ctx.tick >= *heard + static_cast<Tick>(p_.neighbour_timeout);
}

// eq. (2) at the end of Ready: the vector to every neighbour as it stands now.
void PaperMotion::record_references(const FormationContext& ctx) {
  for (const auto& [id, pos] : last_position_) {
    const auto member = ctx.members.find(id);
    if (member == ctx.members.end()) continue;
    const auto sum = ready_sums_.find(id);
    references_[id] = sum != ready_sums_.end() && sum->second.count > 0
                          ? vscale(sum->second.total, 1.0 / sum->second.count)
                          : vsub(pos, {ctx.pose.x, ctx.pose.y});
    // Way out (extends eq. 2's record): a pair that stood well off the shape's own geometry at Ready -- one
    // of them took its place as reached short of a dead robot's body (blocked place) -- keeps the geometry
    // instead, or the shape would carry that offset to the goal, away from the body, and never match its
    // matrix there (spares.yaml --seed 66 --kill 11@105 --kill 1@1061). Noise leaves the mean within a few
    // cm; kOffShape is well above that.
    constexpr double kOffShape = 0.2;  // x spacing
    const int label = member->second;
    if (label >= 0 && ctx.label >= 0 &&
        static_cast<std::size_t>(std::max(label, ctx.label)) < ctx.places.size()) {
      const Vec2 geometry =
          vsub(ctx.places[static_cast<std::size_t>(label)], ctx.places[static_cast<std::size_t>(ctx.label)]);
      if (vnorm(vsub(references_[id], geometry)) > kOffShape * p_.spacing) references_[id] = geometry;
    }
  }
  if (parent_) parent_reference_ = reference_to(ctx, *parent_);
}

// The reference vector to `id`: as recorded at Ready, else (a robot we did not hear then, or still in Ready)
// the shape's own geometry between the two labels, else as it stands now.
Vec2 PaperMotion::reference_to(const FormationContext& ctx, RobotId id) const {
  if (auto it = references_.find(id); it != references_.end()) return it->second;
  auto m = ctx.members.find(id);
  if (m != ctx.members.end() && m->second >= 0 && ctx.label >= 0 &&
      static_cast<std::size_t>(std::max(m->second, ctx.label)) < ctx.places.size()) {
    return vsub(ctx.places[static_cast<std::size_t>(m->second)],
                ctx.places[static_cast<std::size_t>(ctx.label)]);
  }
  if (auto it = last_position_.find(id); it != last_position_.end())
    return vsub(it->second, {ctx.pose.x, ctx.pose.y});
  return {};
}

Vec2 PaperMotion::motion_velocity(const FormationContext& ctx, MotionStep& out) {
  const Vec2 position{ctx.pose.x, ctx.pose.y};
  Vec2 desired;
  // Where the desired motion leads (the leader's and a cut-off robot's target; a follower's spot where F_net
  // vanishes) and whether that place stands still (a target does; a follower's, while its parent is at rest).
  Vec2 place = position;
  bool place_still = false;
  bool alone = false;  // cut off from its parent: it makes for its place on its own
  // eq. (7): m = m_obstacle |F_goal|. The leader's own; a follower takes its parent's broadcast speed for the
  // formation's |F_goal| (so the repulsion fades as the shape comes to rest at the goal and a robot can take
  // a place beside a dead robot's body), never below kRestingShare of the cruise (the slide needs a
  // direction).
  const double m_floor = p_.m_obstacle * kRestingShare * p_.cruise_speed;
  double m = p_.m_obstacle * p_.cruise_speed;
  if (leader_ == ctx.self) {
    // The leader takes the centroid of the live shape to the goal: its own target is the goal plus its
    // place's offset from that centroid.
    const Vec2 target = own_target(ctx);
    if (vnorm(vsub(target, position)) < leader_stop_distance()) {
      state_ = RobotState::Arrived;
      arrived_alone_ = false;
      arrived_parent_.reset();
      out.events.push_back("arrived");
      wall_.reset();
      boundary_.reset();
      return {};
    }
    // Pace: cruise while every follower keeps up (a follower at full speed behind its parent has
    // |F_net| ~ the speed limit); slow down linearly as the largest lag towards the goal grows past 1.5x
    // the limit, and wait (stop) at 1.5x + strain_scale: the leader never leaves a follower behind.
    double cruise = p_.cruise_speed;
    if (p_.strain_scale > 0.0) {
      const double over = std::max(0.0, children_strain_ - kKeepUpStrain * p_.max_speed);
      cruise *= std::clamp(1.0 - over / p_.strain_scale, kSlowest, 1.0);
    }
    desired = goal_force(position, target, p_.k_goal, cruise, 0.0);  // eq. (3)
    place = target;
    place_still = true;
    m = std::max(p_.m_obstacle * vnorm(desired), m_floor);  // eq. (7)
  } else if (!parent_ || parent_lost(ctx)) {
    // No parent (the tree cannot reach this robot's label: deaths cut it off), or a parent alive (not marked
    // dead) but unheard: this robot's piece of the swarm cannot hear the leader's. It takes its own place to
    // where the goal puts it (eq. 3 on its own place, as the leader does): every piece goes to the goal and
    // the shape is whole again there.
    const Vec2 target = own_target(ctx);
    if (vnorm(vsub(target, position)) < p_.arrival_tolerance) {
      state_ = RobotState::Arrived;
      arrived_alone_ = true;
      arrived_parent_ = parent_;
      out.events.push_back("arrived alone");
      wall_.reset();
      boundary_.reset();
      return {};
    }
    desired = goal_force(position, target, p_.k_goal, p_.max_speed, 0.0);
    m = std::max(p_.m_obstacle * vnorm(desired), m_floor);
    to_parent_ = {};
    place = target;
    place_still = true;
    alone = true;
  } else if (parent_) {
    const Neighbour* n = ctx.neighbours->find(*parent_);
    Vec2 to_parent;
    const auto parent_section = n != nullptr ? section_of(*n) : std::nullopt;
    const bool parent_resting = parent_section && parent_section->arrived;
    if (!parent_resting || resting_parent_ != parent_) {
      parent_rest_ = {};
      resting_parent_ = parent_resting ? parent_ : std::nullopt;
    }
    if (n != nullptr && ctx.neighbours->fresh(*parent_)) {
      to_parent = vpolar(n->range, n->azimuth);
      if (parent_resting) {
        // A parent at rest stands in one place: the mean of where it was heard since it came to rest, a
        // range-and-bearing noise averaged away (one noisy reading let a follower arrive off its place).
        parent_rest_.total = vadd(parent_rest_.total, vadd(position, to_parent));
        ++parent_rest_.count;
        to_parent = vsub(vscale(parent_rest_.total, 1.0 / parent_rest_.count), position);
      }
    } else if (parent_rest_.count > 0) {
      to_parent = vsub(vscale(parent_rest_.total, 1.0 / parent_rest_.count), position);
    } else if (auto it = last_position_.find(*parent_); it != last_position_.end()) {
      // Not heard this tick (lost copies, or it drifted out of range behind an obstacle): where it was, moved
      // on at the velocity it last said it had.
      const auto heard = ctx.neighbours->last_heard(*parent_).value_or(ctx.tick);
      const double dt = static_cast<double>(ctx.tick - std::min(heard, ctx.tick)) / ctx.params->tick_rate;
      to_parent = vsub(vadd(it->second, vscale(last_velocity_[*parent_], dt)), position);
    }
    to_parent_ = to_parent;
    const Vec2 f_net = net_force(spring(p_.k_o, to_parent), spring(p_.k_o, parent_reference_));  // eq. (5)
    net_force_ = vnorm(f_net);
    // How far behind towards the goal (every robot holds it): what the leader waits for. Not along the
    // parent's velocity, which vanishes when the leader waits.
    if (const Vec2 to_goal = vsub(p_.goal, position); vnorm(to_goal) > 1e-6) {
      lag_ = std::max(0.0, vdot(f_net, vscale(to_goal, 1.0 / vnorm(to_goal))));
    }
    // eq. (5) plus the parent's own velocity (it broadcasts it): F_net corrects the follower's place and the
    // feed-forward carries it along, so a follower keeps up with no standing lag, and one held off its place
    // by an obstacle still moves on with its parent while it slides (the paper's F_net alone needs a lag of
    // v / (2 k_o r0) to move at v; beside the paper's box, where the diagonal spring pulls the corner robot
    // backwards as it gives way, that lag was ~0.7 m and the leader waited for it).
    Vec2 feed;
    if (auto it = last_velocity_.find(*parent_); it != last_velocity_.end()) feed = it->second;
    desired = vclamp(vadd(f_net, feed), p_.max_speed);
    m = std::max(p_.m_obstacle * vnorm(feed), m_floor);
    const auto& section = parent_section;
    place = vsub(vadd(position, to_parent), parent_reference_);
    place_still = (section && section->arrived) || vnorm(feed) < kRestingShare * p_.cruise_speed;
    if (section && section->arrived && net_force_ < p_.arrival_net_force) {
      state_ = RobotState::Arrived;
      arrived_alone_ = false;
      arrived_parent_ = parent_;
      out.events.push_back("arrived");
      wall_.reset();
      boundary_.reset();
      return {};
    }
  }

  // Obstacles: Algorithm 2's mask from the neighbours heard now, eq. (6)-(7), size discrimination.
  std::vector<NeighbourBearing> bearings;
  for (const auto& [id, n] : ctx.neighbours->all()) {
    if (ctx.neighbours->fresh(n)) bearings.push_back({n.range, n.bearing});
  }
  UltrasonicArray readings = ctx.perception->ultrasonic;
  const auto mask = mask_neighbour_directions(readings, bearings, p_.mask_angle, p_.mask_slack);
  auto sense = sense_obstacles(readings, mask, ctx.pose.theta,
                               {m, p_.obstacle_range, p_.fusion_range, p_.small_obstacle_width});
  // Size latch: once a large obstacle is seen, whatever is seen next without a break of kLargeLatchTicks is
  // still that obstacle (sliding along a wall, only the side sensor sees it, which alone would read as a
  // post).
  constexpr Tick kLargeLatchTicks = 30;
  if (!wall_.active()) {
    if (sense.size == ObstacleSize::Large) large_until_ = ctx.tick + kLargeLatchTicks;
    if (sense.size == ObstacleSize::Small && ctx.tick < large_until_) {
      sense.size = ObstacleSize::Large;
      large_until_ = ctx.tick + kLargeLatchTicks;
    }
  }
  const bool was_following = wall_.active();
  Vec2 around;
  const WallFollowParams wf{p_.obstacle_range, p_.wall_distance, 0.5, p_.cruise_speed,
                            p_.small_obstacle_width / 2};
  const Vec2 o = vpolar(1.0, ctx.pose.theta + sense.nearest_bearing);
  const int away = side_away_from_neighbours(*ctx.neighbours, o, 1.5 * p_.spacing);
  // A small obstacle: round it on the side away from the neighbours (the robot leaves the shape and
  // rejoins it).
  // The formation's direction of travel: the parent's broadcast velocity (the leader: its own pull).
  Vec2 travel = desired;
  if (leader_ != ctx.self && parent_) {
    if (auto it = last_velocity_.find(*parent_); it != last_velocity_.end() && vnorm(it->second) > 0.01) {
      travel = it->second;
    }
  }
  // Pinned: over each window of kPinnedTicks, it moved less than kProgressShare of the way its desired
  // motion asked for (at least kMinAsked), an obstacle remembered near: it follows the obstacle's boundary
  // (wall_follow.hpp) until the way is clear. Judged against what it asked for, not a fixed speed, so a
  // follower of a leader that slows down is not pinned.
  trace_.add(readings, mask, ctx.pose, ctx.tick, p_.fusion_range);
  asked_ += vnorm(desired) / ctx.params->tick_rate;
  bool pinned = false;
  if (ctx.tick >= anchor_tick_ + kPinnedTicks) {
    pinned = asked_ > kMinAsked && vnorm(vsub(position, anchor_)) < kProgressShare * asked_;
    anchor_ = position;
    anchor_tick_ = ctx.tick;
    asked_ = 0.0;
  }
  // The last approach, and a cut-off robot's way: a place that stands still within fusion_range, or a cut-off
  // robot's own target, is reached as a Moving robot reaches its place in the formation phase
  // (place_approach.hpp): straight, going round only the unexplained echoes nearer than the place (eq. 1's
  // go-round), with a random detour when it makes no progress; no eq. (6), slide, wall- or
  // boundary-following. Those keep an obstacle's range (0.6 m) or go round at wall_distance, so a dead
  // robot's body standing beside a place (0.25-0.5 m off it) held its robot off for good, circling it, and a
  // robot on its own among posts slid to and fro before every gap.
  const BoundaryFollowParams bf{p_.wall_distance + kRobotRadius, p_.max_speed, 1.0, 20, 1200};
  // A follower going round an obstacle's boundary towards a place that stands still (its parent at rest)
  // and that stops hearing its parent keeps going round it while its own target is that same place (the same
  // episode, side and Bug2 leave rule) until the episode ends: following a wall between it and its place took
  // it out of its parent's radio range, where the cut-off robot's way made straight for the place again,
  // back into range, and it was pinned again at the same spot, on the border of the radio range, for good
  // (unseen/pocket.yaml --seed 104: a robot outside the room's wall, its place inside). An episode about a
  // place that moved with the shape is no such search: the cut-off robot's way takes over as before.
  const bool near_place = vnorm(vsub(place, position)) < p_.fusion_range;
  const bool same_search = alone && boundary_.active() && vnorm(vsub(place, hit_place_)) < bf.keep;
  if (place_still && (near_place || (alone && !same_search))) {
    if (boundary_.active()) out.events.push_back("boundary_follow_end");
    if (was_following) out.events.push_back("wall_follow_end");
    boundary_.reset();
    wall_.reset();
    slide_side_ = 0;
    echoes_.add(readings, mask, ctx.pose, ctx.tick, p_.obstacle_range);
    const double to_place = vnorm(vsub(place, position));
    // The echoes of the last kEchoMemoryTicks (Algorithm 2's mask applied when each was heard), each seen as
    // a robot standing a body radius beyond the echo point: a post the cones swept past while the robot
    // turned is still gone round (this tick's readings alone let a robot graze a post beside it).
    std::vector<NeighbourPosition> echoes;
    for (const Vec2 e : echoes_.points(ctx.tick, kEchoMemoryTicks)) {
      const Vec2 rel = vsub(e, position);
      const double r = vnorm(rel);
      if (r < to_place)  // nearer than the place: not a body just beyond it
        echoes.push_back({r + kRobotRadius, std::atan2(rel.y, rel.x), RightOfWay::Mutual, true});
    }
    const auto wall = trace_.surface(position, ctx.tick, p_.obstacle_range + kRobotRadius + 0.3, kTraceTicks);
    const auto across =
        wall ? trace_.across(position, *wall, ctx.tick, 2.0 * bf.keep, kTraceTicks) : std::nullopt;
    return approach_.step(position, place, desired, ctx.tick, echoes, wall,
                          {p_.k_collision, p_.r_o, p_.max_speed, p_.arrival_tolerance, p_.fusion_range, bf},
                          rng_, out.events, across);
  }
  approach_.reset();
  const auto echo = trace_.surface(position, ctx.tick, p_.obstacle_range + kRobotRadius + 0.3, kTraceTicks);
  if (!boundary_.active() && !wall_.active() && echo && pinned) {
    // A head-on tie goes to a side drawn from the seed and the id: deterministic per run, and two robots
    // pinned face to face do not both pick the same way.
    const int tie = ((seed_ * 0x9E3779B97F4A7C15ull) >> 7 ^ ctx.self) & 1 ? 1 : -1;
    // The way round: towards the side of the desired motion the parent stands on, when it clearly stands on
    // one (it is inside the shape, where the way was clear: a corner robot held at a box goes round its inner
    // end, not its outer one), else the tangent nearer the desired motion.
    Vec2 prefer = desired;
    if (leader_ != ctx.self && vnorm(to_parent_) > 1e-6) {
      const Vec2 d_hat = vscale(desired, 1.0 / vnorm(desired));
      const Vec2 across = vsub(to_parent_, vscale(d_hat, vdot(to_parent_, d_hat)));
      if (vnorm(across) > kParentSide * vnorm(to_parent_)) prefer = vadd(desired, across);
    }
    // Bug's rule for the way round: pinned again no nearer its place than when it last started (by less
    // than the distance it keeps from the obstacle, which going round can gain without getting past), the
    // same obstacle or cluster still blocks it: the same way round, its time on that side running on (the
    // dead-end turn-back below still comes). Choosing afresh each time made a robot among posts alternate
    // sides every few dozen ticks and stay where it was (posts.yaml, seed 2: for 5,000 ticks).
    const double gap = vnorm(vsub(place, position));
    if (bug_side_ != 0 && gap > bug_gap_ - bf.keep) {
      boundary_.start(bug_side_, ctx.tick, bug_since_, bug_turns_);
    } else {
      boundary_.start(BoundaryFollower::choose_side(position, *echo, prefer, tie), ctx.tick);
      bug_gap_ = gap;
    }
    hit_place_ = place;
    hit_gap_ = gap;
    out.events.push_back("boundary_follow_start " + std::to_string(boundary_.side()));
  }
  if (boundary_.active()) {
    Vec2 v;
    // Bug2's leave rule: while its place stands where it stood when this episode began, a robot leaves the
    // boundary only nearer it than it was then (by the distance it keeps from the obstacle). Leaving wherever
    // the pull pointed away from the obstacle let it back into a concave one (a U open towards it), where
    // the leader ran between the U's corners for good. A place that moved (a follower's, with the shape) is
    // not a fixed point to measure progress against: then it leaves as soon as the way is clear.
    const bool same_place = place_still && vnorm(vsub(place, hit_place_)) < bf.keep;
    const bool may_leave = !same_place || vnorm(vsub(place, position)) < hit_gap_ - p_.arrival_tolerance;
    const auto across =
        echo ? trace_.across(position, *echo, ctx.tick, 2.0 * bf.keep, kTraceTicks) : std::nullopt;
    const bool following = boundary_.update(echo, position, desired, ctx.tick, bf, v, may_leave, across);
    bug_side_ = boundary_.side();
    bug_since_ = boundary_.since();
    bug_turns_ = boundary_.turns();
    if (following) return v;
    out.events.push_back("boundary_follow_end");
    anchor_ = position;
    anchor_tick_ = ctx.tick;
    asked_ = 0.0;
  }
  if (wall_.update(sense, desired, travel, ctx.pose, wf, around, away)) {
    if (!was_following) out.events.push_back("wall_follow_start");
    return around;
  }
  if (was_following) out.events.push_back("wall_follow_end");
  // A large one: eq. (6) repulsion, and the part of the desired motion that pushes into the obstacle is
  // dropped, so the robot slides along it instead of stalling against it; head-on, it slides towards its
  // neighbours: the perimeter gives way inwards and the shape shrinks on that side.
  // eq. (6) over the echoes remembered for a moment (obstacle_forces.hpp: EchoMemory).
  echoes_.add(readings, mask, ctx.pose, ctx.tick, p_.obstacle_range);
  sense.force = echoes_.force(position, ctx.tick, m, p_.obstacle_range, kEchoMemoryTicks);
  const double f_obs = vnorm(sense.force);
  if (f_obs > 1e-9) {
    last_obstacle_tick_ = ctx.tick;
  } else if (ctx.tick > last_obstacle_tick_ + kEchoMemoryTicks) {
    slide_side_ = 0;
  }
  const double d_norm = vnorm(desired);
  if (f_obs > 1e-9 && d_norm > 1e-9) {
    const Vec2 n = vscale(sense.force, 1.0 / f_obs);
    const double into = vdot(desired, n);
    Vec2 slide = vsub(desired, vscale(n, into));
    // Head-on (the repulsion straight against the desired motion) is a wall ahead only if something
    // remembered lies on the way: between two obstacles on either side (a gap between posts, 0.8-1 m) the
    // summed repulsion also points straight back, and dropping the desired motion along it turned every such
    // gap into a dead end (posts.yaml: lone robots and leaders slid to and fro before a gap for thousands of
    // ticks). There eq. (6) alone, against the full desired motion, takes the robot through.
    const bool head_on = vnorm(slide) < 0.5 * d_norm;
    const bool gap_ahead =
        head_on && echoes_.gap_ahead(position, vscale(desired, 1.0 / d_norm), p_.obstacle_range,
                                     2.0 * kRobotRadius, ctx.tick, kEchoMemoryTicks);
    if (into < 0.0 && !gap_ahead) {
      if (head_on) {
        // The side is judged against the remembered obstacle (-n, stable while the robot turns) and kept
        // until the obstacle is gone, so that a robot never swings from one side to the other.
        if (slide_side_ == 0) {
          // Towards the parent's side (it stands inside the shape, where the way is clear); the leader, which
          // has none, towards its neighbours.
          const Vec2 to_obstacle = vscale(n, -1.0);
          const double parent_side = to_obstacle.x * to_parent_.y - to_obstacle.y * to_parent_.x;
          const int toward = side_away_from_neighbours(*ctx.neighbours, to_obstacle, 1.5 * p_.spacing);
          if (parent_ && std::abs(parent_side) > 0.05) {
            slide_side_ = parent_side > 0 ? 1 : -1;
          } else {
            slide_side_ =
                toward != 0 ? -toward : (vdot(slide, vrotate(n, std::numbers::pi / 2)) >= 0 ? -1 : 1);
          }
        }
        // +1: left of the obstacle direction -n, i.e. n turned by -pi/2.
        slide = vadd(slide, vscale(vrotate(n, -slide_side_ * std::numbers::pi / 2), 0.5 * d_norm));
      }
      desired = slide;
    }
  }
  return vadd(desired, sense.force);
}

}  // namespace swarmform::controller::motion
