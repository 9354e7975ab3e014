"""The text report of `pampipe export`: the anchoring law's size and domain, and the gait table of each
section (docs/commands.md §9)."""

from __future__ import annotations

from pathlib import Path

from pampipe.views.tables import table


def result_text(export) -> str:
    """The law and the gait table of an export (``str(export)``; the command adds where it wrote them)."""
    law = export.law
    rows = [(s.name, s.diameter * 1e3, s.reason.name.lower(), len(s.steps), s.cycle_time)
            for s in export.sections]
    lines = [f"pampipe_required_pressure: {law.function.n_instructions()} operations; anchoring needs "
             f"{law.narrowest * 1e3:.4g} mm < D < {law.widest * 1e3:.4g} mm; "
             f"supply {law.supply_pressure / 1e3:.4g} kPa",
             table(["section", "D [mm]", "reason", "gait steps", "cycle [s]"], rows)]
    return "\n".join(lines)


def written_text(export, folder: Path) -> str:
    """What `export` prints: the files written into ``folder``, the law and the gait table, and how to open
    the sketch when the folder's name is not the sketch's."""
    lines = [f"wrote {', '.join(str(folder / n) for n in sorted(export.files))}", result_text(export)]
    if export.sketch != f"{folder.resolve().name}.ino":
        lines.append(f"to open the sketch in the Arduino IDE, put the three files in a folder named "
                     f"{export.sketch.removesuffix('.ino')}")
    return "\n".join(lines)
