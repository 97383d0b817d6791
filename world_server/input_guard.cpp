#include "world_server/input_guard.hpp"

#include <algorithm>
#include <cmath>

namespace swarmform::server {

std::string_view to_string(Abuse what) {
  switch (what) {
    case Abuse::CommandOverLimit:
      return "commands_over_limit";
    case Abuse::ClaimOverLimit:
      return "claims_over_limit";
    case Abuse::SpoofedCommand:
      return "spoofed_commands";
    case Abuse::RefusedClaim:
      return "refused_claims";
    case Abuse::UnprovenClaim:
      return "unproven_claims";
    case Abuse::BadTelemetry:
      return "bad_telemetry_commands";
    case Abuse::BadCommand:
      return "bad_commands";
    case Abuse::Count:
      break;
  }
  return "unknown";
}

GuardLimits realtime_limits(double tick_rate) {
  GuardLimits l;
  const double per_second = std::ceil(std::max(1.0, tick_rate)) * 2.0 + 8.0;
  l.commands_per_window = static_cast<std::uint32_t>(std::min(per_second, 1e6));
  return l;
}

std::uint32_t receive_budget(const GuardLimits& limits) {
  return limits.commands_per_window + limits.claims_per_second + kAliveSamplesPerSecond;
}

InputGuard::Writer& InputGuard::writer(dds::PublicationHandle handle, std::int64_t now_ns) {
  prune(now_ns);
  Writer& w = writers_[handle];
  w.seen_at = now_ns;
  return w;
}

void InputGuard::prune(std::int64_t now_ns) {
  if (now_ns - pruned_at_ < kSecond) return;
  pruned_at_ = now_ns;
  std::erase_if(writers_, [&](const auto& kv) { return now_ns - kv.second.seen_at > kForgetAfter; });
}

bool InputGuard::admit_command(dds::PublicationHandle handle, std::uint64_t window, std::int64_t now_ns) {
  Writer& w = writer(handle, now_ns);
  if (w.command_window != window) {
    w.command_window = window;
    w.commands = 0;
  }
  return ++w.commands <= limits_.commands_per_window;
}

bool InputGuard::admit_claim(dds::PublicationHandle handle, std::int64_t now_ns) {
  Writer& w = writer(handle, now_ns);
  const std::int64_t second = now_ns / kSecond;
  if (w.claim_second != second) {
    w.claim_second = second;
    w.claims = 0;
  }
  return ++w.claims <= limits_.claims_per_second;
}

std::optional<std::uint64_t> InputGuard::report(dds::PublicationHandle handle, Abuse what,
                                                std::int64_t now_ns, std::size_t sub, std::uint64_t n) {
  if (n == 0) return std::nullopt;
  totals_[static_cast<std::size_t>(what)] += n;
  Throttle& t = writer(handle, now_ns)
                    .throttles[static_cast<std::size_t>(what) * kSubKinds + std::min(sub, kSubKinds - 1)];
  t.unlogged += n;
  if (t.logged_at != 0 && now_ns - t.logged_at < kSecond) return std::nullopt;
  t.logged_at = now_ns;
  const std::uint64_t all = t.unlogged;
  t.unlogged = 0;
  return all;
}

}  // namespace swarmform::server
