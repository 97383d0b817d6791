// The world's first look at a command sample, made on Cyclone's receive thread from the sample's info alone
// (its writer and its instance), before the sample is decoded or stored in the reader (docs/faults.md,
// docs/design-notes/input-bounds-and-floods.md). Pure bookkeeping, thread-safe: CommandReader installs it
// as the command topic's filter and tells it what the world learns when it takes samples.
//
// - Budget: a writer gets at most `per_window` samples (claims, commands and liveliness assertions alike) a
//   window. A window ends with each wall-clock second and, in lockstep, with each tick of the world
//   (set_window). Sized above what the world's own per-kind budget (world_server/input_guard.hpp) admits, so
//   it never drops what that would take; what it drops no thread of the world ever decodes, stores or takes,
//   however fast it comes, and the world's reader holds at most a window's worth per writer.
// - Ids outside the run: the id is in the sample's key, which the filter does not decode; the instance is
//   known, though. The world says which instances are ids inside the run (learned) and which writer sent an
//   id at or above `accept_ids` (banned): a banned writer's samples are kept only for instances known to be
//   ids inside the run, so a writer making up ids gets at most one window of them stored (each an instance
//   for as long as it lives), not one per id for ever.
// - Memory: one small entry per writer seen in the last kForgetAfter, one instance handle per id inside the
//   run.
#pragma once

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <unordered_map>
#include <vector>

#include "common/dds/identity.hpp"
#include "common/types.hpp"

namespace swarmform::dds {

using InstanceHandle = std::uint64_t;  // dds_instance_handle_t of a reader's instance

class ReceiveBudget {
 public:
  static constexpr std::int64_t kSecond = 1'000'000'000;  // ns
  static constexpr std::int64_t kForgetAfter = 5 * kSecond;

  // per_window 0: no budget (every writer's samples are kept; ids are still checked).
  ReceiveBudget(std::uint32_t per_window, std::uint32_t accept_ids);

  // The receive thread: whether to keep a sample of `writer` for `instance`, at `now_ns`.
  bool admit(PublicationHandle writer, InstanceHandle instance, std::int64_t now_ns);

  // The world's thread. Lockstep: a new tick, a new window for every writer.
  void set_window(std::uint64_t window);
  // A sample taken: `id` is `instance`'s. Returns false when id is at or above accept_ids: the sample is to
  // be dropped, and `writer` is banned from instances not known to be ids inside the run.
  bool taken(PublicationHandle writer, InstanceHandle instance, RobotId id);

  // Samples dropped over a writer's budget since the last call, per writer (appended to `out`).
  struct Drops {
    PublicationHandle writer = 0;
    std::uint64_t count = 0;
  };
  void take_drops(std::vector<Drops>& out);
  // Samples dropped for ids outside the run: taken ones (taken() false) and a banned writer's for instances
  // not known to be inside the run.
  std::uint64_t out_of_range() const;
  std::uint64_t over_budget() const;
  std::size_t writers_tracked() const;

 private:
  struct Writer {
    std::uint64_t window = 0;
    std::int64_t second = 0;
    std::uint32_t count = 0;
    std::uint64_t unreported = 0;  // dropped over budget since take_drops
    std::int64_t seen_at = 0;
    bool banned = false;
  };
  bool known(InstanceHandle instance) const;
  void prune(std::int64_t now_ns);

  const std::uint32_t per_window_;
  const std::uint32_t accept_ids_;
  mutable std::mutex mutex_;
  std::uint64_t window_ = 0;
  std::unordered_map<PublicationHandle, Writer> writers_;
  std::vector<InstanceHandle> instances_;      // [id]: the instance of id (0: not learned yet)
  std::vector<PublicationHandle> unreported_;  // writers with unreported drops, each once
  std::uint64_t out_of_range_ = 0, over_budget_ = 0;
  std::int64_t pruned_at_ = 0;
};

}  // namespace swarmform::dds
