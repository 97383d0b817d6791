// What the paper controller follows incrementally (bench/inprocess/README.md, P4) gives exactly what a full
// read gives: the stigmergy's change log, revision, counts and slot index, and BarrierWatch against
// read_barrier, under random puts, merges (with keys beyond the shape and lying values), copies and clears;
// MotionInputsWatch.
#include <gtest/gtest.h>

#include <random>
#include <set>
#include <vector>

#include "robot_agent/controller/allotment.hpp"
#include "robot_agent/controller/barrier.hpp"
#include "robot_agent/controller/motion_inputs_watch.hpp"
#include "robot_agent/controller/motion_phase.hpp"
#include "robot_agent/controller/stigmergy.hpp"

namespace swarmform::controller {
namespace {

// A random change of the labels or barrier namespace (or another), as robots make them.
void random_change(Stigmergy& s, std::mt19937_64& rng, int labels, Tick now) {
  std::uniform_int_distribution<int> what(0, 9), label(0, labels + 2), id(0, 40);
  const int w = what(rng);
  if (w < 3) {
    put_label_holder(s, label(rng), static_cast<RobotId>(id(rng)));
  } else if (w < 4) {
    put_label_freed(s, label(rng), now - std::uniform_int_distribution<Tick>(0, 30)(rng));
  } else if (w < 6) {
    barrier_enter(s, static_cast<RobotId>(id(rng)), label(rng));
  } else if (w < 7) {
    barrier_withdraw(s, static_cast<RobotId>(id(rng)));
  } else if (w < 8) {  // a neighbour's newer entry, sometimes with a value no honest robot writes
    const std::int64_t value = w % 2 ? std::int64_t{1} << 33 : id(rng);
    s.merge({stig::key(stig::Ns::Barrier, static_cast<std::uint32_t>(id(rng))), value,
             50u + static_cast<std::uint32_t>(now), 99});
  } else {
    s.put(stig::key(stig::Ns::Parents, static_cast<std::uint32_t>(id(rng))), id(rng) - 5);
  }
}

TEST(Incremental, BarrierWatchSaysWhatReadBarrierSays) {
  constexpr int kLabels = 12;
  constexpr int kTimeout = 10;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    std::mt19937_64 rng(seed);
    Stigmergy s(3);
    std::vector<BarrierWatch> watch(41);
    int passed = 0;
    for (Tick now = 100; now < 400; ++now) {
      const int changes = std::uniform_int_distribution<int>(0, 6)(rng);
      for (int k = 0; k < changes; ++k) random_change(s, rng, kLabels, now);
      if (now == 250) s = Stigmergy(s);  // a copy: the watches must rescan, not follow a foreign log
      if (now == 300 && seed % 5 == 0) s.clear();
      const BarrierView view = read_barrier(s, kLabels, now, kTimeout);
      for (RobotId self = 0; self <= 40; ++self) {
        const bool expected = view.passed() && view.members.contains(self);
        ASSERT_EQ(watch[self].passed_with(s, self, kLabels, now, kTimeout), expected)
            << "seed " << seed << " tick " << now << " robot " << self;
        passed += expected;
      }
    }
    (void)passed;
  }
}

TEST(Incremental, TheBarrierPassesWhenEveryLabelHoldersEntryNamesIt) {
  Stigmergy s(0);
  BarrierWatch watch;
  for (int l = 0; l < 4; ++l) put_label_holder(s, l, static_cast<RobotId>(l + 10));
  for (int l = 0; l < 3; ++l) barrier_enter(s, static_cast<RobotId>(l + 10), l);
  EXPECT_FALSE(watch.passed_with(s, 10, 4, 1, 5));
  barrier_enter(s, 13, 3);
  EXPECT_TRUE(watch.passed_with(s, 10, 4, 1, 5));
  EXPECT_FALSE(watch.passed_with(s, 99, 4, 1, 5));  // not a member
  put_label_freed(s, 3, 1);  // its holder's label freed: three valid entries of four labels...
  EXPECT_FALSE(watch.passed_with(s, 10, 4, 2, 5));
  EXPECT_TRUE(watch.passed_with(s, 10, 4, 6, 5));  // ...until the label is abandoned
}

TEST(Incremental, ChangeLogRevisionCountsAndLookupsFollowEveryChange) {
  std::mt19937_64 rng(7);
  Stigmergy s(1);
  Stigmergy::ChangeCursor cursor;
  std::span<const std::uint32_t> keys;
  EXPECT_FALSE(s.changes_since(cursor, keys));  // first call: rescan
  for (Tick now = 10; now < 300; ++now) {
    const auto before = s.revision();
    const auto digest = s.digest();
    const std::vector<StigmergyEntry> table = s.entries();
    random_change(s, rng, 20, now);
    // The log holds exactly the keys whose entry changed; the revision moves iff the table did.
    ASSERT_TRUE(s.changes_since(cursor, keys));
    std::set<std::uint32_t> changed(keys.begin(), keys.end());
    std::set<std::uint32_t> differ;
    for (const auto& e : s.entries()) {
      const StigmergyEntry* old = nullptr;
      for (const auto& o : table) {
        if (o.key == e.key) old = &o;
      }
      if (old == nullptr || old->value != e.value || old->version != e.version || old->writer != e.writer)
        differ.insert(e.key);
    }
    EXPECT_EQ(changed, differ);
    EXPECT_EQ(s.revision() != before, !differ.empty() || s.digest() != digest);
    // Counts and lookups against a plain scan.
    std::size_t non_negative = 0;
    for (const auto& e : s.entries()) {
      if (stig::ns_of(e.key) == static_cast<std::uint32_t>(stig::Ns::Labels) && e.value >= 0) ++non_negative;
      ASSERT_NE(s.entry(e.key), nullptr);
      EXPECT_EQ(s.entry(e.key)->value, e.value);
    }
    EXPECT_EQ(s.non_negative_in(stig::Ns::Labels), non_negative);
    EXPECT_EQ(s.entry(stig::key(stig::Ns::Leader, 7)), nullptr);
  }
  Stigmergy copy(s);
  EXPECT_NE(copy.revision(), s.revision());  // a copy is another series
  EXPECT_FALSE(copy.changes_since(cursor, keys));
}

// MotionInputsWatch (motion_inputs_watch.hpp): "changed" for a change of a watched namespace or a dead mark
// coming or going, and for nothing else: a live robot's parent entry changing is not an input of the members
// or of the leader/parent choice.
namespace watch {

std::uint32_t parents(RobotId id) {
  return stig::key(stig::Ns::Parents, id);
}

TEST(MotionInputsWatch, ChangesOnlyForWatchedNamespacesAndDeadMarks) {
  Stigmergy s;
  MotionInputsWatch w{stig::Ns::Boundary};
  EXPECT_TRUE(w.changed(s)) << "the first reading";
  EXPECT_FALSE(w.changed(s)) << "nothing since";
  s.put(parents(3), 7);  // robot 3 names parent 7: not watched
  s.put(stig::key(stig::Ns::Labels, 2), 5);
  EXPECT_FALSE(w.changed(s));
  s.put(stig::key(stig::Ns::Boundary, 4), 1);
  EXPECT_TRUE(w.changed(s));
  s.put(parents(3), motion::kDeadMark);  // robot 3 marked dead
  EXPECT_TRUE(w.changed(s));
  s.put(parents(3), motion::kDeadMark);  // again: no change of who is dead
  s.put(parents(5), 1);
  EXPECT_FALSE(w.changed(s));
  s.put(parents(3), 2);  // robot 3 back, naming a parent
  EXPECT_TRUE(w.changed(s));
  Stigmergy copy = s;  // another table (a copy): read afresh
  EXPECT_TRUE(w.changed(copy));
  EXPECT_FALSE(w.changed(copy));
}

TEST(MotionInputsWatch, NoticesADeathAmongManyOtherChangesAndAfterTheLogOverflowed) {
  Stigmergy s;
  MotionInputsWatch w{stig::Ns::Barrier, stig::Ns::Labels};
  ASSERT_TRUE(w.changed(s));
  for (int i = 0; i < 5000; ++i) s.put(parents(static_cast<RobotId>(i % 50)), i % 7);  // live parents only
  s.put(parents(9), motion::kDeadMark);
  EXPECT_TRUE(w.changed(s)) << "the log overflowed: a rescan says changed";
  for (int i = 0; i < 20; ++i) s.put(parents(static_cast<RobotId>(i % 5)), i % 3);
  EXPECT_FALSE(w.changed(s)) << "robot 9's mark was read in the rescan";
  s.put(parents(9), 4);
  EXPECT_TRUE(w.changed(s));
}

}  // namespace watch

}  // namespace
}  // namespace swarmform::controller
