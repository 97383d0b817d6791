// check_telemetry (docs/faults.md): every field of an agent's telemetry range-checked, every event string
// size-capped; what is out of range is dropped (the robot keeps its last accepted value) and counted.
#include <gtest/gtest.h>

#include <limits>

#include "world_server/run/telemetry_check.hpp"

namespace {

using swarmform::Telemetry;
using swarmform::world::check_telemetry;
using swarmform::world::TelemetryLimits;

TelemetryLimits limits() {
  TelemetryLimits l;
  l.labels = 9;
  l.robots = 12;
  return l;
}

Telemetry accepted() {
  Telemetry t;
  t.state = 2;
  t.label = 4;
  t.parent = 3;
  t.net_force = 0.5;
  return t;
}

TEST(TelemetryCheck, AnHonestReportPassesUntouched) {
  Telemetry t = accepted();
  t.state = 6;
  t.label = 8;
  t.parent = 11;
  t.leader = true;
  t.net_force = 1e6;
  t.events = {"label_taken 3 parent_label 0", "arrived"};
  const Telemetry before = t;
  const auto d = check_telemetry(t, accepted(), limits());
  EXPECT_FALSE(d.any());
  EXPECT_EQ(t.label, before.label);
  EXPECT_EQ(t.events, before.events);
  Telemetry none;  // defaults: idle, no label, no parent
  EXPECT_FALSE(check_telemetry(none, accepted(), limits()).any());
}

TEST(TelemetryCheck, OutOfRangeFieldsKeepTheLastAcceptedValueAndAreCounted) {
  Telemetry t;
  t.state = 7;
  t.label = 2000000000;
  t.parent = -2;
  t.net_force = std::numeric_limits<double>::quiet_NaN();
  const auto d = check_telemetry(t, accepted(), limits());
  EXPECT_EQ(d.fields, 4u);
  EXPECT_EQ(t.state, 2);
  EXPECT_EQ(t.label, 4);
  EXPECT_EQ(t.parent, 3);
  EXPECT_EQ(t.net_force, 0.5);
  EXPECT_EQ(d.first, "state 7 outside 0..6");
  for (const double f : {-1.0, std::numeric_limits<double>::infinity(), 2e6}) {
    Telemetry u = accepted();
    u.net_force = f;
    EXPECT_EQ(check_telemetry(u, accepted(), limits()).fields, 1u) << f;
  }
  Telemetry p = accepted();
  p.parent = 12;  // one past the last robot
  EXPECT_EQ(check_telemetry(p, accepted(), limits()).fields, 1u);
  Telemetry l = accepted();
  l.label = 9;  // one past the last label
  EXPECT_EQ(check_telemetry(l, accepted(), limits()).fields, 1u);
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
