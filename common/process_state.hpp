// Whether a process of this host is still there, from /proc: the world looks at its agents' (the launcher
// gives it their pids), an agent at its world's (--world-pid). A SIGKILLed or exited process is gone (a
// zombie its parent has not reaped yet is gone too); a stopped, starved or sleeping one is present: slow, not
// dead.
#pragma once

#include <sys/types.h>

namespace swarmform {

enum class ProcessState {
  Present,  // running, sleeping, stopped (SIGSTOP), in disk wait
  Gone,     // no such process, or a zombie (it exited; its parent has not reaped it yet)
};

ProcessState process_state(pid_t pid);

}  // namespace swarmform
