"""docs/testing-your-swarm.md's two examples, run as a user would run them from the checkout: the shell test
(examples/ci/swarm_test.sh) and the GoogleTest (examples/ci/swarm_gtest.cpp, built by tests/examples/CMakeLists.txt).
Each must pass, and must fail when an expectation does not hold (a test that cannot fail proves nothing). The page
must show the files as they are. DDS test domains 54 (shell) and 55 (GoogleTest), through SWARM_DOMAINS."""

import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "tests", "scripts"))
import helpers  # noqa: E402

BUILD_DIR = os.environ.get("BUILD_DIR") or os.path.join(ROOT, "build")
DOC = os.path.join(ROOT, "docs", "testing-your-swarm.md")
SHELL = os.path.join(ROOT, "examples", "ci", "swarm_test.sh")
GTEST_SOURCE = os.path.join(ROOT, "examples", "ci", "swarm_gtest.cpp")
GTEST = os.environ.get("SWARM_GTEST_EXAMPLE")


def env_for(offset):
    d = helpers.test_domain(offset)
    return dict(os.environ, SWARM_NO_BUILD="1", BUILD_DIR=BUILD_DIR, SWARM_DOMAINS=f"{d}-{d}", MPLBACKEND="Agg")


def leftover_runs():
    """The examples' temporary folders still in /tmp (their cleanup failed)."""
    return {e for e in os.listdir(tempfile.gettempdir()) if e.startswith("swarm-gtest-")}


class DocShowsTheFilesTest(unittest.TestCase):
    def test_the_page_quotes_both_files_whole(self):
        with open(DOC) as f:
            doc = f.read()
        for path in (SHELL, GTEST_SOURCE):
            with open(path) as f:
                self.assertIn(f.read(), doc, f"docs/testing-your-swarm.md does not show {path} as it is")


@unittest.skipUnless(os.access(os.path.join(BUILD_DIR, "robot_agent", "robot_agent"), os.X_OK),
                     f"robot_agent is not built in {BUILD_DIR}")
class ShellExampleTest(unittest.TestCase):
    def test_it_passes(self):
        r = subprocess.run(["sh", SHELL], cwd=ROOT, env=env_for(54), capture_output=True, text=True, timeout=500)
        self.assertEqual(r.returncode, 0, f"stdout:\n{r.stdout}\nstderr:\n{r.stderr}")
        self.assertIn("swarm test passed", r.stdout)
        self.assertIn("expectation met: alive_at_end == 4", r.stderr)

    def test_it_fails_naming_the_expectation_when_one_does_not_hold(self):
        with open(SHELL) as f:
            script = f.read().replace("alive_at_end == 4", "alive_at_end == 6")
        r = subprocess.run(["sh", "-c", script], cwd=ROOT, env=env_for(54), capture_output=True, text=True,
                           timeout=500)
        self.assertEqual(r.returncode, 4, r.stderr)
        self.assertIn("EXPECTATION FAILED: alive_at_end == 6 (alive_at_end is 4)", r.stderr)
        self.assertNotIn("swarm test passed", r.stdout)


@unittest.skipUnless(GTEST and os.access(GTEST, os.X_OK), "the GoogleTest example is not built")
class GoogleTestExampleTest(unittest.TestCase):
    def test_it_passes_and_cleans_up(self):
        before = leftover_runs()
        r = subprocess.run([GTEST], cwd=ROOT, env=env_for(55), capture_output=True, text=True, timeout=500)
        self.assertEqual(r.returncode, 0, f"stdout:\n{r.stdout}\nstderr:\n{r.stderr}")
        self.assertIn("[  PASSED  ] 1 test", r.stdout)
        self.assertEqual(leftover_runs() - before, set(), "the example left its run folder behind")


if __name__ == "__main__":
    unittest.main()
