// The label timeout scaled to the shape (label_timeout.hpp): small shapes keep the configured one; large ones
// get the time their holders' heartbeats need to fit the messages and cross the shape.
#include <gtest/gtest.h>

#include "robot_agent/controller/label_timeout.hpp"
#include "robot_agent/controller/message.hpp"
#include "robot_agent/controller/stigmergy.hpp"

namespace swarmform::controller {
namespace {

ShapeMatrix block(int n) {
  return ShapeMatrix{n, n, std::vector<int>(static_cast<std::size_t>(n * n), 0)};
}

TEST(LabelTimeout, SmallShapesKeepTheConfiguredTimeout) {
  // The paper's 9 labels and shapes/' largest (30): the default 40 ticks, unchanged.
  EXPECT_EQ(scaled_label_timeout(40, 9, 24, 2), 40);
  EXPECT_EQ(scaled_label_timeout(40, 30, 24, 3), 40);
  EXPECT_EQ(scaled_label_timeout(500, 1024, 24, 15), 768);  // a longer configured one stays if longer
  EXPECT_EQ(scaled_label_timeout(1000, 1024, 24, 15), 1000);
}

TEST(LabelTimeout, HeartbeatsOfEveryHolderFitHalfOfEveryMessage) {
  for (const int labels : {100, 400, 1024, 5000}) {
    for (const std::size_t entries : {std::size_t{4}, std::size_t{24}}) {
      const int timeout = scaled_label_timeout(40, labels, entries, 1);
      const double period = timeout / 3;  // the heartbeat period (paper_controller.hpp)
      const double per_message = labels * Stigmergy::kResendCount / period;
      EXPECT_LE(per_message, static_cast<double>(entries) / 2.0 + 1e-9)
          << labels << " labels, " << entries << " entries";
    }
  }
  EXPECT_EQ(scaled_label_timeout(40, 100, 24, 1), 75);
  EXPECT_EQ(scaled_label_timeout(40, 400, 24, 1), 300);
}

TEST(LabelTimeout, AHeartbeatCrossesTheShapeWithinAPeriod) {
  // A long thin shape with few labels: its diameter in hops, not its label count, sets the period.
  EXPECT_EQ(scaled_label_timeout(40, 61, 24, 20), 60);
  EXPECT_EQ(shape_diameter_hops(ShapeMatrix{1, 61, std::vector<int>(61, 0)}, 1.0, 3.0), 20);
  EXPECT_EQ(shape_diameter_hops(block(32), 1.0, 3.0), 15);  // 31 sqrt 2 = 43.8 m
  EXPECT_EQ(shape_diameter_hops(block(1), 1.0, 3.0), 1);
  EXPECT_EQ(shape_diameter_hops(block(10), 1.0, 0.0), 1);  // no radio range given: no hop bound
}

TEST(LabelTimeout, EntriesPerMessageFollowTheByteLimit) {
  EXPECT_EQ(formation_entries_per_message(1024), kMaxEntriesPerMessage);
  EXPECT_EQ(formation_entries_per_message(0), 1u);
  EXPECT_LT(formation_entries_per_message(200), kMaxEntriesPerMessage);
}

}  // namespace
}  // namespace swarmform::controller
