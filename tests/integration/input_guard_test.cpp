// InputGuard (docs/faults.md): budgets per writer, reports throttled to one a second per writer and kind,
// and what it holds for writers bounded.
#include <gtest/gtest.h>

#include "world_server/input_guard.hpp"

namespace {

using swarmform::server::Abuse;
using swarmform::server::GuardLimits;
using swarmform::server::InputGuard;

constexpr std::int64_t kS = InputGuard::kSecond;
constexpr std::int64_t kT0 = 1000 * kS;

TEST(InputGuard, EachWriterHasItsOwnCommandBudgetAWindow) {
  InputGuard g(GuardLimits{3, 2});
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(g.admit_command(7, 10, kT0));
  EXPECT_FALSE(g.admit_command(7, 10, kT0));  // the flooder is over its budget for tick 10...
  EXPECT_TRUE(g.admit_command(8, 10, kT0));   // ...which costs the owner (another writer) nothing
  EXPECT_TRUE(g.admit_command(7, 11, kT0));   // a new window, a new budget
  EXPECT_TRUE(g.admit_claim(7, kT0));
  EXPECT_TRUE(g.admit_claim(7, kT0 + 1));
  EXPECT_FALSE(g.admit_claim(7, kT0 + 2));
  EXPECT_TRUE(g.admit_claim(7, kT0 + kS));
}

TEST(InputGuard, ReportsAreLoggedOnceASecondWithTheirCount) {
  InputGuard g(GuardLimits{});
  EXPECT_EQ(g.report(5, Abuse::SpoofedCommand, kT0), 1u);  // the first is logged at once
  for (int i = 1; i < 1000; ++i) EXPECT_FALSE(g.report(5, Abuse::SpoofedCommand, kT0 + i * 1000));
  EXPECT_EQ(g.report(5, Abuse::RefusedClaim, kT0 + 5), 1u);        // another kind has its own throttle
  EXPECT_EQ(g.report(6, Abuse::SpoofedCommand, kT0 + 6), 1u);      // and another writer
  EXPECT_EQ(g.report(5, Abuse::SpoofedCommand, kT0 + kS), 1000u);  // the 999 unlogged plus this one
  EXPECT_EQ(g.total(Abuse::SpoofedCommand), 1002u);                // writer 5: 1001, writer 6: 1
  EXPECT_EQ(g.total(Abuse::RefusedClaim), 1u);
  // Sub-kinds (a command's verdicts) each get their first report logged.
  EXPECT_EQ(g.report(5, Abuse::BadCommand, kT0, 2), 1u);
  EXPECT_EQ(g.report(5, Abuse::BadCommand, kT0, 3), 1u);
  EXPECT_FALSE(g.report(5, Abuse::BadCommand, kT0 + 1, 2));
  EXPECT_EQ(g.total(Abuse::BadCommand), 3u);
}

TEST(InputGuard, WritersNotSeenForAWhileAreForgotten) {
  InputGuard g(GuardLimits{});
  for (std::uint64_t w = 1; w <= 1000; ++w) g.admit_claim(w, kT0);
  EXPECT_EQ(g.writers_tracked(), 1000u);
  g.forget(1);
  EXPECT_EQ(g.writers_tracked(), 999u);
  g.admit_claim(5000, kT0 + InputGuard::kForgetAfter + 2 * kS);
  EXPECT_EQ(g.writers_tracked(), 1u);
}

}  // namespace
