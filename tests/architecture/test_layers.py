"""The import direction of the layers holds (docs/physics.md is physics; this is architecture).

    cli -> commands -> api -> {identification, planning, locomotion, diagnosis, synth, simulation, ...}
        -> model -> errors
    io (file formats) -> {experiment, mission, model, units}; plots read results only.

Rules, checked on every module's imports (``import`` and ``from ... import``, anywhere in the file):
* the model imports nothing of pampipe but the model, ``errors`` and ``units``-free helpers;
* the science packages never import the I/O layer, the API, the commands, the CLI or the plots;
* the I/O layer never imports a science package;
* plots never import the model (they draw what the results carry);
* only ``cli`` imports ``commands``, and nothing imports ``cli`` but ``__main__``.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent / "pampipe"
SCIENCE = ("identification", "planning", "locomotion", "diagnosis", "synth", "simulation", "design", "export",
           "slip")
RULES = [
    # (modules the rule applies to, forbidden import prefixes)
    (("model",), ("io", "api", "commands", "cli", "plots", "report", *SCIENCE, "experiment", "mission",
                  "schema", "units")),
    (SCIENCE, ("io", "api", "commands", "cli", "plots")),
    (("io",), (*SCIENCE, "api", "commands", "cli", "plots")),
    (("plots",), ("model", "io", "commands", "cli")),
    (("experiment", "mission"), ("io", "api", "commands", "cli", "plots", *SCIENCE)),
]


def module_name(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(p for p in parts if p != "__init__")


def pampipe_imports(source: str, module: str) -> set[str]:
    """Every pampipe module a source imports, relative to the package (``model.muscle``, ``io``...)."""
    found = set()
    package = module.split(".")
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            found |= {a.name.removeprefix("pampipe.") for a in node.names if a.name.startswith("pampipe.")}
        elif isinstance(node, ast.ImportFrom):
            if node.level:  # relative import: resolve against the importing module's package
                base = package[:len(package) - node.level] if module else []
                name = ".".join([*base, node.module] if node.module else base)
            elif node.module and node.module.startswith("pampipe"):
                name = node.module.removeprefix("pampipe").removeprefix(".")
            else:
                continue
            if name:
                found.add(name)
            else:  # from pampipe import x
                found |= {a.name for a in node.names}
    return found


def violations(module: str, imports: set[str]) -> list[str]:
    out = []
    top = module.split(".")[0]
    for scope, forbidden in RULES:
        if top in scope:
            for name in sorted(imports):
                if name.split(".")[0] in forbidden and name.split(".")[0] != top:
                    out.append(f"pampipe.{module} imports pampipe.{name}")
    if top != "cli" and any(n.split(".")[0] == "commands" for n in imports) and top != "commands":
        out.append(f"pampipe.{module} imports a command module (only cli may)")
    if top not in ("__main__",) and "cli" in {n.split(".")[0] for n in imports} and top != "cli":
        out.append(f"pampipe.{module} imports pampipe.cli")
    return out


def test_the_checker_catches_violations():
    """A fabricated model module that reads a file and a plot that recomputes physics are flagged."""
    bad_model = pampipe_imports("from pampipe.io.config import load_pam\nimport numpy", "model.bad")
    assert violations("model.bad", bad_model) == ["pampipe.model.bad imports pampipe.io.config"]
    bad_plot = pampipe_imports("from ..model import forces", "plots.bad")
    assert violations("plots.bad", bad_plot) == ["pampipe.views.plots.bad imports pampipe.model"]
    science = pampipe_imports("def f():\n    from pampipe.io import pamfile\n", "identification.bad")
    assert violations("identification.bad", science) == ["pampipe.identification.bad imports pampipe.io"]
    fine = pampipe_imports("from pampipe.model.muscle import Muscle", "planning.fine")
    assert violations("planning.fine", fine) == []


@pytest.mark.parametrize("path", sorted(ROOT.rglob("*.py")), ids=lambda p: module_name(p) or "pampipe")
def test_imports_follow_the_layer_direction(path):
    module = module_name(path)
    assert violations(module, pampipe_imports(path.read_text(encoding="utf-8"), module)) == []
