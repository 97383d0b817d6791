"""`swarm sweep --cluster`: a Dask scheduler and two workers started here as processes of their own (Debian's
dask-scheduler and dask-worker, on 127.0.0.1), running the stand-in harness (fake_sweep_build/; seeds 100 and
up take 0.5 s each). The cluster's sweep equals the local one; a worker SIGKILLed mid-sweep loses no run (the
scheduler starts its runs again elsewhere, and the sweep records it); a worker of another commit is refused
with both commits named. As root, the same across machines: the scheduler and the sweep in one network
namespace, each worker in one of its own (`swarm run --hosts`'s namespaces and switch, hosts.py), removed at
the end. Every process started here is killed by its pid at the end."""

import csv
import json
import os
import shutil
import signal
import subprocess
import tempfile
import time
import unittest

import helpers
from swarmform import hosts as hosts_mod

FAKE = os.path.join(helpers.HERE, "fake_sweep_build")
SCENARIO = os.path.join("data", "walk4.yaml")  # relative: the runs' commands are, on every worker
DEADLINE_S = 60


def rows_of(sweep_dir):
    with open(os.path.join(sweep_dir, "sweep.csv"), newline="") as f:
        return [{k: v for k, v in row.items() if "wall" not in k} for row in csv.DictReader(f)]


def judged(sweep_dir):
    """sweep.json but for how and where it ran."""
    with open(os.path.join(sweep_dir, "sweep.json")) as f:
        res = json.load(f)

    def strip(v):
        if isinstance(v, dict):
            return {k: strip(x) for k, x in v.items() if "wall" not in k and k != "retries"}
        return [strip(x) for x in v] if isinstance(v, list) else v
    return strip({k: v for k, v in res.items() if k not in ("cwd", "started_utc", "cluster")})


class ClusterTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-cluster-")
        self.procs = []
        self.hosts = None
        if self._testMethodName.endswith("on_hosts_of_their_own"):
            return  # its scheduler lives in a namespace
        self.address = f"tcp://127.0.0.1:{helpers.free_port()}"
        self.start(["dask-scheduler", "--host", "127.0.0.1", "--port", self.address.rsplit(":", 1)[1],
                    "--dashboard-address", ":0", "--no-show"], "scheduler")

    def tearDown(self):
        for p in self.procs:
            if p.poll() is None:
                p.kill()
            p.wait(timeout=30)
        if self.hosts is not None:
            self.hosts.remove()
        shutil.rmtree(self.dir)

    def start(self, argv, name, env=None):
        log = open(os.path.join(self.dir, f"{name}.log"), "w")
        e = dict(os.environ, PYTHONPATH=os.path.join(helpers.ROOT, "scripts"), BUILD_DIR=FAKE,
                 PYTHONDONTWRITEBYTECODE="1")
        e.update(env or {})
        p = subprocess.Popen(argv, stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL, env=e,
                             cwd=helpers.ROOT)
        log.close()
        self.procs.append(p)
        return p

    def worker(self, name, env=None):
        return self.start(["dask-worker", self.address, "--no-nanny", "--nthreads", "1", "--name", name,
                           "--dashboard-address", ":0"], name, env)

    def wait_for_workers(self, n, wrap=()):
        code = (f"from distributed import Client\nc = Client({self.address!r}, timeout=30)\n"
                f"c.wait_for_workers({n}, timeout=30)\nc.close()\n")
        r = subprocess.run([*wrap, "/usr/bin/python3", "-c", code], capture_output=True, text=True,
                           timeout=DEADLINE_S)
        self.assertEqual(r.returncode, 0, r.stderr[-2000:])

    def sweep(self, out, *args):
        return helpers.swarm("sweep", "--scenario", SCENARIO, "--expect", "any", "--quiet", "--out", out, *args,
                             build_dir=FAKE, timeout=DEADLINE_S)

    def test_the_cluster_gives_the_local_sweep_and_a_killed_worker_loses_no_run(self):
        victim = self.worker("w1")
        self.worker("w2")
        self.wait_for_workers(2)
        local, remote = os.path.join(self.dir, "local"), os.path.join(self.dir, "remote")
        seeds = ("--seeds", "100-115,1-3")
        self.assertEqual(self.sweep(local, *seeds, "--jobs", "2").returncode, 0)
        cmd = [helpers.SWARM, "sweep", "--scenario", SCENARIO, "--expect", "any", "--quiet", "--out", remote,
               *seeds, "--cluster", self.address]
        env = dict(os.environ, SWARM_NO_BUILD="1", BUILD_DIR=FAKE)
        p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
                             cwd=helpers.HERE)
        self.procs.append(p)
        journal = os.path.join(remote, "runs.jsonl")
        deadline = time.monotonic() + DEADLINE_S
        while time.monotonic() < deadline and p.poll() is None:
            if os.path.exists(journal) and os.path.getsize(journal) > 0:
                break
            time.sleep(0.05)
        victim.send_signal(signal.SIGKILL)  # mid-sweep: its running and queued runs are in flight
        out, err = p.communicate(timeout=DEADLINE_S)
        self.assertEqual(p.returncode, 0, out + err)
        self.assertEqual(rows_of(remote), rows_of(local))
        self.assertEqual(judged(remote), judged(local))
        with open(os.path.join(remote, "sweep.json")) as f:
            cluster = json.load(f)["cluster"]
        self.assertEqual(cluster["address"], self.address)
        self.assertGreaterEqual(cluster["runs_started_again"], 1, cluster)
        self.assertEqual(sum(cluster["runs_per_worker"]), 19)

    def test_a_worker_of_another_commit_is_refused_naming_both(self):
        self.worker("stale", env={"SWARM_DATA_DIR": self.dir, "SWARM_INSTALLED_COMMIT": "0123456789ab"})
        self.wait_for_workers(1)
        r = self.sweep(os.path.join(self.dir, "s"), "--seeds", "1", "--cluster", self.address)
        self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
        self.assertIn("refused, not this build (commit ", r.stderr)
        self.assertIn("(commit 0123456789ab, build of", r.stderr)

    def test_workers_on_hosts_of_their_own(self):
        try:
            hosts_mod.check_can_make_hosts()
            if hosts_mod.in_named_namespace():
                raise hosts_mod.HostsError("inside a named network namespace")
        except hosts_mod.HostsError as e:
            self.skipTest(f"no network namespaces here ({e}): the other tests cover one host")
        self.hosts = hosts_mod.Hosts(2)
        self.hosts.create()
        here, _ = self.hosts.world_wrap()
        self.address = f"tcp://{hosts_mod.WORLD_ADDRESS}:8786"  # the world's host is this test's own
        self.start([*here, "dask-scheduler", "--host", hosts_mod.WORLD_ADDRESS, "--port", "8786",
                    "--dashboard-address", ":0", "--no-show"], "scheduler")
        for h in (0, 1):
            there, _ = self.hosts.agent_wrap(h)
            self.start([*there, "dask-worker", self.address, "--no-nanny", "--nthreads", "1", "--name", f"h{h}",
                        "--dashboard-address", ":0"], f"h{h}")
        self.wait_for_workers(2, here)
        local, remote = os.path.join(self.dir, "local"), os.path.join(self.dir, "remote")
        seeds = ("--seeds", "100-107,1-3")
        self.assertEqual(self.sweep(local, *seeds, "--jobs", "2").returncode, 0)
        env = dict(os.environ, SWARM_NO_BUILD="1", BUILD_DIR=FAKE)
        r = subprocess.run([*here, helpers.SWARM, "sweep", "--scenario", SCENARIO, "--expect", "any", "--quiet",
                            "--out", remote, *seeds, "--cluster", self.address], capture_output=True, text=True,
                           env=env, cwd=helpers.HERE, timeout=DEADLINE_S)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertEqual(rows_of(remote), rows_of(local))
        self.assertEqual(judged(remote), judged(local))
        with open(os.path.join(remote, "sweep.json")) as f:
            self.assertEqual(json.load(f)["cluster"]["workers"], 2)

    def test_no_scheduler_is_a_clear_error(self):
        r = self.sweep(os.path.join(self.dir, "s"), "--seeds", "1", "--cluster",
                       f"tcp://127.0.0.1:{helpers.free_port()}")
        self.assertEqual(r.returncode, 1)
        self.assertIn("no Dask scheduler answered", r.stderr)


if __name__ == "__main__":
    unittest.main()
