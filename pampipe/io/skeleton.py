"""The experiment skeleton `next-test -o DIR` writes for the chosen test (docs/commands.md §14.3).

    DIR/pam.yaml          the PAM file ranked (its moduli start the refit; its uncertainty is the prior)
    DIR/next-test.yaml    the experiment: that PAM, the test, ``fit.prior.pam: pam.yaml``
    DIR/data/NAME.csv     the header and one row per set point, the measured column left empty

Once the rows are measured (more rows per set point are welcome, as recorded), `pampipe identify
DIR/next-test.yaml -o refit.yaml` refits the muscle from the new test with the old fit as its prior
(docs/formats.md §3, ``prior.pam``). Columns per kind (docs/formats.md §3): radial ``pressure [kPa],
force [N]``; axial and isometric (an axial test, ``protocol: isometric``) ``pressure [kPa], length [mm],
force [N]``; slip ``time [s], pressure [kPa], axial_load [N], displacement [mm]`` (one ramp of the axial
load per trial).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pampipe.io import yamlwrite
from pampipe.io.files import atomic_write_text
from pampipe.io.pamfile import pam_document

#: Rows per axial set point: lengths from the free length to the rest length.
AXIAL_ROWS = 12


def test_name(test) -> str:
    """``radial-88.9mm-0N``, ``isometric-250mm``, ``axial``, ``slip-76.2mm``."""
    if test.kind == "radial":
        return f"radial-{test.pipe_diameter * 1e3:.4g}mm-{test.axial_load:.0f}N"
    if test.kind == "slip":
        return f"slip-{test.pipe_diameter * 1e3:.4g}mm"
    if test.kind == "isometric":
        return f"isometric-{test.length * 1e3:.4g}mm"
    return "axial"


def entry(test, data: str) -> dict:
    """The experiment file's entry of a menu ``test`` (docs/formats.md §3)."""
    out = {"name": test_name(test), "kind": "axial" if test.kind == "isometric" else test.kind, "data": data}
    if test.kind == "isometric":
        out["protocol"] = "isometric"
    if test.kind in ("radial", "slip"):
        out["pipe_diameter"] = f"{test.pipe_diameter * 1e3:.6g} mm"
    if test.kind == "radial":
        out["axial_load"] = f"{test.axial_load:.6g} N"
    return out


def rows(test, muscle) -> str:
    """The CSV text: header and one row per set point, the measured columns empty."""
    kpa = [f"{p / 1e3:.6g}" for p in test.pressures]
    if test.kind == "radial":
        return "pressure [kPa],force [N]\n" + "".join(f"{p},\n" for p in kpa)
    if test.kind == "isometric":
        held = f"{test.length * 1e3:.6g}"
        return "pressure [kPa],length [mm],force [N]\n" + "".join(f"{p},{held},\n" for p in kpa)
    if test.kind == "slip":
        return "time [s],pressure [kPa],axial_load [N],displacement [mm]\n" + "".join(
            f",{p},,\n" for p in kpa for _ in range(test.trials))
    text = "pressure [kPa],length [mm],force [N]\n"
    for pressure, p in zip(test.pressures, kpa, strict=True):
        free = float(np.ravel(muscle.free_length(pressure))[0])
        span = muscle.geometry.initial_length - free
        lengths = (free + span * (k + 0.5) / AXIAL_ROWS for k in range(AXIAL_ROWS))
        text += "".join(f"{p},{length * 1e3:.6g},\n" for length in lengths)
    return text


def write_skeleton(folder: Path, pam, test, muscle, *, comments=()) -> list[Path]:
    """Write the skeleton of ``test`` for ``pam`` into ``folder`` (module docstring); the paths written."""
    name = test_name(test)
    data = f"data/{name}.csv"
    experiment = {"pam": "pam.yaml", "tests": [entry(test, data)], "fit": {"prior": {"pam": "pam.yaml"}}}
    notes = [*comments, f"Fill the measured column of {data} (add rows as recorded), then:",
             f"  pampipe identify {Path(folder) / 'next-test.yaml'} -o refit.yaml"]
    texts = {"pam.yaml": yamlwrite.dump(pam_document(pam)),
             "next-test.yaml": yamlwrite.dump(experiment, comments=notes), data: rows(test, muscle)}
    paths = [Path(folder) / k for k in texts]
    for path, text in zip(paths, texts.values(), strict=True):
        atomic_write_text(path, text, create_folder=True)
    return paths
