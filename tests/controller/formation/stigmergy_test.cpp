// Virtual stigmergy: Buzz semantics, multi-hop flooding under loss, one conflict rule everywhere.
#include <gtest/gtest.h>

#include <limits>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <vector>

#include "robot_agent/controller/stigmergy.hpp"

namespace swarmform::controller {
namespace {

TEST(Stigmergy, PutBumpsTheVersionAndRecordsTheWriter) {
  Stigmergy s(5);
  s.put(stig::key(stig::Ns::Labels, 3), 5);
  EXPECT_EQ(s.entry(stig::key(stig::Ns::Labels, 3))->version, 1u);
  s.merge({stig::key(stig::Ns::Labels, 3), 9, 7, 9});
  s.put(stig::key(stig::Ns::Labels, 3), 5);
  const auto* e = s.entry(stig::key(stig::Ns::Labels, 3));
  EXPECT_EQ(e->version, 8u);
  EXPECT_EQ(e->writer, 5u);
  EXPECT_EQ(e->value, 5);
}

TEST(Stigmergy, MergeKeepsTheNewerEntry) {
  Stigmergy s(1);
  const std::uint32_t k = 42;
  EXPECT_TRUE(s.merge({k, 10, 2, 3}));
  EXPECT_FALSE(s.merge({k, 11, 1, 9}));  // older version loses even with a higher writer
  EXPECT_TRUE(s.merge({k, 12, 2, 4}));   // same version: the higher writer wins
  EXPECT_FALSE(s.merge({k, 13, 2, 2}));
  EXPECT_TRUE(s.merge({k, 14, 2, 4}));   // same version and writer: the higher value
  EXPECT_FALSE(s.merge({k, 14, 2, 4}));  // identical: no change
  EXPECT_EQ(*s.get(k), 14);
}

TEST(Stigmergy, DigestIsTheSameForTheSameTableWhateverTheOrderAndChangesWithAnyEntry) {
  const std::vector<StigmergyEntry> entries = {{stig::key(stig::Ns::Labels, 0), 4, 2, 4},
                                               {stig::key(stig::Ns::Labels, 1), 7, 1, 7},
                                               {stig::key(stig::Ns::Barrier, 4), 0, 1, 4},
                                               {stig::key(stig::Ns::Labels, 1), 8, 2, 8}};
  Stigmergy a(1);
  Stigmergy b(2);
  EXPECT_EQ(a.digest(), 0u);
  a.merge_all(entries);
  b.merge_all(std::vector<StigmergyEntry>(entries.rbegin(), entries.rend()));
  EXPECT_NE(a.digest(), 0u);
  EXPECT_EQ(a.digest(), b.digest());  // the same entries won, in another order
  // Each field of an entry moves the digest.
  for (int field = 0; field < 3; ++field) {
    StigmergyEntry e = *a.entry(stig::key(stig::Ns::Labels, 0));
    if (field == 0) e.version += 1;
    if (field == 1) e.writer += 1;
    if (field == 2) e.value += 1;
    Stigmergy c = a;
    ASSERT_TRUE(c.merge(e));
    EXPECT_NE(c.digest(), a.digest()) << "field " << field;
  }
  // A put changes it; clear resets it.
  Stigmergy d = a;
  d.put(stig::key(stig::Ns::Barrier, 1), 3);
  EXPECT_NE(d.digest(), a.digest());
  d.clear();
  EXPECT_EQ(d.digest(), 0u);
  // The digest is the table's, however it got there: rebuilt from the entries alone it matches.
  Stigmergy e(9);
  e.merge_all(a.entries());
  EXPECT_EQ(e.digest(), a.digest());
}

TEST(Stigmergy, NamespacesAreKeyRanges) {
  Stigmergy s(1);
  s.put(stig::key(stig::Ns::Barrier, 0), 4);
  s.put(stig::key(stig::Ns::Barrier, 65535), 5);
  s.put(stig::key(stig::Ns::Labels, 0), 1);
  const auto barrier = s.in_namespace(stig::Ns::Barrier);
  ASSERT_EQ(barrier.size(), 2u);
  EXPECT_EQ(barrier.at(65535).value, 5);
  EXPECT_EQ(s.in_namespace(stig::Ns::Labels).size(), 1u);
  EXPECT_EQ(s.in_namespace(stig::Ns::Parents).size(), 0u);
}

TEST(Stigmergy, OutgoingSendsChangesFirstThenRoundRobin) {
  Stigmergy s(1);
  for (std::uint32_t i = 0; i < 10; ++i) s.merge({i, 0, 1, 2});
  for (int i = 0; i < Stigmergy::kResendCount; ++i) (void)s.outgoing(100);  // drain the pending changes
  s.put(7, 99);
  const auto first = s.outgoing(3);
  ASSERT_EQ(first.size(), 3u);
  EXPECT_EQ(first[0].key, 7u);
  // The round-robin visits every key within a few messages.
  std::set<std::uint32_t> seen;
  for (int i = 0; i < 10; ++i) {
    for (const auto& e : s.outgoing(2)) seen.insert(e.key);
  }
  EXPECT_EQ(seen.size(), 10u);
}

// More changes than a message carries, and the low keys changing again all the time (hundreds of holders'
// heartbeats): every changed entry still goes out, the longest-waiting first. Sent in key order, the high
// keys starved for as long as the low ones kept changing.
TEST(Stigmergy, ChangedEntriesGoOutInTurnWhenMoreChangedThanAMessageCarries) {
  Stigmergy s(1);
  for (std::uint32_t k = 0; k < 100; ++k) s.put(k, 1);
  std::map<std::uint32_t, int> sends;
  for (int message = 0; message < 15; ++message) {
    for (std::uint32_t k = 0; k < 10; ++k) s.put(k, message);  // the low keys change every tick
    std::set<std::uint32_t> in_message;
    for (const auto& e : s.outgoing(24)) {
      EXPECT_TRUE(in_message.insert(e.key).second) << "key " << e.key << " twice in one message";
      ++sends[e.key];
    }
  }
  for (std::uint32_t k = 10; k < 100; ++k) EXPECT_GE(sends[k], 1) << "key " << k << " never sent";
}

// A chain of robots, each hearing only its two neighbours, every copy lost with probability `loss`.
struct Chain {
  explicit Chain(int n, double loss_probability, std::uint32_t seed) : loss(loss_probability), rng(seed) {
    for (int i = 0; i < n; ++i) robots.emplace_back(static_cast<RobotId>(i));
  }
  void tick(std::size_t quota) {
    std::vector<std::vector<StigmergyEntry>> sent;
    for (auto& r : robots) sent.push_back(r.outgoing(quota));
    std::bernoulli_distribution lost(loss);
    for (std::size_t i = 0; i < robots.size(); ++i) {
      for (std::size_t j : {i - 1, i + 1}) {
        if (j >= robots.size() || lost(rng)) continue;
        robots[j].merge_all(sent[i]);
      }
    }
  }
  bool agree(std::uint32_t key) const {
    for (const auto& r : robots) {
      if (!r.entry(key) || !(*r.entry(key) == *robots.front().entry(key))) return false;
    }
    return true;
  }
  double loss;
  std::mt19937 rng;
  std::vector<Stigmergy> robots;
};

TEST(Stigmergy, FloodsAlongAMultiHopChainWithTwentyPercentLoss) {
  for (std::uint32_t seed = 1; seed <= 5; ++seed) {
    Chain chain(12, 0.2, seed);
    // Many keys, more than one message carries, so the round-robin has to do its part.
    for (std::uint32_t k = 0; k < 40; ++k) chain.robots[k % 12].put(1000 + k, k);
    int ticks = 0;
    auto all_agree = [&] {
      for (std::uint32_t k = 0; k < 40; ++k) {
        if (!chain.agree(1000 + k)) return false;
      }
      return true;
    };
    while (!all_agree() && ticks < 400) {
      chain.tick(8);
      ++ticks;
    }
    EXPECT_LT(ticks, 400) << "seed " << seed;
    EXPECT_EQ(chain.robots.back().size(), 40u);
  }
}

TEST(Stigmergy, AConflictResolvesTheSameWayOnEveryRobot) {
  for (std::uint32_t seed = 1; seed <= 10; ++seed) {
    Chain chain(10, 0.2, seed);
    const std::uint32_t key = stig::key(stig::Ns::Labels, 4);
    // The two ends claim label 4 at the same version; a robot in the middle claims it too, later.
    chain.robots[0].put(key, 0);
    chain.robots[9].put(key, 9);
    for (int t = 0; t < 3; ++t) chain.tick(4);
    chain.robots[5].put(key, 5);  // version 1 or 2 depending on what reached it
    for (int t = 0; t < 300 && !chain.agree(key); ++t) chain.tick(4);
    ASSERT_TRUE(chain.agree(key)) << "seed " << seed;
    const auto& e = *chain.robots[3].entry(key);
    // Whatever the order of arrival: the highest (version, writer, value) everyone has seen.
    const StigmergyEntry a{key, 0, 1, 0}, b{key, 9, 1, 9};
    EXPECT_FALSE(stigmergy_newer(a, e));
    EXPECT_FALSE(stigmergy_newer(b, e));
    if (e.version == 1) {
      EXPECT_EQ(e.writer, 9u);  // equal versions: the higher writer
    }
  }
}

// The send queue kept beside the table (a sends-left count per entry and a FIFO of keys) against the rule
// written the plain way, as it was before: a std::map of key -> sends left and one of turn -> key, the
// longest-waiting first, then round-robin over the whole table. Random puts, merges (most of them stale),
// messages of random sizes, copies and clears, with keys inside and outside the direct slot index (namespaces
// 16 and up, indices of 8192 and up): every message and every table must be the same.
class ReferenceStigmergy {
 public:
  explicit ReferenceStigmergy(RobotId self) : self_(self) {}
  void put(std::uint32_t key, std::int64_t value) {
    const auto it = table_.find(key);
    store({key, value, it == table_.end() ? 1u : it->second.version + 1u, self_});
  }
  void merge(const StigmergyEntry& e) {
    const auto it = table_.find(e.key);
    if (it == table_.end() || stigmergy_newer(e, it->second)) store(e);
  }
  std::vector<StigmergyEntry> outgoing(std::size_t max_entries) {
    std::vector<StigmergyEntry> out;
    const std::size_t waiting = queue_.size();
    for (std::size_t i = 0; i < waiting && out.size() < max_entries; ++i) {
      const auto front = queue_.begin();
      const std::uint32_t key = front->second;
      queue_.erase(front);
      out.push_back(table_.at(key));
      auto it = pending_.find(key);
      if (--it->second <= 0) {
        pending_.erase(it);
      } else {
        queue_.emplace(next_turn_++, key);
      }
    }
    const std::size_t n_changed = out.size();
    const auto chosen = [&](std::uint32_t key) {
      for (std::size_t i = 0; i < n_changed; ++i) {
        if (out[i].key == key) return true;
      }
      return false;
    };
    if (!table_.empty() && out.size() < max_entries) {
      auto it = table_.lower_bound(cursor_);
      for (std::size_t visited = 0; visited < table_.size() && out.size() < max_entries; ++visited) {
        if (it == table_.end()) it = table_.begin();
        if (!chosen(it->first)) out.push_back(it->second);
        ++it;
      }
      cursor_ = it == table_.end() ? 0u : it->first;
    }
    return out;
  }
  void clear() { *this = ReferenceStigmergy(self_); }
  std::optional<std::int64_t> get(std::uint32_t key) const {
    const auto it = table_.find(key);
    return it == table_.end() ? std::nullopt : std::optional<std::int64_t>(it->second.value);
  }
  std::vector<StigmergyEntry> entries() const {
    std::vector<StigmergyEntry> out;
    for (const auto& [key, e] : table_) out.push_back(e);
    return out;
  }

 private:
  void store(const StigmergyEntry& e) {
    table_[e.key] = e;
    auto [it, inserted] = pending_.try_emplace(e.key, Stigmergy::kResendCount);
    if (inserted) {
      queue_.emplace(next_turn_++, e.key);
    } else {
      it->second = Stigmergy::kResendCount;
    }
  }
  RobotId self_;
  std::map<std::uint32_t, StigmergyEntry> table_;
  std::map<std::uint32_t, int> pending_;
  std::map<std::uint64_t, std::uint32_t> queue_;
  std::uint64_t next_turn_ = 0;
  std::uint32_t cursor_ = 0;
};

TEST(Stigmergy, TheSendQueueSendsWhatThePlainRuleSends) {
  for (std::uint32_t seed = 1; seed <= 20; ++seed) {
    std::mt19937 rng(seed);
    Stigmergy fast(3);
    ReferenceStigmergy plain(3);
    // Keys: labels and barrier entries of a large shape, a few beyond the slot index.
    std::vector<std::uint32_t> keys;
    for (std::uint32_t i = 0; i < 300; ++i) keys.push_back(stig::key(stig::Ns::Labels, i * 7));
    for (std::uint32_t i = 0; i < 100; ++i) keys.push_back(stig::key(stig::Ns::Barrier, i));
    for (std::uint32_t i = 0; i < 20; ++i) keys.push_back(stig::key(stig::Ns::Labels, 8192 + i * 100));
    for (std::uint32_t i = 0; i < 20; ++i) keys.push_back(stig::key(17u + i % 3, i));
    std::uniform_int_distribution<std::size_t> pick(0, keys.size() - 1);
    std::uniform_int_distribution<int> action(0, 99), small(0, 5), quota(0, 30);
    std::vector<StigmergyEntry> fast_sent, plain_sent;
    for (int step = 0; step < 4000; ++step) {
      const int a = action(rng);
      if (a < 20) {
        const std::uint32_t key = keys[pick(rng)];
        const std::int64_t value = small(rng) - 1;
        fast.put(key, value);
        plain.put(key, value);
      } else if (a < 75) {
        // Entries heard from a neighbour: versions near the ones held, so some win and most lose.
        const int n = small(rng) * 4;
        std::vector<StigmergyEntry> heard;
        for (int i = 0; i < n; ++i) {
          const std::uint32_t key = keys[pick(rng)];
          const auto* held = fast.entry(key);
          const std::uint32_t version =
              (held ? held->version : 0u) + static_cast<std::uint32_t>(small(rng)) / 2u;
          // Now and then the lowest entry there is (version 0, writer 0, the lowest value): only a forged
          // message carries it, and it must still be taken where the key is absent.
          if (small(rng) == 0 && small(rng) == 0) {
            heard.push_back({key, std::numeric_limits<std::int64_t>::min(), 0u, 0u});
            continue;
          }
          heard.push_back({key, small(rng) - 1, std::max(version, 1u), static_cast<RobotId>(small(rng))});
        }
        fast.merge_all(heard);
        for (const auto& e : heard) plain.merge(e);
      } else if (a < 98) {
        const auto q = static_cast<std::size_t>(quota(rng));
        ASSERT_EQ(fast.outgoing(q), plain.outgoing(q)) << "seed " << seed << " step " << step;
      } else if (a == 98) {
        Stigmergy copy = fast;  // a copy sends what the original would
        fast = copy;
      } else {
        fast.clear();
        plain.clear();
      }
      ASSERT_EQ(fast.entries(), plain.entries()) << "seed " << seed << " step " << step;
      const std::uint32_t key = keys[pick(rng)];
      ASSERT_EQ(fast.get(key), plain.get(key)) << "seed " << seed << " step " << step;
    }
  }
}

}  // namespace
}  // namespace swarmform::controller
