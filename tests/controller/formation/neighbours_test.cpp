// The neighbour table (Buzz's `neighbors`): id order, expiry, the tick last heard after expiry, forged
// senders, and the entries it leaves out when the sender's stigmergy digest is the receiver's own.
#include <gtest/gtest.h>

#include <map>
#include <optional>
#include <random>
#include <vector>

#include "robot_agent/controller/message.hpp"
#include "robot_agent/controller/neighbours.hpp"

namespace swarmform::controller {
namespace {

RobotMessage message_from(RobotId id, std::uint64_t digest = 0) {
  RobotMessage m;
  m.sender = id;
  m.state = RobotState::Searching;
  m.pose = {static_cast<double>(id), 0.0, 0.0};
  m.table_digest = digest;
  m.entries = {{0x20000u + id, 5, 1, id}, {0x20100u + id, 6, 2, id}};
  return m;
}

Perception heard(Tick tick, const std::vector<RobotMessage>& messages, double range = 1.0) {
  Perception p;
  p.tick = tick;
  for (const auto& m : messages) p.messages.push_back({m.sender, range, 0.5, encode_message(m)});
  return p;
}

std::vector<RobotId> ids(const NeighbourTable& t) {
  std::vector<RobotId> out;
  for (const auto& [id, n] : t.all()) out.push_back(id);
  return out;
}

TEST(NeighbourTable, IteratesInIdOrderWhateverOrderTheyWereHeard) {
  NeighbourTable t(20);
  t.update(heard(1, {message_from(9), message_from(3), message_from(7)}), 0);
  t.update(heard(2, {message_from(5), message_from(1), message_from(9)}), 0);
  EXPECT_EQ(ids(t), (std::vector<RobotId>{1, 3, 5, 7, 9}));
  ASSERT_NE(t.find(7), nullptr);
  EXPECT_EQ(t.find(7)->message.pose.x, 7.0);
  EXPECT_EQ(t.find(4), nullptr);
  EXPECT_TRUE(t.fresh(9));
  EXPECT_FALSE(t.fresh(3));  // heard at tick 1, not 2
}

TEST(NeighbourTable, KeepsEachMessageWithItsSenderThroughInsertsAndExpiries) {
  // Inserts before them and expiries shift their places in the table.
  NeighbourTable t(3);
  std::vector<RobotId> heard_ids = {513, 257, 1};
  for (Tick tick = 1; tick <= 12; ++tick) {
    if (tick == 4) heard_ids.push_back(0);     // an insert in front of all of them
    if (tick == 6) heard_ids = {513, 1, 769};  // 257 and 0 fall silent and expire at 9
    std::vector<RobotMessage> messages;
    for (RobotId id : heard_ids) {
      RobotMessage m = message_from(id);
      m.pose.y = static_cast<double>(tick);
      messages.push_back(m);
    }
    t.update(heard(tick, messages), 999);
    for (RobotId id : heard_ids) {
      const Neighbour* n = t.find(id);
      ASSERT_NE(n, nullptr) << "id " << id << " tick " << tick;
      EXPECT_EQ(n->message.sender, id);
      EXPECT_EQ(n->message.pose.x, static_cast<double>(id));
      EXPECT_EQ(n->message.pose.y, static_cast<double>(tick));
    }
  }
  EXPECT_EQ(ids(t), (std::vector<RobotId>{1, 513, 769}));
}

TEST(NeighbourTable, NewcomersHeardAmongKnownNeighboursEachGetTheirOwnMessage) {
  // Newcomers land before, between and after the known ids in one tick, one of them heard twice (its second
  // copy wins), so every known neighbour's place moves while its message is being read.
  NeighbourTable t(20);
  t.update(heard(1, {message_from(10), message_from(20)}), 0);
  std::vector<RobotMessage> messages = {message_from(25), message_from(20), message_from(5),
                                        message_from(15), message_from(10), message_from(5)};
  for (std::size_t k = 0; k < messages.size(); ++k) messages[k].pose.y = static_cast<double>(k);
  t.update(heard(2, messages), 0);
  EXPECT_EQ(ids(t), (std::vector<RobotId>{5, 10, 15, 20, 25}));
  const std::vector<std::pair<RobotId, double>> expected = {
      {25, 0.0}, {20, 1.0}, {15, 3.0}, {10, 4.0}, {5, 5.0}};
  for (const auto& [id, y] : expected) {
    ASSERT_NE(t.find(id), nullptr) << id;
    EXPECT_EQ(t.find(id)->message.sender, id);
    EXPECT_EQ(t.find(id)->message.pose.y, y) << id;
    EXPECT_EQ(t.find(id)->last_heard, Tick{2});
  }
}

TEST(NeighbourTable, ExpiresTheSilentButRemembersWhenTheyWereLastHeard) {
  NeighbourTable t(20);
  t.update(heard(10, {message_from(3), message_from(4)}), 0);
  t.update(heard(29, {message_from(4)}), 0);
  EXPECT_EQ(ids(t), (std::vector<RobotId>{3, 4}));  // 19 ticks silent: still there
  t.update(heard(30, {message_from(4)}), 0);
  EXPECT_EQ(ids(t), (std::vector<RobotId>{4}));  // 20 ticks silent: gone
  EXPECT_EQ(t.last_heard(3), Tick{10});          // but remembered
  EXPECT_EQ(t.last_heard(4), Tick{30});
  EXPECT_FALSE(t.last_heard(5).has_value());
  t.update(heard(31, {message_from(3)}), 0);  // back again
  EXPECT_EQ(t.last_heard(3), Tick{31});
}

TEST(NeighbourTable, DropsOwnAndForgedAndUndecodableMessages) {
  NeighbourTable t(20);
  Perception p = heard(1, {message_from(0), message_from(2)});
  p.messages[1].sender = 8;  // robot 8's message claims to be robot 2's
  p.messages.push_back({6, 1.0, 0.0, {1, 2, 3}});
  t.update(p, 0);
  EXPECT_TRUE(t.all().empty());
  EXPECT_EQ(t.dropped_messages(), 2u);  // our own is skipped, not counted
}

TEST(NeighbourTable, ABadMessageFromAKnownNeighbourDropsItAsLastHeardAtItsLastGoodTick) {
  NeighbourTable t(20);
  t.update(heard(5, {message_from(2), message_from(3)}), 0);
  Perception p = heard(6, {message_from(2), message_from(3)});
  p.messages[0].data.push_back(0);  // a trailing byte: refused after the message was read into 2's entry
  p.messages[1].sender = 4;         // robot 4's message claims to be robot 3's
  t.update(p, 0);
  EXPECT_EQ(t.dropped_messages(), 2u);
  EXPECT_EQ(ids(t), (std::vector<RobotId>{3}));  // 3 itself was not heard at 6, but is still live
  EXPECT_EQ(t.last_heard(2), Tick{5});           // remembered at its last good message
  EXPECT_FALSE(t.last_heard(4).has_value());     // a forger never heard well is not remembered
  EXPECT_EQ(t.find(3)->message.sender, 3u);
  EXPECT_EQ(t.find(3)->last_heard, Tick{5});
  t.update(heard(7, {message_from(2)}), 0);  // a good message brings it back
  ASSERT_NE(t.find(2), nullptr);
  EXPECT_EQ(t.find(2)->message.pose.x, message_from(2).pose.x);
}

std::vector<StigmergyEntry> entries_of(const NeighbourTable& t, RobotId id) {
  const auto heard = t.entries_heard(*t.find(id));
  return {heard.begin(), heard.end()};
}

TEST(NeighbourTable, LeavesOutTheEntriesOfATableWithTheReceiversOwnDigest) {
  NeighbourTable t(20);
  t.update(heard(1, {message_from(2, 77), message_from(3, 78), message_from(4, 0)}), 0, 77);
  EXPECT_TRUE(entries_of(t, 2).empty());                     // same digest: nothing to learn
  EXPECT_EQ(entries_of(t, 3), message_from(3, 78).entries);  // another table
  EXPECT_EQ(entries_of(t, 4), message_from(4).entries);      // no digest
  t.update(heard(2, {message_from(2, 77)}), 0);              // 0: keep every message's entries
  EXPECT_EQ(entries_of(t, 2), message_from(2).entries);
  EXPECT_TRUE(entries_of(t, 3).empty());  // not heard at tick 2: no entries of this tick
}

TEST(NeighbourTable, KeepsEachNeighboursEntriesOfThisTickApartAndDropsThoseOfABadMessage) {
  NeighbourTable t(20);
  Perception p = heard(1, {message_from(5), message_from(3), message_from(9)});
  p.messages[2].data.push_back(0);  // 9's message has a trailing byte: refused after its entries were read
  t.update(p, 0);
  EXPECT_EQ(entries_of(t, 5), message_from(5).entries);
  EXPECT_EQ(entries_of(t, 3), message_from(3).entries);
  EXPECT_EQ(t.find(9), nullptr);
}

// IdTicks (the expired neighbours' ticks, an open-addressing table) finds what a std::map of the same sets
// finds: random ids, clustered and spread (0, the largest id, ids that collide in a small table), re-sets of
// an id, growth through many sizes, and clears.
// A radio that loses packets in bursts: a link that came back from a 15-tick loss is given twice that before
// its neighbour is taken for gone (neighbours.hpp, learn_loss_gaps); without learning the timeout stands.
TEST(NeighbourTable, ALinkThatCameBackFromALongLossKeepsItsNeighbourTwiceThatLong) {
  NeighbourTable learning(20);
  learning.learn_loss_gaps(2.4, 60);
  NeighbourTable fixed(20);
  for (NeighbourTable* t : {&learning, &fixed}) {
    t->update(heard(1, {message_from(3)}), 0);
    t->update(heard(17, {message_from(3)}), 0);  // ticks 2..16 lost: a gap of 15
    t->update(heard(18, {message_from(3)}), 0);
    t->update(heard(18 + 25, {}), 0);  // silent 25 ticks
  }
  EXPECT_EQ(learning.silence_limit(3), 30u);
  EXPECT_EQ(fixed.silence_limit(3), 20u);
  EXPECT_EQ(ids(learning), (std::vector<RobotId>{3}));
  EXPECT_TRUE(ids(fixed).empty());
  learning.update(heard(18 + 30, {}), 0);
  EXPECT_TRUE(ids(learning).empty()) << "silent for its limit: gone";
  EXPECT_EQ(learning.last_heard(3), Tick{18});
}

// Only a loss the neighbour cannot have spent out of radio range is learned: heard well inside the range
// before and after it, and shorter than the way out of range and back.
TEST(NeighbourTable, ASilenceNearTheRangesEdgeOrLongerThanTheWayOutAndBackIsNotLearned) {
  NeighbourTable near_edge(20);
  near_edge.learn_loss_gaps(2.4, 60);
  near_edge.update(heard(1, {message_from(3)}, 2.9), 0);
  near_edge.update(heard(17, {message_from(3)}, 1.0), 0);
  EXPECT_EQ(near_edge.silence_limit(3), 20u) << "last heard beyond 2.4 m: it may have been out of range";
  NeighbourTable slow_way(20);
  slow_way.learn_loss_gaps(2.4, 10);
  slow_way.update(heard(1, {message_from(3)}), 0);
  slow_way.update(heard(17, {message_from(3)}), 0);
  EXPECT_EQ(slow_way.silence_limit(3), 20u) << "15 ticks > 10: long enough to go out of range and back";
  NeighbourTable short_loss(20);
  short_loss.learn_loss_gaps(2.4, 60);
  short_loss.update(heard(1, {message_from(3)}), 0);
  short_loss.update(heard(6, {message_from(3)}), 0);
  EXPECT_EQ(short_loss.silence_limit(3), 20u) << "twice a 4-tick loss is within the timeout";
}

TEST(IdTicks, FindsWhatAMapFinds) {
  std::mt19937 rng(11);
  IdTicks fast;
  std::map<RobotId, Tick> plain;
  std::uniform_int_distribution<int> action(0, 999), kind(0, 3);
  std::uniform_int_distribution<RobotId> small(0, 300), any(0, 0xFFFFFFFFu);
  std::uniform_int_distribution<Tick> tick(0, 1000000);
  const auto some_id = [&] {
    switch (kind(rng)) {
      case 0:
        return any(rng);
      case 1:
        return small(rng) * 16u;  // the same low bits
      case 2:
        return static_cast<RobotId>(kind(rng) == 0 ? 0u : 0xFFFFFFFFu);
      default:
        return small(rng);
    }
  };
  for (int step = 0; step < 60000; ++step) {
    const int a = action(rng);
    if (a == 0 && step % 7 == 0) {
      fast.clear();
      plain.clear();
    } else if (a < 400) {
      const RobotId id = some_id();
      const Tick t = tick(rng);
      fast.set(id, t);
      plain[id] = t;
    }
    const RobotId id = some_id();
    const auto it = plain.find(id);
    ASSERT_EQ(fast.find(id), it == plain.end() ? std::nullopt : std::optional<Tick>(it->second))
        << "step " << step << " id " << id;
    ASSERT_EQ(fast.size(), plain.size()) << "step " << step;
  }
}

}  // namespace
}  // namespace swarmform::controller
