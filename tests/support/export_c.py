"""Helpers of the export tests: the exported files written to a folder, and a C driver for them, built with
the host's compiler.

The driver reads "D incline friction payload" lines on stdin and prints "code P1 P2 P3" (``law``), or
prints the gait table (``table``): one "S" line per section (reason, cycle time, stride, the name's
bytes in hex) followed by seven "T" lines (valves, anchors, duration, pressures).
"""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import numpy as np

from pampipe.export import Export, Provenance, generate

#: The brief's warnings, plus (float) every implicit float→double promotion and double→float narrowing.
FLAGS = ["-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror"]
FLOAT_FLAGS = ["-DPAMPIPE_REAL_FLOAT", "-Wdouble-promotion", "-Wfloat-conversion"]

DRIVER = r"""
#include <stdio.h>
#include <string.h>
#include "pampipe_plan.h"

static void print_hex(const char *text)
{
    size_t i, n = strlen(text);
    if (n == 0) { printf("-"); }
    for (i = 0; i < n; ++i) { printf("%02x", (unsigned)(unsigned char)text[i]); }
}

int main(int argc, char **argv)
{
    int i, k, s;
    if (argc > 1 && strcmp(argv[1], "table") == 0) {
        for (s = 0; s < PAMPIPE_SECTIONS; ++s) {
            const pampipe_gait_section *g = &pampipe_gait[s];
            printf("S %d %.17g %.17g %.17g %.17g %.17g %.17g ", g->reason, (double)g->cycle_time_s,
                   (double)g->stride_m, (double)g->inner_diameter_m, (double)g->incline_rad,
                   (double)g->friction, (double)g->length_m);
            print_hex(g->name);
            printf("\n");
            for (k = 0; k < PAMPIPE_GAIT_STEPS; ++k) {
                const pampipe_gait_step *t = &g->step[k];
                printf("T %s", pampipe_step_name[k]);
                for (i = 0; i < PAMPIPE_SEGMENTS; ++i) { printf(" %d", t->valve[i]); }
                for (i = 0; i < PAMPIPE_SEGMENTS; ++i) { printf(" %d", t->anchored[i]); }
                printf(" %.17g", (double)t->duration_s);
                for (i = 0; i < PAMPIPE_SEGMENTS; ++i) { printf(" %.17g", (double)t->pressure_Pa[i]); }
                printf("\n");
            }
        }
        for (i = 0; i < PAMPIPE_SEGMENTS; ++i) {
            printf("N ");
            print_hex(pampipe_segment_name[i]);
            printf("\n");
        }
        return 0;
    }
    {
        double d, phi, mu, m;
        while (scanf("%lf %lf %lf %lf", &d, &phi, &mu, &m) == 4) {
            pampipe_real p[PAMPIPE_SEGMENTS];
            int code = pampipe_required_pressure((pampipe_real)d, (pampipe_real)phi, (pampipe_real)mu,
                                                 (pampipe_real)m, p);
            printf("%d", code);
            for (i = 0; i < PAMPIPE_SEGMENTS; ++i) { printf(" %.17g", (double)p[i]); }
            printf("\n");
        }
    }
    return 0;
}
"""


def write_export(mission, folder: Path) -> Export:
    """Export ``mission`` (a loaded Mission) and write its files into ``folder``; returns the Export."""
    export = generate(mission, provenance=Provenance(str(mission.source), ()))
    folder.mkdir(parents=True, exist_ok=True)
    for name, text in export.files.items():
        (folder / name).write_text(text)
    return export


def compiler() -> str | None:
    """The host's C compiler (gcc, else cc), or None."""
    return shutil.which("gcc") or shutil.which("cc")


def build(folder: Path, *, real: str = "double") -> Path:
    """Compile the exported files in ``folder`` with the driver; ``real`` is "double" or "float"."""
    (folder / "driver.c").write_text(DRIVER)
    exe = folder / f"driver_{real}"
    flags = FLAGS + (FLOAT_FLAGS if real == "float" else [])
    sources = [str(folder / "pampipe_plan.c"), str(folder / "driver.c")]
    done = subprocess.run([compiler(), *flags, "-I", str(folder), "-o", str(exe), *sources, "-lm"],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return exe


def run_law(exe: Path, rows) -> tuple[np.ndarray, np.ndarray]:
    """(codes, pressures) of the exported function at each (D, incline, friction, payload) row."""
    text = "\n".join(" ".join(repr(float(v)) for v in row) for row in rows) + "\n"
    out = subprocess.run([str(exe)], input=text, check=True, capture_output=True, text=True).stdout
    lines = [line.split() for line in out.splitlines()]
    return (np.array([int(x[0]) for x in lines]), np.array([[float(v) for v in x[1:]] for x in lines]))


def run_table(exe: Path) -> tuple[list[dict], list[str]]:
    """The gait table as printed by the driver: one dict per section, and the segment names."""
    sections, names = [], []
    for line in subprocess.run([str(exe), "table"], check=True, capture_output=True,
                               text=True).stdout.splitlines():
        kind, *fields = line.split()
        if kind == "S":
            values = [float(v) for v in fields[1:7]]
            sections.append({"reason": int(fields[0]), "cycle_time_s": values[0], "stride_m": values[1],
                             "inner_diameter_m": values[2], "incline_rad": values[3], "friction": values[4],
                             "length_m": values[5], "name": _unhex(fields[7]), "steps": []})
        elif kind == "T":
            valves = [int(v) for v in fields[1:4]]
            sections[-1]["steps"].append({
                "step": fields[0], "valves": valves, "anchored": [bool(int(v)) for v in fields[4:7]],
                "duration_s": float(fields[7]), "pressures_Pa": [float(v) for v in fields[8:11]]})
        else:
            names.append(_unhex(fields[0]))
    return sections, names


def _unhex(text: str) -> str:
    return "" if text == "-" else bytes.fromhex(text).decode("utf-8")
