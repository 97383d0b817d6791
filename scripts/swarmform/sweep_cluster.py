"""`swarm sweep --cluster tcp://HOST:PORT`: the sweep's runs on a Dask distributed scheduler's workers (Debian's
python3-distributed) instead of this machine's cores; everything else (the grid, the probes, the judging, the
output) stays here, so the results are the local sweep's. docs/sweeps.md "On a cluster" says how to start the
scheduler and the workers.

Each worker runs from a checkout of the same commit, built, with its scripts/ on PYTHONPATH (so that it imports
this module): a run is the same relative command (`build/harness/swarm_inprocess --scenario ...`) started in the
worker's checkout at the place this sweep was started from within ours. Before any run every worker says its
checkout's commit, the commit its build was made from and whether it has the harness; one that differs from
this machine's (or has no harness) is refused, both named.

A worker that dies mid-run loses nothing: the scheduler gives its running tasks to another worker (at most its
`distributed.scheduler.allowed-failures` times, default 3, then the run fails as "lost N workers"). How many
times each run was started again is read from the scheduler and recorded (runs.jsonl and sweep.json's
`cluster`)."""

import os
import signal
import subprocess
import time
from typing import Any, Callable, Optional, Sequence

from . import places


class ClusterError(Exception):
    pass


def build_commit() -> Optional[str]:
    """The commit the build was made from (its generated build-info header, as summary.json's provenance), or
    None without one."""
    try:
        with open(os.path.join(places.build_dir(), "generated", "swarmform_build_info.hpp"), "rb") as f:
            for line in f.read().decode("utf-8", "replace").splitlines():
                if line.startswith("#define SWARMFORM_GIT_COMMIT "):
                    return line.split('"')[1] if '"' in line else None
    except OSError:
        pass
    return None


def worker_identity() -> dict[str, Any]:
    """Run on each worker: its checkout's and its build's commits, and whether its harness is built."""
    exe = places.program("swarm_inprocess")
    return {"commit": places.commit(), "build": build_commit(), "root": places.SOURCE_ROOT,
            "harness": os.access(exe, os.X_OK)}


def run_on_worker(cmd: Sequence[str], rel_cwd: str, timeout: float) -> dict[str, Any]:
    """Run on a worker: `cmd` in its checkout's `rel_cwd`, cut (its process group SIGKILLed) after `timeout`
    seconds (0: never). Returns what the local sweep needs to judge it."""
    started = time.monotonic()
    p = subprocess.Popen(list(cmd), cwd=os.path.join(places.SOURCE_ROOT, rel_cwd), stdin=subprocess.DEVNULL,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, process_group=0)
    timed_out = False
    try:
        out, err = p.communicate(timeout=timeout or None)
    except subprocess.TimeoutExpired:
        timed_out = True
        try:
            os.killpg(p.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        out, err = p.communicate()
    return {"exit_code": p.returncode, "stdout": out.decode("utf-8", "backslashreplace"),
            "stderr": err.decode("utf-8", "backslashreplace"), "wall": time.monotonic() - started,
            "timed_out": timed_out, "worker": os.uname().nodename + ":" + str(os.getpid())}


def _suspicious(keys: Sequence[str], dask_scheduler: Any = None) -> dict[str, int]:
    """Run on the scheduler: how many workers died while running each task."""
    return {k: int(getattr(dask_scheduler.tasks.get(k), "suspicious", 0) or 0) for k in keys}


def relative_cwd() -> str:
    """Where this sweep runs, within the checkout (the runs' commands are relative to it). Raises ClusterError."""
    rel = os.path.relpath(os.getcwd(), places.SOURCE_ROOT)
    if rel.startswith("..") or places.installed():
        raise ClusterError("--cluster runs the sweep's commands in each worker's checkout: start the sweep from "
                           f"inside the source tree ({places.SOURCE_ROOT}), not {os.getcwd()}")
    return rel


def connect(address: str, connect_timeout: float = 15.0) -> Any:
    """A Client of the scheduler at `address`, its workers checked against this checkout. Raises ClusterError."""
    try:
        from distributed import Client
    except ImportError:
        raise ClusterError("--cluster needs Dask's distributed (Debian: apt install python3-distributed)") from None
    try:
        client = Client(address, timeout=connect_timeout)  # the default client: distributed.wait needs one
    except (OSError, TimeoutError) as e:
        raise ClusterError(f"--cluster {address}: no Dask scheduler answered within {connect_timeout:g} s ({e})") \
            from None
    try:
        ids = client.run(worker_identity)
    except Exception as e:  # a worker that cannot import this module raises whatever its unpickling raised
        client.close()
        raise ClusterError(f"--cluster {address}: the workers could not run swarmform's code ({type(e).__name__}: "
                           f"{e}); start them with PYTHONPATH=<checkout>/scripts (docs/sweeps.md)") from None
    if not ids:
        client.close()
        raise ClusterError(f"--cluster {address}: the scheduler has no worker")
    mine, my_build = places.commit(), build_commit()
    bad = [f"{w} (commit {i['commit']}, build of {i['build']}{'' if i['harness'] else ', no harness built'})"
           for w, i in sorted(ids.items()) if (i["commit"], i["build"]) != (mine, my_build) or not i["harness"]]
    if bad:
        client.close()
        raise ClusterError(f"--cluster {address}: refused, not this build (commit {mine}, build of {my_build}): "
                           f"{', '.join(bad)}")
    return client


def execute(client: Any, runs: Sequence[Any], timeout: float, on_done: Callable[[Any, dict[str, Any]], None],
            stop: Any, progress: Any) -> dict[str, Any]:
    """Submits every run; calls on_done(run, result) as each comes back (result as run_on_worker's, or
    {"lost": why} for a run that killed the scheduler's allowed-failures workers); returns the cluster's figures
    for sweep.json. Looks at `stop` (Ctrl-C) twice a second: what is still queued or running is cancelled."""
    from distributed import wait
    rel = relative_cwd()
    futures = {}
    for run in runs:
        key = f"swarm-run-{run.index}-{os.getpid()}-{time.monotonic_ns()}"
        futures[client.submit(run_on_worker, run.cmd, rel, timeout, key=key, pure=False)] = run
    done = failed = 0
    workers: dict[str, int] = {}
    pending = set(futures)
    try:
        while pending and not stop:
            try:
                finished, pending = wait(pending, timeout=0.5, return_when="FIRST_COMPLETED")
            except TimeoutError:
                continue
            for fut in finished:
                run = futures[fut]
                try:
                    result = fut.result()
                except Exception as e:  # KilledWorker: it took allowed-failures workers with it
                    result = {"lost": str(e)}
                run.retries = _suspicious_of(client, fut.key)
                on_done(run, result)
                if "worker" in result:
                    workers[result["worker"]] = workers.get(result["worker"], 0) + 1
                done += 1
                failed += 0 if run.success else 1
                progress.show(done, failed, len(pending), force=done == len(runs) or progress.tty)
    finally:
        client.cancel(list(pending))
    return {"address": client.scheduler.address, "workers": len(workers), "runs_per_worker": sorted(workers.values()),
            "runs_started_again": sum(getattr(r, "retries", 0) for r in runs)}


def _suspicious_of(client: Any, key: str) -> int:
    try:
        return int(client.run_on_scheduler(_suspicious, [key]).get(key, 0))
    except Exception:  # the scheduler forgot the task already: nobody died running it
        return 0
