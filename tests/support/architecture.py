"""The architecture of pampipe as data (docs/architecture.md), and the checks that read a package against it.

Parts: every folder of ``pampipe/`` and every module at its root, named as in :func:`import_graph.part_of`
(``__init__`` is the package face). The import direction, from the top:

    cli -> commands -> {api, views} -> science -> {pneumatics, model} -> errors
    io -> specs -> units
    runtime (plumbing) -> {errors, units};  results (the protocol) -> {errors, units, runtime, views}

Results sit above their views (python-control's shape): a module that defines a result class (decorated
with ``@notebook``) names the view that renders it with a plain import inside a loader, and no view imports a
module that defines a result. Those edges, result -> view, are the only ones from the science into views;
the circle between folders is counted without them (between files there is none at all).

Each rule names the parts it applies to and the parts they may not import, by any means
(:mod:`tests.support.import_graph`); a part may always import itself. Each check returns its findings as
lines that name the rule, the file and the line; an empty list is a pass.
"""

from __future__ import annotations

import ast
from collections.abc import Callable
from dataclasses import dataclass
from functools import cache

from tests.support.import_graph import Edge, Package, circles, describe, part_of

FACE = "__init__"
SCIENCE = frozenset({"identification", "planning", "locomotion", "bends", "slip", "design", "diagnosis",
                     "export", "simulation", "rehearsal", "nexttest"})
#: Every part of the package, by layer from the top; a new folder or root module must find its place here.
LAYERS = {
    "the command line": {"__main__", "cli"},
    "the commands (argparse and run)": {"commands"},
    "the face for users": {FACE, "api"},
    "the views of results": {"views"},
    "the science": set(SCIENCE),
    "below the science": {"pneumatics", "model"},
    "files and the objects they hold": {"io", "specs", "units"},
    "plumbing and the result protocol": {"runtime", "results", "errors", "_version"},
}
EVERY_PART = frozenset().union(*LAYERS.values())


@dataclass(frozen=True)
class Rule:
    key: str  # the test id
    name: str
    applies_to: frozenset[str]
    may_not_import: frozenset[str]
    allowed: Callable[[Package, Edge], bool] | None = None  # an edge the rule lets through after all


def rule(key: str, name: str, applies_to, may_not_import, allowed=None) -> Rule:
    return Rule(key, name, frozenset(applies_to), frozenset(may_not_import), allowed)


@cache
def result_modules(package: Package) -> frozenset[str]:
    """The modules that define a result class: a class decorated with ``notebook(...)``; read once per
    package (every edge into the views asks, and parsing the package per edge cost minutes)."""
    return frozenset(name for name, tree in package.trees.items() for node in ast.walk(tree)
                     if isinstance(node, ast.ClassDef)
                     and any(_calls(d, "notebook") for d in node.decorator_list))


def _calls(node: ast.AST, name: str) -> bool:
    return isinstance(node, ast.Call) and getattr(node.func, "id", getattr(node.func, "attr", None)) == name


def names_its_view(package: Package, edge: Edge) -> bool:
    """A result module (or the result protocol) importing a view: results above their views."""
    return part_of(edge.target) == "views" and (
        edge.source in result_modules(package) or part_of(edge.source) == "results")


#: The rules of the target layout (issue 34). The views may import neither commands, cli nor api: the first
#: three rows say so for every part.
RULES = (
    rule("commands", "only cli imports commands", EVERY_PART - {"cli"}, {"commands"}),
    rule("cli", "nothing imports the command line but __main__", EVERY_PART - {"__main__"},
         {"cli", "__main__"}),
    rule("api", "the api and the package face are for users, never imported from below them",
         EVERY_PART - {"__main__", "cli", "commands", FACE, "api"}, {"api", FACE}),
    rule("science", "the science never imports io, and of the views only a result names the view of it",
         SCIENCE, {"io", "views"}, names_its_view),
    rule("views", "no view imports a module that defines a result (results sit above their views)", {"views"},
         SCIENCE, lambda package, edge: edge.target not in result_modules(package)),
    rule("pneumatics", "pneumatics sit below the science", {"pneumatics"}, SCIENCE | {"io", "views"}),
    rule("model", "the model imports only the errors", {"model"}, EVERY_PART - {"errors"}),
    rule("io", "io reads files into specs and model objects, never into the science or views", {"io"},
         SCIENCE | {"views"}),
    rule("specs", "specs are SI objects: they import neither files, science, plumbing nor results", {"specs"},
         SCIENCE | {"io", "views", "pneumatics", "runtime", "results"}),
    rule("units", "units import only the errors", {"units"}, EVERY_PART - {"errors"}),
    rule("runtime", "runtime is plumbing: it imports only errors and units", {"runtime"},
         EVERY_PART - {"errors", "units"}),
    rule("results", "results, the root protocol, import nothing above them but the views they draw through",
         {"results"}, EVERY_PART - {"errors", "units", "runtime", "_version", "views"}),
    rule("errors", "errors and _version import nothing", {"errors", "_version"}, EVERY_PART),
)
#: The package root: the face, the entry points, the errors, the result protocol and the version.
ROOT_MODULES = frozenset({"__init__", "__main__", "api", "cli", "errors", "results", "_version"})
MAX_FILE_LINES = 500
MAX_FUNCTION_LINES = 80
#: Names a newcomer confuses when two modules (or a folder and a module) carry them (issue 34).
CONFUSABLE = ("nlp", "mission", "inventory", "simulation", "synthetic", "uncertainty", "cells", "slip")


def rule_violations(package: Package, rule: Rule) -> list[str]:
    """Every import that breaks ``rule``."""
    out = []
    for edge in package.edges:
        source, target = part_of(edge.source), part_of(edge.target)
        if source in rule.applies_to and target in rule.may_not_import and target != source \
                and not (rule.allowed and rule.allowed(package, edge)):
            out.append(f"{rule.name}: {edge}")
    return out


def file_circles(package: Package) -> list[str]:
    """Every circle of imports between files (a package's __init__.py is a file)."""
    return [f"{len(members)} files in a circle ({', '.join(members)}), e.g. {describe(circle)}"
            for members, circle in circles(package.graph())]


def folder_circles(package: Package) -> list[str]:
    """Every circle of imports between parts (folders and root modules), with one file and line per step,
    counted without the edges by which a result names its view (:func:`names_its_view`)."""
    graph = package.graph(part_of, skip=lambda edge: names_its_view(package, edge))
    return [f"{', '.join(members)} in a circle, e.g. {describe(circle, part_of)}"
            for members, circle in circles(graph)]


def layer_gaps(package: Package) -> list[str]:
    """Parts of the package that no layer holds, and parts that the layers name but the package lacks."""
    unplaced = sorted(package.parts - EVERY_PART)
    missing = sorted(EVERY_PART - package.parts - {FACE})
    return ([f"{part}: a part of the package in no layer of LAYERS" for part in unplaced]
            + [f"{part}: named in LAYERS, not in the package" for part in missing])


def root_violations(package: Package) -> list[str]:
    """Root modules beyond the face, the entry points, errors, results and the version."""
    root = {m.path.split("/")[-1][:-3] for m in package.modules.values() if m.path.count("/") == 1}
    return [f"{package.root}/{name}.py: a root module beyond {sorted(ROOT_MODULES)}"
            for name in sorted(root - ROOT_MODULES)]


def long_files(package: Package, limit: int = MAX_FILE_LINES) -> list[str]:
    return [f"{m.path}: {m.source.count(chr(10))} lines (at most {limit})" for m in package.modules.values()
            if m.source.count("\n") > limit]


def long_functions(package: Package, limit: int = MAX_FUNCTION_LINES) -> list[str]:
    """Functions longer than ``limit`` lines. The inner lines of a multi-line string template (the C and
    sketch text export writes) are data, not logic, and do not count; a docstring counts."""
    out = []
    for module in package.modules.values():
        for node in ast.walk(package.trees[module.name]):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                lines = node.end_lineno - node.lineno + 1 - len(_template_lines(node))
                if lines > limit:
                    out.append(f"{module.path}:{node.lineno} {node.name}: {lines} lines (at most {limit})")
    return out


def _template_lines(function: ast.FunctionDef | ast.AsyncFunctionDef) -> set[int]:
    """The lines strictly inside the function's multi-line string literals, its docstring aside."""
    docstring = ast.get_docstring(function, clean=False) is not None and function.body[0].value
    inner: set[int] = set()
    for node in ast.walk(function):
        literal = isinstance(node, ast.Constant) and isinstance(node.value, str)
        if (literal or isinstance(node, ast.JoinedStr)) and node is not docstring:
            inner |= set(range(node.lineno + 1, node.end_lineno))
    return inner


def twins(package: Package, names=CONFUSABLE) -> list[str]:
    """Names of the list that more than one module or folder carries (a leading underscore aside)."""
    carriers: dict[str, list[str]] = {}
    for module in package.modules.values():
        carriers.setdefault(module.name.split(".")[-1].lstrip("_"), []).append(module.path)
    return [f"{name}: {', '.join(sorted(carriers[name]))}" for name in names
            if len(carriers.get(name, ())) > 1]
