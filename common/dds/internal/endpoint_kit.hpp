// What every endpoint file of common/dds needs to make its entities and take from them: partitioned
// publishers and subscribers, readers and writers with the QoS of their channel (qos.hpp), read conditions,
// kept instances, loans returned on scope exit, and the wording of a refused sample's reason. Private to
// common/dds; knows nothing of the IDL.
#pragma once

#include <cstdint>
#include <string>

#include "common/dds/entity.hpp"
#include "common/dds/qos.hpp"

namespace swarmform::dds::internal {

// A publisher or subscriber whose only partition is `partition`.
Entity make_partitioned(dds_entity_t participant, const std::string& partition, bool publisher);

inline Pace pace_of(bool realtime) {
  return realtime ? Pace::Realtime : Pace::Lockstep;
}

Entity make_writer(dds_entity_t parent, dds_entity_t topic, Channel channel, Pace pace = Pace::Lockstep);

Entity make_reader(dds_entity_t parent, dds_entity_t topic, Channel channel,
                   const dds_listener_t* listener = nullptr, Pace pace = Pace::Lockstep);

Entity make_condition(dds_entity_t reader);

// Registers the instance of `key` with `writer` for the writer's lifetime. Cyclone keeps an instance in its
// key map only while something holds it: an unregistered instance whose sample has left the writer's history
// (at once for best effort, on acknowledgement for reliable) is removed after the write, and its memory goes
// to the domain's gc thread through a request. So each write allocated, hashed and freed the instance, and
// queued work for a thread whose wake-ups preempted the world's in its publish phase (perf: 173 of its
// preemptions in a 256-agent run, BENCHMARKS.md). A registered instance stays, so a write finds it in place.
void keep_instance(dds_entity_t writer, const void* key);

// Returns the loan of `n` samples taken into `ptrs` when it goes out of scope.
class Loan {
 public:
  Loan(dds_entity_t reader, void** ptrs, int n) : reader_(reader), ptrs_(ptrs), n_(n) {}
  ~Loan() {
    if (n_ > 0) (void)dds_return_loan(reader_, ptrs_, n_);  // cannot fail for a loan we hold
  }
  Loan(const Loan&) = delete;
  Loan& operator=(const Loan&) = delete;

 private:
  dds_entity_t reader_;
  void** ptrs_;
  int n_;
};

// Why a sample is refused, in the words of a RefusalLog line: another wire version, another run.
std::string version_text(std::uint16_t v);
std::string nonce_text(std::uint64_t got, std::uint64_t want);

}  // namespace swarmform::dds::internal
