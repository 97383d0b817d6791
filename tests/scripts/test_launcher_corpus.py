"""The launcher's own commands fed the world's fuzz corpus (tests/fuzz/corpus/scenario and shape, each file as it
is and once mutated at the byte level, seeded): `swarm run --check` on every input against the real world_server
(BUILD_DIR) exits 0 (it would run) or 2 naming the file, and raises nothing (a traceback, from the command line),
whatever the bytes. The launcher is called in this process (its `cli.main`, as scripts/swarm calls it), so that
56 inputs cost 56 world_server --check runs and no Python start-ups. The C++ side of the same corpus is the fuzz
stage's (tests/fuzz); this is the Python side around it."""

import contextlib
import io
import os
import random
import shutil
import sys
import tempfile
import unittest

import helpers

sys.path.insert(0, os.path.join(helpers.ROOT, "scripts"))
from swarmform import cli  # noqa: E402  (after the path above)

BUILD_DIR = os.environ.get("BUILD_DIR") or os.path.join(helpers.ROOT, "build")
CORPUS = os.path.join(helpers.ROOT, "tests", "fuzz", "corpus")
PAPER = os.path.join(helpers.ROOT, "scenarios", "paper.yaml")


def mutated(data: bytes, rng: random.Random) -> bytes:
    """One byte-level mutation: a byte replaced by a non-ASCII one, or the file cut and junk appended."""
    if data and rng.random() < 0.5:
        i = rng.randrange(len(data))
        return data[:i] + bytes([rng.randrange(0x80, 0x100)]) + data[i + 1:]
    cut = rng.randrange(len(data) + 1)
    return data[:cut] + bytes(rng.randrange(256) for _ in range(rng.randrange(1, 9)))


@unittest.skipUnless(os.access(os.path.join(BUILD_DIR, "world_server", "world_server"), os.X_OK),
                     f"world_server is not built in {BUILD_DIR}")
class LauncherCorpusTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-corpus-")

    def tearDown(self):
        shutil.rmtree(self.dir)

    def inputs(self):
        """(kind, path) of every corpus file and its mutation, written under self.dir with the same names."""
        out = []
        for kind in ("scenario", "shape"):
            for name in sorted(os.listdir(os.path.join(CORPUS, kind))):
                with open(os.path.join(CORPUS, kind, name), "rb") as f:
                    data = f.read()
                for variant, body in (("as-is", data), ("mutated", mutated(data, random.Random(f"{kind}/{name}")))):
                    folder = os.path.join(self.dir, kind, variant)
                    os.makedirs(folder, exist_ok=True)
                    path = os.path.join(folder, name)
                    with open(path, "wb") as f:
                        f.write(body)
                    out.append((kind, path))
        return out

    def test_every_input_is_checked_with_exit_0_or_2_and_never_a_traceback(self):
        os.environ["BUILD_DIR"] = BUILD_DIR
        codes = []
        for kind, path in self.inputs():
            where = ["--scenario", path] if kind == "scenario" else ["--scenario", PAPER, "--shape", path]
            err = io.StringIO()
            with self.subTest(path=os.path.relpath(path, self.dir)):
                with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
                    try:
                        code = cli.main(["run", "--check"] + where)
                    except SystemExit as e:  # argparse's own refusals
                        code = e.code
                codes.append(code)
                self.assertIn(code, (0, 2), err.getvalue())
                if code == 2:
                    self.assertIn(os.path.basename(path), err.getvalue(), "the message must name the file")
        self.assertIn(0, codes, "no input would run: the check itself is broken")
        self.assertIn(2, codes, "no input was refused: the corpus has bad files")


if __name__ == "__main__":
    unittest.main()
