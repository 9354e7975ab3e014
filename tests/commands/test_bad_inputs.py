"""The bad-input corpus: every case under tests/bad_inputs/ through the CLI (issues 7 and 14).

Each case is a folder with its input files and a ``case.yaml``: the command, its arguments (``{dir}`` is
the case folder, copied to a temporary place first so nothing in the repository is written), the
expected exit code and a fragment the message must contain. No case may produce a traceback.

Inputs that cannot live in git are made when the case runs:

* ``fifo: [name, ...]``: named pipes (a FIFO with no writer blocks a naive reader forever);
* ``generate: {name: [[text, count], ...]}``: a file of ``text`` repeated ``count`` times, piece by piece
  (``{i}`` in the text becomes the repetition's index);
* ``sparse: {name: size}``: a file of ``size`` bytes that takes no disk space.

Exit 0 cases check that a value is read as meant (``010`` is 10): the fragment must be in stdout.
"""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import pytest
import yaml

from pampipe.cli import main
from tests.support.problems import BAD_INPUTS

CORPUS = BAD_INPUTS
CASES = sorted(p.name for p in CORPUS.iterdir() if (p / "case.yaml").is_file())
#: The cases of bad input (exit 2); the others (exit 0 or 3) print their result document under --json.
BAD = [name for name in CASES if yaml.safe_load((CORPUS / name / "case.yaml").read_text())["exit"] == 2]


def _prepare(name: str, tmp_path: Path) -> tuple[dict, Path, list[str]]:
    case = yaml.safe_load((CORPUS / name / "case.yaml").read_text())
    folder = tmp_path / name
    shutil.copytree(CORPUS / name, folder, symlinks=True)
    for fifo in case.get("fifo", []):
        os.mkfifo(folder / fifo)
    for file, pieces in case.get("generate", {}).items():
        with open(folder / file, "w", encoding="utf-8") as handle:
            for text, count in pieces:
                if "{i}" in text:
                    handle.writelines(text.replace("{i}", str(i)) for i in range(count))
                else:
                    handle.write(text * count)
    for file, size in case.get("sparse", {}).items():
        with open(folder / file, "wb") as handle:
            handle.truncate(size)
    args = [case["command"], *(a.replace("{dir}", str(folder)) for a in case["args"])]
    return case, folder, args


@pytest.mark.parametrize("name", CASES)
def test_bad_input_case(name, tmp_path, capsys):
    case, folder, args = _prepare(name, tmp_path)
    code = main(args)
    out = capsys.readouterr()
    # mask the case folder, so that a fragment cannot match the case's own name in a path
    out = type(out)(out.out.replace(str(folder), "{dir}"), out.err.replace(str(folder), "{dir}"))
    assert code == case["exit"], out.err
    assert "Traceback" not in out.err + out.out
    if code == 0:  # read as meant: the value shows in the result
        assert case["message"] in out.out, out.out
        return
    # bad input (2) is explained on stderr; an infeasible plan (3) may list its reasons in the report
    assert case["message"] in (out.err if code == 2 else out.err + out.out), out.err + out.out
    assert out.err.count("\n") <= 3, "the error should be one short paragraph"
    assert len(out.err) < 2000, "a message never repeats a huge input"


@pytest.mark.parametrize("name", BAD)
def test_bad_input_case_under_json_prints_one_error_document(name, tmp_path, capsys):
    """Under --json, stdout holds exactly one JSON document, an error document for bad input."""
    _, _, args = _prepare(name, tmp_path)
    assert main([*args, "--json"]) == 2
    document = json.loads(capsys.readouterr().out)
    assert document["error"]["code"] == 2 and document["error"]["message"]


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
