"""Starting a run's N agents a slice at a time from the launcher's loop, never all in one go.

While the launcher starts agents it reads nothing from the world, and the world blocks writing its status pipe
(64 KB) once that is full: starting 1024 agents (a fork and exec each, tens of ms on a busy host) held the
launcher 50 s, the world stopped at the 501st claim, and every agent after it gave up on an unanswered claim. So
`step` starts at most SLICE_AGENTS agents or SLICE_S seconds' worth, and the launcher reads the world's output
between slices (launcher.py `_follow`: no sleep while `pending`)."""

import time
from typing import Callable

SLICE_AGENTS = 32
SLICE_S = 0.05


class AgentStarter:
    """`start(rid)` starts agent `rid` (skipping one already started is its business); `after_slice()` runs after
    every slice that started any (the launcher rewrites agents.json, so the world learns the pids as they come)."""

    def __init__(self, robots: int, start: Callable[[int], None], after_slice: Callable[[], None],
                 slice_agents: int = SLICE_AGENTS, slice_s: float = SLICE_S) -> None:
        self.robots, self.start, self.after_slice = robots, start, after_slice
        self.slice_agents, self.slice_s = slice_agents, slice_s
        self.next_id = robots  # nothing to start until begin()

    def begin(self) -> None:
        self.next_id = 0

    @property
    def pending(self) -> bool:
        return self.next_id < self.robots

    def cancel(self) -> None:
        self.next_id = self.robots

    def step(self) -> None:
        """One slice (nothing when none is pending)."""
        if not self.pending:
            return
        until = time.monotonic() + self.slice_s
        started = 0
        while self.pending and started < self.slice_agents and (started == 0 or time.monotonic() < until):
            self.start(self.next_id)
            self.next_id += 1
            started += 1
        self.after_slice()
