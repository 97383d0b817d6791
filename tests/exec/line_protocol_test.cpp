// The line protocol's agent side, as text: what a behaviour reads, and which answers are refused and why.
#include "robot_agent/exec/line_protocol.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace swarmform::agent {
namespace {

using nlohmann::json;

TEST(LineProtocol, HelloCarriesTheVersionTheRobotAndTheBehavioursParams) {
  Mission m;
  m.behaviour = "random_walk";
  m.params["k_move"] = 0.5;
  m.max_message_bytes = 64;
  const json j = json::parse(encode_hello(m, 7));
  EXPECT_EQ(j["type"], "hello");
  EXPECT_EQ(j["protocol"], kProtocolVersion);
  EXPECT_EQ(j["robot"], 7);
  EXPECT_EQ(j["behaviour"], "random_walk");
  EXPECT_EQ(j["params"]["k_move"], 0.5);
  EXPECT_EQ(j["max_message_bytes"], 64);
  EXPECT_EQ(j["goal"]["x"], m.goal.x);
}

// A run without a goal says so: null, not a point the behaviour would take for one.
TEST(LineProtocol, HelloWithoutAGoalSaysNull) {
  Mission m;
  m.has_goal = false;
  m.goal = {0.0, 0.0};
  m.goal_radius = 0.0;
  EXPECT_TRUE(json::parse(encode_hello(m, 0))["goal"].is_null());
}

TEST(LineProtocol, PerceptionIsExactAndPayloadsAreHex) {
  Perception p;
  p.tick = 42;
  p.pose = {0.1, -2.0 / 3.0, 3.0};
  p.ultrasonic = {0.25, 0.5, 2.0, 1.0, 0.3};
  p.messages.push_back(RabReading{5, 1.25, -0.5, {0x00, 0xab, 0xff}});
  const json j = json::parse(encode_perception(p));
  EXPECT_EQ(j["tick"], 42);
  EXPECT_EQ(j["pose"]["y"].get<double>(), -2.0 / 3.0);  // round-trip precision, not 6 digits
  EXPECT_EQ(j["ultrasonic"][4].get<double>(), 0.3);
  EXPECT_EQ(j["messages"][0]["sender"], 5);
  EXPECT_EQ(j["messages"][0]["data"], "00abff");
}

TEST(LineProtocol, TheGoalAsItStandsTravelsWhenTheRunHasOne) {
  Perception p;
  EXPECT_FALSE(json::parse(encode_perception(p)).contains("goal"));
  p.goal = Goal{{-4.0, 2.0 / 3.0}, 1.5};
  const json g = json::parse(encode_perception(p))["goal"];
  EXPECT_EQ(g["x"].get<double>(), -4.0);
  EXPECT_EQ(g["y"].get<double>(), 2.0 / 3.0);
  EXPECT_EQ(g["radius"].get<double>(), 1.5);
}

TEST(LineProtocol, OptionalSensorsTravelOnlyWhenEquippedAndExactly) {
  Perception p;
  const json bare = json::parse(encode_perception(p));
  for (const char* key : {"proximity", "light", "ground", "battery", "lidar"})
    EXPECT_FALSE(bare.contains(key)) << key;
  p.proximity = std::array<double, kProximityCount>{1.0, 0.0, 1.0 / 3.0, 0.5, 0.0, 0.0, 0.0, 0.25};
  p.light = std::array<double, kLightCount>{0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 2.0 / 7.0};
  p.ground = std::array<double, kGroundCount>{0.0, 1.0, 0.5, 1.0 / 9.0};
  p.battery = 0.123456789012345;
  p.lidar = {LidarRay{-1.8325957145940461, 4.0}, LidarRay{0.1, 1.0 / 3.0}};
  const json j = json::parse(encode_perception(p));
  EXPECT_EQ(j["proximity"].get<std::vector<double>>(),
            std::vector<double>(p.proximity->begin(), p.proximity->end()));
  EXPECT_EQ(j["light"][7].get<double>(), 2.0 / 7.0);
  EXPECT_EQ(j["ground"][3].get<double>(), 1.0 / 9.0);
  EXPECT_EQ(j["battery"].get<double>(), 0.123456789012345);
  ASSERT_EQ(j["lidar"].size(), 2U);
  EXPECT_EQ(j["lidar"][0][0].get<double>(), -1.8325957145940461);
  EXPECT_EQ(j["lidar"][0][1].get<double>(), 4.0);
  EXPECT_EQ(j["lidar"][1][1].get<double>(), 1.0 / 3.0);
}

TEST(LineProtocol, CommandIsRead) {
  const Command c = parse_command(
      R"({"type":"command","tick":9,"left":0.05,"right":-0.02,"message":"0aFF","state":2,"events":["hi 1"]})",
      9, 16);
  EXPECT_EQ(c.left_speed, 0.05);
  EXPECT_EQ(c.right_speed, -0.02);
  EXPECT_EQ(c.message, (std::vector<std::uint8_t>{0x0a, 0xff}));
  EXPECT_EQ(c.telemetry.state, 2);
  EXPECT_EQ(c.telemetry.events, std::vector<std::string>{"hi 1"});
  EXPECT_TRUE(c.telemetry.extra.empty());
  EXPECT_EQ(parse_command(R"({"type":"command","tick":9,"left":0,"right":0,"telemetry":[2, 0.25]})", 9, 16)
                .telemetry.extra,
            (std::vector<double>{2.0, 0.25}));
  EXPECT_TRUE(parse_command(R"({"type":"command","tick":9,"left":0,"right":0})", 9, 16).message.empty());
}

void expect_refused(const std::string& line, const std::string& says) {
  try {
    (void)parse_command(line, 9, 4);
    ADD_FAILURE() << "accepted: " << line;
  } catch (const ProtocolError& e) {
    EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
  }
}

TEST(LineProtocol, BadCommandsAreRefusedSayingWhy) {
  expect_refused("left=1 right=2", "not JSON");
  expect_refused(R"({"type":"command","tick":9,"left":NaN,"right":0})", "non-finite");
  expect_refused(R"({"type":"command","tick":9,"left":1e999,"right":0})",
                 "not JSON");  // overflows the parser
  expect_refused(R"({"type":"command","tick":9,"left":-Infinity,"right":0})", "non-finite");
  expect_refused(R"([1,2])", "not an object");
  expect_refused(R"({"type":"cmd","tick":9,"left":0,"right":0})", "\"type\"");
  expect_refused(R"({"type":"command","tick":8,"left":0,"right":0})",
                 "tick 9 with a command whose \"tick\" is 8");
  expect_refused(R"({"type":"command","left":0,"right":0})", "missing");
  expect_refused(R"({"type":"command","tick":9,"right":0})", "no \"left\"");
  expect_refused(R"({"type":"command","tick":9,"left":"fast","right":0})", "not a number");
  expect_refused(R"({"type":"command","tick":9,"left":0,"right":0,"message":"abc"})", "odd");
  expect_refused(R"({"type":"command","tick":9,"left":0,"right":0,"message":"zz"})", "not hex");
  expect_refused(R"({"type":"command","tick":9,"left":0,"right":0,"message":"0011223344"})",
                 "max_message_bytes");
  expect_refused(R"({"type":"command","tick":9,"left":0,"right":0,"state":-1})", "state");
  expect_refused(R"({"type":"command","tick":9,"left":0,"right":0,"events":"x"})", "events");
  expect_refused(R"({"type":"command","tick":9,"left":0,"right":0,"telemetry":3})", "telemetry");
  expect_refused(R"({"type":"command","tick":9,"left":0,"right":0,"telemetry":["a"]})", "telemetry");
}

TEST(LineProtocol, HelloReplyChecksTheVersion) {
  EXPECT_EQ(parse_hello_reply(R"({"type":"hello","protocol":1,"name":"walker"})"), "walker");
  EXPECT_THROW((void)parse_hello_reply(R"({"type":"hello","protocol":2})"), ProtocolError);
  EXPECT_THROW((void)parse_hello_reply(R"({"type":"command","protocol":1})"), ProtocolError);
  EXPECT_THROW((void)parse_hello_reply(R"({"type":"hello"})"), ProtocolError);
  try {
    (void)parse_hello_reply(R"({"type":"hello","protocol":2})");
  } catch (const ProtocolError& e) {
    EXPECT_STREQ(e.what(), "speaks protocol 2, this agent speaks 1");
  }
}

}  // namespace
}  // namespace swarmform::agent
