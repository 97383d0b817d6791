// Whether an agent's process is still there, from /proc (the agents run on the world's host when the
// launcher gave their pids). A SIGKILLed or exited agent is gone (a zombie its parent has not reaped yet is
// gone too); a stopped, starved or sleeping one is present: slow, not dead.
#pragma once

#include <sys/types.h>

namespace swarmform::server {

enum class ProcessState {
  Present,  // running, sleeping, stopped (SIGSTOP), in disk wait
  Gone,     // no such process, or a zombie (it exited; its parent has not reaped it yet)
};

ProcessState process_state(pid_t pid);

}  // namespace swarmform::server
