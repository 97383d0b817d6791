// `robot_agent --id K --count N` (and `bare_round robot --id K --count N`, so that P1's ratio compares like
// with like): N robots, ids K..K+N-1, each its own OS process, forked from this one.
//
// Why fork rather than start N executables: each start of robot_agent spends ~20 ms of CPU, mostly in the
// dynamic loader, relocating libddsc and what Debian links it with (libcrypto, libssl, iceoryx): `perf stat
// robot_agent --help` 21.9 ms against 1.6 ms for an empty C program; 256 agents started one by one on 2 cores
// spent 5.4-5.8 s of CPU in their main threads until connected, ~21 ms each. A forked child shares its
// parent's loaded and relocated libraries (and their pages: RSS 8.8 -> 5.9 MiB an agent) and starts at once.
// 256 agents, same build, 3 alternated runs each: connected 8.5-12.0 s as executables, 5.0-7.7 s as a block
// (BENCHMARKS.md).
//
// Each child is a whole agent as `robot_agent --id K` would be: its own process, DDS participant and signal
// watcher (it forks before any thread exists). The parent only supervises: it forwards SIGINT and SIGTERM to
// every child still running, reaps them, and exits 0 when every child exited 0, otherwise with the highest
// child exit code (128 + signal for a child killed by a signal). Each child gets SIGTERM if the parent dies
// (PR_SET_PDEATHSIG), so killing the parent's pid stops the whole block.
#pragma once

#include <cstdint>
#include <functional>
#include <iosfwd>

namespace swarmform::dds {

// At most this many robots in one block: a bound on what one command may fork.
inline constexpr std::uint32_t kMaxRobotBlock = 4096;

// True when ids first..first+count-1 all fit in 32 bits (count >= 1).
inline bool block_ids_fit(std::uint32_t first, std::uint32_t count) {
  return count >= 1 && first <= UINT32_MAX - (count - 1);
}

// Forks `count` children; child i runs robot(first + i) and exits with its result. Prints one line per child
// to `out` ("<name>: id K pid P") so a caller can kill a given robot. Returns the block's exit code; 2 (said
// on stderr, nothing forked) when the ids do not fit in 32 bits.
int run_robot_block(const char* name, std::uint32_t first, std::uint32_t count,
                    const std::function<int(std::uint32_t)>& robot, std::ostream& out);

}  // namespace swarmform::dds
