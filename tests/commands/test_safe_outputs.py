"""Outputs and the last-resort handler (issue 14, items 3 and 4).

Written files get the umask's mode (or the mode of the file they replace); a read-only folder, a
FIFO or a device is exit 2, never a traceback; an unexpected exception is exit 3 with a "please report"
hint; ``--reproducible`` zeroes wall-clock timings only; an interrupt says what was written.
"""

from __future__ import annotations

import json
import os
import stat
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

from pampipe.cli import main
from tests.support.problems import PROBLEMS, ROOT

MISSION = PROBLEMS / "missions" / "vertical-climb-3in.yaml"
EXPERIMENT = PROBLEMS / "experiments" / "paper-protocol.yaml"


def _plan_with_umask(target, umask: int) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "pampipe", "plan", str(MISSION), "-o", str(target)],
                          capture_output=True, text=True, cwd=ROOT, timeout=600,
                          preexec_fn=lambda: os.umask(umask))


@pytest.mark.parametrize(("umask", "mode"), [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664)])
def test_new_output_gets_the_umask_mode(tmp_path, umask, mode):
    target = tmp_path / "plan.json"
    out = _plan_with_umask(target, umask)
    assert out.returncode == 0, out.stderr
    assert stat.S_IMODE(target.stat().st_mode) == mode


def test_replaced_output_keeps_its_mode(tmp_path, capsys):
    target = tmp_path / "plan.json"
    target.write_text("old\n")
    target.chmod(0o640)
    assert main(["plan", str(MISSION), "-o", str(target)]) == 0
    assert stat.S_IMODE(target.stat().st_mode) == 0o640 and target.read_text().startswith("{")


def test_fifo_data_file_exits_2_without_blocking(tmp_path):
    """A FIFO without a writer blocks a reader forever: the run must end, with exit 2."""
    (tmp_path / "pam.yaml").write_text((PROBLEMS / "pams" / "paper-radial-pam.yaml").read_text())
    (tmp_path / "experiment.yaml").write_text("pam: pam.yaml\ntests:\n  - {name: a, kind: axial, "
                                              "data: axial.csv}\n")
    os.mkfifo(tmp_path / "axial.csv")
    out = subprocess.run([sys.executable, "-m", "pampipe", "identify", str(tmp_path / "experiment.yaml")],
                         capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert out.returncode == 2 and "FIFO" in out.stderr


def test_read_only_folder_is_exit_2_and_leaves_nothing(tmp_path, capsys, monkeypatch):
    """Simulated (root writes anywhere): the temporary file cannot be created."""
    import tempfile

    def refuse(*args, **kwargs):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(tempfile, "mkstemp", refuse)
    assert main(["plan", str(MISSION), "-o", str(tmp_path / "plan.json")]) == 2
    err = capsys.readouterr().err
    assert "permission denied" in err.lower() and "Traceback" not in err
    assert not list(tmp_path.iterdir())


NOBODY = 65534  # the conventional uid of `nobody`: any uid without rights to the folder would do

#: plan once where it may write (which imports and loads all it needs while the interpreter, maybe under
#: /root, is still readable), then drop to uid NOBODY when root, and plan into the read-only folder.
AS_NOBODY = """
import fractions, os, sys  # fractions: imported late, on the error path
from pampipe.cli import main
mission, warm, target, nobody = sys.argv[1:]
assert main(["plan", mission, "-o", warm]) == 0
if os.geteuid() == 0:
    os.setgroups([])
    os.setgid(int(nobody))
    os.setuid(int(nobody))
sys.exit(main(["plan", mission, "-o", target]))
"""


def test_read_only_folder_for_real():
    """A folder the user cannot write into is exit 2 naming the problem, no traceback, nothing written.

    Root may write anywhere, and CI runs as root: there the command runs in a process that has dropped
    to uid ``NOBODY``, so the folder is read-only for it whoever runs the suite."""
    with tempfile.TemporaryDirectory() as base:  # under the system tmp: ``nobody`` can reach into it
        base = Path(base)
        os.chmod(base, 0o755)
        folder = base / "ro"
        folder.mkdir()
        folder.chmod(0o555)
        try:
            out = subprocess.run([sys.executable, "-c", AS_NOBODY, str(MISSION), str(base / "warm.json"),
                                  str(folder / "plan.json"), str(NOBODY)],
                                 capture_output=True, text=True, cwd=ROOT, timeout=600,
                                 env={**os.environ, "PAMPIPE_NLP_CACHE": "off"})
        finally:
            folder.chmod(0o755)
        assert (base / "warm.json").is_file(), out.stderr
        assert out.returncode == 2, out.stderr
        assert "Traceback" not in out.stderr
        assert "permission denied" in out.stderr.lower() and str(folder) in out.stderr, out.stderr
        assert not list(folder.iterdir())


def test_output_whose_parent_is_a_file(tmp_path, capsys):
    """A check no uid can pass: the output's parent is a regular file, so nothing can be created there."""
    parent = tmp_path / "a-file"
    parent.write_text("mine")
    assert main(["plan", str(MISSION), "-o", str(parent / "plan.json")]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and str(parent) in err, err
    assert parent.read_text() == "mine" and sorted(tmp_path.iterdir()) == [parent]


def test_a_failed_write_leaves_no_temporary_file(tmp_path, capsys, monkeypatch):
    from pampipe.io import files

    def broken(target, text, **kwargs):
        files.atomic_write(target, lambda tmp: (tmp.write_text("half"), _raise_disk_full()))

    monkeypatch.setattr("pampipe.commands.common.atomic_write_text", broken)
    assert main(["plan", str(MISSION), "-o", str(tmp_path / "plan.json")]) == 2
    assert "No space left" in capsys.readouterr().err
    assert not list(tmp_path.iterdir())


def _raise_disk_full():
    raise OSError(28, "No space left on device")


def test_unexpected_exception_is_exit_3_with_a_report_hint(monkeypatch, capsys):
    def crash(args):
        raise ZeroDivisionError("float division by zero")

    monkeypatch.setattr("pampipe.commands.plan.run", crash)
    assert main(["plan", str(MISSION), "--json"]) == 3
    out = capsys.readouterr()
    assert "internal error: ZeroDivisionError" in out.err and "please report" in out.err
    assert "Traceback" not in out.err and out.err.count("\n") == 1
    assert json.loads(out.out)["error"]["code"] == 3
    assert main(["plan", str(MISSION), "--debug"]) == 3
    assert "Traceback" in capsys.readouterr().err  # only with --debug


def test_misspelt_command_gets_a_suggestion(capsys):
    assert main(["plna", str(MISSION)]) == 2
    assert "did you mean 'plan'?" in capsys.readouterr().err


def test_interrupt_after_writing_says_what_was_written(tmp_path, monkeypatch, capsys):
    target = tmp_path / "fit.yaml"

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr("pampipe.commands.identify.emit", interrupted)  # after -o is written
    assert main(["identify", str(EXPERIMENT), "-o", str(target)]) == 130
    err = capsys.readouterr().err
    assert target.exists() and f"interrupted after writing {target}" in err
    assert "no output" not in err


def test_reproducible_zeroes_wall_clock_only(capsys):
    assert main(["gait", str(MISSION), "--json", "--reproducible"]) == 0
    document = json.loads(capsys.readouterr().out)
    durations = [s["duration_s"] for s in document["steps"]]
    assert document["cycle_time_s"] > 1  # physical: the valves take seconds (zeroed before issue 14)
    assert sum(durations) == pytest.approx(document["cycle_time_s"], rel=1e-9)  # 12-digit JSON floats
    assert main(["identify", str(EXPERIMENT), "--json", "--reproducible"]) == 0
    solver = json.loads(capsys.readouterr().out)["solver"]
    timings = {k: v for k, v in solver.items() if k.endswith("wall_time_s")}
    assert set(timings) >= {"wall_time_s", "build_wall_time_s", "reduce_wall_time_s"}
    assert not any(timings.values())
