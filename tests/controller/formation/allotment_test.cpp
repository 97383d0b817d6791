// Label allotment, conflicts, dead holders and the barrier: the functions, then one controller fed crafted
// messages.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <string>

#include "common/shape.hpp"
#include "robot_agent/controller/allotment.hpp"
#include "robot_agent/controller/barrier.hpp"
#include "robot_agent/controller/builtins.hpp"
#include "robot_agent/controller/message.hpp"
#include "robot_agent/controller/paper_controller.hpp"
#include "robot_agent/controller/paper_telemetry.hpp"

namespace swarmform::controller {
namespace {

ShapeMatrix triangle_shape() {
  return load_shape_file(std::string(SWARMFORM_SHAPES_DIR) + "/triangle.txt");
}

Mission triangle_mission() {
  Mission m;
  m.behaviour = "paper";
  m.shape = triangle_shape();
  return m;
}

// A message from robot `id` at `pose` as the medium would deliver it to a robot at `self_pose`.
RabReading reading(const RobotMessage& m, const Pose2D& self_pose) {
  const double dx = m.pose.x - self_pose.x, dy = m.pose.y - self_pose.y;
  return {m.sender, std::hypot(dx, dy), std::atan2(dy, dx) - self_pose.theta, encode_message(m)};
}

RobotMessage shape_robot(RobotId id, int label, Vec2 at, std::vector<int> free_labels) {
  RobotMessage m;
  m.sender = id;
  m.state = RobotState::Reached;
  m.label = label;
  m.pose = {at.x, at.y, 1.5707963};
  m.has_origin = true;
  m.origin = {0.0, 0.0};
  m.free_labels = std::move(free_labels);
  return m;
}

Perception perceive(Tick t, Pose2D pose, const std::vector<RobotMessage>& heard) {
  Perception p;
  p.tick = t;
  p.pose = pose;
  p.ultrasonic.fill(kUltrasonicMaxRange);
  for (const auto& m : heard) p.messages.push_back(reading(m, pose));
  return p;
}

bool has_event(const Command& c, const std::string& prefix) {
  return std::any_of(c.telemetry.events.begin(), c.telemetry.events.end(),
                     [&](const std::string& e) { return e.rfind(prefix, 0) == 0; });
}

TEST(Allotment, ConflictRuleKeepsTheHigherId) {
  EXPECT_TRUE(keeps_label(9, 5));
  EXPECT_FALSE(keeps_label(5, 9));
}

TEST(Allotment, ChooseOfferPairsClosestFirst) {
  // Two offers, two searchers: the one closer to label 2's place gets it even though the other is
  // closer to both in sum; the other takes label 1.
  std::vector<LabelOffer> offers{{1, 0, 0, {}, {-1.0, -1.0}}, {2, 0, 0, {}, {0.0, -1.0}}};
  std::vector<Searcher> searchers{{3, {0.0, -1.2}}, {4, {-0.4, -1.3}}};
  EXPECT_EQ(choose_offer(offers, searchers, 3)->label, 2);
  EXPECT_EQ(choose_offer(offers, searchers, 4)->label, 1);
  // More searchers than offers: the farthest gets none.
  searchers.push_back({5, {5.0, 5.0}});
  EXPECT_FALSE(choose_offer(offers, searchers, 5).has_value());
}

TEST(Allotment, FreeGridLabelsLeaveOutHeldAndHeardLabels) {
  const ShapeTable table(triangle_shape(), 1.0);
  Stigmergy s(0);
  NeighbourTable nb;
  EXPECT_EQ(free_grid_labels(table, 0, s, nb), (std::vector<int>{1, 2, 3}));
  put_label_holder(s, 2, 7);
  EXPECT_EQ(free_grid_labels(table, 0, s, nb), (std::vector<int>{1, 3}));
  put_label_freed(s, 2, 100);  // freed again: offered again
  EXPECT_EQ(free_grid_labels(table, 0, s, nb), (std::vector<int>{1, 2, 3}));
  Perception p = perceive(5, {}, {shape_robot(8, 3, {1, -1}, {})});
  nb.update(p, 0);
  EXPECT_EQ(free_grid_labels(table, 0, s, nb), (std::vector<int>{1, 2}));
}

// LabelTicks (label -> tick, indexed) finds what a std::map of the same sets finds, under random sets of
// labels in and beyond its current size, negative labels and clears.
TEST(Allotment, LabelTicksFindsWhatAMapFinds) {
  std::mt19937 rng(7);
  LabelTicks fast;
  std::map<int, Tick> plain;
  std::uniform_int_distribution<int> label(-3, 1200), action(0, 999);
  std::uniform_int_distribution<Tick> tick(0, 100000);
  for (int step = 0; step < 20000; ++step) {
    const int a = action(rng);
    if (a == 0) {
      fast.clear();
      plain.clear();
    } else if (a < 500) {
      const int l = label(rng);
      const Tick t = tick(rng);
      fast.set(l, t);
      if (l >= 0) plain[l] = t;
    }
    const int l = label(rng);
    const auto it = plain.find(l);
    const std::optional<Tick> expected = it == plain.end() ? std::nullopt : std::optional<Tick>(it->second);
    ASSERT_EQ(fast.find(l), expected) << "step " << step << " label " << l;
  }
}

TEST(Allotment, LabelsOfSilentHoldersAreFreedAfterTheTimeout) {
  const ShapeTable table(triangle_shape(), 1.0);
  Stigmergy s(0);
  put_label_holder(s, 2, 7);
  put_label_holder(s, 4, 8);  // not in label 0's grid: not ours to free
  NeighbourTable nb(20);
  LabelTicks changed{{2, 0}, {4, 0}};
  // Entry seen at tick 0, holder never heard: freed after the timeout from then.
  EXPECT_TRUE(labels_to_free(table, 0, s, nb, changed, 0, 39, 40).empty());
  EXPECT_EQ(labels_to_free(table, 0, s, nb, changed, 0, 40, 40), (std::vector<int>{2}));
  // Heard at 100: the timeout runs from then.
  nb.update(perceive(100, {}, {shape_robot(7, 2, {0, -1}, {}), shape_robot(8, 4, {-2, -2}, {})}), 0);
  EXPECT_TRUE(labels_to_free(table, 0, s, nb, changed, 0, 139, 40).empty());
  EXPECT_EQ(labels_to_free(table, 0, s, nb, changed, 0, 140, 40), (std::vector<int>{2}));
  // A heartbeat (the entry changed at 130) counts like being heard.
  changed.set(2, 130);
  EXPECT_TRUE(labels_to_free(table, 0, s, nb, changed, 0, 169, 40).empty());
  EXPECT_EQ(labels_to_free(table, 0, s, nb, changed, 0, 170, 40), (std::vector<int>{2}));
  // Our own label and untracked labels are never freed.
  EXPECT_TRUE(labels_to_free(table, 0, s, nb, {}, 0, 10000, 40).empty());
  // Label 4 lies beyond label 1 (not in label 0's grid): watched once 1 is freed, and its silent holder's
  // label freed.
  put_label_freed(s, 1, 150);
  EXPECT_EQ(watched_labels(table, 0, s), (std::vector<int>{1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(labels_to_free(table, 0, s, nb, changed, 0, 170, 40), (std::vector<int>{2, 4}));
  // Unless its holder stands in the barrier: counted there, and perhaps alive beyond everyone's range.
  barrier_enter(s, 8, 4);
  EXPECT_EQ(labels_to_free(table, 0, s, nb, changed, 0, 170, 40), (std::vector<int>{2}));
}

TEST(Barrier, CountsEntriesWhoseLabelTheyStillHoldAndDropsAbandonedLabels) {
  Stigmergy s(0);
  for (RobotId id = 0; id < 9; ++id) put_label_holder(s, static_cast<int>(id), id);
  for (RobotId id = 0; id < 8; ++id) barrier_enter(s, id, static_cast<int>(id));
  auto v = read_barrier(s, 9, 1000, 40);
  EXPECT_EQ(v.count, 8);
  EXPECT_EQ(v.threshold, 9);
  EXPECT_FALSE(v.passed());
  // Robot 8 dies before reaching; its label is freed at 1000 and nobody takes it.
  put_label_freed(s, 8, 1000);
  EXPECT_FALSE(read_barrier(s, 9, 1039, 40).passed());
  v = read_barrier(s, 9, 1040, 40);
  EXPECT_EQ(v.threshold, 8);
  EXPECT_EQ(v.abandoned, (std::vector<int>{8}));
  EXPECT_TRUE(v.passed());
  // Robot 3 died after entering, and a spare (id 20) took label 3: 3's entry no longer counts, 20's does.
  put_label_holder(s, 3, 20);
  EXPECT_EQ(read_barrier(s, 9, 1040, 40).count, 7);
  barrier_enter(s, 20, 3);
  v = read_barrier(s, 9, 1040, 40);
  EXPECT_EQ(v.count, 8);
  EXPECT_TRUE(v.members.contains(20));
  EXPECT_FALSE(v.members.contains(3));
}

TEST(Allotment, ASearcherTakesTheClosestOfferedLabelAndLosesItToAHigherId) {
  PaperController c;
  c.init(triangle_mission(), 5);
  const Pose2D me{0.1, -1.3, 0.0};  // closest to label 2's place (0, -1)
  const auto seed = shape_robot(0, 0, {0, 0}, {1, 2, 3});
  Command cmd = c.step(perceive(1, me, {seed}));
  ASSERT_EQ(c.state(), RobotState::Moving);
  EXPECT_EQ(c.label(), 2);
  EXPECT_TRUE(has_event(cmd, "label_taken 2"));
  EXPECT_EQ(controller::kPaperColumns.parent_of(cmd.telemetry),
            -1);  // the seed's label is not yet in its stigmergy

  // Robot 9 claims label 2 too, at the same version: the higher id keeps it.
  auto rival = shape_robot(9, 2, {0.5, -1.5}, {});
  rival.state = RobotState::Moving;
  rival.entries = {{stig::key(stig::Ns::Labels, 2), 9, 1, 9}};
  cmd = c.step(perceive(2, me, {seed, rival}));
  EXPECT_EQ(c.state(), RobotState::Searching);
  EXPECT_EQ(c.label(), -1);
  EXPECT_TRUE(has_event(cmd, "label_lost 2 to 9"));
}

TEST(Allotment, AHolderKeepsItsLabelAgainstALowerIdAndReassertsIt) {
  PaperController c;
  c.init(triangle_mission(), 5);
  const Pose2D me{0.1, -1.3, 0.0};
  const auto seed = shape_robot(0, 0, {0, 0}, {1, 2, 3});
  c.step(perceive(1, me, {seed}));
  ASSERT_EQ(c.label(), 2);
  auto rival = shape_robot(3, 2, {0.5, -1.5}, {});
  rival.state = RobotState::Moving;
  rival.entries = {{stig::key(stig::Ns::Labels, 2), 3, 2, 3}};  // even with a newer version
  const Command cmd = c.step(perceive(2, me, {seed, rival}));
  EXPECT_EQ(c.state(), RobotState::Moving);
  EXPECT_EQ(c.label(), 2);
  const auto s = label_status(c.stigmergy(), 2);
  EXPECT_EQ(s.holder, 5u);
  EXPECT_EQ(c.stigmergy().entry(stig::key(stig::Ns::Labels, 2))->version, 3u);
  // The re-assertion goes out at once.
  const auto out = decode_message(cmd.message);
  ASSERT_TRUE(out.has_value());
  EXPECT_TRUE(std::any_of(out->entries.begin(), out->entries.end(), [](const StigmergyEntry& e) {
    return e.key == stig::key(stig::Ns::Labels, 2) && e.value == 5 && e.version == 3;
  }));
  EXPECT_EQ(out->label, 2);
}

TEST(Allotment, SimultaneousClaimsOnTwoControllersEndWithOneHolder) {
  // Two searchers equally placed hear the same single offer and both... the pairing gives it to one; the
  // other hears nothing for itself. Even when both claim (crafted), the exchange leaves the higher id.
  PaperController a, b;
  a.init(triangle_mission(), 4);
  b.init(triangle_mission(), 6);
  const auto seed = shape_robot(0, 0, {0, 0}, {2});
  const Pose2D pa{-0.2, -1.3, 0.0}, pb{0.2, -1.3, 0.0};
  // Each hears the seed but not the other (as if the other's message was lost): both claim label 2.
  Command ca = a.step(perceive(1, pa, {seed}));
  Command cb = b.step(perceive(1, pb, {seed}));
  ASSERT_EQ(a.label(), 2);
  ASSERT_EQ(b.label(), 2);
  for (Tick t = 2; t < 6; ++t) {
    auto ma = *decode_message(ca.message);
    auto mb = *decode_message(cb.message);
    ca = a.step(perceive(t, pa, {seed, mb}));
    cb = b.step(perceive(t, pb, {seed, ma}));
  }
  EXPECT_EQ(a.state(), RobotState::Searching);
  EXPECT_EQ(b.label(), 2);
  EXPECT_EQ(label_status(a.stigmergy(), 2).holder, 6u);
  EXPECT_EQ(label_status(b.stigmergy(), 2).holder, 6u);
}

// ---- A way out of every formation phase ----

RobotMessage searcher(RobotId id, Vec2 at, RobotId candidate, double distance, std::uint8_t age) {
  RobotMessage m;
  m.sender = id;
  m.state = RobotState::Searching;
  m.pose = {at.x, at.y, 0.0};
  m.seed_candidate = candidate;
  m.seed_distance = distance;
  m.seed_age = age;
  return m;
}

// Robots 1 and 2 hear each other; robot 5 (the best candidate) is heard by both, then dies. Without ageing
// each kept hearing 5 from the other for ever; with it the relayed report grows one hop older a tick and is
// dropped past max_age.
TEST(SeedElection, ADeadCandidatesMinimumAgesOut) {
  constexpr int kMaxAge = 30;
  SeedElection e1, e2;
  NeighbourTable n1, n2;
  const Vec2 p1{1.0, 0.0}, p2{2.0, 0.0}, p5{0.5, 0.0};
  e1.update(1, 1.0, n1, 0, kMaxAge);  // each knows only itself before the first message
  e2.update(2, 2.0, n2, 0, kMaxAge);
  Tick t = 1;
  for (; t <= 5; ++t) {  // 5 alive: both hear its own report (age 0)
    const auto m1 = searcher(1, p1, e1.candidate(), e1.distance(), e1.age());
    const auto m2 = searcher(2, p2, e2.candidate(), e2.distance(), e2.age());
    n1.update(perceive(t, {p1.x, p1.y, 0}, {m2, searcher(5, p5, 5, 0.5, 0)}), 1);
    n2.update(perceive(t, {p2.x, p2.y, 0}, {m1, searcher(5, p5, 5, 0.5, 0)}), 2);
    e1.update(1, 1.0, n1, t, kMaxAge);
    e2.update(2, 2.0, n2, t, kMaxAge);
  }
  EXPECT_EQ(e1.candidate(), 5u);
  EXPECT_EQ(e1.age(), 1);
  EXPECT_EQ(e2.candidate(), 5u);
  Tick dropped = 0;
  for (; t <= 100 && !dropped; ++t) {  // 5 is dead: 1 and 2 only hear each other
    const auto m1 = searcher(1, p1, e1.candidate(), e1.distance(), e1.age());
    const auto m2 = searcher(2, p2, e2.candidate(), e2.distance(), e2.age());
    n1.update(perceive(t, {p1.x, p1.y, 0}, {m2}), 1);
    n2.update(perceive(t, {p2.x, p2.y, 0}, {m1}), 2);
    e1.update(1, 1.0, n1, t, kMaxAge);
    e2.update(2, 2.0, n2, t, kMaxAge);
    if (e1.candidate() != 5u && e2.candidate() != 5u) dropped = t;
  }
  ASSERT_NE(dropped, 0) << "the dead candidate's minimum never aged out";
  EXPECT_LE(dropped, 6 + kMaxAge);
  // Then robot 1, the best live one, is everybody's candidate, and settles.
  for (Tick end = t + 3; t < end; ++t) {
    const auto m1 = searcher(1, p1, e1.candidate(), e1.distance(), e1.age());
    const auto m2 = searcher(2, p2, e2.candidate(), e2.distance(), e2.age());
    n1.update(perceive(t, {p1.x, p1.y, 0}, {m2}), 1);
    n2.update(perceive(t, {p2.x, p2.y, 0}, {m1}), 2);
    e1.update(1, 1.0, n1, t, kMaxAge);
    e2.update(2, 2.0, n2, t, kMaxAge);
  }
  EXPECT_EQ(e1.candidate(), 1u);
  EXPECT_EQ(e1.age(), 0);
  EXPECT_EQ(e2.candidate(), 1u);
  EXPECT_EQ(e2.age(), 1);
}

TEST(Allotment, ALabelLeftUntakenIsGivenUpAfterTheTimeoutAtThePlace) {
  const ShapeTable table(triangle_shape(), 1.0);
  Stigmergy s(0);
  NeighbourTable nb;
  put_label_holder(s, 1, 7);  // held
  put_label_freed(s, 3, 90);  // already freed: its own timeout runs, and it passes its grid's watch on
  // Label 2 was never claimed, nor were 6, 7 and 8 (label 3's grid, watched through the freed 3). At our
  // place since tick 100: nothing before 140, then those.
  EXPECT_TRUE(labels_left_untaken(table, 0, s, nb, 100, 139, 40).empty());
  EXPECT_EQ(labels_left_untaken(table, 0, s, nb, 100, 140, 40), (std::vector<int>{2, 6, 7, 8}));
  // A neighbour reporting label 2 as its own (its claim not yet in our stigmergy): not untaken.
  nb.update(perceive(140, {}, {shape_robot(8, 2, {0, -1}, {})}), 0);
  EXPECT_EQ(labels_left_untaken(table, 0, s, nb, 100, 140, 40), (std::vector<int>{6, 7, 8}));
  // Label 3 taken again: its grid is its new holder's to watch.
  put_label_holder(s, 3, 9);
  EXPECT_TRUE(labels_left_untaken(table, 0, s, nb, 100, 140, 40).empty());
}

// The seed took label 0 and died before anyone joined: a searcher hears no member of the shape any more, so
// it frees label 0 once its holder has been silent for label_timeout, and (the only searcher: its own
// candidate) is elected at label 0's known place.
TEST(Allotment, ASeedDeadBeforeAnyoneJoinedIsFreedAndReElectedAtItsPlace) {
  Mission mission = triangle_mission();
  PaperController c;
  c.init(mission, 3);
  const Pose2D pose{0.5, 0.5, 0.0};
  RobotMessage seed = shape_robot(9, 0, {0.0, 0.0}, {});  // no free labels: nobody can join it
  seed.entries = {{stig::key(stig::Ns::Labels, 0), 9, 1, 9}};
  Tick t = 1;
  for (; t <= 5; ++t) c.step(perceive(t, pose, {seed}));
  EXPECT_EQ(label_status(c.stigmergy(), 0).holder, 9u);
  EXPECT_EQ(c.state(), RobotState::Searching);
  const int timeout = c.params().label_timeout;
  Tick freed = 0, elected = 0;
  for (; t <= 200 && !elected; ++t) {
    const Command cmd = c.step(perceive(t, pose, {}));
    if (has_event(cmd, "label_freed 0 holder 9")) freed = t;
    if (has_event(cmd, "seed_elected 0")) elected = t;
  }
  EXPECT_EQ(freed, 5 + timeout);
  ASSERT_NE(elected, 0);
  EXPECT_LE(elected, freed + 1);
  EXPECT_EQ(c.label(), 0);
  EXPECT_EQ(c.state(), RobotState::Moving);
  EXPECT_NEAR(c.origin().x, 0.0, 1e-6);  // it goes to label 0's place, not where it stands
  EXPECT_NEAR(c.origin().y, 0.0, 1e-6);
}

}  // namespace
}  // namespace swarmform::controller
