// The pure parts of the stall rule (docs/wire.md "Liveliness, stalls and deaths"): a process's own clock of
// progress, the world's judgement of lost agents after its own stall, and refusals said once a second.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <sstream>

#include "common/dds/refusal_log.hpp"
#include "common/own_clock.hpp"
#include "common/process_state.hpp"
#include "world_server/stall_guard.hpp"
#include "world_server/stragglers.hpp"

namespace {

using swarmform::OwnClock;
using swarmform::server::StallGuard;

constexpr std::int64_t kMs = 1000000;

// The world's loop wakes every 100 ms from `from` for `d`: all of it awake time. Returns the last wake-up.
dds_time_t awake_for(StallGuard& g, dds_time_t from, dds_duration_t d) {
  for (dds_time_t t = from + DDS_MSECS(100); t <= from + d; t += DDS_MSECS(100)) g.observe(t);
  return from + d;
}

TEST(OwnClock, GapsBeyondTheLoopsPromiseAreLeftOutOfAwakeTime) {
  OwnClock c(250 * kMs);
  EXPECT_EQ(c.observe(1000 * kMs), 1000 * kMs);
  EXPECT_EQ(c.observe(1100 * kMs), 1100 * kMs);  // a normal wake-up
  EXPECT_EQ(c.stalls(), 0u);
  // Stopped for 3 s: only the promised 250 ms count as awake.
  EXPECT_EQ(c.observe(4100 * kMs), 1350 * kMs);
  EXPECT_EQ(c.stalls(), 1u);
  EXPECT_EQ(c.stalled_total(), 2750 * kMs);
  EXPECT_EQ(c.last_stall_end(), 1350 * kMs);
  EXPECT_EQ(c.observe(4200 * kMs), 1450 * kMs);
}

TEST(StallGuard, ALossIsADeathAtOnceUnlessTheWorldItselfJustStalled) {
  StallGuard g;
  g.observe(DDS_SECS(10));
  g.observe(DDS_SECS(10) + DDS_MSECS(100));
  EXPECT_FALSE(g.suspect(1));  // no own stall: a death now
  g.observe(DDS_SECS(14));     // the world was stopped ~4 s
  EXPECT_TRUE(g.suspect(2));   // right after it: only a suspect
  EXPECT_TRUE(g.suspect(3));
  std::vector<swarmform::dds::PublicationHandle> dead;
  g.observe(DDS_SECS(14) + DDS_MSECS(100));
  EXPECT_TRUE(g.clear(2));  // its liveliness came back in time: never dead
  EXPECT_FALSE(g.clear(2));
  g.expired(dead);
  EXPECT_TRUE(dead.empty());
  // Within the grace 3 is still only a suspect: its samples may be waiting out the reader's budget window
  // (a lease of grace buried a live agent whose burst after a 4 s stall was over its budget).
  dds_time_t t = awake_for(g, DDS_SECS(14) + DDS_MSECS(100), StallGuard::kGrace - DDS_MSECS(200));
  g.expired(dead);
  EXPECT_TRUE(dead.empty());
  EXPECT_GE(StallGuard::kGrace,
            swarmform::dds::ReceiveBudget::kSecond + swarmform::dds::kLivelinessAssertPeriod);
  t = awake_for(g, t, DDS_MSECS(200));
  g.expired(dead);  // 3 stayed lost for the grace: a death now
  ASSERT_EQ(dead.size(), 1u);
  EXPECT_EQ(dead[0], 3u);
  EXPECT_EQ(g.suspicions_cleared(), 1u);
  // Long after the stall, losses are deaths at once again.
  awake_for(g, t, DDS_SECS(2));
  EXPECT_FALSE(g.suspect(4));
}

TEST(StallGuard, AWriterThatWentAwayIsNotBroughtBackByItsOwnLateSamples) {
  // 1024 agents on 2 cores: 566 agents exited while the world stalled; their last claims, taken after their
  // writers' going, cleared the suspicion, and the world kept their robots alive (and missed) to the end.
  StallGuard g;
  g.observe(DDS_SECS(10));
  g.observe(DDS_SECS(14));          // the world was stopped ~4 s
  EXPECT_TRUE(g.suspect(5));        // its liveliness lapsed during the stall
  EXPECT_TRUE(g.suspect(5, true));  // then its writer went away
  EXPECT_TRUE(g.suspect(6, true));  // went away at once
  EXPECT_TRUE(g.suspect(7));        // only lapsed
  EXPECT_FALSE(g.clear(5));         // a sample it wrote before it went: no proof of life
  EXPECT_FALSE(g.clear(6));
  EXPECT_TRUE(g.suspected(5));
  EXPECT_TRUE(g.clear(7));  // a live one's sample still is
  std::vector<swarmform::dds::PublicationHandle> dead;
  awake_for(g, DDS_SECS(14), StallGuard::kGrace);
  g.expired(dead);
  std::sort(dead.begin(), dead.end());
  EXPECT_EQ(dead, (std::vector<swarmform::dds::PublicationHandle>{5, 6}));
  EXPECT_EQ(g.suspicions_cleared(), 1u);
}

TEST(StallGuard, ALostWriterHeardAgainThenGoneCountsAsADeathNotAComeback) {
  // A world stopped 12 s (past its agents' 10 s world timeout): 6 agents exited, their last samples cleared
  // their suspicion before their going was seen, and the end-of-run line said all 9 came back while
  // summary.json recorded 6 deaths.
  StallGuard g;
  g.observe(DDS_SECS(10));
  g.observe(DDS_SECS(22));  // the world was stopped ~12 s
  EXPECT_TRUE(g.suspect(5));
  EXPECT_TRUE(g.suspect(6));
  EXPECT_TRUE(g.clear(5));  // a sample written before it exited
  EXPECT_TRUE(g.clear(6));  // a live one
  EXPECT_EQ(g.suspicions_cleared(), 2u);
  EXPECT_TRUE(g.suspect(5, true));  // then its writer is seen gone
  std::vector<swarmform::dds::PublicationHandle> dead;
  awake_for(g, DDS_SECS(22), StallGuard::kGrace);
  g.expired(dead);
  ASSERT_EQ(dead, (std::vector<swarmform::dds::PublicationHandle>{5}));
  g.died(5);  // the server recorded its death
  EXPECT_EQ(g.suspicions_cleared(), 1u);
  EXPECT_EQ(g.suspects_died(), 1u);
  // A death long after the stall is not one of its losses, and a comeback then stays a comeback.
  awake_for(g, DDS_SECS(22) + StallGuard::kGrace, DDS_SECS(4));
  g.expired(dead);
  g.died(6);
  EXPECT_EQ(g.suspicions_cleared(), 1u);
  EXPECT_EQ(g.suspects_died(), 1u);
}

TEST(AgentProcess, AStoppedProcessIsPresentAKilledOneIsGoneEvenBeforeItIsReaped) {
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::pause();
    ::_exit(0);
  }
  using swarmform::process_state;
  using swarmform::ProcessState;
  EXPECT_EQ(process_state(child), ProcessState::Present);
  ASSERT_EQ(::kill(child, SIGSTOP), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, WUNTRACED), child);  // it is stopped now
  EXPECT_EQ(process_state(child), ProcessState::Present);  // stopped: slow, not dead
  ASSERT_EQ(::kill(child, SIGKILL), 0);
  ASSERT_EQ(::waitid(P_PID, static_cast<id_t>(child), nullptr, WEXITED | WNOWAIT),
            0);  // a zombie, not reaped
  EXPECT_EQ(process_state(child), ProcessState::Gone);
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_EQ(process_state(child), ProcessState::Gone);  // reaped: no such process
  EXPECT_EQ(process_state(0), ProcessState::Gone);
}

TEST(Stragglers, AreKeptUntilTheyComeBackAndCounted) {
  using swarmform::server::Stragglers;
  Stragglers s;
  EXPECT_TRUE(s.add(11, 3));
  EXPECT_FALSE(s.add(11, 3));  // already one
  EXPECT_TRUE(s.add(12, 4));
  EXPECT_TRUE(s.contains(11));
  EXPECT_FALSE(s.contains(13));
  EXPECT_EQ(s.remove(11), std::optional<swarmform::RobotId>(3));  // it came back
  EXPECT_FALSE(s.remove(11).has_value());
  EXPECT_FALSE(s.contains(11));
  EXPECT_EQ(s.size(), 1u);
  EXPECT_EQ(s.total(), 2u);
  EXPECT_TRUE(s.recheck_due(DDS_SECS(5)));
  EXPECT_FALSE(s.recheck_due(DDS_SECS(5) + Stragglers::kRecheck - 1));
  EXPECT_TRUE(s.recheck_due(DDS_SECS(5) + Stragglers::kRecheck));
}

TEST(StallGuard, ALossDuringAFloodIsOnlySuspectedUntilTheFloodHasPassed) {
  // Honest agents' liveliness can wait behind a flood's datagrams in the world's socket (the realtime flood
  // test lost 5 agents at once, 2 runs in 15): a loss within the suspect window of a refused sample waits for
  // a sample or the grace, as after the world's own stall.
  StallGuard g;
  g.observe(DDS_SECS(10));
  EXPECT_FALSE(g.suspect(1));  // no stall, no flood: a death now
  g.flooded();
  g.observe(DDS_SECS(10) + DDS_MSECS(100));
  EXPECT_TRUE(g.suspect(2));
  EXPECT_TRUE(g.suspected(2));
  EXPECT_TRUE(g.clear(2));  // its next command came in: never dead
  // The flood over for longer than the window: losses are deaths at once again.
  for (int i = 2; i <= 20; ++i) g.observe(DDS_SECS(10) + i * DDS_MSECS(100));
  EXPECT_FALSE(g.suspect(3));
}

TEST(RefusalLog, SaysEachWriterAtMostOnceASecondWithTheCount) {
  std::ostringstream out;
  swarmform::dds::RefusalLog log("robot_agent 3", out);
  for (int i = 0; i < 100; ++i) log.refuse(7, "writer 7", "packet", "not ours", i * 10 * kMs);  // 1 s
  log.refuse(7, "writer 7", "packet", "not ours", 1000 * kMs);
  log.refuse(8, "writer 8", "END packet", "not ours", 1000 * kMs);
  EXPECT_EQ(log.total(), 102u);
  EXPECT_EQ(out.str(),
            "robot_agent 3: refused 1 packet sample(s) from writer 7: not ours\n"
            "robot_agent 3: refused 100 packet sample(s) from writer 7: not ours\n"
            "robot_agent 3: refused 1 END packet sample(s) from writer 8: not ours\n");
}

}  // namespace
