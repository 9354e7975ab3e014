"""The bad-input corpus: every case under tests/bad_inputs/ through the CLI (issue 7).

Each case is a folder with its input files and a ``case.yaml``: the command, its arguments (``{dir}`` is
the case folder, copied to a temporary place first so nothing in the repository is written), the
expected exit code and a fragment the message must contain. No case may produce a traceback.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest
import yaml

from pampipe.cli import main

CORPUS = Path(__file__).resolve().parent / "bad_inputs"
CASES = sorted(p.name for p in CORPUS.iterdir() if (p / "case.yaml").is_file())


@pytest.mark.parametrize("name", CASES)
def test_bad_input_case(name, tmp_path, capsys):
    case = yaml.safe_load((CORPUS / name / "case.yaml").read_text())
    folder = tmp_path / name
    shutil.copytree(CORPUS / name, folder, symlinks=True)
    args = [case["command"], *(a.replace("{dir}", str(folder)) for a in case["args"])]
    code = main(args)
    out = capsys.readouterr()
    # mask the case folder, so that a fragment cannot match the case's own name in a path
    out = type(out)(out.out.replace(str(folder), "{dir}"), out.err.replace(str(folder), "{dir}"))
    assert code == case["exit"], out.err
    # bad input (2) is explained on stderr; an infeasible plan (3) may list its reasons in the report
    assert case["message"] in (out.err if code == 2 else out.err + out.out), out.err + out.out
    assert "Traceback" not in out.err + out.out
    assert out.err.count("\n") <= 3, "the error should be one short paragraph"


def test_corpus_is_not_empty():
    assert len(CASES) >= 70


def test_unreadable_file_is_reported(tmp_path, capsys, monkeypatch):
    """Permission denied (simulated: the suite may run as root, who can read anything)."""
    path = tmp_path / "pam.yaml"
    path.write_text("name: x\n")
    real_open = os.open

    def deny(name, *args, **kwargs):
        if Path(name) == path:
            raise PermissionError(13, "Permission denied", str(name))
        return real_open(name, *args, **kwargs)

    monkeypatch.setattr(os, "open", deny)
    assert main(["simulate", str(path), "-d", "3 in"]) == 2
    assert "permission denied" in capsys.readouterr().err
