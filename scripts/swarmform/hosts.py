"""`swarm run --hosts K [--link SPEC]`: the hosts of a deployment emulated by Linux network namespaces.

A run with prefix P = sfh<launcher pid> makes (every name starts with P, so runs never collide):
  P-sw        the switch: bridge P-br, one port per host (P-pw: the world's, P-p<h>: agent host h's)
  P-w         the world's host: interface P-w, 10.77.0.1/24
  P-a<h>      agent host h (0..K-1): interface P-h<h>, 10.77.0.<10+h>/24; agent i lives on host i mod K
Every host is joined to the switch by a veth pair. world_server runs in P-w with `--interface 10.77.0.1`, each
robot_agent in its host with `--world-host 10.77.0.1 --interface <its address>`: real UDP between namespaces,
the same star discovery and partition-per-robot delivery as across machines (docs/multi-host.md).

--link shapes every host's interface, outbound, so a datagram from any host to any other meets one shaper:
  loss P%     nftables `numgen random mod 10000 < P*100 drop` in the host's output chain
  rate R      tc tbf (R as tc spells it: 20mbit, 500kbit, ...)
  delay D     tc netem (where the kernel has it; refused with a message where it does not: no home-made relay)

Nothing is left behind: `Hosts.remove()` (the launcher's `finally`, so also on Ctrl-C and on an exception)
SIGKILLs every process still in the namespaces and deletes them (their veths, bridge, nftables rules and qdiscs
go with them). A SIGKILLed launcher cannot clean up: its children die with it (PR_SET_PDEATHSIG) and the next
`--hosts` run removes its namespaces (`remove_leftovers`: a prefix whose pid file names no live launcher).
hosts.json in the run directory says which namespace, interface and switch port each host has.
"""

import os
import re
import shutil
import signal
import subprocess
from typing import Any, Optional, Union

from . import jsonfile

Link = dict[str, Union[float, str]]  # --link: loss (percent), rate, delay (tc's spelling)

STATE_DIR = "/run/swarmform-hosts"  # P.pid: the launcher's pid and start time, written before any namespace
NAME = re.compile(r"^sfh(\d+)-")
SUBNET = "10.77.0"
WORLD_ADDRESS = f"{SUBNET}.1"
MAX_HOSTS = 64
CMD_TIMEOUT_S = 30
NETNS_ROOT_HINT = ("--hosts creates network namespaces and must be started from the root one: run it without "
                   "`ip netns exec` (namespaces made from inside another do not work)")
LINK_HELP = ("shape every emulated host's link (needs --hosts): 'loss P%%' (nftables), 'rate R' (tc tbf, e.g. "
             "20mbit), 'delay D' (tc netem, e.g. 20ms; only where the kernel has netem); e.g. "
             "--link \"loss 5%% rate 20mbit\"")


class HostsError(Exception):
    pass


def parse_link(text: str) -> Link:
    """--link text -> {"loss": percent (float), "rate": str, "delay": str}; HostsError naming the bad part."""
    words = text.split()
    if not words or len(words) % 2:
        raise HostsError(f"--link {text!r}: want KEY VALUE pairs: loss P%, rate R, delay D")
    out: Link = {}
    for key, value in zip(words[::2], words[1::2]):
        if key in out:
            raise HostsError(f"--link {text!r}: {key} given twice")
        if key == "loss":
            m = re.fullmatch(r"(\d+(?:\.\d+)?)%", value)
            if not m or not 0 < float(m[1]) <= 100:
                raise HostsError(f"--link {text!r}: loss wants a percentage in (0, 100], e.g. 5%, got {value!r}")
            out[key] = float(m[1])
        elif key == "rate":
            if not re.fullmatch(r"\d+(?:\.\d+)?(?:bit|kbit|mbit|gbit|bps|kbps|mbps|gbps)", value):
                raise HostsError(f"--link {text!r}: rate wants a tc rate such as 20mbit or 500kbit, got {value!r}")
            out[key] = value
        elif key == "delay":
            if not re.fullmatch(r"\d+(?:\.\d+)?(?:us|ms|s)", value):
                raise HostsError(f"--link {text!r}: delay wants a time such as 20ms, got {value!r}")
            out[key] = value
        else:
            raise HostsError(f"--link {text!r}: unknown {key!r} (loss, rate or delay)")
    return out


def check_can_make_hosts() -> None:
    """HostsError unless this process is root in the root network namespace."""
    if os.geteuid() != 0:
        raise HostsError("--hosts needs root (it creates network namespaces, veths and a bridge); run as root, "
                         "or leave --hosts out to run on loopback")
    inside = in_named_namespace()
    if inside:
        raise HostsError(f"this process runs in the network namespace {inside}: {NETNS_ROOT_HINT}")


def in_named_namespace() -> Optional[str]:
    """The `ip netns` namespace this process runs in, or None (the root one, or one without a name). Compares
    inodes with /run/netns/*: /proc/1/ns/net may be unreadable even to root in a container."""
    try:
        mine = os.stat("/proc/self/ns/net")
        names = os.listdir("/run/netns")
    except OSError:
        return None
    for name in names:
        try:
            st = os.stat(os.path.join("/run/netns", name))
        except OSError:
            continue
        if (st.st_dev, st.st_ino) == (mine.st_dev, mine.st_ino):
            return name
    return None


def _run(cmd: list[str], what: str) -> str:
    try:
        p = subprocess.run(cmd, capture_output=True, encoding="utf-8", errors="backslashreplace", timeout=CMD_TIMEOUT_S)
    except (OSError, subprocess.TimeoutExpired) as e:
        raise HostsError(f"{what}: {' '.join(cmd)}: {e}") from None
    if p.returncode != 0:
        raise HostsError(f"{what}: `{' '.join(cmd)}` failed: {(p.stderr or p.stdout).strip()}")
    return p.stdout


def _namespaces() -> list[str]:
    try:
        out = subprocess.run(["ip", "netns", "list"], capture_output=True, encoding="utf-8", errors="backslashreplace",
                             timeout=CMD_TIMEOUT_S).stdout
    except (OSError, subprocess.TimeoutExpired):
        return []
    return [line.split()[0] for line in out.splitlines() if line.strip()]


def _start_time(pid: int) -> Optional[int]:
    """The process's start time (clock ticks since boot), or None if there is no such process."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return int(f.read().rsplit(")", 1)[1].split()[19])
    except (OSError, IndexError, ValueError):
        return None


def _kill_namespace_processes(ns: str) -> None:
    try:
        out = subprocess.run(["ip", "netns", "pids", ns], capture_output=True,
                             encoding="utf-8", errors="backslashreplace",
                             timeout=CMD_TIMEOUT_S).stdout
    except (OSError, subprocess.TimeoutExpired):
        return
    for word in out.split():
        if word.isdigit() and int(word) != os.getpid():
            try:
                os.kill(int(word), signal.SIGKILL)
            except OSError:
                pass


def _delete_namespace(ns: str) -> None:
    _kill_namespace_processes(ns)
    try:
        subprocess.run(["ip", "netns", "del", ns], capture_output=True, timeout=CMD_TIMEOUT_S)
    except (OSError, subprocess.TimeoutExpired):
        pass  # left for the next run's remove_leftovers


def _owner_alive(prefix: str) -> bool:
    """True if the pid file of `prefix` names a launcher that still runs (same pid and start time)."""
    try:
        with open(os.path.join(STATE_DIR, f"{prefix}.pid")) as f:
            pid, start = (int(x) for x in f.read().split())
    except (OSError, ValueError):
        return False
    return _start_time(pid) == start


def remove_leftovers() -> list[str]:
    """Removes the namespaces (and their processes) of --hosts runs whose launcher is gone (a SIGKILL, a
    crash); returns the prefixes removed."""
    removed: set[str] = set()
    for ns in _namespaces():
        m = NAME.match(ns)
        if not m:
            continue
        prefix = ns[:m.end() - 1]
        if prefix in removed or not _owner_alive(prefix):
            _delete_namespace(ns)
            removed.add(prefix)
    try:
        names = os.listdir(STATE_DIR)
    except OSError:
        names = []
    for name in names:
        prefix = name[:-len(".pid")]
        if name.endswith(".pid") and (prefix in removed or not _owner_alive(prefix)):
            try:
                os.unlink(os.path.join(STATE_DIR, name))
            except OSError:
                pass
    return sorted(removed)


class Hosts:
    """One run's namespaces. `create()` builds them (HostsError on failure, having removed what it made)."""

    def __init__(self, count: int, link: Optional[Link] = None, prefix: Optional[str] = None) -> None:
        if not 1 <= count <= MAX_HOSTS:
            raise HostsError(f"--hosts {count}: want 1..{MAX_HOSTS} agent hosts")
        self.count, self.link = count, link or {}
        self.prefix = prefix or f"sfh{os.getpid()}"
        self.switch = f"{self.prefix}-sw"
        self.bridge = f"{self.prefix}-br"
        self.world = {"namespace": f"{self.prefix}-w", "interface": f"{self.prefix}-w", "address": WORLD_ADDRESS,
                      "switch_port": f"{self.prefix}-pw"}
        self.agent_hosts = [{"namespace": f"{self.prefix}-a{h}", "interface": f"{self.prefix}-h{h}",
                             "address": f"{SUBNET}.{10 + h}", "switch_port": f"{self.prefix}-p{h}"}
                            for h in range(count)]
        self._pid_file = os.path.join(STATE_DIR, f"{self.prefix}.pid")
        self._made = False

    def namespaces(self) -> list[str]:
        return [self.switch, self.world["namespace"]] + [h["namespace"] for h in self.agent_hosts]

    def host_of(self, rid: int) -> dict[str, str]:
        return self.agent_hosts[rid % self.count]

    def world_wrap(self) -> tuple[list[str], list[str]]:
        """The command prefix and the world_server flags for the world's host."""
        return ["ip", "netns", "exec", self.world["namespace"]], ["--interface", WORLD_ADDRESS]

    def viewer_flags(self) -> list[str]:
        """swarm_viewer's flags under --view: its DDS side in the world's host, its page in the launcher's
        namespace (the viewer makes its listening socket before it enters the world's: no relay)."""
        return ["--netns", self.world["namespace"], "--world-host", WORLD_ADDRESS, "--interface", WORLD_ADDRESS]

    def agent_wrap(self, rid: int) -> tuple[list[str], list[str]]:
        """The command prefix and the robot_agent flags for agent `rid`."""
        h = self.host_of(rid)
        return ["ip", "netns", "exec", h["namespace"]], ["--world-host", WORLD_ADDRESS, "--interface", h["address"]]

    def create(self) -> None:
        os.makedirs(STATE_DIR, exist_ok=True)
        with open(self._pid_file, "w") as f:  # first: a namespace of ours is never taken for a leftover
            f.write(f"{os.getpid()} {_start_time(os.getpid())}\n")
        self._made = True
        try:
            for ns in self.namespaces():
                _run(["ip", "netns", "add", ns], "creating a host")
                _run(["ip", "-n", ns, "link", "set", "lo", "up"], "creating a host")
            _run(["ip", "-n", self.switch, "link", "add", self.bridge, "type", "bridge"], "creating the switch")
            _run(["ip", "-n", self.switch, "link", "set", self.bridge, "up"], "creating the switch")
            for h in [self.world] + self.agent_hosts:
                self._plug(h)
        except BaseException:
            self.remove()
            raise

    def _plug(self, h: dict[str, str]) -> None:
        ns, iface, port = h["namespace"], h["interface"], h["switch_port"]
        what = f"joining {ns} to the switch"
        _run(["ip", "link", "add", "name", iface, "netns", ns, "type", "veth", "peer", "name", port, "netns",
              self.switch], what)
        _run(["ip", "-n", ns, "addr", "add", f"{h['address']}/24", "dev", iface], what)
        _run(["ip", "-n", ns, "link", "set", iface, "up"], what)
        _run(["ip", "-n", self.switch, "link", "set", port, "master", self.bridge, "up"], what)
        self._shape(ns, iface)

    def _shape(self, ns: str, iface: str) -> None:
        for key, tool, package in (("loss", "nft", "nftables"), ("rate", "tc", "iproute2"),
                                   ("delay", "tc", "iproute2")):
            if key in self.link and shutil.which(tool) is None:
                raise HostsError(f"--link {key} needs `{tool}`, which is not installed (Debian package {package}; "
                                 "scripts/setup installs it)")
        if "loss" in self.link:
            what = f"--link loss on {ns} (nftables)"
            table = f"{self.prefix}-link"
            _run(["ip", "netns", "exec", ns, "nft", "add", "table", "inet", table], what)
            _run(["ip", "netns", "exec", ns, "nft", "add", "chain", "inet", table, "out",
                  "{ type filter hook output priority 0; }"], what)
            _run(["ip", "netns", "exec", ns, "nft", "add", "rule", "inet", table, "out", "oifname", iface,
                  "numgen", "random", "mod", "10000", "<", str(round(float(self.link["loss"]) * 100)), "drop"], what)
        parent = ["root"]
        if "delay" in self.link:
            cmd = ["tc", "-n", ns, "qdisc", "add", "dev", iface, "root", "handle", "1:", "netem", "delay",
                   str(self.link["delay"])]
            p = subprocess.run(cmd, capture_output=True, encoding="utf-8", errors="backslashreplace",
                               timeout=CMD_TIMEOUT_S)
            if p.returncode != 0 and "unknown" in (p.stderr or ""):
                raise HostsError("--link delay needs the kernel's netem queueing discipline (sch_netem), which this "
                                 f"kernel lacks (tc: {p.stderr.strip()}); loss and rate work without it")
            if p.returncode != 0:
                raise HostsError(f"--link delay on {ns}: `{' '.join(cmd)}` failed: {p.stderr.strip()}")
            parent = ["parent", "1:1", "handle", "10:"]
        if "rate" in self.link:
            _run(["tc", "-n", ns, "qdisc", "add", "dev", iface] + parent +
                 ["tbf", "rate", str(self.link["rate"]), "burst", "64kbit", "latency", "200ms"],
                 f"--link rate on {ns} (tc tbf)")

    def describe(self, robots: int) -> dict[str, Any]:
        """hosts.json's content: each host's namespace, interface, address, switch port (and agents)."""
        return {"prefix": self.prefix, "switch": {"namespace": self.switch, "bridge": self.bridge},
                "link": self.link, "world": self.world,
                "agent_hosts": [dict(h, agents=list(range(i, robots, self.count)))
                                for i, h in enumerate(self.agent_hosts)]}

    def remove(self) -> None:
        """Every process in the namespaces SIGKILLed, the namespaces deleted, the pid file removed."""
        if not self._made:
            return
        existing = set(_namespaces())
        for ns in self.namespaces():
            if ns in existing:
                _delete_namespace(ns)
        try:
            os.unlink(self._pid_file)
        except OSError:
            pass
        self._made = False


def write_description(hosts: Hosts, run_dir: str, robots: int) -> None:
    # Read while the run goes on (tests wait for it to appear): never a half-written file.
    jsonfile.write_atomically(os.path.join(run_dir, "hosts.json"), hosts.describe(robots))
