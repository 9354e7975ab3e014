"""The text report of `pampipe simulate`: per pipe and load the anchoring numbers and the table against
pressure; for an extensile muscle its free length against pressure (docs/commands.md §2)."""

from __future__ import annotations

import numpy as np

from pampipe.views.tables import table


def result_text(result) -> str:
    """The report of `simulate` (``str(result)``): one head line and one table per (pipe, load) case."""
    parts = []
    for c in result.cases:
        head = (f"{result.pam} in a {c.pipe_diameter * 1e3:.2f} mm pipe, axial load {c.axial_load:.2f} N: "
                f"anchored length {c.anchored_length * 1e3:.2f} mm, amplification factor "
                f"{c.amplification_factor:.4f}, anchoring pressure {c.anchoring_pressure / 1e3:.2f} kPa")
        rows = [(p / 1e3, bool(a), f / 1e0, fl, pc / 1e3, np.pi * f)
                for p, a, f, fl, pc in zip(c.pressures, c.anchored, c.radial_force, c.force_per_length,
                                           c.contact_pressure, strict=True)]
        parts.append(head + "\n" + table(
            ["P [kPa]", "anchored", "F_r [N]", "f_r [N/m]", "p_c [kPa]", "N_tot [N]"], rows))
    return "\n\n".join(parts)


def extension_text(result) -> str:
    """An extensile muscle's free length, extension and diameter against pressure (no pipe)."""
    head = (f"{result.pam} (extensile) at zero axial load: L0 = {result.initial_length * 1e3:.2f} mm, it "
            f"lengthens toward B/sqrt(3) = {result.limit * 1e3:.2f} mm")
    rows = [(p / 1e3, length * 1e3, 100 * (length / result.initial_length - 1), d * 1e3)
            for p, length, d in zip(result.pressures, result.free_length, result.diameter, strict=True)]
    return head + "\n" + table(["P [kPa]", "L [mm]", "extension [%]", "D [mm]"], rows)
