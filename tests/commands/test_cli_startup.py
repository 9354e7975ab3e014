"""Start-up of the command line (issue 39 item 1): `--help`, `--version`, a command's `--help` and argument
errors answer without importing the science's libraries, and print what the fully built parser prints."""

from __future__ import annotations

import contextlib
import io
import json
import os
import subprocess
import sys

import pytest

from pampipe import cli
from tests.support.problems import ROOT

#: Libraries no help text or argument error needs.
HEAVY = ("casadi", "pydantic", "matplotlib", "scipy", "pandas", "yaml", "wntr")
#: `pampipe --help` and friends list the commands by name: not even numpy.
TOP = [["--help"], ["--version"], ["plna"], [], ["--debug"]]


def _loaded_after(argvs: list[list[str]]) -> list[tuple[int, list[str]]]:
    """(exit code, top-level modules of numpy and HEAVY newly loaded) of `pampipe ARGV` for each ARGV, run one
    after the other in one fresh interpreter."""
    code = ("import contextlib, io, json, sys\nfrom pampipe.cli import main\nfound = []\n"
            f"for argv in {argvs!r}:\n"
            "    before = set(sys.modules)\n"
            "    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):\n"
            "        status = main(argv)\n"
            "    new = {m.split('.')[0] for m in set(sys.modules) - before}\n"
            f"    new = sorted(new & {{'numpy', *{HEAVY!r}}})\n"
            "    found.append((status, new))\n"
            "print(json.dumps(found))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=300,
                         check=True)
    return [(status, new) for status, new in json.loads(out.stdout)]


def test_help_version_and_a_misspelt_command_import_no_library():
    found = _loaded_after(TOP)
    assert [status for status, _ in found] == [0, 0, 2, 2, 2]
    assert all(new == [] for _, new in found), found


def test_every_commands_help_and_argument_errors_import_no_heavy_library():
    argvs = [[name.replace("_", "-"), *rest] for name in cli.COMMANDS  # next_test: `pampipe next-test`
             for rest in (["--help"], ["missing.yaml", "--no-such-option"])]
    found = _loaded_after(argvs)
    assert [status for status, _ in found] == [0, 2] * len(cli.COMMANDS)
    heavy = {tuple(argv): new for argv, (_, new) in zip(argvs, found, strict=True) if set(new) & set(HEAVY)}
    assert not heavy, heavy


def test_the_checks_can_fail():
    """A module that imports one of the libraries is seen (the check above is not vacuous)."""
    code = ("import sys\nbefore = set(sys.modules)\nimport yaml\n"
            "print(sorted({m.split('.')[0] for m in set(sys.modules) - before} & {'yaml'}))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "['yaml']"


def _printed(argv: list[str]) -> str:
    stdout = io.StringIO()
    with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(io.StringIO()):
        assert cli.main(argv) == 0
    return stdout.getvalue()


def test_the_top_level_help_is_that_of_the_full_parser(monkeypatch):
    monkeypatch.setenv("COLUMNS", "100")
    assert _printed(["--help"]) == cli.build_parser().format_help()


@pytest.mark.parametrize("name", cli.COMMANDS)
def test_each_commands_help_is_that_of_the_full_parser(monkeypatch, name):
    monkeypatch.setenv("COLUMNS", "100")
    command = name.replace("_", "-")  # the module next_test is the command next-test
    assert _printed([command, "--help"]) == cli.build_parser().commands[name].format_help()


def test_a_plan_without_confidence_loads_no_sampling_and_no_processes(tmp_path):
    """The demo plan (issue 39 item 2): the confidence machinery (its sampling, the executors and with them
    multiprocessing and concurrent.futures) is imported only with --confidence."""
    code = ("import contextlib, io, json, sys\nfrom pampipe.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):\n"
            "    status = main(['plan', 'problems/missions/vertical-climb-3in.yaml'])\n"
            "print(json.dumps([status, sorted(m for m in sys.modules if m in {'multiprocessing', "
            "'concurrent.futures', 'pampipe.planning.confidence', 'pampipe.planning.sampling', "
            "'pampipe.runtime.executors'})]))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=300,
                         check=True, env={**os.environ, "PAMPIPE_NLP_CACHE": str(tmp_path)})
    assert json.loads(out.stdout) == [0, []]
