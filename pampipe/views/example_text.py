"""The text of `pampipe example`: the bundled problems by kind, or the files copied and the command to try."""

from __future__ import annotations

from pathlib import Path

#: The command that takes each kind of bundled problem.
COMMANDS = {"missions": "plan", "experiments": "identify", "pams": "simulate", "inventories": "design"}


def listing_text(catalogue: dict[str, list[str]]) -> str:
    """Every bundled problem by kind (:func:`pampipe.io.bundled.catalogue`) and how to copy one."""
    text = "\n".join(f"{kind}: {', '.join(names)}" for kind, names in catalogue.items())
    return text + "\ncopy one with: pampipe example NAME DIR"


def copied_text(kind: str, files: list[Path], unchanged: list[Path] = ()) -> str:
    """The files copied (the problem first; those already there with the same bytes said so) and the
    command that runs it."""
    hint = f"pampipe {COMMANDS[kind]} {files[0]}" + (" --pipe-diameter '3 in'" if kind == "pams" else "")
    lines = [f"{'unchanged (already there)' if p in unchanged else 'wrote'} {p}" for p in files]
    return "\n".join(lines) + f"\ntry: {hint}"
