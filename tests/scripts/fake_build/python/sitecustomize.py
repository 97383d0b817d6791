"""On PYTHONPATH (tests/scripts/helpers.py `swarm`) when the launcher runs the stand-in executables: the stand-in
world binds no DDS port, so the launcher's check that a --domain is not held on this host answers "free". The unit
tests' fixed domains (77, 9) must not depend on what else runs on the host; the check itself has its own test."""
try:
    from swarmform import domains

    domains.ports_free = lambda domain: True
except ImportError:  # not the launcher (PYTHONPATH without scripts/)
    pass
