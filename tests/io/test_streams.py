"""stdout and stderr are guarded, and text from input files is made safe (issue 27).

Before: `plan --json > /dev/full` printed a traceback, `plan > /dev/full` called itself a bug, and
`plan >&-` exited 0 with the report lost; a section name holding ESC [2J cleared the terminal.
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
import yaml

from pampipe.cli import main
from pampipe.io.streams import safe_text
from tests.support.problems import PROBLEMS, ROOT

MISSION = PROBLEMS / "missions" / "vertical-climb-3in.yaml"


def shell(command: str) -> subprocess.CompletedProcess:
    """Run ``command`` in sh with ``PAMPIPE`` standing for this interpreter's pampipe."""
    return subprocess.run(["sh", "-c", command.replace("PAMPIPE", f"{sys.executable} -m pampipe")],
                          capture_output=True, text=True, cwd=ROOT, timeout=300)


@pytest.mark.parametrize("json_flag", ["", "--json"])
@pytest.mark.parametrize("redirect", [">/dev/full", ">&-"])
def test_unwritable_stdout_is_exit_2_with_one_line(redirect, json_flag):
    if redirect == ">/dev/full" and not __import__("os").path.exists("/dev/full"):
        pytest.skip("no /dev/full here")
    done = shell(f"PAMPIPE plan {MISSION} {json_flag} {redirect}")
    assert done.returncode == 2, done.stderr
    assert "Traceback" not in done.stderr and "bug" not in done.stderr
    errors = [line for line in done.stderr.splitlines()
              if line.startswith(("pampipe plan: error", "pampipe: error"))]
    assert len(errors) == 1 and "stdout" in errors[0], done.stderr


def test_unwritable_stderr_is_exit_2():
    done = shell(f"PAMPIPE plan {MISSION} 2>/dev/full")
    assert done.returncode == 2  # the first warning fails: the run stops there


def test_broken_pipe_is_exit_2():
    """The reader has gone (EPIPE) before pampipe writes its report."""
    process = subprocess.Popen([sys.executable, "-m", "pampipe", "plan", str(MISSION), "--json"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT)
    process.stdout.close()  # long before the child has imported anything
    error = process.stderr.read()
    assert process.wait(timeout=300) == 2
    assert "Traceback" not in error and "stdout" in error


def test_safe_text_escapes_what_a_terminal_would_obey():
    assert safe_text("a\x1b[2Jb\u202ec\u2066d\x07\r\x00\u200b") == (
        "a\\x1b[2Jb\\u202ec\\u2066d\\x07\\x0d\\x00\\u200b")
    plain = "PAM1 → 3 in, 90°\n\tok  Steigleitung-éè ↑"
    assert safe_text(plain) == plain
    ascii_text = "".join(map(chr, range(128)))  # an ASCII text takes a shorter scan: the same escapes
    expected = "".join(c if c in "\n\t" or " " <= c <= "~" else f"\\x{ord(c):02x}" for c in ascii_text)
    assert safe_text(ascii_text) == expected
    for c in ascii_text:  # one character in an otherwise safe text (most texts: returned as they are)
        escaped = c if c in "\n\t" or " " <= c <= "~" else f"\\x{ord(c):02x}"
        assert safe_text(f'{{"name": "s{c}"}}') == f'{{"name": "s{escaped}"}}'


def test_a_hostile_section_name_reaches_the_terminal_escaped(tmp_path, capsys):
    document = yaml.safe_load(MISSION.read_text())
    for segment in document["robot"]["segments"]:
        segment["pam"] = str(PROBLEMS / "pams" / "paper-radial-pam.yaml")
    document["route"][0]["name"] = "riser\x1b[2J\u202eevil"
    path = tmp_path / "hostile.yaml"
    path.write_text(yaml.safe_dump(document, allow_unicode=True), encoding="utf-8")
    assert main(["plan", str(path)]) == 0
    out = capsys.readouterr()
    text = out.out + out.err
    assert "\x1b" not in text and "\u202e" not in text
    assert text.count("riser\\x1b[2J\\u202eevil") >= 2  # in the report and in a warning
    assert main(["plan", str(path), "--json"]) == 0
    out = capsys.readouterr()
    assert json.loads(out.out)["sections"][0]["name"] == "riser\x1b[2J\u202eevil"  # JSON keeps the name
    assert "\x1b" not in out.err
