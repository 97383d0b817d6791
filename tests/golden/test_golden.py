"""The fixed runs of golden.json against their committed trajectory_sha256, and, for a run whose behaviour
declares sensors, the SHA-256 of its readings.csv (readings_sha256): the in-process and the multi-process run
write the same bytes (README.md of this folder).

  python3 test_golden.py [-v]                 the tests (BUILD_DIR: the build, default build/; GOLDEN_MODE:
                                              inprocess, multiprocess or both, default both)
  python3 test_golden.py --write BUILD_DIR    rerun every in-process run and rewrite golden.json's hashes,
                                              printing old -> new (a deliberate change of behaviour only)
Each run has a deadline; a run that overruns is killed with its process group (the launcher's world and
agents). Temporary folders are removed. The multi-process runs use DDS test domain offset 0.
"""

import hashlib
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "tests", "scripts"))
import helpers  # noqa: E402  (after the path above)
from swarmform import inprocess  # noqa: E402  (helpers puts scripts/ on the path)

GOLDEN = os.path.join(HERE, "golden.json")
RUN_DEADLINE_S = 600  # a loaded 2-core machine runs the paper's 2,000 ticks in well under a minute


def load():
    with open(GOLDEN) as f:
        return json.load(f)


def plugin_dir(build_dir, name):
    return os.path.join(build_dir, "examples", "behaviours", name)


def launcher_command(build_dir, entry, out, domain):
    """The command line of one golden run through the launcher (real processes), and its environment."""
    env = dict(os.environ, SWARM_NO_BUILD="1", BUILD_DIR=build_dir)
    return [helpers.SWARM, "run", *run_args(build_dir, entry), "--mode", "lockstep", "--no-pictures", "--domain",
            str(domain), "--out", out], env


def run_args(build_dir, entry):
    args = list(entry["args"])
    if "plugin" in entry:
        args += ["--plugin-dir", plugin_dir(build_dir, entry["plugin"])]
    return args


def file_sha256(path):
    """SHA-256 of a file, or None when it is missing."""
    if not os.path.exists(path):
        return None
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def trajectory_sha256(build_dir, mode, entry, domain=None, readings=False):
    """Runs one golden run; returns (sha256 or None, readings.csv's sha256 or None, the command, and why it failed
    if it did). `readings`: in-process, record the run (in a temporary folder) to hash its readings.csv; the
    multi-process run is always recorded."""
    exe = os.path.join(build_dir, "harness", "swarm_inprocess")
    if mode == "inprocess" and not readings:
        summary, said = inprocess.summary_of(exe, run_args(build_dir, entry), ROOT, RUN_DEADLINE_S)
        return (summary["trajectory_sha256"] if summary else None), None, said
    tmp = tempfile.mkdtemp(prefix="swarm-golden-")
    try:
        out = os.path.join(tmp, "run")
        if mode == "inprocess":
            argv, env = [exe, *run_args(build_dir, entry), "--quiet", "--out", out], dict(os.environ)
        else:
            argv, env = launcher_command(build_dir, entry, out, domain)
        # Its own process group: on a timeout the launcher's world and agents go with it.
        p = subprocess.Popen(argv, cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                             stdin=subprocess.DEVNULL, start_new_session=True)
        try:
            text, _ = p.communicate(timeout=RUN_DEADLINE_S)
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, signal.SIGKILL)
            text, _ = p.communicate(timeout=30)
            return None, None, f"{' '.join(argv)}: over {RUN_DEADLINE_S} s\n{text}"
        if p.returncode != 0:
            return None, None, f"{' '.join(argv)}: exit {p.returncode}\n{text}"
        with open(os.path.join(out, "summary.json")) as f:
            sha = json.load(f)["trajectory_sha256"]
        return sha, file_sha256(os.path.join(out, "readings.csv")), " ".join(argv)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


BUILD_DIR = os.environ.get("BUILD_DIR") or os.path.join(ROOT, "build")
MODES = {"both": ("inprocess", "multiprocess"), "inprocess": ("inprocess",),
         "multiprocess": ("multiprocess",)}[os.environ.get("GOLDEN_MODE", "both")]


class GoldenTrajectories(unittest.TestCase):
    def check(self, mode, name):
        entry = load()[name]
        if mode == "multiprocess" and not entry.get("multiprocess"):
            self.skipTest(f"{name} is an in-process golden run only")
        if "plugin" in entry and not os.path.isdir(plugin_dir(BUILD_DIR, entry["plugin"])):
            self.skipTest(f"the {entry['plugin']} example is not built in {BUILD_DIR}")
        self.assertRegex(entry["sha256"], "^[0-9a-f]{64}$", f"{name}: golden.json holds no hash")
        sha, readings, said = trajectory_sha256(BUILD_DIR, mode, entry, helpers.test_domain(0),
                                                readings="readings_sha256" in entry)
        self.assertIsNotNone(sha, said)
        self.assertEqual(sha, entry["sha256"],
                         f"{name} ({mode}) left its golden trajectory: {said}\nIf the change of behaviour is "
                         "meant, rewrite golden.json with test_golden.py --write and say why in the commit.")
        if "readings_sha256" in entry:
            self.assertEqual(readings, entry["readings_sha256"],
                             f"{name} ({mode}): readings.csv is not the golden one: {said}")


def add_tests():
    for name in load():
        for mode in ("inprocess", "multiprocess"):
            if mode in MODES:
                setattr(GoldenTrajectories, f"test_{name}_{mode}",
                        lambda self, m=mode, n=name: self.check(m, n))


add_tests()


def write(build_dir):
    golden = load()
    for name, entry in golden.items():
        sha, readings, said = trajectory_sha256(build_dir, "inprocess", entry, readings=True)
        if sha is None:
            sys.exit(f"test_golden.py --write: {name}: {said}")
        print(f"{name}: {entry['sha256'] or '(none)'} -> {sha}")
        entry["sha256"] = sha
        if readings is not None:  # the behaviour declares sensors
            print(f"{name} readings.csv: {entry.get('readings_sha256', '(none)')} -> {readings}")
            entry["readings_sha256"] = readings
    with open(GOLDEN, "w") as f:
        json.dump(golden, f, indent=2)
        f.write("\n")


if __name__ == "__main__":
    if len(sys.argv) >= 2 and sys.argv[1] in ("-h", "--help"):
        print(__doc__)
    elif len(sys.argv) == 3 and sys.argv[1] == "--write":
        write(os.path.abspath(sys.argv[2]))
    elif len(sys.argv) >= 2 and sys.argv[1] == "--write":
        sys.exit("test_golden.py --write: give the build folder, e.g. --write build")
    else:
        unittest.main()
