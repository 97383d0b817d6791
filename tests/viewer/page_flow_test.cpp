// viewer/page_flow.hpp: which frames go to which page, live and in replay.
#include "viewer/page_flow.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace {

using swarmform::viewer::ClientId;
using swarmform::viewer::PageFlow;

bool sent_to(const std::vector<PageFlow::Send>& sends, ClientId c) {
  for (const PageFlow::Send& s : sends) {
    if (s.client == c) return true;
  }
  return false;
}

TEST(PageFlow, ASlowPageHasAtMostTwoFramesInFlightAndGetsTheNewestWhenItHasDrawn) {
  PageFlow flow;
  flow.opened(1, true);  // the frame of now, at once
  bool jump = false;
  EXPECT_FALSE(flow.drawn(1, jump));  // drew it: nothing waits
  // Frames 10 a second, the page drawing none of them for a while: two go, the rest wait (not queued in its
  // socket).
  int sent = 0;
  for (int i = 0; i < 50; ++i) sent += sent_to(flow.offer(false), 1) ? 1 : 0;
  EXPECT_EQ(sent, PageFlow::kInFlight);
  EXPECT_EQ(flow.in_flight(1), PageFlow::kInFlight);
  EXPECT_EQ(flow.skipped(), 47u);  // the first that waited went on waiting as the newest; 47 replaced
  // It drew one: the newest goes now, and it is full again.
  EXPECT_TRUE(flow.drawn(1, jump));
  EXPECT_FALSE(jump);
  EXPECT_EQ(flow.in_flight(1), PageFlow::kInFlight);
  // It drew the other two: nothing waits, the next frame goes at once.
  EXPECT_FALSE(flow.drawn(1, jump));
  EXPECT_FALSE(flow.drawn(1, jump));
  EXPECT_EQ(flow.in_flight(1), 0);
  EXPECT_TRUE(sent_to(flow.offer(false), 1));
}

TEST(PageFlow, APageThatKeepsUpGetsEveryFrame) {
  PageFlow flow;
  flow.opened(1, false);
  bool jump = false;
  for (int i = 0; i < 100; ++i) {
    ASSERT_TRUE(sent_to(flow.offer(false), 1)) << "frame " << i;
    EXPECT_FALSE(flow.drawn(1, jump));
  }
  EXPECT_EQ(flow.skipped(), 0u);
}

TEST(PageFlow, AClientThatNeverSaysDrawnGetsEveryFrame) {
  PageFlow flow;
  flow.opened(1, true);  // a script on the page's protocol
  flow.opened(2, true);  // a page
  bool jump = false;
  flow.drawn(2, jump);
  int to_script = 0, to_page = 0;
  for (int i = 0; i < 20; ++i) {
    const auto sends = flow.offer(false);
    to_script += sent_to(sends, 1) ? 1 : 0;
    to_page += sent_to(sends, 2) ? 1 : 0;
  }
  EXPECT_EQ(to_script, 20);
  EXPECT_EQ(to_page, PageFlow::kInFlight);
  flow.closed(2);
  EXPECT_FALSE(flow.drawn(2, jump));  // a closed page's late "drawn": nothing to send
}

TEST(PageFlow, APageThatSkippedAJumpGetsTheNextFrameAsAJump) {
  // Replay: a seek while the page draws, then the timeline plays on. The page's next frame is a played one,
  // but it must count as a jump (the page's ticks/s counts played frames: the seek's distance is not a rate).
  PageFlow flow;
  flow.opened(1, false);
  bool jump = false;
  flow.offer(false);
  flow.drawn(1, jump);
  flow.offer(false);
  flow.offer(false);                            // full
  EXPECT_FALSE(sent_to(flow.offer(true), 1));   // the seek's frame waits
  EXPECT_FALSE(sent_to(flow.offer(false), 1));  // replaced by the timeline's next, played
  ASSERT_TRUE(flow.drawn(1, jump));
  EXPECT_TRUE(jump);
  // Played frames after it are played again.
  flow.offer(false);
  ASSERT_TRUE(flow.drawn(1, jump));
  EXPECT_FALSE(jump);
}

}  // namespace
