"""--confidence, --samples and --seed are declared once (commands/common.py) for plan, rehearse, export and
next-test, with one validator each (issue 42 review): the same bad value gets the same exit 2 and message from
every command, before any file is read."""

from __future__ import annotations

import argparse
import re
from pathlib import Path

import pytest

from pampipe.cli import build_parser, main

COMMANDS = {"plan": ["M.yaml"], "rehearse": ["M.yaml"], "export": ["M.yaml"],
            "next-test": ["P.yaml", "M.yaml", "--menu", "X.yaml"]}


def _actions(command: str) -> dict[str, argparse.Action]:
    name = command.replace("-", "_")
    return {o: a for a in build_parser((name,)).commands[name]._actions for o in a.option_strings}


@pytest.mark.parametrize(("option", "value", "message"), [
    ("--confidence", "1.2", "'1.2' must be a probability in [0.5, 1)"),
    ("--confidence", "0.3", "'0.3' must be a probability in [0.5, 1)"),
    ("--samples", "99", "--samples: 99 must be at least 100"),
    ("--samples", "4e3", "--samples: '4e3' is not a whole number"),
    ("--seed", "-1", "--seed: -1 must be at least 0"),
])
def test_one_validator_one_message_for_every_command(capsys, option, value, message):
    for command, args in COMMANDS.items():
        if option not in _actions(command):  # export draws with plan's seed: it has no --seed
            assert (command, option) == ("export", "--seed")
            continue
        assert main([command, *args, option, value]) == 2, command
        assert message in capsys.readouterr().err, (command, option)


def test_the_options_are_declared_once():
    for command in COMMANDS:
        actions = _actions(command)
        assert actions["--confidence"].metavar == "C" and actions["--samples"].metavar == "N"
        assert actions["--samples"].type("100") == 100
        assert actions["--confidence"].type("95 %") == pytest.approx(0.95)
    assert _actions("next-test")["--confidence"].default == 0.95
    assert _actions("plan")["--confidence"].default is None
    folder = Path(__file__).resolve().parents[2] / "pampipe" / "commands"
    declared = [name for name in ("common", *(c.replace("-", "_") for c in COMMANDS))
                if re.search(r"add_argument\(\s*\"--(confidence|samples|seed)\"",
                             (folder / f"{name}.py").read_text())]
    assert declared == ["common"]
