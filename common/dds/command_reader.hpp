// The world's side of sf_command: a reader per face that takes every agent's claims and commands (reused
// buffers, a cap per take), drops a writer's samples over its budget and ids outside the run before they
// are decoded or stored (receive_budget.hpp), follows the liveliness of every command writer, and, under DDS
// Security, tells which robot a writer authenticated as.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "common/dds/command_sample.hpp"
#include "common/dds/identity.hpp"
#include "common/dds/matching.hpp"
#include "common/dds/participant.hpp"
#include "common/dds/receive_budget.hpp"
#include "common/dds/waiter.hpp"
#include "common/types.hpp"

namespace swarmform::dds {

inline constexpr std::size_t kMaxCommandTake = 1024;

// World side. A listener follows the liveliness of every command writer and wakes `waiter` when one is lost.
class CommandReader {
 public:
  // `accept_ids` > 0: samples (claims and commands) for ids at or above it are never returned by take, and
  // once a writer sent one, its samples for instances not known to be ids below it are dropped before the
  // reader stores them (counted by filtered()), so no writer can make the reader hold an instance per
  // made-up id. The world passes its robot count plus kMaxExtraChannels (near misses still get their
  // "no robot K in this run" answer).
  // `samples_per_window` > 0: each writer's budget of samples a window (ReceiveBudget; a window ends each
  // second and at each set_window), the excess dropped on the receive thread before it is decoded or stored.
  // `face`: stamped on every sample it takes (CommandSample::face), for a world with several faces.
  // `count_arrivals`: every sample stored is counted on `waiter` (Waiter::arrived), for a taker that does not
  // attach condition() and wakes on the counts instead; the taker then reports its drains (Waiter::drained).
  CommandReader(const Participant& participant, Waiter& waiter, bool realtime = false,
                std::uint32_t accept_ids = 0, std::uint32_t face = 0, bool count_arrivals = false,
                std::uint32_t samples_per_window = 0);
  ~CommandReader();
  CommandReader(const CommandReader&) = delete;
  CommandReader& operator=(const CommandReader&) = delete;

  dds_entity_t condition() const;
  // Takes what is available, at most `max_samples`, into buf[0..n) (grown as needed, elements reused: no
  // allocation once warm). The cap bounds the buffer under a flood; what is left is taken by the next call
  // (the reader's condition stays triggered).
  // `first`: fill from buf[first] on (buf holds at least `first` elements), to gather several readers'
  // samples in one buffer; returns how many were taken.
  std::size_t take(std::vector<CommandSample>& buf, std::size_t max_samples = kMaxCommandTake,
                   std::size_t first = 0);
  // Liveliness changes of command writers since the last call, in the order they happened (appended to
  // `out`): alive = false when a writer lost liveliness or went away, true when one appeared or came back;
  // gone = the writer went away (deleted, or its participant's lease ran out), not only its liveliness.
  struct LivelinessChange {
    PublicationHandle writer = 0;
    bool alive = false;
    bool gone = false;
  };
  void take_liveliness_changes(std::vector<LivelinessChange>& out);
  // Samples dropped for ids at or above `accept_ids` so far (thread-safe).
  std::uint64_t filtered() const;
  // Lockstep: the world's tick, a new budget window for every writer.
  void set_window(std::uint64_t window);
  // Samples dropped over their writer's budget since the last call, per writer (appended to `out`), and in
  // all.
  void take_budget_drops(std::vector<ReceiveBudget::Drops>& out);
  std::uint64_t over_budget() const;
  // On a secure participant (the reader then reads partition robot/*): the robot whose partition `writer`
  // writes in, when it writes in exactly one partition robot/K. DDS Security let that writer match only if
  // its participant's certificate and permissions are robot K's, so this is the writer's authenticated robot
  // id. Looked up once per writer. nullopt: not secure, unknown writer, or any other partition set.
  std::optional<RobotId> authenticated_robot(PublicationHandle writer);
  // Whether `writer` is still matched: false once it went away (its participant deleted or forgotten). Its
  // samples taken after that are stale: a writer's data and its going reach the reader by different threads.
  bool matched(PublicationHandle writer) const;
  // `writer`'s GUID and its participant's (matching.hpp); nullopt once it is no longer matched.
  std::optional<RemoteWriter> remote(PublicationHandle writer) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace swarmform::dds
