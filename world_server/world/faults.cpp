// The fault format's parser and checks (faults.hpp; reference: docs/scenario-format.md, "Faults").
#include "world_server/world/faults.hpp"

#include <charconv>
#include <cmath>
#include <sstream>

namespace swarmform::world {
namespace {

constexpr Tick kMaxTick = 1000000000;

struct KindName {
  FaultKind kind;
  std::string_view name;
};
constexpr KindName kKinds[] = {{FaultKind::Kill, "kill"},       {FaultKind::Stall, "stall"},
                               {FaultKind::Restart, "restart"}, {FaultKind::Ultrasonic, "ultrasonic"},
                               {FaultKind::Wheel, "wheel"},     {FaultKind::Loss, "loss"},
                               {FaultKind::Range, "range"}};

[[noreturn]] void bad(std::string_view /*text*/, const std::string& what) {
  throw FaultSyntaxError(what);
}

// An unsigned decimal integer of at most `max`, the whole of `s`.
std::optional<std::uint64_t> unsigned_of(std::string_view s, std::uint64_t max) {
  if (s.empty() || s.size() > 18) return std::nullopt;
  std::uint64_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || v > max) return std::nullopt;
  return v;
}

std::optional<double> number_of(std::string_view s) {
  if (s.empty()) return std::nullopt;
  double v = 0.0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::string robot_text(const Fault& f) {
  return f.robot ? "robot " + std::to_string(*f.robot) : "every robot";
}

}  // namespace

std::string_view to_string(FaultKind k) {
  for (const auto& [kind, name] : kKinds) {
    if (kind == k) return name;
  }
  return "unknown";
}

bool Fault::in_world() const {
  return kind == FaultKind::Ultrasonic || kind == FaultKind::Wheel || kind == FaultKind::Loss ||
         kind == FaultKind::Range;
}

Fault parse_fault(std::string_view text) {
  Fault f;
  f.text = std::string(text);
  const auto colon = text.find(':');
  const auto at = text.find('@');
  if (colon == std::string_view::npos || at == std::string_view::npos || at < colon) {
    bad(text, "expected KIND:TARGET@TICK[+TICKS][=VALUE], e.g. stall:3@200+30");
  }
  // The kind.
  const std::string_view kind = text.substr(0, colon);
  bool known = false;
  for (const auto& [k, name] : kKinds) {
    if (name == kind) {
      f.kind = k;
      known = true;
    }
  }
  if (!known) {
    std::string list;
    for (const auto& kn : kKinds) list += (list.empty() ? "" : ", ") + std::string(kn.name);
    bad(text, "unknown kind '" + std::string(kind) + "' (known: " + list + ")");
  }
  // The target: all, ID or ID/PART.
  const std::string_view target = text.substr(colon + 1, at - colon - 1);
  const auto slash = target.find('/');
  const std::string_view who = target.substr(0, slash);
  const std::string_view part =
      slash == std::string_view::npos ? std::string_view() : target.substr(slash + 1);
  if (who == "all") {
    if (f.kind != FaultKind::Loss && f.kind != FaultKind::Range) {
      bad(text, "'all' is a target of loss and range only; " + std::string(kind) + " needs a robot id");
    }
  } else if (const auto id = unsigned_of(who, 0xffffffffULL)) {
    f.robot = static_cast<RobotId>(*id);
  } else {
    bad(text, "the target '" + std::string(who) + "' is not a robot id" +
                  (f.kind == FaultKind::Loss || f.kind == FaultKind::Range ? " or all" : ""));
  }
  if (slash != std::string_view::npos) {
    if (f.kind == FaultKind::Ultrasonic) {
      const auto s = unsigned_of(part, kUltrasonicCount - 1);
      if (!s) {
        bad(text, "the sensor '" + std::string(part) + "' is not one of 0.." +
                      std::to_string(kUltrasonicCount - 1) +
                      " (0 right, 1 front-right, 2 front, 3 front-left, 4 left)");
      }
      f.part = static_cast<int>(*s);
    } else if (f.kind == FaultKind::Wheel) {
      if (part == "left") {
        f.part = 0;
      } else if (part == "right") {
        f.part = 1;
      } else {
        bad(text, "the wheel '" + std::string(part) + "' is not left or right");
      }
    } else {
      bad(text,
          "/" + std::string(part) + ": only ultrasonic (/SENSOR) and wheel (/left, /right) take a part");
    }
  } else if (f.kind == FaultKind::Wheel) {
    bad(text, "which wheel: wheel:ID/left or wheel:ID/right");
  }
  // The tick, then +TICKS and =VALUE in this order.
  std::string_view rest = text.substr(at + 1);
  const auto plus = rest.find('+');
  const auto equals = rest.find('=');
  if (plus != std::string_view::npos && equals != std::string_view::npos && equals < plus) {
    bad(text, "write +TICKS before =VALUE");
  }
  const std::string_view tick = rest.substr(0, std::min(plus, equals));
  const auto t = unsigned_of(tick, kMaxTick);
  if (!t) bad(text, "the tick '" + std::string(tick) + "' is not an integer in [0, 1000000000]");
  f.tick = *t;
  if (plus != std::string_view::npos) {
    const std::string_view d =
        rest.substr(plus + 1, equals == std::string_view::npos ? equals : equals - plus - 1);
    const auto ticks = unsigned_of(d, kMaxTick);
    if (!ticks || *ticks == 0) bad(text, "the duration '+" + std::string(d) + "' is not a tick count >= 1");
    f.duration = *ticks;
  }
  if (equals != std::string_view::npos) {
    const std::string_view v = rest.substr(equals + 1);
    if (f.kind != FaultKind::Range) bad(text, "=VALUE belongs to range only (the cut range in metres)");
    const auto m = number_of(v);
    if (!m || *m <= 0.0) bad(text, "the range '" + std::string(v) + "' is not a positive number of metres");
    f.value = *m;
  }
  switch (f.kind) {
    case FaultKind::Kill:
    case FaultKind::Restart:
      if (f.duration) bad(text, std::string(kind) + " takes no duration (+TICKS)");
      break;
    case FaultKind::Stall:
      if (!f.duration) bad(text, "a stall needs its duration: stall:ID@TICK+TICKS");
      break;
    case FaultKind::Range:
      if (equals == std::string_view::npos) bad(text, "a range cut needs the new range: =METRES");
      break;
    default:
      break;
  }
  return f;
}

std::string check_fault(const std::vector<Fault>& faults, std::size_t index, const FaultContext& context) {
  const Fault& f = faults.at(index);
  if (f.robot && *f.robot >= context.robots) {
    return "no robot " + std::to_string(*f.robot) + " in a run of " + std::to_string(context.robots) +
           " (ids 0.." + std::to_string(context.robots - 1) + ")";
  }
  if (f.kind == FaultKind::Range && f.value >= context.comm_range) {
    std::ostringstream what;
    what << "the cut range " << f.value << " m is not below the comm range " << context.comm_range << " m";
    return what.str();
  }
  if (f.kind == FaultKind::Restart) {
    // The kill it follows must come after any earlier restart of the robot (a restart of a live robot has no
    // process to replace).
    Tick after = 0;
    bool earlier = false;
    for (const Fault& g : faults) {
      if (g.kind == FaultKind::Restart && g.robot == f.robot && g.tick < f.tick &&
          (!earlier || g.tick > after)) {
        after = g.tick;
        earlier = true;
      }
    }
    bool killed = false;
    for (const auto& [id, tick] : context.kills)
      killed = killed || (id == *f.robot && tick < f.tick && (!earlier || tick >= after));
    if (!killed) {
      return "robot " + std::to_string(*f.robot) + " is not killed before tick " + std::to_string(f.tick) +
             (earlier ? " since its restart at tick " + std::to_string(after) : std::string()) +
             " (a restart follows a kill: add kill:" + std::to_string(*f.robot) + "@T with " +
             (earlier ? std::to_string(after) + " <= T < " : "T < ") + std::to_string(f.tick) + ")";
    }
  }
  if (f.kind == FaultKind::Stall) {
    for (std::size_t j = 0; j < index; ++j) {
      const Fault& g = faults[j];
      if (g.kind != FaultKind::Stall || g.robot != f.robot) continue;
      if (f.tick < *g.end_tick() && g.tick < *f.end_tick()) {
        return "overlaps '" + g.text + "' (one stall of a robot at a time)";
      }
    }
  }
  return "";
}

std::vector<FaultEdge> world_fault_edges(const std::vector<Fault>& faults, Tick t) {
  std::vector<FaultEdge> out;
  for (const Fault& f : faults) {
    if (!f.in_world()) continue;
    if (f.tick == t) out.push_back({&f, true});
    if (f.end_tick() == t) out.push_back({&f, false});
  }
  return out;
}

std::string describe_world_fault(const Fault& f, bool start) {
  std::ostringstream d;
  d << f.text << ": ";
  if (!start) {
    d << "over (it lasted " << *f.duration << " ticks)";
    return d.str();
  }
  switch (f.kind) {
    case FaultKind::Ultrasonic:
      if (f.part < 0) {
        d << "every ultrasonic sensor of " << robot_text(f);
      } else {
        d << "ultrasonic sensor " << f.part << " of " << robot_text(f);
      }
      d << " reads its maximum range (" << kUltrasonicMaxRange << " m)";
      break;
    case FaultKind::Wheel:
      d << "the " << (f.part == 0 ? "left" : "right") << " wheel of " << robot_text(f) << " stops";
      break;
    case FaultKind::Loss:
      d << (f.robot ? "every message to and from " + robot_text(f) : std::string("every message"))
        << " is lost";
      break;
    case FaultKind::Range:
      d << "the message range of " << robot_text(f) << " is cut to " << f.value << " m";
      break;
    default:
      d << "not a world fault";
      break;
  }
  if (f.duration) d << " for " << *f.duration << " ticks";
  return d.str();
}

}  // namespace swarmform::world
