"""scripts/swarmform/security.py: the per-run DDS Security directory `swarm run --secure` makes (docs/security.md).
Needs only the openssl command line."""

import os
import shutil
import stat
import subprocess
import tempfile
import unittest

import helpers  # noqa: F401  (puts scripts/ on sys.path)
from swarmform import security


def openssl(*args):
    return subprocess.run(["openssl", *args], capture_output=True, text=True, timeout=60)


class SecurityDirTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="swarm-security-")
        cls.sec = security.make_security_dir(cls.tmp, 3, 42)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp)

    def path(self, name):
        return os.path.join(self.sec, name)

    def test_every_identity_has_a_private_key_a_certificate_and_signed_permissions(self):
        self.assertEqual(stat.S_IMODE(os.stat(self.sec).st_mode), 0o700)
        identities = ["world", "observer", "robot-0", "robot-1", "robot-2"]
        for ident in identities:
            self.assertEqual(stat.S_IMODE(os.stat(self.path(f"{ident}.key")).st_mode), 0o600, ident)
            subject = openssl("x509", "-in", self.path(f"{ident}.pem"), "-noout", "-subject", "-nameopt", "RFC2253")
            self.assertEqual(subject.stdout.strip(), f"subject=CN={ident},O=swarmform", subject.stderr)
            # Signed by this run's CA, and the signature holds.
            v = openssl("verify", "-CAfile", self.path("ca.pem"), self.path(f"{ident}.pem"))
            self.assertEqual(v.returncode, 0, v.stdout + v.stderr)
            v = openssl("smime", "-verify", "-in", self.path(f"{ident}.permissions.p7s"), "-CAfile", self.path("ca.pem"))
            self.assertEqual(v.returncode, 0, v.stderr)
            self.assertIn(f"<subject_name>{security.subject(ident)}</subject_name>", v.stdout)
            self.assertIn("<domains><id>42</id></domains>", v.stdout)
        self.assertEqual(security.check_keys(self.sec), [])
        self.assertFalse(os.path.exists(self.path("ca.key")), "the CA's key must be gone once all is signed")
        v = openssl("smime", "-verify", "-in", self.path("governance.p7s"), "-CAfile", self.path("ca.pem"))
        self.assertEqual(v.returncode, 0, v.stderr)
        self.assertIn("<allow_unauthenticated_participants>false</allow_unauthenticated_participants>", v.stdout)
        self.assertIn("<data_protection_kind>ENCRYPT</data_protection_kind>", v.stdout)

    def test_robot_k_may_read_only_its_own_partition_and_write_commands_only_there(self):
        with open(self.path("robot-1.permissions.xml")) as f:
            doc = f.read()
        self.assertIn("<publish><topics><topic>sf_command</topic></topics><partitions><partition>robot/1</partition>",
                      doc)
        self.assertIn("<subscribe><topics><topic>sf_sensor</topic></topics><partitions><partition>robot/1</partition>",
                      doc)
        self.assertNotIn("robot/0", doc)
        self.assertNotIn("robot/*", doc)
        self.assertNotIn("sf_world_state", doc)
        self.assertIn("<default>DENY</default>", doc)

    def test_a_domain_above_230_and_a_second_directory_are_refused(self):
        with self.assertRaisesRegex(security.SecurityError, "domain 231"):
            security.make_security_dir(self.tmp, 1, 231)
        with self.assertRaisesRegex(security.SecurityError, "exists already"):
            security.make_security_dir(self.tmp, 1, 42)


if __name__ == "__main__":
    unittest.main()


class FaceDomainsTest(unittest.TestCase):
    def test_the_worlds_faces_local_domain_ids_are_granted_as_cyclone_checks_them(self):
        # docs/wire.md "Faces": face f's local id is (D + f) mod 231 (common/dds/cyclone_config.cpp).
        self.assertEqual(security.face_domain_ids(42, 64), [42])
        self.assertEqual(security.face_domain_ids(229, 130), [229, 230, 0])
        self.assertEqual(len(security.face_domain_ids(0, 1024)), 16)
        self.assertEqual(len(security.face_domain_ids(0, 100000)), 45)
        self.assertIn("<domains><id>229</id><id>230</id><id>0</id></domains>",
                      security.governance_xml(security.face_domain_ids(229, 130)))
        faces = security.face_domain_ids(229, 130)
        self.assertEqual(security._granted_domains("world", faces), [229, 230, 0])
        self.assertEqual(security._granted_domains("robot-63", faces), [229])
        self.assertEqual(security._granted_domains("robot-64", faces), [229, 230])
        self.assertEqual(security._granted_domains("robot-129", faces), [229, 0])
        self.assertEqual(security._granted_domains("observer", faces), [229])
