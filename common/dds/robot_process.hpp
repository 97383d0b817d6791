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

// Keeps memory the process frees for its next allocations instead of handing it back to the kernel at once
// (glibc's trim threshold, fixed at 32 MiB instead of its sliding default). A robot's receive thread freed
// and re-took ~100 KB of its arena every few rounds: each time glibc returned the pages (madvise) and the
// next round faulted them back in, ~0.4 page faults a robot a round, and a fault costs tens of µs on a
// virtual machine: at N = 64 in lockstep the emulator ran ~275 ticks/s with them, ~370 without (P1,
// BENCHMARKS.md). A process keeps at most its peak heap, which for a robot is a few hundred KB. Call it
// before any thread exists; it holds across fork(). world_server, whose receive threads take N commands a
// round, calls it too. Best effort: false where the C library refuses it.
bool keep_freed_heap();

}  // namespace swarmform::dds
