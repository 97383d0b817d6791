// Faults a user schedules (scenario `faults:`, or `--fault` on the command line), in one text format:
//
//   KIND:TARGET@TICK[+TICKS][=VALUE]        e.g. stall:3@200+30, wheel:1/left@120, range:all@500=1.5
//
// (docs/scenario-format.md, "Faults", is the reference.) World faults (ultrasonic, wheel, loss, range) are
// executed by World itself, so the in-process harness and the DDS world_server give the same run; process
// faults (kill, stall, restart) are executed by whoever owns the agent processes (world_server with
// --agent-pid, the launcher for a restart) or, in-process, on the robot's controller. No DDS here.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "common/types.hpp"

namespace swarmform::world {

enum class FaultKind {
  Kill,        // kill:ID@TICK                 the agent is SIGKILLed (in-process: the robot dies)
  Stall,       // stall:ID@TICK+TICKS          SIGSTOP, then SIGCONT TICKS later (in-process: not stepped)
  Restart,     // restart:ID@TICK              a new agent for a killed robot (in-process: a fresh controller)
  Ultrasonic,  // ultrasonic:ID[/S]@TICK[+T]   sensor S (0 right .. 2 front .. 4 left; all
               //                               five if left out) reads its maximum range
  Wheel,       // wheel:ID/left|right@TICK[+T] that wheel stops (speed 0 whatever is commanded)
  Loss,        // loss:ID|all@TICK[+T]         every message to and from the robot (or every message) is lost
  Range,       // range:ID|all@TICK[+T]=M      the message range of the robot (or of all) is cut to M metres
};
std::string_view to_string(FaultKind k);

struct Fault {
  FaultKind kind = FaultKind::Kill;
  std::optional<RobotId> robot;  // none: every robot (`all`; loss and range only)
  int part = -1;                 // ultrasonic: the sensor (-1: every sensor); wheel: 0 left, 1 right
  Tick tick = 0;                 // the first tick it acts on
  std::optional<Tick> duration;  // ticks it lasts; none: to the end of the run
  double value = 0.0;            // range: the cut range, m
  std::string text;              // as written (for events and errors)

  // Acts on tick t: tick <= t < tick + duration.
  bool active_at(Tick t) const { return t >= tick && (!duration || t < tick + *duration); }
  // The tick it stops acting on (tick + duration), if it ends.
  std::optional<Tick> end_tick() const {
    return duration ? std::optional<Tick>(tick + *duration) : std::nullopt;
  }
  // Executed by the world library (the same in-process and over DDS).
  bool in_world() const;
};

// A fault text that cannot be read; what() says what is wrong with it (the caller adds where it came from
// and the text).
struct FaultSyntaxError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// Parses one fault text (the syntax only: robot ids, ranges and order are checked by check_faults).
Fault parse_fault(std::string_view text);

// What the faults need from the scenario to be checked.
struct FaultContext {
  std::size_t robots = 0;
  double comm_range = 0.0;
  std::vector<std::pair<RobotId, Tick>> kills;  // every kill (the scenario's `kills` and kill faults)
};
// The first problem of faults[index] against the scenario, or "" (ids in range, a range cut below the comm
// range, a restart only of a robot killed before it, no two stalls of one robot at once).
std::string check_fault(const std::vector<Fault>& faults, std::size_t index, const FaultContext& context);

// The reference of the format, for --help texts.
inline constexpr const char* kFaultFormatHelp =
    "KIND:TARGET@TICK[+TICKS][=VALUE], repeatable: kill:ID@T, stall:ID@T+TICKS, restart:ID@T (after a kill), "
    "ultrasonic:ID[/SENSOR]@T[+TICKS], wheel:ID/left|right@T[+TICKS], loss:ID|all@T[+TICKS], "
    "range:ID|all@T[+TICKS]=METRES (docs/scenario-format.md, Faults)";

// The world faults that start (first active tick) or end (first tick no longer active) at tick t, in the
// order given: for the front ends' events.
struct FaultEdge {
  const Fault* fault = nullptr;
  bool start = true;
};
std::vector<FaultEdge> world_fault_edges(const std::vector<Fault>& faults, Tick t);
// The event detail of a world fault's start or end: its text and what it does, e.g.
// "wheel:1/left@120: the left wheel of robot 1 stops".
std::string describe_world_fault(const Fault& f, bool start);

}  // namespace swarmform::world
