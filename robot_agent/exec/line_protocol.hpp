// The line protocol between robot_agent and a behaviour run as a child process (robot_agent --exec),
// version kProtocolVersion: one JSON object per line, UTF-8, '\n'-terminated. docs/agent-protocol.md is the
// reference a behaviour's author reads; this file is its one implementation on the agent's side. Pure: text
// in, plain structs out; every malformed line throws ProtocolError saying what is wrong with it.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

#include "common/hex.hpp"
#include "common/mission.hpp"
#include "common/types.hpp"

namespace swarmform::agent {

inline constexpr int kProtocolVersion = 1;
inline constexpr std::size_t kMaxLineBytes = 1 << 20;  // a longer line from the behaviour is garbage
inline constexpr std::size_t kMaxEvents = 16;          // events a command may report in one tick
inline constexpr std::size_t kMaxEventBytes = 200;     // each
inline constexpr std::size_t kMaxTelemetry = 64;       // telemetry values a command may carry

struct ProtocolError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Agent -> behaviour, once, first: {"type":"hello","protocol":1,"robot":K,"behaviour":...,"params":{...},...}
std::string encode_hello(const Mission& mission, RobotId self);
// Behaviour -> agent, its first line: {"type":"hello","protocol":1[,"name":"..."]}. Returns the name ("" if
// none); throws ProtocolError for another type or protocol version.
std::string parse_hello_reply(const std::string& line);
// Agent -> behaviour, each tick:
// {"type":"perception","tick":T,"pose":{...},"ultrasonic":[...],"messages":[...]}
std::string encode_perception(const Perception& perception);
// Behaviour -> agent, each tick: {"type":"command","tick":T,"left":L,"right":R[,"message":"hex"][,"state":S]
// [,"events":[...]]}. Throws ProtocolError for a line that is not that, a tick other than `tick`, a speed
// that is not a finite number, a message that is not hex or longer than `max_message_bytes`.
Command parse_command(const std::string& line, Tick tick, std::size_t max_message_bytes);

// Message payloads travel as lowercase hex strings (two digits a byte, common/hex.hpp): JSON has no bytes.

}  // namespace swarmform::agent
