// How a robot process (robot_agent, and bench/bare_round's robots so that P1's ratio compares like with like)
// is scheduled next to its world on one machine.
#pragma once

namespace swarmform::dds {

// Puts the calling thread, and every thread it creates afterwards (Cyclone's receive, timed-event and gc
// threads inherit it), under SCHED_BATCH: the same CPU share as before, but a robot woken by its packet no
// longer preempts the thread that woke it. With N robots, the world's loop that writes N packets was
// otherwise preempted by every robot it woke (the world's publish phase took 54-72 ms of a 100 ms tick at
// N = 256, almost all of it waiting for the CPU back). Call it first in main(), before any thread exists.
// Best effort: returns false (and changes nothing) where the system refuses it.
bool yield_to_world_on_wakeup();

}  // namespace swarmform::dds
