"""One exit-code table, common/exit_codes.json: the C++ constants (the header CMake generates, printed by
exit_codes_dump) and the Python ones are the same table; each program's --help epilogue is the table's text for
it; and no program writes an exit code as a number of its own (a literal would pass unnoticed otherwise)."""

import json
import os
import re
import subprocess
import unittest

import helpers
from swarmform import exit_codes, expect, launcher

ROOT = helpers.ROOT
TIMEOUT_S = 60
# The programs' sources that decide exit codes, and what a code written as a literal looks like in them.
CPP_SOURCES = ("world_server/main.cpp", "world_server/server.hpp", "world_server/server.cpp", "robot_agent/main.cpp",
               "harness/swarm_inprocess_main.cpp")
CPP_LITERALS = (re.compile(r"\bkExit\w*\s*=\s*\d"), re.compile(r"\breturn\s+\d+\s*;"),
                re.compile(r"\bstopped\(\s*\d"), re.compile(r"\breturn\b.*\?\s*\d+\s*:"),
                re.compile(r"\breturn\b.*:\s*\d+\s*;"),
                re.compile(r"\(exit \d"), re.compile(r"\bexit codes?:? \d", re.IGNORECASE))
PY_SOURCES = ("scripts/swarmform/launcher.py", "scripts/swarmform/expect.py", "scripts/swarmform/cli.py",
              "scripts/swarmform/__main__.py")
PY_LITERALS = (re.compile(r"\bEXIT_\w+\s*=\s*\d"), re.compile(r"\bLaunchError\(.*,\s*\d+\)"),
               re.compile(r"\bcode:\s*int\s*=\s*\d"), re.compile(r"sys\.exit\(\d"),
               re.compile(r"\bexit codes?:? \d", re.IGNORECASE))


def _run(*cmd: str) -> str:
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=TIMEOUT_S)
    if p.returncode != 0:
        raise AssertionError(f"{' '.join(cmd)}: exit {p.returncode}\n{p.stderr}")
    return p.stdout


def _words(text: str) -> str:
    return " ".join(text.split())


class ExitCodeTableTest(unittest.TestCase):
    def test_the_cpp_constants_are_the_python_table(self):
        cpp = json.loads(_run(os.environ["EXIT_CODES_DUMP"]))
        self.assertEqual(cpp, exit_codes.CODES)
        self.assertEqual(len(set(cpp.values())), len(cpp), "one meaning per code")

    def test_the_python_names_are_the_table_s(self):
        for name, code in exit_codes.CODES.items():
            if hasattr(exit_codes, name.upper()):
                self.assertEqual(getattr(exit_codes, name.upper()), code, name)
        self.assertEqual(launcher.EXIT_RECORDING_FAILED, exit_codes.CODES["recording_failed"])
        self.assertEqual(launcher.EXIT_AGENTS_MISSING, exit_codes.CODES["agents_missing"])
        self.assertEqual(expect.EXIT_EXPECTATION_FAILED, exit_codes.CODES["expectation_failed"])

    def test_every_program_s_help_lists_its_codes_from_the_table(self):
        programs = {"world_server": os.environ["WORLD_SERVER_EXE"], "robot_agent": os.environ["ROBOT_AGENT_EXE"],
                    "swarm_inprocess": os.environ["SWARM_INPROCESS_EXE"]}
        for program, exe in programs.items():
            with self.subTest(program=program):
                text = exit_codes.help_text(program)
                self.assertIn(_words(text), _words(_run(exe, "--help")))  # CLI11 may re-space the footer
                for name, code in exit_codes.CODES.items():
                    row = next(r for r in exit_codes.TABLE["codes"] if r["name"] == name)
                    self.assertEqual(program in row["programs"], f" {code} {row['meaning']}" in text
                                     or f" {code}+N {row['meaning']}" in text, name)
        self.assertIn(_words(exit_codes.help_text("swarm_run")), _words(_run(helpers.SWARM, "run", "--help")))

    def test_no_program_writes_a_code_as_a_literal(self):
        found = []
        for rel, patterns in [(p, CPP_LITERALS) for p in CPP_SOURCES] + [(p, PY_LITERALS) for p in PY_SOURCES]:
            with open(os.path.join(ROOT, rel), encoding="utf-8") as f:
                for n, line in enumerate(f, 1):
                    if line.lstrip().startswith(("//", "#")):
                        continue
                    found += [f"{rel}:{n}: {line.strip()}" for p in patterns if p.search(line)]
        self.assertEqual(found, [], "exit codes come from common/exit_codes.json, by name")

    def test_the_scan_finds_a_literal(self):
        self.assertTrue(any(p.search("      return stopped(5);") for p in CPP_LITERALS))
        self.assertTrue(any(p.search("    return 2;") for p in CPP_LITERALS))
        self.assertTrue(any(p.search("EXIT_DISK_FULL = 5") for p in PY_LITERALS))
        self.assertFalse(any(p.search("    return stopped(kExitIdLost);") for p in CPP_LITERALS))


if __name__ == "__main__":
    unittest.main()
