#include "common/dds/waiter.hpp"

#include <algorithm>

namespace swarmform::dds {

namespace {
Entity make_guard(dds_entity_t participant) {
  return Entity(dds_create_guardcondition(participant), "dds_create_guardcondition");
}
}  // namespace

// The waitset belongs to the library, not to the participant: a world with several faces (each its own
// domain instance) waits for the readers of all of them on one waitset.
Waiter::Waiter(const Participant& participant)
    : waitset_(dds_create_waitset(DDS_CYCLONEDDS_HANDLE), "dds_create_waitset"),
      guard_(make_guard(participant.get())) {
  attach(guard_.get());
}

void Waiter::attach(dds_entity_t entity) {
  check(dds_waitset_attach(waitset_.get(), entity, entity), "dds_waitset_attach");
}

bool Waiter::wait_until(dds_time_t deadline) {
  // Counted samples are level-triggered, as a read condition is: while enough are pending, no sleep (and the
  // wake their listener may have sent is taken below, or it would cut the next sleep short).
  const dds_return_t n =
      enough_pending()
          ? 1
          : check(dds_waitset_wait_until(waitset_.get(), nullptr, 0, deadline), "dds_waitset_wait");
  // Reset the guard before the caller looks at what woke it: a wake() after this reset is never lost.
  bool triggered = false;
  check(dds_take_guardcondition(guard_.get(), &triggered), "dds_take_guardcondition");
  return n > 0;
}

void Waiter::wake() {
  check(dds_set_guardcondition(guard_.get(), true), "dds_set_guardcondition");
}

bool Waiter::enough_pending() const {
  // drained_at_ is a past value of arrivals_, so the difference never wraps.
  return arrivals_.load() - drained_at_.load() >= need_.load();
}

void Waiter::arrived() {
  arrivals_.fetch_add(1);
  // Checked after the count: either this sees the taker's latest need(), or the taker's own check before it
  // sleeps (wait_until) sees this sample. Sequentially consistent atomics, so one of the two does.
  if (enough_pending()) wake();
}

void Waiter::drained(std::uint64_t arrivals_before) {
  drained_at_.store(arrivals_before);
}

void Waiter::need(std::uint64_t samples) {
  need_.store(std::max<std::uint64_t>(samples, 1));
}

}  // namespace swarmform::dds
