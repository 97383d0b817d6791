"""The launcher's free-domain picker (scripts/swarmform/domains.py): lock files keep two launchers apart, the port
probe skips a domain with a world on it, the range comes from SWARM_DOMAINS, and a full range is a clear error.
No real DDS port is touched: the probe is a stand-in (the real one runs in test_launcher_e2e)."""

import shutil
import socket
import tempfile
import unittest

import helpers  # noqa: F401  (puts scripts/ on the path)
from swarmform import domains


class DomainPickerTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-domains-")
        self.env = {"SWARM_DOMAINS": "5-7"}

    def tearDown(self):
        shutil.rmtree(self.dir)

    def pick(self, probe=lambda d: True):
        return domains.pick_free_domain(self.env, probe=probe, directory=self.dir)

    def test_two_launchers_get_two_domains_and_a_released_one_is_free_again(self):
        first = self.pick()
        second = self.pick()
        self.assertEqual((first.domain, second.domain), (5, 6))
        first.release()
        self.assertEqual(self.pick().domain, 5)
        second.release()

    def test_a_domain_whose_world_ports_are_held_is_skipped(self):
        lease = self.pick(probe=lambda d: d != 5)
        self.assertEqual(lease.domain, 6)
        lease.release()

    def test_no_free_domain_is_a_clear_error(self):
        with self.assertRaisesRegex(domains.DomainError, r"no free DDS domain in 5\.\.7 .*SWARM_DOMAINS"):
            self.pick(probe=lambda d: False)

    def test_bad_range_names_the_variable(self):
        for text in ("7", "a-b", "9-3", "0-300"):
            with self.assertRaisesRegex(domains.DomainError, "SWARM_DOMAINS"):
                domains.domain_range({"SWARM_DOMAINS": text})
        self.assertEqual(domains.domain_range({}), (0, 99))

    def test_the_port_probe_sees_a_held_port(self):
        # The world's discovery and data ports of domain D are 7400 + 100 D + 10 and + 11
        # (common/dds/cyclone_config.cpp). The probe is tried on a port this test holds (an ephemeral one, so no
        # real domain is touched): held, then free once released.
        self.assertEqual(domains.world_ports(3), (7710, 7711))
        s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
        real = domains.world_ports
        domains.world_ports = lambda d: (port, port)
        try:
            self.assertFalse(domains.ports_free(0))
            s.close()
            self.assertTrue(domains.ports_free(0))
        finally:
            domains.world_ports = real
            s.close()

    def test_the_run_nonce_is_sixteen_hex_digits_and_never_zero(self):
        n = domains.run_nonce()
        self.assertRegex(n, r"^[0-9a-f]{16}$")
        self.assertNotEqual(int(n, 16), 0)


if __name__ == "__main__":
    unittest.main()
