"""Random mutations of problem files for property-based fuzzing (hypothesis), and a CLI probe.

A mutation picks one node of the parsed YAML tree and changes its value (numbers, NaN/inf, strings,
quantities with random units, quantities twisted with operators, percent signs, commas and quote
marks, wrong types), deletes or renames its key, adds an unknown key, or
changes the structure (a mapping becomes a list or a scalar). The property under test: the CLI
either succeeds (0), or reports bad input (2) or no solution (3) with a message, never a traceback.
"""

from __future__ import annotations

import copy
import io
from contextlib import redirect_stderr, redirect_stdout

from hypothesis import strategies as st

from pampipe.cli import main

UNITS = ["mm", "m", "in", "ft", "kPa", "psi", "MPa", "bar", "Pa", "N", "kN", "lbf", "kg", "g", "lb", "deg",
         "rad", "s", "ms", "", "furlong", "K", "m/s", "1/m", "%"]

NUMBERS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True, width=64),
    st.sampled_from([0.0, -1.0, 1e-30, 1e30, 1e300, -0.0, 0.5, 3.0, 1e6]),
    st.integers(min_value=-10**12, max_value=10**12),
)
QUANTITIES = st.builds(lambda x, u: f"{x!r} {u}".strip(), NUMBERS, st.sampled_from(UNITS))
# what users and attackers type around a quantity (issue 14): operators on the number, percent signs,
# decimal commas, inch and foot marks, trailing text, absolute pressures, huge exponents
MARKS = ["**", "*", "/", "^", "+", "-", "%", " %", ",", "'", "''", '"', "″", ";", " 76.2", "e", "#", "(", ")",
         "**400", "**9**9", " psia", " bara", " psig", "  ", "1/", "°"]
TWISTED = st.builds(lambda x, m, u, where: (f"{x}{m} {u}" if where else f"{x} {u}{m}").strip(),
                    st.sampled_from(["0", "5", "0,4", "2,5", "10", "1e400", "-1", "(-1)", "9", ".5", "1_0"]),
                    st.sampled_from(MARKS), st.sampled_from(UNITS), st.booleans())
QUANTITIES = st.one_of(QUANTITIES, TWISTED)
SCALARS = st.one_of(NUMBERS, QUANTITIES, st.text(max_size=12), st.none(), st.booleans())
VALUES = st.one_of(SCALARS, st.lists(SCALARS, max_size=4), st.dictionaries(st.text(max_size=6), SCALARS,
                                                                           max_size=3))

# how often the CLI answered each way, for the fuzz report
OUTCOMES: dict[int, int] = {}


def _nodes(tree, path=()):
    """Every (path, value) in a nested dict/list tree, the root included."""
    yield path, tree
    if isinstance(tree, dict):
        for key, value in tree.items():
            yield from _nodes(value, (*path, key))
    elif isinstance(tree, list):
        for i, value in enumerate(tree):
            yield from _nodes(value, (*path, i))


def _parent(tree, path):
    for part in path[:-1]:
        tree = tree[part]
    return tree


@st.composite
def mutated(draw, original: dict, max_mutations: int = 3):
    """A copy of ``original`` with 1..max_mutations random mutations."""
    tree = copy.deepcopy(original)
    for _ in range(draw(st.integers(1, max_mutations))):
        nodes = list(_nodes(tree))
        path, value = draw(st.sampled_from(nodes))
        kind = draw(st.sampled_from(["value", "value", "value", "delete", "rename", "extra", "structure"]))
        if not path:
            if kind == "structure":
                return draw(st.one_of(st.lists(SCALARS, max_size=3), SCALARS))
            kind = "extra"
        if kind == "extra":
            target = value if isinstance(value, dict) else _parent(tree, path) if path else tree
            if isinstance(target, dict):
                target[draw(st.text(min_size=1, max_size=8))] = draw(VALUES)
            continue
        parent, key = _parent(tree, path), path[-1]
        if kind == "value":
            parent[key] = draw(VALUES)
        elif kind == "delete":
            del parent[key]
        elif kind == "rename" and isinstance(parent, dict):
            new = draw(st.sampled_from([key[:-1], key + "s", key.upper(), key.replace("_", "-")]))
            parent[new or "x"] = parent.pop(key)
        elif kind == "structure":
            parent[key] = draw(st.sampled_from([[value], {"value": value}, str(value), 1]))
    return tree


def probe(args: list[str]) -> tuple[int, str]:
    """Run the CLI in-process; return (exit code, stderr). Any escaping exception fails the property."""
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        code = main(args)
    OUTCOMES[code] = OUTCOMES.get(code, 0) + 1
    message = err.getvalue()
    assert code in (0, 2, 3), (code, message)
    assert "Traceback" not in message + out.getvalue()
    if code in (2, 3):
        assert message.strip(), "an error exit must say why"
    return code, message
