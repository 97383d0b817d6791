// Bounds what any DDS writer can make the world do, log or hold (docs/faults.md). Pure bookkeeping keyed
// by the writer's publication handle (no DDS, no World): the server asks it before acting on a sample.
//
// - Budgets: a writer gets at most `commands_per_window` commands a window (lockstep: a tick of the world;
//   realtime: a wall-clock second) and `claims_per_second` claims a second. The excess is dropped and
//   counted. Each writer has its own budget, so a flooding writer never spends the owner's: an owner's one
//   command a tick is always within its budget, whoever else writes (the reader stays keep-all per robot).
// - Throttled reports: bad input of one kind from one writer is logged once a second at most, with the count
//   of what was not logged since; every occurrence is counted for summary.json.
// - Memory: one small entry per writer seen in the last kForgetAfter; older ones are dropped (and a writer
//   that goes away is forgotten at once), so a writer that owns no id can make the world hold O(1).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>
#include <unordered_map>

#include "common/dds/identity.hpp"

namespace swarmform::server {

enum class Abuse : std::uint8_t {
  CommandOverLimit,  // a command past its writer's budget
  ClaimOverLimit,    // a claim past its writer's budget
  SpoofedCommand,    // a command for an id its writer does not own
  RefusedClaim,      // a claim the registry refused (taken id, id outside the run)
  UnprovenClaim,     // a claim for an id that needs one issued by the run's starter, without a valid proof
  BadTelemetry,      // an owner's command whose telemetry had fields out of range (telemetry_check.hpp)
  BadCommand,        // an owner's command the world did not take as it came (World::apply_command's verdict)
  Count,
};
std::string_view to_string(Abuse what);

struct GuardLimits {
  std::uint32_t commands_per_window = 8;
  // An honest agent sends up to 6 claims in a second: 5 at 0.1 s, then one at 0.5 s
  // (robot_agent/dds_link.cpp), until answered. 4 dropped (and logged on stderr) the claims of every agent
  // whose answer took over 0.4 s, as at 1024 agents starting on a loaded host: one line per agent. The budget
  // stays per writer, so a flooding writer is cut as before.
  std::uint32_t claims_per_second = 8;
};

// Realtime: a command budget per second from the tick rate: twice the ticks a second, plus slack for a
// re-sent claim's neighbours and a burst after a stall.
GuardLimits realtime_limits(double tick_rate);

// Each writer's budget of samples a window on the world's receive thread, before any sample is decoded
// (dds::ReceiveBudget; its window ends each second and, in lockstep, each tick): what `limits` admits of
// commands and claims in a window, plus the liveliness assertions of an agent with nothing to write (3 a
// lease of 0.5 s, common/dds/qos.hpp) with room to spare. It must never drop what InputGuard would admit:
// an owner's command dropped there is a missed tick (realtime) or a stalled round (lockstep).
inline constexpr std::uint32_t kAliveSamplesPerSecond = 8;
std::uint32_t receive_budget(const GuardLimits& limits);

class InputGuard {
 public:
  static constexpr std::int64_t kSecond = 1'000'000'000;  // ns
  static constexpr std::int64_t kForgetAfter = 5 * kSecond;

  explicit InputGuard(GuardLimits limits) : limits_(limits) {}

  // True while `writer` is within its command budget for `window` (the tick, or the second in realtime).
  bool admit_command(dds::PublicationHandle writer, std::uint64_t window, std::int64_t now_ns);
  bool admit_claim(dds::PublicationHandle writer, std::int64_t now_ns);

  // Counts one occurrence of `what` from `writer`; when it is to be logged now (the first in a second for
  // this writer, kind and `sub`-kind), returns how many occurrences that log line stands for (>= 1). `sub`
  // (< kSubKinds) tells apart reports of one kind that must each be seen, e.g. a command's verdicts.
  // `n`: occurrences this call stands for (the receive thread's drops come counted).
  static constexpr std::size_t kSubKinds = 8;
  std::optional<std::uint64_t> report(dds::PublicationHandle writer, Abuse what, std::int64_t now_ns,
                                      std::size_t sub = 0, std::uint64_t n = 1);
  // Counts `n` occurrences without a writer to throttle on (e.g. telemetry event strings dropped).
  void count(Abuse what, std::uint64_t n) { totals_[static_cast<std::size_t>(what)] += n; }

  void forget(dds::PublicationHandle writer) { writers_.erase(writer); }

  std::uint64_t total(Abuse what) const { return totals_[static_cast<std::size_t>(what)]; }
  std::size_t writers_tracked() const { return writers_.size(); }

 private:
  struct Throttle {
    std::int64_t logged_at = 0;  // ns; 0 never
    std::uint64_t unlogged = 0;  // occurrences since
  };
  struct Writer {
    std::uint64_t command_window = 0;
    std::uint32_t commands = 0;
    std::int64_t claim_second = 0;
    std::uint32_t claims = 0;
    std::int64_t seen_at = 0;
    std::array<Throttle, static_cast<std::size_t>(Abuse::Count) * kSubKinds> throttles{};
  };
  Writer& writer(dds::PublicationHandle handle, std::int64_t now_ns);
  void prune(std::int64_t now_ns);

  GuardLimits limits_;
  std::unordered_map<dds::PublicationHandle, Writer> writers_;
  std::array<std::uint64_t, static_cast<std::size_t>(Abuse::Count)> totals_{};
  std::int64_t pruned_at_ = 0;
};

}  // namespace swarmform::server
