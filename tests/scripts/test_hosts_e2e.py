"""`scripts/swarm run --hosts K [--link SPEC]` against the real programs (BUILD_DIR): the world and the
agents in network namespaces of their own, over real UDP through a bridge.

- 12 agents of the paper's scenario over 3 agent hosts reach the goal with the trajectory hash of the same run on
  loopback (lockstep is deterministic whatever the transport; the loopback run is in a namespace this test makes,
  so it never meets another run's traffic);
- 2 hosts whose links lose 20% of the datagrams: the run completes, no robot taken for dead; `loss 5% rate
  20mbit`: the nftables rule and the tbf qdisc are on every host's interface while the run goes;
- one host's link cut mid-run (`ip link set down` on its switch port). Lockstep: its agents' processes are there,
  so the world waits for them (world_server/README.md "In lockstep slowness is never death"): no tick is
  stepped until the link is restored, then they go on with the same controllers, nobody dead. Realtime: its
  agents are recorded dead, the other host's carry on; restored: they rejoin. (Either run ends by Ctrl-C.)
- a launcher killed with SIGKILL leaves its namespaces, and the next --hosts run removes them;
- the flags' errors (a --link without --hosts, delay without netem here, a bad --link) are clear, exit 2;
- scripts/bench-hosts runs tiny in every setting and writes figures (none asserted as a speed);
- `--view-paused --view` over 2 hosts: the page, served in the root namespace, gets the world's frames across the
  hosts' bridge, and its resume reaches the world (the paused run completes only then).
After every run: no namespace, link, pid file or process of the run is left (asserted).

Needs root and the root network namespace (namespaces made from inside another do not work): each test skips with
the reason otherwise. DDS test domains 56-57 (tests/support/test_domain.hpp). Every wait has a deadline.
"""

import asyncio
import json
import os
import shutil
import signal
import subprocess
import tempfile
import time
import unittest

import helpers
import websockets  # Debian's python3-websockets (scripts/setup)

BUILD_DIR = os.environ.get("BUILD_DIR") or os.path.join(helpers.ROOT, "build")
PAPER = os.path.join(helpers.ROOT, "scenarios", "paper.yaml")
WALK = os.path.join(helpers.HERE, "data", "walk4.yaml")
STATE_DIR = "/run/swarmform-hosts"


def _why_not():
    if not os.access(os.path.join(BUILD_DIR, "world_server", "world_server"), os.X_OK):
        return f"world_server is not built in {BUILD_DIR}"
    if os.geteuid() != 0:
        return "needs root: --hosts creates network namespaces"
    from swarmform import hosts
    inside = hosts.in_named_namespace()
    if inside:
        return f"runs in the network namespace {inside}; needs the root one (nested namespaces do not work)"
    return None


def events(run_dir):
    with open(os.path.join(run_dir, "events.jsonl"), encoding="utf-8") as f:
        return [json.loads(line) for line in f if line.strip() and line.endswith("\n")]


def summary(run_dir):
    with open(os.path.join(run_dir, "summary.json"), encoding="utf-8") as f:
        return json.load(f)


def namespaces():
    out = subprocess.run(["ip", "netns", "list"], capture_output=True, text=True, timeout=30).stdout
    return [line.split()[0] for line in out.splitlines() if line.strip()]


def wait_for(what, predicate, deadline_s, proc=None):
    """Polls `predicate()` until true; fails the test at the deadline or when `proc` ended meanwhile."""
    end = time.monotonic() + deadline_s
    while time.monotonic() < end:
        if predicate():
            return
        if proc is not None and proc.poll() is not None:
            raise AssertionError(f"the run ended (exit {proc.returncode}) while waiting for {what}")
        time.sleep(0.2)
    raise AssertionError(f"no {what} within {deadline_s} s")


@unittest.skipIf(_why_not(), _why_not())
class HostsEndToEndTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-hosts-e2e-")
        self.own_ns = None

    def tearDown(self):
        if self.own_ns and self.own_ns in namespaces():
            subprocess.run(["ip", "netns", "del", self.own_ns], capture_output=True, timeout=30)
        shutil.rmtree(self.dir)

    def out(self, name):
        return os.path.join(self.dir, name)

    def swarm_args(self, out, *extra):
        return [helpers.SWARM, "run", "--no-pictures", "--out", out, *extra]

    def env(self):
        return dict(os.environ, SWARM_NO_BUILD="1", BUILD_DIR=BUILD_DIR, PYTHONDONTWRITEBYTECODE="1")

    def run_swarm(self, out, *extra, timeout=240):
        r = subprocess.run(self.swarm_args(out, *extra), capture_output=True, text=True, timeout=timeout,
                           env=self.env())
        return r

    @staticmethod
    def log(out, rid):
        try:
            with open(os.path.join(out, "logs", f"agent-{rid}.log"), encoding="utf-8") as f:
                return f.read()[-2000:]
        except OSError as e:
            return str(e)

    def assert_nothing_left(self, out):
        """No namespace, root-namespace link, pid file or process of the run at `out` remains."""
        with open(os.path.join(out, "hosts.json"), encoding="utf-8") as f:
            hosts = json.load(f)
        prefix = hosts["prefix"]
        self.assertEqual([ns for ns in namespaces() if ns.startswith(prefix + "-")], [], "namespaces left")
        links = subprocess.run(["ip", "-o", "link"], capture_output=True, text=True, timeout=30).stdout
        self.assertNotIn(prefix + "-", links, "links left in the root namespace")
        self.assertFalse(os.path.exists(os.path.join(STATE_DIR, prefix + ".pid")), "pid file left")
        with open(os.path.join(out, "agents.json"), encoding="utf-8") as f:
            pids = list(json.load(f).values())
        self.assertEqual([p for p in pids if helpers.pid_alive(p)], [], "agents left running")
        return hosts

    def test_twelve_agents_on_three_hosts_arrive_with_the_loopback_trajectory(self):
        domain = str(helpers.test_domain(56))
        flags = ["--scenario", PAPER, "--robots", "12", "--domain", domain]
        # The loopback run, in a namespace of this test's own (its own loopback).
        self.own_ns = f"sfht{os.getpid()}-lo"
        subprocess.run(["ip", "netns", "add", self.own_ns], check=True, timeout=30)
        subprocess.run(["ip", "-n", self.own_ns, "link", "set", "lo", "up"], check=True, timeout=30)
        loop = self.out("loopback")
        r = subprocess.run(["ip", "netns", "exec", self.own_ns] + self.swarm_args(loop, *flags), capture_output=True,
                           text=True, timeout=240, env=self.env())
        self.assertEqual(r.returncode, 0, f"loopback run:\n{r.stderr}")
        hosts_run = self.out("hosts")
        r = self.run_swarm(hosts_run, *flags, "--hosts", "3")
        self.assertEqual(r.returncode, 0, f"--hosts 3 run:\n{r.stderr}")
        self.assertNotIn("Traceback", r.stderr)
        hosts = self.assert_nothing_left(hosts_run)
        self.assertEqual([h["agents"] for h in hosts["agent_hosts"]],
                         [[0, 3, 6, 9], [1, 4, 7, 10], [2, 5, 8, 11]])
        self.assertEqual(len({h["address"] for h in hosts["agent_hosts"]} | {hosts["world"]["address"]}), 4)
        a, b = summary(loop), summary(hosts_run)
        self.assertEqual(b["outcome"], "arrived", b)
        self.assertIsNotNone(b["goal_tick"])
        self.assertEqual(b["deaths"], [])
        self.assertEqual(b["trajectory_sha256"], a["trajectory_sha256"])
        self.assertEqual(b["goal_tick"], a["goal_tick"])
        # Every agent claimed its id from its own host's address (the world logs the claims' pids; the agents'
        # logs name the interface they were given).
        for h in hosts["agent_hosts"]:
            with open(os.path.join(hosts_run, "logs", f"agent-{h['agents'][0]}.log"), encoding="utf-8") as f:
                self.assertIn("agent id=", f.read())

    def test_two_hosts_losing_a_fifth_of_the_datagrams_complete_without_a_death(self):
        out = self.out("lossy")
        r = self.run_swarm(out, "--scenario", WALK, "--robots", "6", "--max-ticks", "150", "--domain",
                           str(helpers.test_domain(57)), "--hosts", "2", "--link", "loss 20%")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("links: loss 20%", r.stderr)
        hosts = self.assert_nothing_left(out)
        self.assertEqual(hosts["link"], {"loss": 20.0})
        s = summary(out)
        self.assertEqual(s["ticks"], 150)
        self.assertEqual(s["deaths"], [])
        self.assertEqual(s["alive_at_end"], 6)

    def test_loss_and_rate_are_applied_to_every_hosts_link(self):
        out = self.out("shaped")
        p = subprocess.Popen(self.swarm_args(out, "--scenario", WALK, "--robots", "4", "--max-ticks", "1000000",
                                             "--domain", str(helpers.test_domain(57)), "--hosts", "2",
                                             "--link", "loss 5% rate 20mbit"),
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=self.env(),
                             process_group=0)
        try:
            ev = os.path.join(out, "events.jsonl")
            wait_for("4 connected agents", lambda: os.path.exists(ev) and len(
                {e["id"] for e in events(out) if e["kind"] == "agent_connected"}) == 4, 60, p)
            with open(os.path.join(out, "hosts.json"), encoding="utf-8") as f:
                hosts = json.load(f)
            for h in [hosts["world"]] + hosts["agent_hosts"]:
                qdisc = subprocess.run(["tc", "-n", h["namespace"], "qdisc", "show", "dev", h["interface"]],
                                       capture_output=True, text=True, timeout=30).stdout
                self.assertIn("tbf", qdisc)
                self.assertIn("rate 20Mbit", qdisc)
                rules = subprocess.run(["ip", "netns", "exec", h["namespace"], "nft", "list", "ruleset"],
                                       capture_output=True, text=True, timeout=30).stdout
                self.assertIn(f'oifname "{h["interface"]}" numgen random mod 10000 < 500 drop', rules)
        finally:
            if p.poll() is None:
                os.killpg(p.pid, signal.SIGINT)
            _, err = p.communicate(timeout=60)
        self.assertEqual(p.returncode, 130, err)
        self.assertIn("links: loss 5% rate 20mbit", err)
        self.assert_nothing_left(out)

    def test_a_host_cut_off_in_lockstep_is_waited_for_and_goes_on_with_the_same_controllers(self):
        # A cut host's agents are alive but unreachable: in lockstep that is slowness, not death. The world
        # waits (it steps no tick while they are cut), and once the link is back they answer the round they
        # were given and go on with their controllers: no death, no rejoin, and the trajectory of the same run
        # uncut. The cut is held past the world's 2 s writer lease (the agents see the world silent and
        # re-claim), well under their 10 s --world-timeout, past which they would exit (and be recorded dead:
        # docs/faults.md), and under the 30 s lockstep_deadline, past which the run would end.
        ticks = ["--max-ticks", "4000"]
        uncut = self.out("uncut")
        r = self.run_swarm(uncut, "--scenario", WALK, "--robots", "6", "--domain", str(helpers.test_domain(57)),
                           "--hosts", "2", *ticks)
        self.assertEqual(r.returncode, 0, r.stderr)
        out = self.out("cut-lockstep")
        p, hosts = self.start_cut_run(out, "lockstep", ticks)
        cut = hosts["agent_hosts"][1]
        try:
            port = self.cut_port(hosts, cut)
            subprocess.run(port + ["down"], check=True, timeout=30)
            stalled = lambda: {e["id"] for e in events(out) if e["kind"] == "agent_stalled"} >= set(cut["agents"])  # noqa
            wait_for(f"{cut['agents']} waited for", stalled, 8, p)
            time.sleep(3)
            subprocess.run(port + ["up"], check=True, timeout=30)
            _, err = p.communicate(timeout=120)
        finally:
            if p.poll() is None:
                os.killpg(p.pid, signal.SIGINT)
                p.communicate(timeout=60)
        self.assertEqual(p.returncode, 0, err)
        self.assert_nothing_left(out)
        ev = events(out)
        self.assertEqual([e for e in ev if e["kind"] in ("death", "rejoin", "command_waited_out")], [])
        stalled = {e["id"]: e["tick"] for e in ev if e["kind"] == "agent_stalled"}
        back = {e["id"]: e["tick"] for e in ev if e["kind"] == "liveliness_regained"}
        self.assertEqual(sorted(stalled), cut["agents"], "only the cut host's agents are waited for")
        s = summary(out)
        self.assertEqual(s["ticks"], 4000)
        self.assertEqual(s["alive_at_end"], 6)
        self.assertEqual(s["deaths"], [])
        # Every tick was stepped with every robot's command: the trajectory of the uncut run.
        self.assertEqual(s["trajectory_sha256"], summary(uncut)["trajectory_sha256"])
        for rid in cut["agents"]:
            # The world stepped nothing while it waited for them, but the round the loss was noticed in may
            # already have held their answer (sent before the cut, taken in the same pass as the loss): that
            # round is stepped, and they are back in the next at the latest (2 runs in 5 under load).
            self.assertIn(back.get(rid, -1) - stalled[rid], (0, 1),
                          f"robot {rid}: {[e for e in ev if e.get('id') == rid]}")
        for rid in cut["agents"]:  # the same controller: never started afresh
            self.assertIn("restarts=0", self.log(out, rid))

    def test_a_host_cut_off_in_realtime_has_its_agents_taken_for_dead_and_rejoin_when_restored(self):
        # Best effort: the agents' liveliness heartbeats do not revive them at the world (docs/multi-host.md);
        # their claims, re-sent while the world's writers are not alive, do.
        self.cut_and_restore("realtime")

    def start_cut_run(self, out, mode, ticks=("--max-ticks", "1000000")):
        """A run of 6 agents on 2 hosts, every agent connected: (the launcher, hosts.json)."""
        p = subprocess.Popen(self.swarm_args(out, "--scenario", WALK, "--robots", "6", *ticks, "--mode", mode,
                                             "--domain", str(helpers.test_domain(57)), "--hosts", "2"),
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=self.env(),
                             process_group=0)
        try:
            hosts_json = os.path.join(out, "hosts.json")
            wait_for("hosts.json", lambda: os.path.exists(hosts_json), 60, p)
            with open(hosts_json, encoding="utf-8") as f:
                hosts = json.load(f)
            ev = os.path.join(out, "events.jsonl")
            connected = lambda: os.path.exists(ev) and len(  # noqa: E731
                {e["id"] for e in events(out) if e["kind"] == "agent_connected"}) == 6
            wait_for("6 connected agents", connected, 60, p)
        except BaseException:
            if p.poll() is None:
                os.killpg(p.pid, signal.SIGINT)
            p.communicate(timeout=60)
            raise
        return p, hosts

    @staticmethod
    def cut_port(hosts, host):
        """`ip link set` of `host`'s switch port, to which "down" or "up" is added."""
        return ["ip", "-n", hosts["switch"]["namespace"], "link", "set", host["switch_port"]]

    def cut_and_restore(self, mode):
        # The run is long; Ctrl-C ends it once the agents rejoined, which also checks that an interrupted
        # --hosts run leaves nothing behind.
        out = self.out(f"cut-{mode}")
        p, hosts = self.start_cut_run(out, mode)
        try:
            cut = hosts["agent_hosts"][1]
            port = self.cut_port(hosts, cut)
            subprocess.run(port + ["down"], check=True, timeout=30)
            dead = lambda: {e["id"] for e in events(out) if e["kind"] == "death"} >= set(cut["agents"])  # noqa
            wait_for(f"deaths of {cut['agents']}", dead, 20, p)
            subprocess.run(port + ["up"], check=True, timeout=30)
            back = lambda: {e["id"] for e in events(out) if e["kind"] == "rejoin"} >= set(cut["agents"])  # noqa
            try:
                wait_for(f"rejoins of {cut['agents']}", back, 30, p)
            except AssertionError as e:
                raise AssertionError(f"{e}; events: {[x for x in events(out) if x['kind'] != 'fault']}; "
                                     f"agent {cut['agents'][0]}'s log: {self.log(out, cut['agents'][0])}") from None
        finally:
            if p.poll() is None:
                os.killpg(p.pid, signal.SIGINT)
            _, err = p.communicate(timeout=60)
        self.assertEqual(p.returncode, 130, err)
        self.assert_nothing_left(out)
        ev = events(out)
        deaths = {e["id"]: e["tick"] for e in ev if e["kind"] == "death"}
        rejoins = {e["id"]: e["tick"] for e in ev if e["kind"] == "rejoin"}
        self.assertEqual(sorted(deaths), cut["agents"], "only the cut host's agents die")
        for rid in cut["agents"]:  # the others carried on meanwhile: the world ticked between death and rejoin
            self.assertGreater(rejoins[rid], deaths[rid])
        s = summary(out)
        self.assertEqual(s["alive_at_end"], 6)
        self.assertGreater(s["ticks"], max(rejoins.values()))

    @unittest.skipUnless(os.access(os.path.join(BUILD_DIR, "viewer", "swarm_viewer"), os.X_OK),
                         f"swarm_viewer is not built in {BUILD_DIR} (the sanitizer stage builds no viewer)")
    def test_the_live_view_reaches_a_world_on_another_host(self):
        out = self.out("view")
        port = helpers.free_port()
        p = subprocess.Popen(self.swarm_args(out, "--scenario", WALK, "--robots", "4", "--max-ticks", "150",
                                             "--domain", str(helpers.test_domain(57)), "--hosts", "2",
                                             "--view-paused", "--view", str(port)),
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=self.env(),
                             process_group=0)
        try:
            first = asyncio.run(self.first_frame_then_resume(port, p))
            _, err = p.communicate(timeout=120)
        finally:
            if p.poll() is None:  # Ctrl-C first: the launcher removes its namespaces
                os.killpg(p.pid, signal.SIGINT)
                try:
                    p.communicate(timeout=60)
                except subprocess.TimeoutExpired:
                    os.killpg(p.pid, signal.SIGKILL)
                    p.communicate(timeout=30)
        self.assertEqual(p.returncode, 0, err)
        self.assertEqual(first["tick"], 0, "the paused run's first frame")
        self.assertEqual(len(first["robots"]), 4)
        self.assertEqual(summary(out)["ticks"], 150)
        self.assertIn("viewer bound", err)
        self.assert_nothing_left(out)

    async def first_frame_then_resume(self, port, proc):
        """The first frame the page gets (the world, paused at tick 0, publishes frames across the bridge),
        then the page's resume."""
        deadline = time.monotonic() + 60
        while True:  # the viewer listens once the world is ready
            try:
                ws = await websockets.connect(f"ws://127.0.0.1:{port}/ws")
                break
            except OSError:
                if time.monotonic() > deadline or proc.poll() is not None:
                    raise AssertionError(f"no viewer on port {port} (run exit {proc.poll()})") from None
                await asyncio.sleep(0.2)
        try:
            while time.monotonic() < deadline:
                m = json.loads(await asyncio.wait_for(ws.recv(), 30))
                if m.get("type") == "frame":
                    await ws.send(json.dumps({"cmd": "resume"}))
                    return m
        finally:
            await ws.close()
        raise AssertionError("no frame within 60 s")

    def test_the_namespaces_of_a_killed_launcher_are_removed_by_the_next_run(self):
        crashed = self.out("crashed")
        p = subprocess.Popen(self.swarm_args(crashed, "--scenario", WALK, "--robots", "4", "--max-ticks", "1000000",
                                             "--domain", str(helpers.test_domain(57)), "--hosts", "2"),
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=self.env(), process_group=0)
        try:
            ev = os.path.join(crashed, "events.jsonl")
            wait_for("4 connected agents", lambda: os.path.exists(ev) and len(
                {e["id"] for e in events(crashed) if e["kind"] == "agent_connected"}) == 4, 60, p)
            os.kill(p.pid, signal.SIGKILL)  # the launcher itself (scripts/swarm execs it): no cleanup can run
            p.wait(timeout=30)
        finally:
            if p.poll() is None:
                os.killpg(p.pid, signal.SIGKILL)
                p.wait(timeout=30)
        with open(os.path.join(crashed, "hosts.json"), encoding="utf-8") as f:
            prefix = json.load(f)["prefix"]
        self.assertEqual(len([ns for ns in namespaces() if ns.startswith(prefix + "-")]), 4, "nothing to clean")
        out = self.out("next")
        r = self.run_swarm(out, "--scenario", WALK, "--robots", "2", "--max-ticks", "20", "--domain",
                           str(helpers.test_domain(57)), "--hosts", "1")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn(f"removed the namespaces left by a --hosts run that did not end cleanly ({prefix}-*)", r.stderr)
        self.assert_nothing_left(out)
        self.assertEqual([ns for ns in namespaces() if ns.startswith(prefix + "-")], [])
        with open(os.path.join(crashed, "agents.json"), encoding="utf-8") as f:
            pids = list(json.load(f).values())
        self.assertEqual([x for x in pids if helpers.pid_alive(x)], [], "the crashed run's agents left running")

    def test_the_benchmark_runs_tiny_and_writes_valid_figures(self):
        # scripts/bench-hosts cannot rot: tiny, every setting, figures > 0 (no speed asserted), nothing left.
        before = [ns for ns in namespaces() if ns.startswith("sfh")]
        out = self.out("bench.json")
        r = subprocess.run([os.path.join(helpers.ROOT, "scripts", "bench-hosts"), "--sizes", "4", "--ticks", "20",
                            "--rounds", "20", "--warmup", "5", "--timeout", "30", "--out", out],
                           capture_output=True, text=True, timeout=300, env=self.env())
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(out, encoding="utf-8") as f:
            results = json.load(f)["results"]
        self.assertEqual([x["setting"] for x in results], ["loopback", "hosts4", "hosts4_loss1", "secure"])
        for x in results:
            self.assertGreater(x["emulator_ticks_per_second"], 0)
            self.assertGreater(x["bare_rounds_per_second"], 0)
            self.assertGreater(x["connect_seconds"], 0)
        self.assertEqual([ns for ns in namespaces() if ns.startswith("sfh")], before)

    def test_bad_link_flags_are_refused_clearly(self):
        r = self.run_swarm(self.out("x"), "--scenario", WALK, "--link", "loss 5%")
        self.assertEqual(r.returncode, 2)
        self.assertIn("--link shapes the links of emulated hosts: it needs --hosts K", r.stderr)
        r = self.run_swarm(self.out("x"), "--scenario", WALK, "--hosts", "2", "--link", "jitter 5ms")
        self.assertEqual(r.returncode, 2)
        self.assertIn("unknown 'jitter'", r.stderr)
        if _netem_missing():  # this kernel: refused, with every namespace made before the refusal removed
            before = [ns for ns in namespaces() if ns.startswith("sfh")]
            r = self.run_swarm(self.out("delay"), "--scenario", WALK, "--hosts", "2", "--link", "delay 20ms")
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn("--link delay needs the kernel's netem", r.stderr)
            self.assertNotIn("Traceback", r.stderr)
            self.assertEqual([ns for ns in namespaces() if ns.startswith("sfh")], before)


def _netem_missing():
    ns = f"sfht{os.getpid()}-probe"
    subprocess.run(["ip", "netns", "add", ns], check=True, timeout=30)
    try:
        p = subprocess.run(["tc", "-n", ns, "qdisc", "add", "dev", "lo", "root", "netem", "delay", "1ms"],
                           capture_output=True, text=True, timeout=30)
        return p.returncode != 0 and "unknown" in p.stderr
    finally:
        subprocess.run(["ip", "netns", "del", ns], capture_output=True, timeout=30)


if __name__ == "__main__":
    unittest.main()
