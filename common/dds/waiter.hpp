// A waitset with a guard condition: the one place a thread blocks, woken by data on an attached condition or
// by wake() from another thread (a signal watcher, a DDS listener). No polling sleeps.
//
// Counted arrivals, for readers that do not attach a read condition (CommandReader with count_arrivals): the
// reader's listener calls arrived() for every sample it stores, and the waiter wakes once the samples that
// came in since the taker's last drain reach what it said it needs (need(k); 1 by default: every arrival
// wakes, as a read condition would). A lockstep world waiting for k commands so sleeps until k samples are
// there, not once per sample (BENCHMARKS.md, P1). The count can only err early: a sample that is not an
// awaited command (an ALIVE, a forged copy, one the reader replaced) wakes it before its k are in, and it
// takes, finds fewer, and says what it still needs; a sample counted during a take that then took it stays
// in the count until the next drain (one early wake at most).
#pragma once

#include <atomic>
#include <cstdint>

#include "common/dds/entity.hpp"
#include "common/dds/participant.hpp"

namespace swarmform::dds {

class Waiter {
 public:
  explicit Waiter(const Participant& participant);
  void attach(dds_entity_t condition_or_entity);
  // Blocks until something triggered, enough counted samples are pending, or `deadline` (dds_time_t,
  // absolute) passed; false on timeout. Returns at once while enough counted samples are pending.
  bool wait_until(dds_time_t deadline);
  // Thread-safe.
  void wake();

  // Thread-safe (a reader's listener): one more sample stored.
  void arrived();
  // The taker, before a take: the count to pass to drained() once that take emptied the readers.
  std::uint64_t arrivals() const { return arrivals_.load(); }
  // The taker: the readers were emptied by a take that began at `arrivals_before` (arrivals()).
  void drained(std::uint64_t arrivals_before);
  // The taker: wake once `samples` (at least 1) counted samples are pending.
  void need(std::uint64_t samples);

 private:
  bool enough_pending() const;

  Entity waitset_;
  Entity guard_;
  std::atomic<std::uint64_t> arrivals_{0};
  std::atomic<std::uint64_t> drained_at_{0};  // arrivals_ when the readers were last known empty (or before)
  std::atomic<std::uint64_t> need_{1};
};

}  // namespace swarmform::dds
