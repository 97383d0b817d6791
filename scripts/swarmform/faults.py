"""Scheduled faults in `swarm run` (--fault; format in docs/scenario-format.md, "Faults").

The world server checks and executes them (a bad fault fails `world_server --check` with a clear message);
the launcher's only part is the one fault the world cannot execute: a restart needs a new agent process, and
the launcher owns the agents. The world's status channel says `restart` (id K, tick T) at the restart's
tick (docs/status-channel.md); the launcher
starts `robot_agent --id K` (its output appended to logs/agent-K.log), updates agents.json, and the new agent
claims id K and rejoins.
"""

import os
import subprocess
from typing import TYPE_CHECKING, Callable

if TYPE_CHECKING:  # the launcher imports this module
    from .launcher import Processes, Status

RETIRED_WAIT_S = 5.0

FAULT_HELP = ("a scheduled fault KIND:TARGET@TICK[+TICKS][=VALUE] (repeatable): kill:ID@T, stall:ID@T+TICKS "
              "(SIGSTOP/SIGCONT), restart:ID@T (a new agent after a kill), ultrasonic:ID[/SENSOR]@T[+TICKS] "
              "(reads its maximum), wheel:ID/left|right@T[+TICKS] (stops), loss:ID|all@T[+TICKS] (messages "
              "lost), range:ID|all@T[+TICKS]=METRES (range cut); docs/scenario-format.md, Faults")


class Restarter:
    """Starts a new agent for each `restart` event of the world."""

    def __init__(self, procs: "Processes", agent_exe: str, domain: int, run_nonce: str, logs: str,
                 write_agents: Callable[[], None], robots: int) -> None:
        """`write_agents()` rewrites agents.json from procs (the launcher's own writer, replaced whole)."""
        self.procs, self.agent_exe, self.domain, self.run_nonce = procs, agent_exe, domain, run_nonce
        self.logs, self.write_agents, self.robots = logs, write_agents, robots

    def restart(self, rid: int, tick: int, status: "Status") -> None:
        """Starts agent `rid` anew (the world's restart fault at `tick`), and says so."""
        if not 0 <= rid < self.robots:
            status.line(f"swarm: the world asked to restart agent {rid}, but the run has {self.robots}; ignored")
            return
        old = self.procs.agents.get(rid)
        if old is not None and old.poll() is None:  # a restart follows a kill: it is dying; make sure of it
            try:
                old.kill()
                old.wait(timeout=RETIRED_WAIT_S)
            except (ProcessLookupError, subprocess.TimeoutExpired):
                pass
        p = self.procs.start_agent(self.agent_exe, rid, self.domain, os.path.join(self.logs, f"agent-{rid}.log"),
                                   self.run_nonce)
        self.write_agents()
        status.line(f"swarm: restarted agent {rid} at tick {tick} (pid {p.pid})")
