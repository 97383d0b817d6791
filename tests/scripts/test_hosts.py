"""The parts of `swarm run --hosts K [--link SPEC]` that need no root (scripts/swarmform/hosts.py, cli.py): the
--link grammar and its errors, the names, addresses and placement of a run's hosts, hosts.json, the refusals
(not root, inside a named namespace, --link without --hosts, --hosts with --in-process) and the leftovers'
owner check. The namespaces themselves: test_hosts_e2e.py."""

import os
import tempfile
import unittest
from unittest import mock

import helpers  # noqa: F401  (puts scripts/ on sys.path)
from swarmform import hosts


class LinkSpecTest(unittest.TestCase):
    def test_each_key_parses(self):
        self.assertEqual(hosts.parse_link("loss 5% rate 20mbit"), {"loss": 5.0, "rate": "20mbit"})
        self.assertEqual(hosts.parse_link("loss 0.5%"), {"loss": 0.5})
        self.assertEqual(hosts.parse_link("delay 20ms rate 500kbit"), {"delay": "20ms", "rate": "500kbit"})

    def test_bad_specs_name_the_bad_part(self):
        for text, said in (("", "want KEY VALUE pairs"), ("loss", "want KEY VALUE pairs"),
                           ("loss 5", "loss wants a percentage"), ("loss 0%", "loss wants a percentage"),
                           ("loss 101%", "loss wants a percentage"), ("rate fast", "rate wants a tc rate"),
                           ("delay 5", "delay wants a time"), ("jitter 5ms", "unknown 'jitter'"),
                           ("loss 1% loss 2%", "loss given twice")):
            with self.subTest(text=text):
                with self.assertRaises(hosts.HostsError) as c:
                    hosts.parse_link(text)
                self.assertIn(said, str(c.exception))


class LayoutTest(unittest.TestCase):
    def test_names_addresses_and_placement(self):
        h = hosts.Hosts(3, {"loss": 1.0}, prefix="sfh42")
        self.assertEqual(h.namespaces(), ["sfh42-sw", "sfh42-w", "sfh42-a0", "sfh42-a1", "sfh42-a2"])
        self.assertTrue(all(len(x) <= 15 for x in ("sfh4194304-p63", "sfh4194304-h63")), "IFNAMSIZ")
        self.assertEqual(h.world_wrap(), (["ip", "netns", "exec", "sfh42-w"], ["--interface", "10.77.0.1"]))
        self.assertEqual(h.agent_wrap(4), (["ip", "netns", "exec", "sfh42-a1"],
                                           ["--world-host", "10.77.0.1", "--interface", "10.77.0.11"]))
        d = h.describe(7)
        self.assertEqual(d["prefix"], "sfh42")
        self.assertEqual([x["agents"] for x in d["agent_hosts"]], [[0, 3, 6], [1, 4], [2, 5]])
        self.assertEqual([x["switch_port"] for x in d["agent_hosts"]], ["sfh42-p0", "sfh42-p1", "sfh42-p2"])
        self.assertEqual(d["link"], {"loss": 1.0})

    def test_host_count_is_bounded(self):
        for k in (0, hosts.MAX_HOSTS + 1):
            with self.assertRaises(hosts.HostsError):
                hosts.Hosts(k)


class LinkShapingCommandsTest(unittest.TestCase):
    """What --link asks of tc and nft, with the tools faked: the netem path cannot run on the build machine's
    kernel (no sch_netem), so this is where it is checked that a kernel with netem gets netem with tbf under it,
    and that one without gets the refusal."""

    def shape(self, link, tc_stderr=""):
        calls = []

        def fake_run(cmd, **_):
            calls.append(cmd)
            failed = tc_stderr and "netem" in cmd
            return mock.Mock(returncode=2 if failed else 0, stdout="", stderr=tc_stderr if failed else "")

        with mock.patch.object(hosts.subprocess, "run", side_effect=fake_run), \
                mock.patch.object(hosts.shutil, "which", return_value="/usr/sbin/tool"):
            hosts.Hosts(2, link, prefix="sfh42")._shape("sfh42-a0", "sfh42-h0")
        return calls

    def test_delay_is_netem_with_the_rate_under_it(self):
        calls = self.shape({"delay": "20ms", "rate": "20mbit"})
        self.assertEqual(calls, [
            ["tc", "-n", "sfh42-a0", "qdisc", "add", "dev", "sfh42-h0", "root", "handle", "1:", "netem", "delay",
             "20ms"],
            ["tc", "-n", "sfh42-a0", "qdisc", "add", "dev", "sfh42-h0", "parent", "1:1", "handle", "10:", "tbf",
             "rate", "20mbit", "burst", "64kbit", "latency", "200ms"]])

    def test_loss_is_an_nftables_rule_on_the_hosts_interface(self):
        calls = self.shape({"loss": 2.5})
        self.assertEqual(calls[-1], ["ip", "netns", "exec", "sfh42-a0", "nft", "add", "rule", "inet", "sfh42-link",
                                     "out", "oifname", "sfh42-h0", "numgen", "random", "mod", "10000", "<", "250",
                                     "drop"])

    def test_delay_without_netem_is_refused_saying_so(self):
        with self.assertRaises(hosts.HostsError) as c:
            self.shape({"delay": "20ms"}, tc_stderr="Error: Specified qdisc kind is unknown.")
        self.assertIn("needs the kernel's netem queueing discipline", str(c.exception))
        self.assertIn("Specified qdisc kind is unknown", str(c.exception))


class RefusalTest(unittest.TestCase):
    def test_not_root(self):
        with mock.patch("os.geteuid", return_value=1000):
            with self.assertRaises(hosts.HostsError) as c:
                hosts.check_can_make_hosts()
        self.assertIn("--hosts needs root", str(c.exception))

    def test_inside_a_named_namespace(self):
        with mock.patch("os.geteuid", return_value=0), \
                mock.patch.object(hosts, "in_named_namespace", return_value="sf-x"):
            with self.assertRaises(hosts.HostsError) as c:
                hosts.check_can_make_hosts()
        self.assertIn("runs in the network namespace sf-x", str(c.exception))

    def test_cli_refuses_link_without_hosts_and_hosts_in_process(self):
        r = helpers.swarm("run", "--link", "loss 5%")
        self.assertEqual(r.returncode, 2)
        self.assertIn("--link shapes the links of emulated hosts: it needs --hosts K", r.stderr)
        r = helpers.swarm("run", "--hosts", "2", "--in-process")
        self.assertEqual(r.returncode, 2)
        self.assertIn("--hosts and --in-process exclude each other", r.stderr)
        r = helpers.swarm("run", "--hosts", "0")
        self.assertEqual(r.returncode, 2)
        self.assertIn("must be >= 1", r.stderr)
        r = helpers.swarm("run", "--hosts", "2", "--link", "loss 5")
        self.assertEqual(r.returncode, 2)
        self.assertIn("loss wants a percentage", r.stderr)
        self.assertNotIn("Traceback", r.stderr)


class LeftoverOwnerTest(unittest.TestCase):
    def test_a_pid_file_names_a_live_owner_only_with_its_start_time(self):
        with tempfile.TemporaryDirectory() as d, mock.patch.object(hosts, "STATE_DIR", d):
            me = os.getpid()
            with open(os.path.join(d, "sfh1.pid"), "w") as f:
                f.write(f"{me} {hosts._start_time(me)}\n")
            with open(os.path.join(d, "sfh2.pid"), "w") as f:
                f.write(f"{me} {hosts._start_time(me) + 1}\n")  # the pid reused by another process
            with open(os.path.join(d, "sfh3.pid"), "w") as f:
                f.write("garbage\n")
            self.assertTrue(hosts._owner_alive("sfh1"))
            self.assertFalse(hosts._owner_alive("sfh2"))
            self.assertFalse(hosts._owner_alive("sfh3"))
            self.assertFalse(hosts._owner_alive("sfh4"))  # no pid file


if __name__ == "__main__":
    unittest.main()
