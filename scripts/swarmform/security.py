"""`swarm run --secure`: a run's DDS Security material, made fresh for every run with the openssl command line.

In RUN_DIR/security/ (mode 0700; every private key 0600; the CA's key is deleted once everything is signed, so
the directory cannot mint another identity):
  ca.pem                        the run's certificate authority (EC P-256, self-signed)
  governance.xml, .p7s          the domain rules: no unauthenticated participant, discovery, liveliness and
                                every topic's data encrypted, read and write access control on every topic
  world.pem, .key               the world's identity        (subject CN=world,O=swarmform)
  robot-K.pem, .key             robot K's identity          (subject CN=robot-K,O=swarmform)
  observer.pem, .key            a viewer's identity         (subject CN=observer,O=swarmform)
  <identity>.permissions.xml, .permissions.p7s   what the identity may publish and subscribe (signed)
docs/security.md says what this protects and what not; common/dds/security_config.hpp reads the same layout.
No network is used: every file comes from `openssl` on this host.
"""

import concurrent.futures
import datetime
import os
import subprocess
from typing import Sequence, Union

Domains = Union[int, Sequence[int]]  # one DDS domain id, or several (the world's faces)

# Topics and who may use them (docs/wire.md). Partitions: robot K's packets and commands in robot/K.
MISSION, SENSOR, COMMAND, WORLD_STATE = "sf_mission", "sf_sensor", "sf_command", "sf_world_state"
# For the viewer (docs/wire.md "Observers"): granted now so a viewer needs no new permissions scheme.
OBSERVE, CONTROL = "sf_observe", "sf_control"
ORGANISATION = "swarmform"
# Cyclone 0.10.2's access control parser refuses a domain id above 230 in governance and permissions
# (access_control_parser.c), though the domain itself may go to 232.
MAX_SECURE_DOMAIN = 230
VALID_DAYS = 7
OPENSSL_TIMEOUT_S = 30


class SecurityError(Exception):
    pass


def subject(identity: str) -> str:
    """The certificate subject of an identity, as the permissions name it (Cyclone compares name by name)."""
    return f"CN={identity},O={ORGANISATION}"


def robot_identity(rid: int) -> str:
    return f"robot-{rid}"


def _openssl(*args: str, cwd: str) -> None:
    try:
        p = subprocess.run(["openssl", *args], cwd=cwd, capture_output=True, timeout=OPENSSL_TIMEOUT_S,
                           encoding="utf-8", errors="backslashreplace")
    except FileNotFoundError:
        raise SecurityError("the `openssl` command is missing (Debian package openssl; scripts/setup installs "
                            "it)") from None
    except subprocess.TimeoutExpired:
        raise SecurityError(f"openssl {args[0]} took over {OPENSSL_TIMEOUT_S} s") from None
    if p.returncode != 0:
        raise SecurityError(f"openssl {' '.join(args[:2])} failed (exit {p.returncode}): {p.stderr.strip()[:400]}")


def _rule(kind: str, topics: Sequence[str], partitions: Sequence[str]) -> str:
    """One <publish> or <subscribe> criterion. partitions: names, '' for the default partition."""
    ts = "".join(f"<topic>{t}</topic>" for t in topics)
    ps = "".join(f"<partition>{p}</partition>" for p in partitions)
    return f"<{kind}><topics>{ts}</topics><partitions>{ps}</partitions></{kind}>"


def _grants(identity: str) -> tuple[list[str], list[str]]:
    """(publish, subscribe) criteria of an identity: the least each needs (docs/security.md has the table)."""
    if identity == "world":
        return ([_rule("publish", [MISSION, WORLD_STATE, OBSERVE], [""]), _rule("publish", [SENSOR], ["robot/*"])],
                [_rule("subscribe", [COMMAND], ["robot/*"]), _rule("subscribe", [CONTROL], [""])])
    if identity == "observer":
        return ([_rule("publish", [CONTROL], [""])],
                [_rule("subscribe", [MISSION, WORLD_STATE, OBSERVE], [""])])
    part = "robot/" + identity.split("-", 1)[1]
    return ([_rule("publish", [COMMAND], [part])],
            [_rule("subscribe", [SENSOR], [part]), _rule("subscribe", [MISSION], [""])])


def _stamp(t: datetime.datetime) -> str:
    return t.strftime("%Y-%m-%dT%H:%M:%S")


# The world's faces (docs/wire.md "Faces"): face f of a world on domain D is a Cyclone domain instance of its own
# in the world's process, created with the local domain id (D + f) mod 231 (common/dds/cyclone_config.cpp
# local_domain_id) and speaking domain D on the wire. Cyclone's access control checks the local id, so the
# governance and the world's permissions name those ids too. Mirrors cyclone_config.hpp's constants.
ROBOTS_PER_FACE, MAX_FACES = 64, 45


def face_domain_ids(domain: int, robots: int) -> list[int]:
    """The local domain ids of the world's faces for `robots` robots on `domain`, face 0 (the domain) first."""
    faces = min((max(robots, 1) - 1) // ROBOTS_PER_FACE, MAX_FACES - 1) + 1
    return [domain] + [(domain + f) % (MAX_SECURE_DOMAIN + 1) for f in range(1, faces)]


def _granted_domains(identity: str, faces: list[int]) -> list[int]:
    """The domain ids an identity's permissions name: the world every face's; robot K the run's domain and its
    face's local id (the world's face checks a remote participant's permissions against its own local id); the
    observer the run's domain (face 0)."""
    if identity == "world":
        return faces
    if identity.startswith("robot-"):
        face = min(int(identity[len("robot-"):]) // ROBOTS_PER_FACE, len(faces) - 1)
        return faces[:1] + ([faces[face]] if face > 0 else [])
    return faces[:1]


def _domains(domain: Domains) -> str:
    """<domains> naming one id, or each of a list of ids."""
    ids = domain if isinstance(domain, (list, tuple)) else [domain]
    return "<domains>" + "".join(f"<id>{d}</id>" for d in ids) + "</domains>"


def permissions_xml(identity: str, now: datetime.datetime, domain: Domains) -> str:
    publish, subscribe = _grants(identity)
    domains = _domains(domain)
    return ('<?xml version="1.0" encoding="UTF-8"?>\n'
            '<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" '
            'xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/'
            'omg_shared_ca_permissions.xsd">\n<permissions>\n'
            f'<grant name="{identity}">\n<subject_name>{subject(identity)}</subject_name>\n'
            f'<validity><not_before>{_stamp(now - datetime.timedelta(hours=1))}</not_before>'
            f'<not_after>{_stamp(now + datetime.timedelta(days=VALID_DAYS))}</not_after></validity>\n'
            f'<allow_rule>{domains}\n' + "\n".join(publish + subscribe) + '\n</allow_rule>\n'
            '<default>DENY</default>\n</grant>\n</permissions>\n</dds>\n')


def governance_xml(domain: Domains) -> str:
    return GOVERNANCE.replace("@DOMAINS@", _domains(domain))


GOVERNANCE = """<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_governance.xsd">
<domain_access_rules>
<domain_rule>
@DOMAINS@
<allow_unauthenticated_participants>false</allow_unauthenticated_participants>
<enable_join_access_control>true</enable_join_access_control>
<discovery_protection_kind>ENCRYPT</discovery_protection_kind>
<liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
<rtps_protection_kind>NONE</rtps_protection_kind>
<topic_access_rules>
<topic_rule>
<topic_expression>*</topic_expression>
<enable_discovery_protection>true</enable_discovery_protection>
<enable_liveliness_protection>true</enable_liveliness_protection>
<enable_read_access_control>true</enable_read_access_control>
<enable_write_access_control>true</enable_write_access_control>
<metadata_protection_kind>SIGN</metadata_protection_kind>
<data_protection_kind>ENCRYPT</data_protection_kind>
</topic_rule>
</topic_access_rules>
</domain_rule>
</domain_access_rules>
</dds>
"""


def _write(path: str, text: str, mode: int = 0o644) -> None:
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, mode)
    with os.fdopen(fd, "w", encoding="utf-8") as f:
        f.write(text)


def _identity(d: str, identity: str, serial: int, now: datetime.datetime, domain: Domains) -> None:
    """Key (0600), certificate signed by the CA, permissions signed by the CA."""
    key = f"{identity}.key"
    # The key file is created 0600 before openssl writes into it (never readable by others, not even briefly).
    os.close(os.open(os.path.join(d, key), os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600))
    _openssl("req", "-x509", "-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:prime256v1", "-nodes", "-keyout", key,
             "-subj", f"/O={ORGANISATION}/CN={identity}", "-CA", "ca.pem", "-CAkey", "ca.key",
             "-set_serial", str(serial), "-days", str(VALID_DAYS), "-out", f"{identity}.pem", cwd=d)
    os.chmod(os.path.join(d, key), 0o600)
    _write(os.path.join(d, f"{identity}.permissions.xml"), permissions_xml(identity, now, domain))
    _openssl("smime", "-sign", "-in", f"{identity}.permissions.xml", "-text", "-out", f"{identity}.permissions.p7s",
             "-signer", "ca.pem", "-inkey", "ca.key", cwd=d)


def make_security_dir(run_dir: str, robots: int, domain: int, workers: int = 4) -> str:
    """Makes RUN_DIR/security for a run of `robots` robots on DDS domain `domain` (the governance and every
    permission name that domain only, and the world's faces' local ids: face_domain_ids); returns its path.
    Raises SecurityError."""
    if not 0 <= domain <= MAX_SECURE_DOMAIN:
        raise SecurityError(f"DDS domain {domain}: Cyclone 0.10.2's access control takes domain ids 0.."
                            f"{MAX_SECURE_DOMAIN} only in governance and permissions; choose another --domain")
    d = os.path.join(run_dir, "security")
    try:
        os.mkdir(d, 0o700)
    except FileExistsError:
        raise SecurityError(f"{d} exists already: a run directory gets its security material once") from None
    os.chmod(d, 0o700)
    now = datetime.datetime.now(datetime.timezone.utc).replace(tzinfo=None)
    os.close(os.open(os.path.join(d, "ca.key"), os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600))
    _openssl("req", "-x509", "-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:prime256v1", "-nodes",
             "-keyout", "ca.key", "-subj", f"/O={ORGANISATION}/CN={ORGANISATION} run CA", "-days", str(VALID_DAYS),
             "-out", "ca.pem", cwd=d)
    faces = face_domain_ids(domain, robots)
    _write(os.path.join(d, "governance.xml"), governance_xml(faces))
    _openssl("smime", "-sign", "-in", "governance.xml", "-text", "-out", "governance.p7s", "-signer", "ca.pem",
             "-inkey", "ca.key", cwd=d)
    identities = ["world", "observer"] + [robot_identity(k) for k in range(robots)]
    with concurrent.futures.ThreadPoolExecutor(max_workers=workers) as pool:
        for f in [pool.submit(_identity, d, ident, serial, now, _granted_domains(ident, faces))
                  for serial, ident in enumerate(identities, 2)]:
            f.result()
    # Nothing is signed after this: without the CA's key no other identity or permission can be made.
    os.remove(os.path.join(d, "ca.key"))
    return d


def check_keys(d: str) -> list[str]:
    """The private keys of a security directory whose mode lets others than the owner read them."""
    return [n for n in sorted(os.listdir(d)) if n.endswith(".key") and os.stat(os.path.join(d, n)).st_mode & 0o077]


