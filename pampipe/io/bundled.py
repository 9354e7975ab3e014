"""The bundled problems (the repository's ``problems/``, installed as ``pampipe/examples``) and the JSON
Schemas of their files (``yaml/``, installed as ``pampipe/schemas``).

A wheel carries them as package data (see ``setup.py``); a source checkout or an editable install reads
``problems/`` and ``yaml/`` beside the package.

A bundled YAML file names its schema on its first line, ``# yaml-language-server:
$schema=../../yaml/mission.schema.json``, relative to the repository. :func:`copy` writes the schemas the
copied files name into ``DIR/yaml/`` and rewrites each line to the copy's path from where the file lands
(``../yaml/mission.schema.json``), so an editor finds the schema in the copied folder, wherever it is.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

from pampipe.errors import InputError
from pampipe.io.files import atomic_write, check_overwrite

KINDS = ("missions", "pams", "experiments", "inventories")


def folder() -> Path:
    """The folder of the bundled problems (pams/, missions/, experiments/)."""
    return _shipped("examples", "problems", "pams", "the bundled problems")


def schemas() -> Path:
    """The folder of the JSON Schemas (mission, pam, experiment, inventory)."""
    return _shipped("schemas", "yaml", "mission.schema.json", "the JSON Schemas")


def _shipped(installed: str, checkout: str, marker: str, what: str) -> Path:
    """``pampipe/<installed>`` of a wheel, else ``<checkout>`` beside the package (a source checkout or an
    editable install): the first that holds ``marker``."""
    package = Path(__file__).resolve().parent.parent
    for candidate in (package / installed, package.parent / checkout):
        if (candidate / marker).exists():
            return candidate
    raise InputError(f"{what} are missing from this installation of pampipe; reinstall it with "
                     "`pip install pampipe`.")


#: The first line of a bundled YAML file that names its schema; group 1 is the path.
SCHEMA_LINE = re.compile(rb"\A# yaml-language-server: \$schema=(\S+)")
#: Where the schemas go inside the folder copied into.
SCHEMA_FOLDER = "yaml"


def catalogue() -> dict[str, list[str]]:
    """Every bundled problem by kind: {'missions': [...], 'pams': [...], 'experiments': [...]}."""
    root = folder()
    return {kind: sorted(p.stem for p in (root / kind).glob("*.yaml")) for kind in KINDS}


def find(name: str) -> Path:
    """The bundled file called ``name`` (with or without .yaml), searched in every kind."""
    stem = Path(name).name.removesuffix(".yaml")
    root = folder()
    hits = [root / kind / f"{stem}.yaml" for kind in KINDS if (root / kind / f"{stem}.yaml").is_file()]
    if not hits:
        known = ", ".join(n for names in catalogue().values() for n in names)
        raise InputError(f"no bundled problem called {name!r}; the bundled problems are: {known}.")
    return hits[0]


def default_pam() -> Path:
    """The paper's radial-test muscle with the demo moduli: the default of `pampipe synth`."""
    return folder() / "pams" / "paper-radial-pam.yaml"


def copy(files: list[Path], target: Path, *, overwrite: bool = False) -> tuple[list[Path], list[Path]]:
    """Copy bundled ``files`` into ``target``, keeping their layout (so relative references hold), with
    the schemas they name (module docstring): (every destination, those already holding the same bytes,
    left as they are).

    Files outside the bundled folder (a wntr network a mission names, like ``ky4``) are found by name
    wherever pampipe is installed, so they are not copied.
    """
    root, target = folder().resolve(), Path(target)
    unique = dict.fromkeys(p for p in (Path(f).resolve() for f in files) if p.is_relative_to(root))
    pairs = {}
    for source in unique:
        dest = target / source.relative_to(root)
        pairs[dest], schema = with_schema_line(source.read_bytes(), dest, target)
        if schema is not None:
            pairs.setdefault(target / SCHEMA_FOLDER / schema, (schemas() / schema).read_bytes())
    # a file already there with the same bytes is kept as it is: a second example that shares a PAM
    # needs no --force
    unchanged = [dest for dest, data in pairs.items() if same_bytes(data, dest)]
    to_write = {dest: data for dest, data in pairs.items() if dest not in unchanged}
    check_overwrite(list(to_write), force=overwrite)
    for dest, data in to_write.items():
        atomic_write(dest, lambda tmp, data=data: tmp.write_bytes(data), create_folder=True)
    return list(pairs), unchanged


def with_schema_line(data: bytes, dest: Path, target: Path) -> tuple[bytes, str | None]:
    """(``data`` with its schema line pointing from ``dest`` to ``target/yaml/``, the schema's file name),
    or (``data``, None) when it names no schema pampipe ships."""
    match = SCHEMA_LINE.match(data)
    if match is None:
        return data, None
    name = Path(match.group(1).decode("utf-8")).name
    if not (schemas() / name).is_file():
        return data, None
    path = os.path.relpath(target / SCHEMA_FOLDER / name, dest.parent).replace(os.sep, "/")
    return data[:match.start(1)] + path.encode("utf-8") + data[match.end(1):], name


def same_bytes(data: bytes, dest: Path) -> bool:
    """True if ``dest`` is a regular file holding exactly ``data``."""
    try:
        return dest.is_file() and not dest.is_symlink() and dest.read_bytes() == data
    except OSError:
        return False


def copy_example(name: str, target: Path, *,
                 overwrite: bool = False) -> tuple[str, list[Path], list[Path]]:
    """Copy the bundled problem ``name`` with every file it uses (a mission's PAMs, an experiment's CSV data)
    into ``target``: (its kind, such as ``missions``; its files there, the problem first; those of them that
    were there already with the same bytes)."""
    from pampipe.io.experiment_schema import load_experiment
    from pampipe.io.inventory_file import load_inventory
    from pampipe.io.mission_schema import load_mission

    source = find(name)
    kind = source.parent.name
    if kind == "missions":
        files = load_mission(source).input_files
    elif kind == "experiments":
        files = load_experiment(source).input_files
    elif kind == "inventories":
        files = load_inventory(source).input_files
    else:
        files = [source]
    return (kind, *copy(files, target, overwrite=overwrite))
