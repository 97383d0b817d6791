// check_telemetry (docs/faults.md): every field of an agent's telemetry range-checked, every event string
// size-capped; what is out of range is dropped (the robot keeps its last accepted value) and counted.
#include <gtest/gtest.h>

#include <limits>

#include "robot_agent/controller/paper_telemetry.hpp"
#include "tests/support/paper_columns.hpp"
#include "world_server/run/telemetry_check.hpp"

namespace {

using swarmform::Telemetry;
using swarmform::world::check_telemetry;
using swarmform::world::TelemetryLimits;

// The paper's limits: its four known columns (label, parent, leader, net_force), 9 labels, 12 robots.
TelemetryLimits limits() {
  TelemetryLimits l;
  l.labels = 9;
  l.robots = 12;
  l.extra = swarmform::controller::kPaperTelemetry.size();
  l.known = swarmform::controller::kPaperColumns;
  return l;
}

Telemetry accepted() {
  Telemetry t;
  t.state = 2;
  t.extra = swarmform::controller::paper_telemetry(4, 3, false, 0.5);
  return t;
}

const swarmform::behaviour::KnownColumns& paper = swarmform::controller::kPaperColumns;

TEST(TelemetryCheck, AnHonestReportPassesUntouched) {
  Telemetry t = accepted();
  t.state = 6;
  t.extra = swarmform::controller::paper_telemetry(8, 11, true, 1e6);
  t.events = {"label_taken 3 parent_label 0", "arrived"};
  const Telemetry before = t;
  const auto d = check_telemetry(t, accepted(), limits());
  EXPECT_FALSE(d.any());
  EXPECT_EQ(t.extra, before.extra);
  EXPECT_EQ(t.events, before.events);
  Telemetry none;  // defaults: idle, nothing reported
  EXPECT_FALSE(check_telemetry(none, accepted(), limits()).any());
}

TEST(TelemetryCheck, OutOfRangeFieldsKeepTheLastAcceptedValueAndAreCounted) {
  Telemetry t;
  t.state = 7;
  t.extra = swarmform::controller::paper_telemetry(2000000000, -2, false, 2e6);
  const auto d = check_telemetry(t, accepted(), limits());
  EXPECT_EQ(d.fields, 4u);
  EXPECT_EQ(t.state, 2);
  EXPECT_EQ(paper.label_of(t), 4);
  EXPECT_EQ(paper.parent_of(t), 3);
  EXPECT_EQ(paper.net_force_of(t), 0.5);
  EXPECT_EQ(d.first, "state 7 outside 0..6");
  for (const double f : {-1.0, 2e6}) {
    Telemetry u = accepted();
    swarmform::testing::set_net_force(u, f);
    EXPECT_EQ(check_telemetry(u, accepted(), limits()).fields, 1u) << f;
  }
  Telemetry p = accepted();
  swarmform::testing::set_parent(p, 12);  // one past the last robot
  EXPECT_EQ(check_telemetry(p, accepted(), limits()).fields, 1u);
  Telemetry l = accepted();
  swarmform::testing::set_label(l, 9);  // one past the last label
  EXPECT_EQ(check_telemetry(l, accepted(), limits()).fields, 1u);
  EXPECT_EQ(paper.label_of(l), 4);
  Telemetry half = accepted();
  swarmform::testing::paper_column(half, paper.label) = 2.5;   // a label is a whole number
  swarmform::testing::paper_column(half, paper.leader) = 0.5;  // a leader flag 0 or 1
  const auto h = check_telemetry(half, accepted(), limits());
  EXPECT_EQ(h.fields, 2u);
  EXPECT_EQ(h.first, "label 2.5 outside -1..8");
  // Out of range on the first report, with nothing accepted before: none (no label).
  Telemetry first = accepted();
  swarmform::testing::set_label(first, 40);
  EXPECT_EQ(check_telemetry(first, Telemetry{}, limits()).fields, 1u);
  EXPECT_EQ(paper.label_of(first), -1);
  // A value that is not finite drops the whole report of columns.
  Telemetry nan = accepted();
  swarmform::testing::set_net_force(nan, std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(check_telemetry(nan, accepted(), limits()).fields, 1u);
  EXPECT_EQ(nan.extra, accepted().extra);
}

// A behaviour that declares no known column: its columns are its own numbers, checked only to be finite
// and as many as it declares (a "label" of 2e9 in its first column is no label).
TEST(TelemetryCheck, ColumnsOfABehaviourWithoutKnownOnesAreOnlyCountedAndFinite) {
  TelemetryLimits l;
  l.extra = 2;
  Telemetry t;
  t.extra = {2e9, -5.0};
  EXPECT_FALSE(check_telemetry(t, Telemetry{}, l).any());
  t.extra = {1.0};
  EXPECT_EQ(check_telemetry(t, Telemetry{}, l).fields, 1u);
  EXPECT_TRUE(t.extra.empty());
}

TEST(TelemetryCheck, LongNonPrintableOrTooManyEventStringsAreDropped) {
  Telemetry t = accepted();
  t.events = {std::string(20000, 'x'), "ok 1", std::string("bell\x07"), std::string("utf8 \xc3\xa9"),
              std::string(256, 'y')};
  for (int i = 0; i < 20; ++i) t.events.push_back("more " + std::to_string(i));
  const auto d = check_telemetry(t, accepted(), limits());
  // Kept: "ok 1", the 256-byte one, then "more 0".."more 13" up to 16 in all; dropped: 3 bad + 6 over 16.
  EXPECT_EQ(t.events.size(), 16u);
  EXPECT_EQ(t.events[0], "ok 1");
  EXPECT_EQ(t.events[1].size(), 256u);
  EXPECT_EQ(t.events[15], "more 13");
  EXPECT_EQ(d.events, 9u);
  EXPECT_EQ(d.fields, 0u);
  EXPECT_EQ(d.first, "an event string of 20000 bytes (at most 256)");
}

}  // namespace
