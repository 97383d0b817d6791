"""scripts/swarmform/claims.py: the tokens the launcher gives its agents, and the environments that carry them."""

import os
import unittest

import helpers  # noqa: F401  (puts scripts/ on the path)
from swarmform import claims

SECRET = bytes(range(32))


class ClaimsTest(unittest.TestCase):
    def test_the_token_is_the_hmac_the_world_derives(self):
        # The same bytes as tests/integration/claim_proof_test.cpp's TokenAndProofAreTheDocumentedHmacs: the world
        # (common/dds/claim_proof.cpp) derives the token the launcher hands out, byte for byte.
        self.assertEqual(claims.claim_token(SECRET, "0123456789abcdef", 8),
                         "17d8631642b43b963d394221fc28b59e10616eb74fe6b726e4c7b4d1e555296c")

    def test_each_id_and_run_has_its_own_token(self):
        tokens = {claims.claim_token(SECRET, nonce, rid) for nonce in ("1", "2") for rid in range(4)}
        self.assertEqual(len(tokens), 8)
        self.assertNotEqual(claims.claim_token(SECRET, "1", 0), claims.claim_token(bytes(32), "1", 0))

    def test_the_world_gets_the_secret_and_an_agent_only_its_token(self):
        secret = claims.run_secret()
        self.assertEqual(len(secret), 32)
        self.assertNotEqual(secret, claims.run_secret())
        world = claims.world_env(secret)
        self.assertEqual(world[claims.RUN_SECRET_ENV], secret.hex())
        self.assertNotIn(claims.CLAIM_TOKEN_ENV, world)
        agent = claims.agent_env(secret, "00000000deadbeef", 3)
        self.assertNotIn(claims.RUN_SECRET_ENV, agent)
        self.assertEqual(agent[claims.CLAIM_TOKEN_ENV], claims.claim_token(secret, "00000000deadbeef", 3))
        self.assertNotIn(secret.hex(), agent.values())
        self.assertNotIn(claims.RUN_SECRET_ENV, os.environ)  # the launcher's own environment is left alone


if __name__ == "__main__":
    unittest.main()
