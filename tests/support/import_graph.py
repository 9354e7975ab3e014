"""Every import of a package, read with ``ast``: the graph the architecture tests check (tests/architecture/).

A module is a file; a package's ``__init__.py`` is the module of its folder (``pampipe.planning``). An edge
goes from the module that imports to the module imported, with its line and the means:

* ``import``: ``import pampipe.x``, ``from pampipe.x import y``, ``from .x import y``, wherever the statement
  stands: at module level, inside a function or a class, under ``if TYPE_CHECKING:``, in a ``try:``;
* ``import_module``: ``importlib.import_module("pampipe.x")`` (or relative, with its package) and
  ``__import__("pampipe.x")``;
* ``string target``: a string that names a module of the package for someone to import later, such as
  ``"pampipe.x.y:name"`` in a decorator or ``"pampipe.x.y"``; also the literal head of a string built at run
  time (``f"pampipe.x.{name}"``, ``"pampipe.x." + name``, ``"pampipe.x.{}".format(name)``).

``from pampipe.x import y`` reaches the module ``pampipe.x.y`` when there is one, else the ``__init__`` of
``pampipe.x`` (so ``from pampipe import __version__`` reaches the package face). A string names a module only
when its first part after the package is a folder or module of the package (``"pampipe.identify(...)"`` in an
error message names nothing).
"""

from __future__ import annotations

import ast
import re
from collections import deque
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

#: A whole string that names an import target: ``pampipe.x.y`` or ``pampipe.x.y:name``.
WHOLE = re.compile(r"([A-Za-z_]\w*(?:\.[A-Za-z_]\w*)+)(?::[A-Za-z_][\w.]*)?")
#: The literal head of a string built at run time: ``pampipe.x.`` or ``pampipe.x:`` before the variable part.
HEAD = re.compile(r"([A-Za-z_]\w*(?:\.[A-Za-z_]\w*)+)[.:]")
#: Where a template string's variable part starts (str.format, %).
PLACEHOLDER = re.compile(r"\{|%[sdr(]")
IMPORTERS = ("import_module", "__import__")


@dataclass(frozen=True)
class Module:
    name: str  # dotted: "pampipe.planning.law"; a package's __init__.py is "pampipe.planning"
    path: str  # as shown in messages: "pampipe/planning/law.py"
    source: str
    is_package: bool


@dataclass(frozen=True)
class Edge:
    source: str
    target: str
    path: str
    line: int
    how: str  # "import", "import_module" or "string target"

    def __str__(self) -> str:
        return f"{self.path}:{self.line} {self.source} -> {self.target} ({self.how})"


class Package:
    """The modules of one package and the edges between them."""

    def __init__(self, root: str, modules: list[Module]):
        self.root = root
        self.modules = {m.name: m for m in modules}
        self.parts = {part_of(name) for name in self.modules} - {"__init__"}
        self.edges = [edge for module in self.modules.values() for edge in self._edges_of(module)]

    @cached_property
    def trees(self) -> dict[str, ast.Module]:
        """Each module's syntax tree, parsed once for every check that reads it."""
        return {name: ast.parse(m.source, m.path) for name, m in self.modules.items()}

    @classmethod
    def from_folder(cls, folder: Path) -> Package:
        """Every ``*.py`` under ``folder`` (the package's own folder, e.g. ``pampipe/``)."""
        base = folder.parent
        return cls.from_sources({p.relative_to(base).as_posix(): p.read_text(encoding="utf-8")
                                 for p in sorted(folder.rglob("*.py"))})

    @classmethod
    def from_sources(cls, sources: dict[str, str]) -> Package:
        """A package from ``{"pampipe/model/x.py": source}``; a folder without an ``__init__.py`` gets an
        empty one, as a real package has."""
        sources = dict(sources)
        for path in list(sources):
            folders = Path(path).parents
            for folder in list(folders)[:-1]:
                sources.setdefault((folder / "__init__.py").as_posix(), "")
        modules = []
        for path, source in sources.items():
            parts = Path(path).with_suffix("").parts
            is_package = parts[-1] == "__init__"
            modules.append(Module(".".join(parts[:-1] if is_package else parts), path, source, is_package))
        (root,) = {m.name.split(".")[0] for m in modules}
        return cls(root, modules)

    # ------------------------------------------------------------------ reading one module's imports

    def resolve(self, dotted: str) -> str | None:
        """The module of the package that importing ``dotted`` runs last: its longest prefix that is a
        module; None outside the package."""
        if dotted != self.root and not dotted.startswith(self.root + "."):
            return None
        while dotted not in self.modules and "." in dotted:
            dotted = dotted.rsplit(".", 1)[0]
        return dotted if dotted in self.modules else None

    def _named(self, text: str, partial: bool) -> str | None:
        """The module a string names as an import target; ``partial``: the string is only the head of one
        built at run time. Its first part after the package must be a part of the package."""
        cut = PLACEHOLDER.search(text)
        if cut:
            text, partial = text[:cut.start()], True
        match = WHOLE.fullmatch(text) or (HEAD.fullmatch(text) if partial else None)
        parts = match.group(1).split(".") if match else []
        if len(parts) < 2 or parts[0] != self.root or parts[1] not in self.parts:
            return None
        return self.resolve(match.group(1))

    def _edges_of(self, module: Module) -> list[Edge]:
        found: list[tuple[str | None, int, str]] = []
        read: set[int] = set()  # nodes already read as (part of) a string or an import_module argument
        package = module.name.split(".") if module.is_package else module.name.split(".")[:-1]
        for node in ast.walk(self.trees[module.name]):
            if id(node) in read:
                continue
            if isinstance(node, ast.Import):
                found += [(self.resolve(a.name), node.lineno, "import") for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = package[:len(package) - node.level + 1] if node.level else []
                full = ".".join([*base, node.module] if node.module else base)
                for alias in node.names:
                    whole = f"{full}.{alias.name}"
                    found.append((whole if whole in self.modules else self.resolve(full), node.lineno,
                                  "import"))
            elif isinstance(node, ast.Call) and _callee(node) in IMPORTERS and node.args:
                known, package_argument = _known_text(node.args[0]), _package_argument(node)
                read |= known.nodes | {id(package_argument)}
                name = PLACEHOLDER.split(known.text)[0].split(":")[0]
                if name.startswith(".") and package_argument:
                    name = _relative(name, package_argument.value)
                found.append((self.resolve(name.rstrip(".:")), node.lineno, "import_module"))
            elif isinstance(node, (ast.Constant, ast.JoinedStr, ast.BinOp, ast.Call)):
                known = _known_text(node)
                read |= known.nodes
                if known.nodes:
                    found.append((self._named(known.text, not known.complete), node.lineno, "string target"))
        return [Edge(module.name, target, module.path, line, how) for target, line, how in found
                if target is not None and target != module.name]

    # ------------------------------------------------------------------ the graph

    def graph(self, nodes=None, skip=None) -> dict[str, dict[str, Edge]]:
        """node -> {node it imports: the first edge that shows it}; ``nodes`` maps a module to its node
        (default: the module itself; :func:`part_of` gives the folder graph); ``skip(edge)``: leave it out."""
        nodes = nodes or (lambda name: name)
        out: dict[str, dict[str, Edge]] = {nodes(name): {} for name in self.modules}
        for edge in sorted(self.edges, key=lambda e: (e.path, e.line)):
            if skip and skip(edge):
                continue
            a, b = nodes(edge.source), nodes(edge.target)
            if a != b:
                out[a].setdefault(b, edge)
        return out


def _callee(call: ast.Call) -> str | None:
    return call.func.id if isinstance(call.func, ast.Name) else getattr(call.func, "attr", None)


@dataclass(frozen=True)
class Known:
    """What a string expression is known to start with before it runs."""

    text: str
    complete: bool  # the text is the whole string
    nodes: frozenset[int] = frozenset()  # ids of the nodes read to know it


NOTHING = Known("", False)


def _known_text(node: ast.AST) -> Known:
    """The text a string expression starts with: a constant, the constant pieces an f-string starts with, the
    known left of ``+`` (and its right, when the left is whole), the template of ``%`` and ``.format``."""
    if isinstance(node, ast.Constant):
        return Known(node.value, True, frozenset({id(node)})) if isinstance(node.value, str) else NOTHING
    if isinstance(node, ast.JoinedStr):
        pieces, nodes = [], {id(node)}
        for value in node.values:
            if not isinstance(value, ast.Constant):
                return Known("".join(pieces), False, frozenset(nodes))
            pieces.append(value.value)
            nodes.add(id(value))
        return Known("".join(pieces), True, frozenset(nodes))
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Add):
        left = _known_text(node.left)
        if not left.complete:
            return Known(left.text, False, left.nodes | {id(node)}) if left.nodes else left
        right = _known_text(node.right)
        return Known(left.text + right.text, right.complete, left.nodes | right.nodes | {id(node)})
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Mod):
        left = _known_text(node.left)
        return Known(left.text, False, left.nodes | {id(node)}) if left.nodes else left
    if isinstance(node, ast.Call) and _callee(node) == "format" and isinstance(node.func, ast.Attribute):
        template = _known_text(node.func.value)
        return Known(template.text, False, template.nodes) if template.nodes else template
    return NOTHING


def _package_argument(call: ast.Call) -> ast.Constant | None:
    """The literal ``package`` of ``import_module(name, package)``."""
    given = [k.value for k in call.keywords if k.arg == "package"] + call.args[1:2]
    return given[0] if given and isinstance(given[0], ast.Constant) else None


def _relative(name: str, package: str) -> str:
    level = len(name) - len(name.lstrip("."))
    base = package.split(".")
    return ".".join([*base[:len(base) - level + 1], name[level:]]).rstrip(".")


def part_of(module: str) -> str:
    """The folder or root module a module belongs to: ``planning`` for ``pampipe.planning.law``, ``api`` for
    ``pampipe.api``, ``__init__`` for the package face ``pampipe``."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


# ---------------------------------------------------------------------- circles


def circles(graph: dict[str, dict[str, Edge]]) -> list[tuple[list[str], list[Edge]]]:
    """Each strongly connected component of more than one node (Tarjan), with one circle through it: the
    edges of the shortest way from its first node back to itself."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    components = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        for w in graph.get(v, {}):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                components.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return [(c, _circle_through(graph, set(c), c[0])) for c in sorted(components)]


def _circle_through(graph: dict[str, dict[str, Edge]], component: set[str], start: str) -> list[Edge]:
    """The shortest way from ``start`` back to itself inside ``component`` (breadth first)."""
    came: dict[str, tuple[str, Edge]] = {}
    queue = deque([start])
    while queue:
        v = queue.popleft()
        for w, edge in sorted(graph[v].items()):
            if w not in component or w in came:
                continue
            came[w] = (v, edge)
            if w == start:
                path = []
                while w != start or not path:
                    v, edge = came[w]
                    path.append(edge)
                    w = v
                return path[::-1]
            queue.append(w)
    raise AssertionError(f"{start} is in a component without a way back")  # Tarjan's components have one


def describe(circle: list[Edge], nodes=None) -> str:
    """``a -> b -> a``, with the file and line of every step."""
    nodes = nodes or (lambda name: name)
    steps = [f"{nodes(e.source)} ({e.path}:{e.line}, {e.how})" for e in circle]
    return " -> ".join([*steps, nodes(circle[0].source)])
