"""The installed package is complete: `cmake --install` of the build into a fresh prefix, then a user's folder
outside the source tree holding only their scenario and their plug-in (the aggregation example's), and
nothing of the source tree in reach (no BUILD_DIR, no PYTHONPATH, a clean environment). With the prefix's
bin/swarm alone they run in-process and as processes over DDS with a kill, get the pictures, judge with
--expect, sweep (the sweep names the commit the prefix was installed from), read the report and open the
view over a recording (the page from the prefix).

Run by ctest (labels examples and integration: the multi-process run starts DDS processes, on
SWARMFORM_TEST_DOMAIN_BASE + 28) with BUILD_DIR and AGGREGATION_DIR set."""

import json
import os
import shutil
import signal
import socket
import subprocess
import tempfile
import time
import unittest
import urllib.request

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLE = os.path.join(os.path.dirname(HERE), "aggregation", "aggregation.yaml")
BUILD_DIR = os.environ.get("BUILD_DIR", "")
PLUGIN = os.path.join(os.environ.get("AGGREGATION_DIR", ""), "libaggregation.so")
DOMAIN_OFFSET = 28  # tests/support/test_domain.hpp


def test_domain():
    text = os.environ.get("SWARMFORM_TEST_DOMAIN_BASE") or "100"
    if not text.isdigit() or int(text) > 232 - 64 + 1:
        raise ValueError(f"SWARMFORM_TEST_DOMAIN_BASE={text!r}: want an integer 0..169")
    return int(text) + DOMAIN_OFFSET


@unittest.skipUnless(BUILD_DIR and os.path.isfile(PLUGIN), "needs BUILD_DIR and AGGREGATION_DIR (ctest)")
class InstalledLauncherTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="swarm-installed-")
        cls.prefix = os.path.join(cls.dir, "prefix")
        r = subprocess.run(["cmake", "--install", BUILD_DIR, "--prefix", cls.prefix], capture_output=True,
                           text=True, timeout=300)
        if r.returncode != 0:
            shutil.rmtree(cls.dir)
            raise AssertionError("cmake --install failed:\n" + r.stdout + r.stderr)
        cls.user = os.path.join(cls.dir, "user")
        os.makedirs(cls.user)
        shutil.copy(EXAMPLE, cls.user)
        shutil.copy(PLUGIN, cls.user)  # beside the scenario: where a plug-in is looked for first
        cls.scenario = os.path.join(cls.user, "aggregation.yaml")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir)

    def swarm(self, *args, timeout=240):
        env = {"PATH": "/usr/bin:/bin", "HOME": self.user, "LANG": "C.UTF-8",
               "SWARMFORM_TEST_DOMAIN_BASE": os.environ.get("SWARMFORM_TEST_DOMAIN_BASE", "")}
        return subprocess.run([os.path.join(self.prefix, "bin", "swarm"), *args], capture_output=True, text=True,
                              timeout=timeout, env=env, cwd=self.user)

    def summary(self, run_dir):
        with open(os.path.join(run_dir, "summary.json"), encoding="utf-8") as f:
            return json.load(f)

    def test_an_in_process_run_with_a_kill_is_judged_and_drawn(self):
        out = os.path.join(self.user, "inprocess")
        r = self.swarm("run", "--in-process", "--scenario", self.scenario, "--out", out, "--kill", "3@100",
                       "--no-animation", "--expect", "behaviour_metrics.largest_cluster >= 1")
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertIn("expectation met: behaviour_metrics.largest_cluster >= 1", r.stderr)
        s = self.summary(out)
        self.assertEqual([d["id"] for d in s["deaths"]], [3], s["deaths"])
        self.assertTrue(os.path.isfile(os.path.join(out, "pictures", "trajectories.png")), os.listdir(out))

    def test_agents_over_dds_with_a_kill(self):
        out = os.path.join(self.user, "multi")
        r = self.swarm("run", "--scenario", self.scenario, "--out", out, "--kill", "5@100", "--no-animation",
                       "--domain", str(test_domain()), timeout=300)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        s = self.summary(out)
        self.assertEqual([d["id"] for d in s["deaths"]], [5], s["deaths"])
        self.assertEqual(s["ticks"], 600)

    def test_a_sweep_names_the_installed_commit_and_the_report_reads_a_run(self):
        out = os.path.join(self.user, "sweep")
        r = self.swarm("sweep", "--scenario", self.scenario, "--seeds", "1-2", "--max-ticks", "200", "--jobs", "2",
                       "--quiet", "--out", out, "--plot")
        self.assertIn(r.returncode, (0, 1), r.stdout + r.stderr)  # judged by the plug-in's own outcome
        with open(os.path.join(out, "sweep.json"), encoding="utf-8") as f:
            sweep = json.load(f)
        with open(os.path.join(self.prefix, "bin", "swarm"), encoding="utf-8") as f:
            wrapper = f.read()
        commit = sweep["commit"]
        self.assertTrue(commit and f'SWARM_INSTALLED_COMMIT="{commit}"' in wrapper, commit)
        self.assertEqual((sweep["planned_runs"], sweep["overall"]["runs"]), (2, 2))
        self.assertEqual(len(os.listdir(os.path.join(out, "figures"))), 6, "--plot: three figures, PNG and SVG")
        run_dir = os.path.join(self.user, "report-run")
        self.assertEqual(self.swarm("run", "--in-process", "--scenario", self.scenario, "--out", run_dir,
                                    "--max-ticks", "50", "--no-animation").returncode, 0)
        rep = self.swarm("report", run_dir)
        self.assertEqual(rep.returncode, 0, rep.stdout + rep.stderr)
        self.assertIn("ticks", rep.stdout)

    def test_the_view_serves_the_installed_page_over_a_recording(self):
        run_dir = os.path.join(self.user, "view-run")
        self.assertEqual(self.swarm("run", "--in-process", "--scenario", self.scenario, "--out", run_dir,
                                    "--max-ticks", "30", "--no-animation").returncode, 0)
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            port = s.getsockname()[1]
        # A mark in the installed page only: the source tree's page, were it served, lacks it.
        with open(os.path.join(self.prefix, "share", "swarmform", "web", "index.html"), "a", encoding="utf-8") as f:
            f.write("<!-- installed-page-mark -->\n")
        env = {"PATH": "/usr/bin:/bin", "HOME": self.user, "LANG": "C.UTF-8"}
        view = subprocess.Popen([os.path.join(self.prefix, "bin", "swarm"), "view", run_dir, "--port", str(port)],
                                stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env, cwd=self.user,
                                start_new_session=True)
        try:
            page, deadline = None, time.monotonic() + 30
            while page is None and time.monotonic() < deadline and view.poll() is None:
                try:
                    with urllib.request.urlopen(f"http://127.0.0.1:{port}/", timeout=2) as r:
                        page = r.read().decode("utf-8", "replace")
                except OSError:
                    time.sleep(0.2)
            self.assertIsNotNone(page, "the view never answered")
            self.assertIn("installed-page-mark", page)
        finally:
            os.killpg(view.pid, signal.SIGTERM)
            try:
                view.wait(timeout=10)
            except subprocess.TimeoutExpired:
                os.killpg(view.pid, signal.SIGKILL)
                view.wait(timeout=10)

    def test_the_default_scenario_is_the_installed_paper_run(self):
        r = self.swarm("run", "--in-process", "--max-ticks", "20", "--no-animation", "--out",
                       os.path.join(self.user, "paper"))
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        with open(os.path.join(self.user, "paper", "world.json"), encoding="utf-8") as f:
            self.assertIn("paper", json.dumps(json.load(f)))

    def test_a_missing_plugin_names_the_folders_searched(self):
        os.makedirs(os.path.join(self.user, "elsewhere"), exist_ok=True)
        moved = os.path.join(self.user, "elsewhere", "aggregation.yaml")
        shutil.copy(self.scenario, moved)
        r = self.swarm("run", "--in-process", "--scenario", moved, "--no-animation")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("--plugin-dir", r.stderr)


if __name__ == "__main__":
    unittest.main()
