"""The bundled problems (the repository's ``problems/``, installed as ``pampipe/examples``).

A wheel carries them as package data in ``pampipe/examples/`` (see ``setup.py``); a source
checkout or an editable install reads ``problems/`` beside the package.
"""

from __future__ import annotations

import filecmp
import shutil
from pathlib import Path

from pampipe.errors import InputError
from pampipe.io.files import atomic_write, check_overwrite

KINDS = ("missions", "pams", "experiments", "inventories")


def folder() -> Path:
    """The folder of the bundled problems (pams/, missions/, experiments/)."""
    package = Path(__file__).resolve().parent.parent
    for candidate in (package / "examples", package.parent / "problems"):
        if (candidate / "pams").is_dir():
            return candidate
    raise InputError("the bundled problems are missing from this installation of pampipe; reinstall it "
                     "with `pip install pampipe`.")


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
    """Copy bundled ``files`` into ``target``, keeping their layout (so relative references hold): (every
    destination, those already holding the same bytes, left as they are).

    Files outside the bundled folder (a wntr network a mission names, like ``ky4``) are found by name
    wherever pampipe is installed, so they are not copied.
    """
    root = folder().resolve()
    unique = dict.fromkeys(p for p in (Path(f).resolve() for f in files) if p.is_relative_to(root))
    pairs = [(f, Path(target) / f.relative_to(root)) for f in unique]
    # a file already there with the same bytes is kept as it is: a second example that shares a PAM
    # needs no --force
    unchanged = [dest for source, dest in pairs if same_bytes(source, dest)]
    pairs_to_write = [(source, dest) for source, dest in pairs if dest not in unchanged]
    check_overwrite([dest for _, dest in pairs_to_write], force=overwrite)
    for source, dest in pairs_to_write:
        atomic_write(dest, lambda tmp, source=source: shutil.copyfile(source, tmp), create_folder=True)
    return [dest for _, dest in pairs], unchanged


def same_bytes(source: Path, dest: Path) -> bool:
    """True if ``dest`` is a regular file holding exactly the bytes of ``source``."""
    try:
        return dest.is_file() and not dest.is_symlink() and filecmp.cmp(source, dest, shallow=False)
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
