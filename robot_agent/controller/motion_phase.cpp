#include "robot_agent/controller/motion_phase.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "robot_agent/controller/boundary.hpp"
#include "robot_agent/controller/collision_avoidance.hpp"
#include "robot_agent/controller/leader_election.hpp"
#include "robot_agent/controller/motion_section.hpp"
#include "robot_agent/controller/obstacle_response.hpp"
#include "robot_agent/controller/obstacle_view.hpp"
#include "robot_agent/controller/parent_tree.hpp"
#include "robot_agent/controller/vec2_math.hpp"

namespace swarmform::controller::motion {

namespace {

constexpr double kResumeFactor = 2.0;  // x arrival_tolerance off its target: an arrived leader moves again

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

std::optional<MotionSection> section_of(const Neighbour& n) {
  return decode_motion_section(n.message.motion);
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

PaperMotion::PaperMotion(const FormationParams& params)
    : p_(motion_params(params)), turn_(p_.goal), seed_(params.seed) {}

void PaperMotion::on_ready(const FormationContext& ctx) {
  state_ = RobotState::Ready;
  ready_tick_ = ctx.ready_tick;
  started_ = true;
  boundary_written_ = false;
  leader_.reset();
  parent_.reset();
  references_.clear();
  ready_sums_.clear();
  follower_.reset();
  last_position_.clear();
  last_velocity_.clear();
  large_latch_.reset();
  marked_dead_.clear();
  // Only at the shape's own barrier: a robot that joins a shape already on its way (a reserve, a robot back
  // from a restart) enters Ready where the members are not standing at their places, and no leader entry
  // exists before the shape's first one is written.
  unheard_members_checked_ = ctx.stigmergy->get(leader_key()).has_value();
  wall_.reset();
  echoes_.clear();
  slide_.side = 0;
  net_force_ = 0.0;
  episode_.reset();
  place_watch_.reset();
  approach_.reset(seed_, ctx.self);
  trace_.clear();
  progress_.restart({ctx.pose.x, ctx.pose.y}, ctx.tick);
  has_live_centroid_ = false;
  choice_ = {};
}

MotionStep PaperMotion::step(const FormationContext& ctx) {
  // The hook promises on_ready before the first step; a caller that skips it (or enters Ready again, a new
  // ready_tick) still gets a clean Ready phase.
  if (!started_ || ctx.ready_tick != ready_tick_) on_ready(ctx);
  // The goal as it stands this tick (a world event may move it): the leader's eq. 3 pulls there, and an
  // arrived leader whose target moved resumes (should_resume).
  if (ctx.perception && ctx.perception->goal) {
    p_.goal = ctx.perception->goal->at;
    p_.goal_radius = ctx.perception->goal->radius;
  }
  turn_.observe(p_.goal, *ctx.stigmergy);
  MotionStep out;
  for (const auto& [id, n] : ctx.neighbours->all()) {
    if (ctx.neighbours->fresh(n)) {
      last_position_[id] = vadd({ctx.pose.x, ctx.pose.y}, vpolar(n.range, n.azimuth));
      if (state_ == RobotState::Ready && ctx.members.count(id) != 0) {
        // eq. (2)'s r0: the mean of the readings while the neighbour stands (Reached or Ready); one that has
        // set off already counts where it is now, as the paper's record at the end of Ready has it.
        PointSum& sum = ready_sums_[id];
        if (n.message.state != RobotState::Ready && n.message.state != RobotState::Reached) sum = {};
        sum.add(vpolar(n.range, n.azimuth));
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
  if (state_ != RobotState::Ready && leader_ == ctx.self) {
    const Stigmergy& st = *ctx.stigmergy;
    turn_.lead(
        *ctx.stigmergy,
        [&](RobotId id) { return id != ctx.self && ctx.members.count(id) != 0 && !marked_dead(st, id); },
        state_ == RobotState::Arrived, p_.max_speed, ctx.params->tick_rate, shape_radius_, out.events);
  }

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
  } else if (state_ == RobotState::Arrived && off_place(ctx)) {
    // Pushed off its place, or its parent pushed off its own (place_watch.hpp): back to its place, from
    // readings of its parent taken afresh (the mean from before its arrival may be where the parent was).
    state_ = RobotState::Motion;
    follower_.reset();
    out.events.push_back("motion_resumed off_place");
  }
  if (state_ == RobotState::Motion) velocity = motion_velocity(ctx, out);
  turn_.publish(ctx.self, *ctx.stigmergy, out.events);

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
      wall_.active() || episode_.active() ||
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

// A member we heard since Ready, last heard well inside radio range, silent for its silence limit: dead.
// A live robot marked dead by a mistaken neighbour rewrites its own entry (a newer version wins).
void PaperMotion::watch_for_the_dead(const FormationContext& ctx) {
  Stigmergy& st = *ctx.stigmergy;
  // The members with a last position (heard since Ready), in id order: the robots heard, not every member
  // of a shape of a thousand labels.
  for (const auto& [id, last] : last_position_) {
    if (id == ctx.self || ctx.members.count(id) == 0) continue;
    const auto heard = ctx.neighbours->last_heard(id);
    if (!heard || *heard < ready_tick_ || ctx.tick < *heard + ctx.neighbours->silence_limit(id)) continue;
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
  // The largest distance of a live place from the live centroid (shape_turn.hpp). Computed with
  // the choice, whose inputs it shares, so it is ready on the tick the goal moves.
  shape_radius_ = 0.0;
  for (std::size_t label = 0; label < present.size() && held > 0; ++label) {
    if (present[label])
      shape_radius_ = std::max(shape_radius_, vnorm(vsub(ctx.places[label], live_centroid_)));
  }
  const auto leader = elect_leader(candidates, ctx.places, ctx.common_heading);
  choice_.leader = leader;
  choice_.parent.reset();
  choice_.split = false;
  if (leader && *leader == ctx.self && ctx.members.count(*leader) != 0) {
    // Deaths can cut labels off the tree (every link to them longer than the radio range): their robots make
    // for their own targets alone (desired_motion.hpp) and never follow again, so the leader's piece must
    // stand at its own target too (leader_stop_distance), or the pieces stand apart.
    const ParentTree& tree = tree_cache_.get(ctx.places, present, ctx.members.at(*leader), p_.spacing,
                                             p_.link_range, p_.comm_range, ctx.common_heading);
    for (std::size_t label = 0; label < present.size() && label < tree.cost.size(); ++label) {
      if (present[label] && tree.cost[label] == kUnreachable) choice_.split = true;
    }
  }
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
  return vadd(p_.goal, turn_.turned(vsub(ctx.places[static_cast<std::size_t>(ctx.label)], live_centroid_)));
}

// The leader stops once its place is this close to its target, i.e. once the live shape's centroid (as the
// leader's own place puts it) is this close to the goal. The world judges arrival by the assigned robots'
// centroid within the goal's radius, not at its centre (docs/recording-format.md): carrying the shape on to
// the centre cost the paper's run 20 ticks. So: inside the radius by the leader's own arrival_tolerance and
// by the world's shape tolerance (0.1 grid spacing), by which the assigned centroid may differ from the
// leader's estimate. A goal too small for those margins: within arrival_tolerance of its centre, and never
// further than half its radius.
//
// Way out (extends the arrival rule): a shape the tree has split (choice_.split) meets at the goal's centre.
// Its cut-off pieces stop within arrival_tolerance of their own targets (cut_off_desire), which the goal's
// centre sets, not the leader's piece: stopping anywhere inside the radius left the pieces up to ~0.3 m
// apart, never judged formed (scenarios/untuned/slalom_loss20_noise.yaml --shape shapes/untuned/zigzag.txt
// --seed 1101 --kill 3@799 --kill 8@2075: the leader's label cut off from every other; --shape shapes/v.txt
// --seed 1101 --kill 8@1248 --kill 3@2075: the V's arm beyond its dead middle). So the leader's piece stops
// as they do. (Pieces that disagree on who is dead aim at different centroids: not mended by this.)
double PaperMotion::leader_stop_distance() const {
  if (choice_.split) return p_.arrival_tolerance;
  constexpr double kShapeTolerance = 0.1;  // x spacing: the world's formation test
  const double inside = p_.goal_radius - p_.arrival_tolerance - kShapeTolerance * p_.spacing;
  return std::max(inside, std::min(p_.arrival_tolerance, 0.5 * p_.goal_radius));
}

// An arrived robot moves again when its target moved (the leader, or a robot that arrived alone: the live
// shape's centroid moved, a death), its parent changed, or its parent is no longer arrived. A robot that
// arrived alone (its piece cut off) follows again once it hears a parent: its own target is where the goal
// puts its place, but the leader's piece stops anywhere inside the goal's radius, up to
// leader_stop_distance() short of that, and the shape is whole only around the leader's place.
// An arrived follower (not the leader, not one that arrived alone) whose place, as its parent's readings of
// the last neighbour_timeout ticks put it, lies further than kResumeFactor x arrival_tolerance off. Watched
// here, every tick in Arrived.
bool PaperMotion::off_place(const FormationContext& ctx) {
  if (!parent_ || arrived_alone_ || leader_ == ctx.self) return false;
  const Vec2 position{ctx.pose.x, ctx.pose.y};
  const Neighbour* n = ctx.neighbours->find(*parent_);
  if (n != nullptr && ctx.neighbours->fresh(*parent_)) {
    place_watch_.add(ctx.tick, vadd(position, vpolar(n->range, n->azimuth)),
                     static_cast<Tick>(p_.neighbour_timeout));
  }
  const auto place =
      place_watch_.place(turn_.turned(parent_reference_), static_cast<std::size_t>(p_.neighbour_timeout / 2));
  return place && vnorm(vsub(*place, position)) > kResumeFactor * p_.arrival_tolerance;
}

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

// The parent is alive as far as the shared table says, but has not been heard for its silence limit
// (neighbour_timeout, or longer on a link that has come back from longer losses: neighbours.hpp).
bool PaperMotion::parent_lost(const FormationContext& ctx) const {
  if (!parent_) return false;
  const auto heard = ctx.neighbours->last_heard(*parent_);
  return !heard || ctx.tick >= *heard + ctx.neighbours->silence_limit(*parent_);
}

// eq. (2) at the end of Ready: the vector to every neighbour as it stands now.
void PaperMotion::record_references(const FormationContext& ctx) {
  for (const auto& [id, pos] : last_position_) {
    const auto member = ctx.members.find(id);
    if (member == ctx.members.end()) continue;
    const auto sum = ready_sums_.find(id);
    // Kept in the shape's frame (shape_turn.hpp): a robot that enters Ready after the shape turned
    // (a reserve) reads the shape as it stands.
    references_[id] = turn_.unturned(sum != ready_sums_.end() && sum->second.count > 0
                                         ? sum->second.mean()
                                         : vsub(pos, {ctx.pose.x, ctx.pose.y}));
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
    return turn_.unturned(vsub(it->second, {ctx.pose.x, ctx.pose.y}));
  return {};
}

// Where the desired motion leads this tick, by the robot's role (desired_motion.hpp).
Desire PaperMotion::desired_motion(const FormationContext& ctx) {
  const Vec2 position{ctx.pose.x, ctx.pose.y};
  // The leader takes the centroid of the live shape to the goal: its own target is the goal plus its place's
  // offset from that centroid.
  if (leader_ == ctx.self)
    return leader_desire(position, own_target(ctx), leader_stop_distance(), children_strain_, p_);
  if (!parent_ || parent_lost(ctx)) return cut_off_desire(position, own_target(ctx), p_);
  ParentView parent;
  parent.id = *parent_;
  parent.reference = turn_.turned(parent_reference_);
  if (auto it = last_position_.find(*parent_); it != last_position_.end()) parent.last_position = it->second;
  if (auto it = last_velocity_.find(*parent_); it != last_velocity_.end()) parent.last_velocity = it->second;
  return follower_.step(*ctx.neighbours, position, ctx.tick, ctx.params->tick_rate, parent, p_);
}

void PaperMotion::arrive(const FormationContext& ctx, Arrival arrival, MotionStep& out) {
  state_ = RobotState::Arrived;
  place_watch_.reset();
  arrived_alone_ = arrival == Arrival::Alone;
  if (leader_ == ctx.self) {
    arrived_parent_.reset();
  } else {
    arrived_parent_ = parent_;
  }
  out.events.push_back(arrived_alone_ ? "arrived alone" : "arrived");
  wall_.reset();
  episode_.end();
}

// A small obstacle ahead (obstacle_forces.hpp's size): wall-following round it on the side away from the
// neighbours (the robot leaves the shape and rejoins it), along the formation's direction of travel (the
// parent's broadcast velocity; the leader: its own pull). None once it is not, or no longer, going round.
std::optional<Vec2> PaperMotion::go_round_small_obstacle(const FormationContext& ctx, Vec2 desired,
                                                         const ObstacleSense& sense) {
  const WallFollowParams wf{p_.obstacle_range, p_.wall_distance, 0.5, p_.cruise_speed,
                            p_.small_obstacle_width / 2};
  const Vec2 o = vpolar(1.0, ctx.pose.theta + sense.nearest_bearing);
  const int away = side_away_from_neighbours(*ctx.neighbours, o, 1.5 * p_.spacing);
  Vec2 travel = desired;
  if (leader_ != ctx.self && parent_) {
    if (auto it = last_velocity_.find(*parent_); it != last_velocity_.end() && vnorm(it->second) > 0.01) {
      travel = it->second;
    }
  }
  Vec2 around;
  if (wall_.update(sense, desired, travel, ctx.pose, wf, around, away)) return around;
  return std::nullopt;
}

// One tick in Motion, stage by stage; each stage's header holds its rules.
Vec2 PaperMotion::motion_velocity(const FormationContext& ctx, MotionStep& out) {
  const Vec2 position{ctx.pose.x, ctx.pose.y};
  // 1. The desired motion (desired_motion.hpp): eq. (3) for the leader and a cut-off robot, eq. (5) with the
  //    parent's velocity for a follower; where it leads; eq. (7)'s obstacle gain; arrival.
  const Desire desire = desired_motion(ctx);
  net_force_ = desire.net_force;
  lag_ = desire.lag;
  if (desire.to_parent) to_parent_ = *desire.to_parent;
  if (desire.arrival != Arrival::None) {
    arrive(ctx, desire.arrival, out);
    return {};
  }

  // 2. The obstacles seen (obstacle_view.hpp): Algorithm 2's mask, eq. (6)-(7), the size and its latch; the
  //    trace remembers them; pinned or not over the last window (progress_window.hpp).
  const auto masking = neighbours_to_mask(*ctx.neighbours, ctx.pose, ctx.params->tick_rate, p_.max_speed,
                                          last_position_, last_velocity_);
  ObstacleView view = look_at_obstacles(masking, ctx.perception->ultrasonic, ctx.pose.theta, desire.m, p_);
  if (!wall_.active()) large_latch_.apply(view.sense, ctx.tick);
  const bool was_following = wall_.active();
  trace_.add(view.readings, view.mask, ctx.pose, ctx.tick, p_.fusion_range);
  const bool pinned = progress_.update(position, vnorm(desire.velocity), ctx.tick, ctx.params->tick_rate);
  const double surface_within = p_.obstacle_range + kRobotRadius + 0.3;
  const BoundaryFollowParams bf{p_.wall_distance + kRobotRadius, p_.max_speed, 1.0, 20, 1200};
  // A moved goal: the push off a surface its place lies beyond (shape_turn.hpp).
  if (leader_ == ctx.self || !has_live_centroid_ || ctx.label < 0 ||
      static_cast<std::size_t>(ctx.label) >= ctx.places.size()) {
    turn_.no_push();
  } else {
    PushView push;
    push.position = position;
    push.place = desire.place;
    push.place_still = desire.place_still;
    push.offset = vsub(ctx.places[static_cast<std::size_t>(ctx.label)], live_centroid_);
    // Held by reference: a std::function of a lambda with four captures would allocate on every tick of every
    // robot in Motion; one of a reference_wrapper never does.
    const auto find_surface = [&] { return trace_.surface(position, ctx.tick, surface_within, kTraceTicks); };
    push.surface = std::cref(find_surface);
    push.large = view.sense.size == ObstacleSize::Large;
    push.arrival_tolerance = p_.arrival_tolerance;
    turn_.push(push);
  }

  // 3. The last approach, and a cut-off robot's way (approach_stage.hpp).
  const bool near_place = vnorm(vsub(desire.place, position)) < p_.fusion_range;
  const bool same_search = desire.alone && episode_.active() && episode_.about(desire.place, bf.keep);
  if (approach_takes_over(desire.place_still, near_place, desire.alone, same_search)) {
    if (episode_.active()) out.events.push_back("boundary_follow_end");
    if (was_following) out.events.push_back("wall_follow_end");
    episode_.end();
    wall_.reset();
    slide_.side = 0;
    echoes_.add(view.readings, view.mask, ctx.pose, ctx.tick, p_.obstacle_range);
    return approach_.step(position, desire.place, desire.velocity, ctx.tick, echoes_, trace_, surface_within,
                          {p_.k_collision, p_.r_o, p_.max_speed, p_.arrival_tolerance, p_.fusion_range, bf},
                          out.events);
  }
  approach_.idle();

  // 4. A boundary episode (boundary_episode.hpp): pinned with an obstacle remembered near.
  const EpisodeInputs episode{
      position, desire.velocity, desire.place, desire.place_still, leader_ != ctx.self ? to_parent_ : Vec2{},
      ctx.tick};
  const auto echo = trace_.surface(position, ctx.tick, surface_within, kTraceTicks);
  if (!episode_.active() && !wall_.active() && echo && pinned) {
    episode_.start(episode, *echo, BoundaryEpisode::tie_break(seed_, ctx.self), bf, out.events);
  }
  if (episode_.active()) {
    if (const auto v = episode_.follow(episode, echo, trace_, p_.arrival_tolerance, bf, out.events))
      return *v;
    progress_.restart(position, ctx.tick);
  }

  // 5. A small obstacle: wall-following (wall_follow.hpp).
  if (const auto around = go_round_small_obstacle(ctx, desire.velocity, view.sense)) {
    if (!was_following) out.events.push_back("wall_follow_start");
    return *around;
  }
  if (was_following) out.events.push_back("wall_follow_end");

  // 6. A large one: eq. (6) over the echoes remembered for a moment, and the slide (obstacle_response.hpp).
  echoes_.add(view.readings, view.mask, ctx.pose, ctx.tick, p_.obstacle_range);
  return respond_to_obstacles(slide_, echoes_, *ctx.neighbours,
                              {position, desire.velocity, desire.m, parent_.has_value(), to_parent_, ctx.tick,
                               p_.obstacle_range, 1.5 * p_.spacing});
}

}  // namespace swarmform::controller::motion
