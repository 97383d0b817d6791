// A tiny fixed worker pool for the per-robot loops of a tick (controllers, ultrasonics, medium delivery),
// shared by the whole process. Determinism is the callers' part: a body must write only the slots of the
// indices it is given (and per-worker scratch), so the result does not depend on which worker ran which
// index. Randomness is never drawn inside a parallel body; callers draw it afterwards, in id order.
//
// Worker count: SWARMFORM_WORKERS if set (>= 1), else hardware_concurrency capped at 2; set_worker_count()
// overrides it (tests compare 1 and 2). 1 worker = a plain serial loop on the calling thread.
#pragma once

#include <cstddef>
#include <functional>

namespace swarmform::parallel {

// body(begin, end, worker): handles indices [begin, end); worker < worker_count() names its scratch.
using RangeBody = std::function<void(std::size_t begin, std::size_t end, std::size_t worker)>;

// Workers (the calling thread included) that for_range uses.
std::size_t worker_count();

// 0 restores the default. Not to be called while a for_range runs.
void set_worker_count(std::size_t workers);

// Runs body over [0, n) in chunks and returns when every chunk is done; the first exception a body threw is
// rethrown here. Calls from different threads take turns; a call from inside a body runs serially, and so
// does a call with fewer than 2 x `min_per_worker` indices (one body(0, n, 0) on the calling thread): waking
// a worker and handing chunks over costs ~15 us a call, more than a small loop saves by it.
void for_range(std::size_t n, const RangeBody& body, std::size_t min_per_worker = 1);

// The world's per-robot sensing loops (medium, ultrasonics) run on the pool from 2 x 64 robots: the measured
// crossover (world_server/world/README.md, "Two cores").
inline constexpr std::size_t kMinRobotsPerWorker = 64;

}  // namespace swarmform::parallel
