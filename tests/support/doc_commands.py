"""The example commands of README.md and docs/workflows.md, read and run as written (issue 21).

Convention (what a doc's ```sh block may assume; keep it when adding blocks):

* Every ```sh block of a doc (README.md, docs/workflows.md) runs in document order in ONE bash shell of that
  doc, so a `cd`, an `export` or a file written by an earlier command holds for the later ones. Each doc has
  its own shell and scratch folder (a reader may open either first), so the two run side by side under
  `pytest -n 2`.
* The shell starts in an empty scratch folder that holds a copy of the repository's `problems/` (as the
  repository root does) and nothing else: any other file a command reads must be written by an earlier command
  of the same doc (a heredoc, `pampipe example`, ...). Absolute paths such as `/tmp/x` are not
  allowed, since two runs at once would share them.
* `pampipe` on PATH is the one under test (the project venv's, or a wheel's in
  tests/packaging/test_wheel_install.py).
* A line starting with `make ` is skipped (the Makefile is the repository's, not the reader's scratch folder).
* A command ends at the end of its line, unless the line ends with `\\` or opens a heredoc (`cat > f <<'EOF'`:
  the command ends at the `EOF` line). It must exit 0, unless its (first, for a heredoc; last, for `\\`) line
  ends with a comment `# exits N`: then it must exit N.

A failure names the doc, the line of the block and of the command, the command, both exit codes and the end of
its output, so a broken merge is quick to find.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

from tests.support.problems import PROBLEMS, ROOT

DOCS = ("README.md", "docs/workflows.md")
#: The reference of every command: its ```sh blocks run in a shell of their own (tests/docs/test_docs_run.py).
REFERENCE = ("docs/commands.md",)
#: Doc commands that a named default test (or doc line) runs with the same inputs and options but where the
#: output goes (``-o``, ``--plots``, ``--json``, ``--report``), or that only read such a command's output: the
#: default run leaves them out of the doc's shell, since the named test runs the same computation; the slow
#: run of the doc runs every command as written (issue 40: the default run within 10 minutes). No command
#: left in may read what a left-out one wrote (tests/docs/test_docs_run.py checks it, and that the named test
#: exists and is not slow); a quote still reads the commands left in of its ```sh block.
ALSO_RUN = {
    ("README.md", "pampipe route ky4 --from J-315 --to J-897 --max-bore"):
        "tests/specs/test_network.py::test_cli_writes_a_mission_that_plan_reads",
    ("README.md", "pampipe design problems/inventories/riser.yaml -o"):
        "tests/commands/test_design.py::test_riser_json_has_the_interface_keys_and_writes_the_pam",
    ("README.md", "pampipe identify problems/experiments/paper-protocol.yaml -o out/fit.yaml --plots"):
        "docs/workflows.md:35",
    ("README.md", "pampipe simulate out/fit.yaml"): "docs/workflows.md:70",
    ("README.md", "pampipe rehearse problems/missions/tethered-climb.yaml --plots"):
        "tests/rehearsal/test_rehearse.py::test_the_tethered_mission_reports_the_tensions_and_its_plots",
    ("README.md", "pampipe diagnose problems/experiments/hidden-contact-stiffening.yaml --plots"):
        "tests/diagnosis/test_diagnose.py::test_bundled_example_writes_plots_and_a_pam_that_simulate_accepts",
    ("README.md", "pampipe simulate out/pam.yaml"):
        "tests/diagnosis/test_diagnose.py::test_bundled_example_writes_plots_and_a_pam_that_simulate_accepts",
}
EXPECTED = re.compile(r"#\s*exits\s+(\d+)\s*$")
HEREDOC = re.compile(r"<<-?\s*(['\"]?)(\w+)\1")
FENCE = "```"


@dataclass(frozen=True)
class Command:
    doc: str
    block_line: int  # the line of the opening ```sh
    line: int  # the command's first line
    text: str
    expected: int

    def where(self) -> str:
        return f"{self.doc}:{self.line} (```sh block at line {self.block_line})"


def commands(docs=DOCS, root: Path = ROOT) -> list[Command]:
    """Every command of every ```sh block, in document order; `make` lines left out."""
    found = []
    for doc in docs:
        lines = (root / doc).read_text(encoding="utf-8").splitlines()
        block, pending, heredoc = None, None, None
        for number, line in enumerate(lines, 1):
            stripped = line.strip()
            if heredoc is None and stripped.startswith(FENCE):
                block = number if block is None and stripped == FENCE + "sh" else None
                continue
            if block is None:
                continue
            if pending is not None:
                start, text, head = pending
                text += "\n" + line
            elif not stripped or stripped.startswith("#") or stripped.startswith("make "):
                continue
            else:
                start, text, head = number, line, line
                heredoc = (match := HEREDOC.search(line)) and match.group(2)
            if (heredoc and (stripped != heredoc or text == line)) or (not heredoc and line.endswith("\\")):
                pending = (start, text, head)
                continue
            pending, heredoc = None, None
            match = EXPECTED.search(head if HEREDOC.search(head) else line)
            found.append(Command(doc, block, start, text, int(match.group(1)) if match else 0))
    return found


def also_run(step: Command) -> str | None:
    """The test (``path::name``) or doc line (``doc:line``) that runs ``step``'s computation, if listed."""
    return next((where for (doc, start), where in ALSO_RUN.items()
                 if step.doc == doc and step.text.startswith(start)), None)


def script(steps: list[Command], status: Path) -> str:
    """One bash script: each command runs in the shell itself (`{ ...; }`), its output to its own log and
    its exit code to ``status/N``; the first unexpected exit code stops the script."""
    parts = ["set -u"]
    for i, step in enumerate(steps):
        log = shlex.quote(str(status / f"{i}.log"))
        parts.append(f"{{\n{step.text}\n}} > {log} 2>&1 < /dev/null\n"
                     f"__rc=$?; echo $__rc > {shlex.quote(str(status / str(i)))}\n"
                     f"[ $__rc -eq {step.expected} ] || exit 0")
    return "\n".join(parts) + "\n"


def run_docs(bin_dir: Path, scratch: Path, steps: list[Command] | None = None) -> list[int]:
    """Run ``steps`` (default: every doc command) in ``scratch`` with ``bin_dir`` first on PATH; fail on the
    first command whose exit code differs from the doc's."""
    steps = commands() if steps is None else steps
    work, status = scratch / "work", scratch / "status"
    shutil.copytree(PROBLEMS, work / "problems", ignore=shutil.ignore_patterns("__pycache__"))
    status.mkdir()
    env = {**os.environ, "PATH": f"{bin_dir}{os.pathsep}{os.environ['PATH']}", "MPLBACKEND": "Agg"}
    if Path(bin_dir) != Path(sys.executable).parent:  # another installation (a wheel's): not this tree
        env.pop("PYTHONPATH", None)
    elif env.get("PYTHONPATH"):  # the tree under test, also from the scratch folder (PYTHONPATH=. too)
        paths = env["PYTHONPATH"].split(os.pathsep)
        env["PYTHONPATH"] = os.pathsep.join(str(Path(p).resolve()) for p in paths)
    subprocess.run(["bash", "-c", script(steps, status)], cwd=work, env=env, check=True)
    codes = []
    for i, step in enumerate(steps):
        if not (status / str(i)).exists():
            pytest.fail(f"{step.where()} never ran: the shell stopped before it.")
        code = int((status / str(i)).read_text())
        if code != step.expected:
            output = (status / f"{i}.log").read_text(errors="replace").splitlines()
            hint = " (end its line with `# exits N` if it is meant to fail)" if step.expected == 0 else ""
            pytest.fail(f"{step.where()} exited {code}, the doc expects {step.expected}{hint}:\n"
                        f"  {step.text}\n--- its output (last 15 lines):\n" + "\n".join(output[-15:]))
        codes.append(code)
    return codes


def printed(steps: list[Command], scratch: Path, doc: str, block_line: int) -> list[str]:
    """The lines (stdout and stderr) that the commands of ``doc``'s ```sh block at ``block_line`` printed in
    the run of :func:`run_docs` into ``scratch``."""
    return [line for i, step in enumerate(steps) if step.doc == doc and step.block_line == block_line
            for line in (scratch / "status" / f"{i}.log").read_text(errors="replace").splitlines()]
