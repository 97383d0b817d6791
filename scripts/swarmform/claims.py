"""Who may take a robot's id (docs/wire.md, "Claim proofs").

The launcher draws a secret per run and gives it to the world in its environment (SWARMFORM_RUN_SECRET), never on
a command line (every user of the host reads those) nor on the wire. Each agent it starts, restarted ones too, gets
only its own id's token (SWARMFORM_CLAIM_TOKEN), from which it proves its claims; the world derives the token
again from the secret. The derivation is common/dds/claim_proof.cpp's, byte for byte.
"""

import hashlib
import hmac
import os
import secrets
import struct

RUN_SECRET_ENV = "SWARMFORM_RUN_SECRET"
CLAIM_TOKEN_ENV = "SWARMFORM_CLAIM_TOKEN"


def run_secret() -> bytes:
    """A fresh secret for one run (32 random bytes)."""
    return secrets.token_bytes(32)


def claim_token(secret: bytes, run_nonce: str, rid: int) -> str:
    """Robot `rid`'s token in the run named by `run_nonce` (hex), as 64 hex digits:
    HMAC-SHA-256(secret, "swarmform claim token" NUL | run_nonce (8 bytes LE) | rid (4 bytes LE))."""
    data = b"swarmform claim token\0" + struct.pack("<QI", int(run_nonce, 16), rid)
    return hmac.new(secret, data, hashlib.sha256).hexdigest()


def world_env(secret: bytes) -> dict[str, str]:
    """The world's environment: this process's, with the run's secret."""
    env = dict(os.environ)
    env[RUN_SECRET_ENV] = secret.hex()
    env.pop(CLAIM_TOKEN_ENV, None)
    return env


def agent_env(secret: bytes, run_nonce: str, rid: int) -> dict[str, str]:
    """Agent `rid`'s environment: this process's, with its token (and never the secret)."""
    env = dict(os.environ)
    env.pop(RUN_SECRET_ENV, None)
    env[CLAIM_TOKEN_ENV] = claim_token(secret, run_nonce, rid)
    return env
