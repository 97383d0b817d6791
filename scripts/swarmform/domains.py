"""A free DDS domain for a run started without --domain (docs/wire.md "Domains and concurrent
runs"), and the run's nonce.

A domain is free when both hold:
  - no process on this host holds the world's fixed ports of the domain: a UDP bind probe of the discovery port
    7400 + 100*D + 10 and the data port + 11 (common/dds/cyclone_config.cpp: base 7400, domain gain 100,
    participant index 0). This finds any world: another run's, a test's, one started by hand;
  - no other launcher holds the domain's lock file (flock), kept for the whole run. This closes the race of two
    launchers probing at the same moment, before either world has bound its ports.
Domains are tried from the low end of the range, SWARM_DOMAINS="LO-HI" (default 0-99: the tests' windows start at
SWARMFORM_TEST_DOMAIN_BASE, 100 by default).
"""

import fcntl
import os
import secrets
import socket
from typing import Callable, Mapping, Optional

PORT_BASE = 7400
DOMAIN_GAIN = 100
MAX_DOMAIN = 232
DEFAULT_RANGE = (0, 99)


class DomainError(Exception):
    pass


def world_ports(domain: int) -> tuple[int, int]:
    """The world's fixed UDP ports on `domain`: discovery unicast and user-data unicast (participant index 0)."""
    base = PORT_BASE + DOMAIN_GAIN * domain
    return base + 10, base + 11


def ports_free(domain: int) -> bool:
    """True if no socket on this host holds the world's ports of `domain` (bind probe, released at once)."""
    for port in world_ports(domain):
        s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        try:
            s.bind(("0.0.0.0", port))
        except OSError:
            return False
        finally:
            s.close()
    return True


def domain_range(env: Optional[Mapping[str, str]] = None) -> tuple[int, int]:
    """(lo, hi) from SWARM_DOMAINS, or the default; DomainError naming the variable when it is malformed."""
    text = (env if env is not None else os.environ).get("SWARM_DOMAINS")
    if not text:
        return DEFAULT_RANGE
    parts = text.split("-")
    if len(parts) != 2 or not all(p.isdigit() for p in parts):
        raise DomainError(f"SWARM_DOMAINS={text!r}: want LO-HI, two domain ids (0..{MAX_DOMAIN})")
    lo, hi = int(parts[0]), int(parts[1])
    if not 0 <= lo <= hi <= MAX_DOMAIN:
        raise DomainError(f"SWARM_DOMAINS={text!r}: want 0 <= LO <= HI <= {MAX_DOMAIN}")
    return lo, hi


def lock_dir() -> str:
    runtime = os.environ.get("XDG_RUNTIME_DIR")
    if runtime and os.path.isdir(runtime) and os.access(runtime, os.W_OK):
        return os.path.join(runtime, "swarmform")
    return os.path.join("/tmp", f"swarmform-{os.getuid()}")


class DomainLease:
    """A domain held for one run: the lock file stays locked until release() (or the process ends)."""

    def __init__(self, domain: int, fd: Optional[int]) -> None:
        self.domain, self._fd = domain, fd

    def release(self) -> None:
        if self._fd is not None:
            os.close(self._fd)  # closing drops the flock
            self._fd = None


def pick_free_domain(env: Optional[Mapping[str, str]] = None, probe: Optional[Callable[[int], bool]] = None,
                     directory: Optional[str] = None) -> DomainLease:
    """The lowest free domain of the range, locked; DomainError when none is. `probe(domain)` (default
    ports_free) and `directory` (default lock_dir()) are for tests."""
    lo, hi = domain_range(env)
    probe = probe or ports_free
    directory = directory or lock_dir()
    os.makedirs(directory, mode=0o700, exist_ok=True)
    for domain in range(lo, hi + 1):
        fd = os.open(os.path.join(directory, f"domain-{domain}.lock"), os.O_RDWR | os.O_CREAT, 0o600)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            os.close(fd)
            continue
        if probe(domain):
            return DomainLease(domain, fd)
        os.close(fd)
    raise DomainError(f"no free DDS domain in {lo}..{hi} on this host (every one has a world or another launcher "
                      "on it); pass --domain D or widen SWARM_DOMAINS=LO-HI")


def run_nonce() -> str:
    """This run's nonce: 16 hex digits, never zero (docs/wire.md "Run nonce")."""
    while True:
        n = secrets.token_hex(8)
        if int(n, 16) != 0:
            return n
