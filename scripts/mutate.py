"""Mutation testing of the modules that decide a plan's safety (``make mutate``).

Each mutant changes one thing in one module — an arithmetic or comparison operator, a numeric
constant, ``min``↔``max``, ``all``↔``any`` (numpy's ``minimum``↔``maximum``, ``fmin``↔``fmax`` too),
``and``↔``or`` — and runs that module's tests against it
(in a fresh interpreter, stopping at the first failure). A mutant is *killed* when a test fails or the
run times out, *survives* when every test passes. The mutants run in copies of a ``git archive`` snapshot
of HEAD, not of the working tree: commit what is to be tested; editing files while a run goes on changes
nothing it judges. Mutants judged equivalent (no input can tell them
from the original) are listed with the reason in ``scripts/mutants-equivalent.txt`` as
``module:line:column:description  # why`` and left out of the score.

    python scripts/mutate.py                      # every target, every mutant
    python scripts/mutate.py --sample 40 --seed 1 # 40 mutants drawn per module
    python scripts/mutate.py --module pampipe/slip/law.py --list
    python scripts/mutate.py --module pampipe/slip/law.py --match 'Gt->GtE'  # the mutants matching a text

Prints each mutant's verdict as it is judged with the module's running score (``--results FILE`` appends
the same lines to a file: a stopped run keeps what it found), then killed, survived and the score per
module, and each survivor (the line to write a test for).
"""

from __future__ import annotations

import argparse
import ast
import io
import json
import os
import random
import shutil
import subprocess
import sys
import tempfile
import tokenize
from collections.abc import Callable
from copy import deepcopy
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
EQUIVALENT = ROOT / "scripts" / "mutants-equivalent.txt"

#: module -> the tests that guard it (paths relative to the repository)
TARGETS: dict[str, tuple[str, ...]] = {
    "pampipe/model/forces.py": ("tests/model/test_forces.py", "tests/model/test_identities.py",
                                "tests/model/test_published.py", "tests/model/test_paths.py"),
    "pampipe/model/muscle.py": ("tests/model/test_muscle_model.py", "tests/model/test_muscle_roots.py",
                                "tests/model/test_identities.py", "tests/model/test_paths.py",
                                "tests/planning/test_planner.py", "tests/api/test_one_door.py"),
    "pampipe/planning/law.py": ("tests/planning/test_evaluator.py",),
    "pampipe/planning/evaluator.py": ("tests/planning/test_evaluator.py",
                                      "tests/planning/test_evaluator_general.py",
                                      "tests/planning/test_confidence_breakdown.py",
                                      "tests/planning/test_confidence.py",
                                      "tests/planning/test_evaluator_tether.py",
                                      "tests/planning/test_evaluator_bores.py"),
    "pampipe/planning/solve.py": ("tests/planning/test_solve.py", "tests/planning/test_uneven_plan.py",
                                  "tests/planning/test_sections.py", "tests/planning/test_limits.py"),
    "pampipe/export/law.py": ("tests/export/test_law_reasons.py", "tests/export/test_law_uneven.py",
                              "tests/export/test_export.py", "tests/export/test_law_domain.py"),
    "pampipe/export/cgen.py": ("tests/export/test_cgen.py", "tests/export/test_export.py"),
    "pampipe/slip/law.py": ("tests/slip/test_law.py", "tests/slip/test_slip.py::test_friction_law_check"),
    "pampipe/bends/geometry.py": ("tests/bends/test_geometry.py",),
    "pampipe/planning/tension.py": ("tests/planning/test_tension.py", "tests/planning/test_tether.py"),
    "pampipe/planning/reach.py": ("tests/planning/test_reach.py", "tests/planning/test_tether.py"),
    "pampipe/identification/geometry.py": ("tests/identification/test_geometry.py",),
    "pampipe/identification/multistart.py": ("tests/identification/test_multistart_starts.py",
                                             "tests/identification/test_multistart.py"),
}

SWAPS = {ast.Add: ast.Sub, ast.Sub: ast.Add, ast.Mult: ast.Div, ast.Div: ast.Mult, ast.Pow: ast.Mult,
         ast.Lt: ast.LtE, ast.LtE: ast.Lt, ast.Gt: ast.GtE, ast.GtE: ast.Gt, ast.Eq: ast.NotEq,
         ast.NotEq: ast.Eq, ast.And: ast.Or, ast.Or: ast.And}
NAMES = {"min": "max", "max": "min", "all": "any", "any": "all"}
#: the same swaps on numpy's (and pampipe.model.ops') functions, ``np.minimum`` ↔ ``np.maximum`` etc.
ATTRIBUTES = {**NAMES, "minimum": "maximum", "maximum": "minimum", "fmin": "fmax", "fmax": "fmin",
              "nanmin": "nanmax", "nanmax": "nanmin", "argmin": "argmax", "argmax": "argmin"}
#: the modules whose attributes ATTRIBUTES swaps (a ``.max`` of anything else may be a field)
LIBRARIES = {"np", "numpy", "ops", "math"}


@dataclass(frozen=True)
class Mutant:
    line: int
    column: int
    description: str
    end_line: int  # the last line of the mutated node
    text: str  # the mutated line's code, without its indentation and comment
    offset: int  # the column in ``text``
    build: Callable[[], str] = field(compare=False, repr=False)  # the whole mutated module

    @property
    def source(self) -> str:
        return self.build()

    def where(self, module: str) -> str:
        """``module:line:column``: where the mutant is today (moves when code above it moves)."""
        return f"{module}:{self.line}:{self.column}"

    def key(self, module: str) -> str:
        """``module: description @offset: code``, named by the mutated line's code, not its number: a key
        in :data:`EQUIVALENT` stays valid while that line is unchanged, whatever moves above it."""
        return f"{module}: {self.description} @{self.offset}: {self.text}"


def _docstring_nodes(tree: ast.AST) -> set[int]:
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant):
                out.add(id(first.value))
    return out


def _code_lines(source: str) -> list[str]:
    """Each line of ``source`` without its comment (by the tokenizer: a ``#`` in a string stays)."""
    lines = source.splitlines()
    for token in tokenize.generate_tokens(io.StringIO(source).readline):
        if token.type == tokenize.COMMENT:
            row, col = token.start
            lines[row - 1] = lines[row - 1][:col]
    return [line.rstrip() for line in lines]


def _points(tree: ast.AST) -> list[tuple[ast.AST, object]]:
    points = []
    skip = _docstring_nodes(tree)
    for node in ast.walk(tree):
        if isinstance(node, ast.BinOp | ast.AugAssign) and type(node.op) in SWAPS:
            points.append((node, "op"))
        elif isinstance(node, ast.BoolOp) and type(node.op) in SWAPS:
            points.append((node, "bool"))
        elif isinstance(node, ast.Compare):
            points += [(node, ("cmp", i)) for i, op in enumerate(node.ops) if type(op) in SWAPS]
        elif isinstance(node, ast.Name) and node.id in NAMES and isinstance(node.ctx, ast.Load):
            points.append((node, "name"))
        elif (isinstance(node, ast.Attribute) and node.attr in ATTRIBUTES and isinstance(node.value, ast.Name)
              and node.value.id in LIBRARIES):
            points.append((node, "attribute"))
        elif (isinstance(node, ast.Constant) and type(node.value) in (int, float) and id(node) not in skip
              and not isinstance(node.value, bool)):
            points.append((node, "const"))
    return points


def _mutate(target: ast.AST, kind) -> str:
    """Change ``target`` in place; the description of the change."""
    if kind in ("op", "bool"):
        old = type(target.op).__name__
        target.op = SWAPS[type(target.op)]()
        return f"{old}->{type(target.op).__name__}"
    if kind == "name":
        text = f"{target.id}->{NAMES[target.id]}"
        target.id = NAMES[target.id]
        return text
    if kind == "attribute":
        text = f"{target.value.id}.{target.attr}->{ATTRIBUTES[target.attr]}"
        target.attr = ATTRIBUTES[target.attr]
        return text
    if kind == "const":
        value = target.value
        target.value = value + 1 if isinstance(value, int) else (value * 1.01 if value else 1e-3)
        return f"{value!r}->{target.value!r}"
    i = kind[1]
    old = type(target.ops[i]).__name__
    target.ops[i] = SWAPS[type(target.ops[i])]()
    return f"{old}->{type(target.ops[i]).__name__}"


def _built(source: str, index: int, kind) -> Callable[[], str]:
    def build() -> str:
        copy = ast.parse(source)
        _mutate(_points(copy)[index][0], kind)
        return ast.unparse(copy)
    return build


def mutants(source: str) -> list[Mutant]:
    """Every single-point mutant of ``source`` (each built on demand from the original, changed at one node);
    mutants whose key would repeat (the same change at the same place of the same code line) are keyed
    ``[2]``, ``[3]``, … in the order of the module."""
    tree = ast.parse(source)
    code = _code_lines(source)
    out, seen = [], {}
    for index, (node, kind) in enumerate(_points(tree)):
        description = _mutate(deepcopy(node), kind)  # a copy: the original tree stays as parsed
        line = code[node.lineno - 1]
        text = line.strip()
        offset = node.col_offset - (len(line) - len(line.lstrip()))
        seen[(description, offset, text)] = count = seen.get((description, offset, text), 0) + 1
        if count > 1:
            text = f"{text} [{count}]"
        out.append(Mutant(node.lineno, node.col_offset, description, node.end_lineno, text, offset,
                          _built(source, index, kind)))
    return out


def equivalents(path: Path = EQUIVALENT) -> set[str]:
    """The keys of ``path`` (:data:`EQUIVALENT`): each line ``key  # why`` (a line starting with ``#`` is a
    comment)."""
    if not path.exists():
        return set()
    lines = (line.strip() for line in path.read_text(encoding="utf-8").splitlines())
    return {line.partition("  # ")[0].strip() for line in lines if line and not line.startswith("#")}


def stale(module: str, found: list[Mutant], keys: set[str]) -> set[str]:
    """The keys of ``module`` in ``keys`` that name none of its mutants ``found`` (its code line changed)."""
    return {k for k in keys if k.startswith(f"{module}:")} - {m.key(module) for m in found}


#: what a mutant's copy of the repository leaves out
SKIP = shutil.ignore_patterns("__pycache__", ".hypothesis", ".pytest_cache")


def snapshot(root: Path, work: str) -> Path:
    """HEAD of the git repository at ``root``, extracted into ``work`` (``git archive``): what the mutants
    run in, so that edits made to the working tree during a run change nothing the run judges."""
    head = Path(work) / "head"
    head.mkdir()
    archive = subprocess.run(["git", "-C", str(root), "archive", "--format=tar", "HEAD"], capture_output=True,
                             check=True)
    subprocess.run(["tar", "-x", "-C", str(head)], input=archive.stdout, check=True)  # links stay links
    return head


def _copy(source: Path, work: str) -> Path:
    """A copy of the snapshot ``source`` in ``work`` (tests, problems and package together: pytest puts the
    folder above ``tests/`` first on sys.path, so a mutated package on PYTHONPATH alone would not be the one
    imported)."""
    copy = Path(work) / "repo"
    shutil.copytree(source, copy, symlinks=True, ignore=SKIP)  # links as links: tests/bad_inputs has some
    return copy


def _env(copy: Path) -> dict:
    return {**os.environ, "PYTHONPATH": str(copy), "PYTHONDONTWRITEBYTECODE": "1"}


def check_isolation(source: Path) -> None:
    """Fail loudly unless a test run in a copy imports the copy's pampipe (else no mutant is ever seen)."""
    with tempfile.TemporaryDirectory() as work:
        copy = _copy(source, work)
        probe = "import pampipe, sys; sys.stdout.write(pampipe.__file__)"
        done = subprocess.run([sys.executable, "-c", probe], cwd=copy, env=_env(copy), capture_output=True,
                              text=True, check=True)
        if not Path(done.stdout).resolve().is_relative_to(copy.resolve()):
            raise SystemExit(f"mutate: the copy imports {done.stdout}, not its own package: no mutant would "
                             "be tested")


def covering(source: Path, module: str, tests: tuple[str, ...], timeout: float) -> dict[str, set[int]]:
    """{test id: the lines of ``module`` it runs} over ``tests`` on the unmutated snapshot ``source``, and
    under "" the lines run outside any test (scripts/mutate_trace.py; in-process only)."""
    with tempfile.TemporaryDirectory() as work:
        copy = _copy(source, work)
        out = Path(work) / "lines.json"
        env = {**_env(copy), "PYTHONPATH": f"{copy}{os.pathsep}{copy / 'scripts'}",
               "MUTATE_TRACE": str(copy / module), "MUTATE_TRACE_OUT": str(out)}
        subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-p", "mutate_trace",
                        "-m", "not slow", *tests], cwd=copy, env=env, capture_output=True, timeout=timeout)
        return {k: set(v) for k, v in json.loads(out.read_text(encoding="utf-8")).items()}


def selected(mutant: Mutant, lines: dict[str, set[int]], tests: tuple[str, ...]) -> tuple[str, ...]:
    """The tests that run the mutated lines (in their order); all of ``tests`` where a line runs outside
    any test (module level: every test depends on it) or in none seen (it may run in a subprocess)."""
    span = set(range(mutant.line, mutant.end_line + 1))
    if span & lines.get("", set()):
        return tests
    ids = tuple(k for k, v in lines.items() if k and span & v)
    return ids or tests


def killed(source: Path, module: str, mutant: Mutant, tests: tuple[str, ...], timeout: float) -> bool:
    """Run ``tests`` (files or test ids) in a copy of the snapshot ``source``, its ``module`` the mutant."""
    with tempfile.TemporaryDirectory() as work:
        copy = _copy(source, work)
        (copy / module).write_text(mutant.source, encoding="utf-8")
        try:
            done = subprocess.run([sys.executable, "-m", "pytest", "-x", "-q", "-p", "no:cacheprovider",
                                   "-m", "not slow", *tests], cwd=copy, env=_env(copy), capture_output=True,
                                  timeout=timeout)
        except subprocess.TimeoutExpired:
            return True
        return done.returncode != 0


def _runner(source: Path, module: str, tests: tuple[str, ...], lines: dict[str, set[int]] | None,
            timeout: float) -> Callable[[Mutant], bool]:
    """Whether a mutant of ``module`` is killed by ``tests`` (those that run its lines, given ``lines``)."""
    def run(mutant: Mutant) -> bool:
        chosen = tests if lines is None else selected(mutant, lines, tests)
        return killed(source, module, mutant, chosen, timeout)
    return run


def judge(module: str, found: list[Mutant], run: Callable[[Mutant], bool],
          report: Callable[[str], None]) -> list[Mutant]:
    """Judge each mutant of ``found`` (``run(mutant)``: True when killed), reporting each verdict as it is
    judged with the module's running score; the survivors."""
    survivors = []
    for i, m in enumerate(found, 1):
        dead = run(m)
        if not dead:
            survivors.append(m)
        kill = i - len(survivors)
        report(f"{module}: {i}/{len(found)} {'killed  ' if dead else 'SURVIVED'} {m.where(module)}  "
               f"{m.key(module)}  [so far {kill}/{i} killed: {kill / i:.0%}]")
    return survivors


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--module", action="append", help="only this target module (repeatable)")
    parser.add_argument("--sample", type=int, help="at most this many mutants per module, drawn with --seed")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--timeout", type=float, default=600, help="seconds per mutant run (a hang: killed)")
    parser.add_argument("--select", action="store_true",
                        help="run each mutant against the tests that run its line only (one traced run "
                             "of the module's tests first; a line run only in a subprocess is not seen: "
                             "its mutant runs every test)")
    parser.add_argument("--match", help="only the mutants whose place or key contains this text")
    parser.add_argument("--list", action="store_true",
                        help="list the mutants of the working tree's modules, run nothing")
    parser.add_argument("--results", type=Path, help="append each verdict to this file as it is judged")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as work, \
            (open(args.results, "a", encoding="utf-8") if args.results else io.StringIO()) as results:
        source = ROOT if args.list else snapshot(ROOT, work)
        if not args.list:
            check_isolation(source)
            dirty = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain", "--untracked-files=no"],
                                   capture_output=True, text=True, check=True).stdout
            if dirty:
                print("mutate: the working tree has uncommitted changes; testing HEAD", file=sys.stderr)

        def report(line: str) -> None:
            print(line, flush=True)
            results.write(line + "\n")
            results.flush()

        skip = equivalents(source / EQUIVALENT.relative_to(ROOT))
        total_kill = total_live = 0
        for module, tests in TARGETS.items():
            if args.module and module not in args.module:
                continue
            every = mutants((source / module).read_text(encoding="utf-8"))
            for key in sorted(stale(module, every, skip)):
                print(f"mutate: {EQUIVALENT.name} names no mutant of {module}: {key}", file=sys.stderr)
            found = [m for m in every if m.key(module) not in skip
                     and (args.match is None or args.match in f"{m.where(module)} {m.key(module)}")]
            if args.sample and len(found) > args.sample:
                found = sorted(random.Random(f"{args.seed}:{module}").sample(found, args.sample),
                               key=lambda m: (m.line, m.column))
            if args.list:
                for m in found:
                    print(f"{m.where(module)}  {m.key(module)}")
                continue
            lines = covering(source, module, tests, args.timeout) if args.select and found else {}
            survivors = judge(module, found, _runner(source, module, tests, lines if args.select else None,
                                                     args.timeout), report)
            kill = len(found) - len(survivors)
            total_kill, total_live = total_kill + kill, total_live + len(survivors)
            score = kill / len(found) if found else 1.0
            report(f"{module}: {kill} killed, {len(survivors)} survived of {len(found)}: score {score:.0%}")
            for m in survivors:
                report(f"  survived {m.where(module)}  {m.key(module)}")
        if not args.list and total_kill + total_live:
            score = total_kill / (total_kill + total_live)
            report(f"all: {total_kill} killed, {total_live} survived: score {score:.0%}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
