"""`pampipe export`: the mission's anchoring law and gait schedule as portable C (docs/commands.md §9).

Library API (no file I/O here: the texts come back, :mod:`pampipe.commands.export` writes them)::

    from pampipe.export import Provenance, generate

    export = generate(mission, provenance=Provenance("mission.yaml", (("mission.yaml", sha),)))
    export.files["pampipe_plan.h"], export.files["pampipe_plan.c"], export.files["pampipe_example.ino"]
    export.law.evaluate(0.0762, 1.5708, 0.3, 2.0)     # the C function's answer, in Python

``pampipe.export_mission`` (:mod:`pampipe.api`) takes a file path or a dict and hashes the inputs.
The law is :meth:`pampipe.model.muscle.Muscle.closed_form_pressure` on CasADi symbols, written to C
by :mod:`pampipe.export.cgen`; the gait table is :func:`pampipe.locomotion.sequential_gait` per section.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import casadi as ca

from pampipe._version import __version__
from pampipe.errors import InputError
from pampipe.export.gait_table import GaitStep, SectionGait, section_gaits
from pampipe.export.law import Law, Reason, confidence_margins, mission_law
from pampipe.export.sources import header, is_sketch_name, sketch, source, stamped
from pampipe.results import notebook

HEADER = "pampipe_plan.h"
SOURCE = "pampipe_plan.c"
DEFAULT_SKETCH = "pampipe_example"


@dataclass(frozen=True)
class Provenance:
    """Where the export came from: the mission as named, and (path, SHA-256) of every input file."""

    mission: str
    inputs: tuple[tuple[str, str], ...]
    version: str = __version__
    casadi: str = field(default_factory=lambda: ca.__version__)


def _text():
    from pampipe.views.export_text import result_text

    return result_text


def _plot():
    from pampipe.views.plots.route import plot_export

    return plot_export


@notebook(headline=(), plot=_plot, text=_text)
@dataclass(frozen=True)
class Export:
    """The exported files (name → text) and what they contain."""

    files: dict[str, str]
    law: Law
    sections: tuple[SectionGait, ...]
    provenance: Provenance
    sketch: str  # the sketch's file name

    def to_dict(self) -> dict:
        """The ``export`` JSON summary (SI, unit-suffixed keys)."""
        law = self.law
        return {
            "files": sorted(self.files), "sketch": self.sketch, "mission": self.provenance.mission,
            "inputs": [{"path": p, "sha256": h} for p, h in self.provenance.inputs],
            "pampipe_version": self.provenance.version, "casadi_version": self.provenance.casadi,
            "segments": [{"name": n, "mass_kg": m, "rest_diameter_m": d0, "largest_diameter_m": d1}
                         for n, m, d0, d1 in zip(law.segments, law.masses, law.rest_diameters,
                                                 law.largest_diameters, strict=True)],
            "supply_pressure_Pa": law.supply_pressure, "safety_factor": law.safety_factor,
            "load_path": law.load_path, "payload_kg": law.payload, "effects": law.effects,
            "diameter_range_m": [law.narrowest, law.widest],
            "reason_codes": {r.name.lower(): int(r) for r in Reason},
            "operations": law.function.n_instructions(),
            "confidence": None if law.confidence is None else {
                "level": law.confidence, "margins_Pa": dict(zip(law.segments, law.margins, strict=True))},
            "sections": [s.as_document() for s in self.sections],
        }


def generate(mission, *, provenance: Provenance, sketch_name: str = DEFAULT_SKETCH, progress=None,
             confidence: float | None = None, **sampling) -> Export:
    """The C export of ``mission`` (InputError if a PAM's effects have no closed form).

    ``progress(text)`` hears how far the gait table of a long route is. With ``confidence`` C the law
    carries the margins that plan at C (:func:`~pampipe.export.law.confidence_margins`; ``sampling``:
    its ``samples``/``seed``).
    """
    if not is_sketch_name(sketch_name):
        raise InputError(f"sketch_name: {sketch_name!r} is not an Arduino sketch name: 1 to 63 ASCII "
                         "letters, digits, '_', '.' or '-', starting with a letter or digit.")
    if getattr(mission, "tether", None) is not None:
        raise InputError(f"{mission.source}: tether: the exported law takes the bore, incline, friction and "
                         "payload only, and a tether's tension grows along the route (docs/physics.md §16); "
                         "export the mission without its tether: block, with tether_drag set to the largest "
                         "tension `pampipe plan` reports.")
    margins = () if confidence is None else confidence_margins(mission, confidence, **sampling)
    law = mission_law(mission, confidence=confidence, margins=margins, samples=sampling.get("samples"))
    gaits = section_gaits(mission, law, progress=progress)
    files = stamped({HEADER: header(law, gaits, provenance), SOURCE: source(law, gaits, provenance),
                     f"{sketch_name}.ino": sketch(law, gaits, provenance, sketch_name)})
    return Export(files, law, gaits, provenance, f"{sketch_name}.ino")


__all__ = ["DEFAULT_SKETCH", "HEADER", "SOURCE", "Export", "GaitStep", "Law", "Provenance", "Reason",
           "SectionGait", "generate", "is_sketch_name"]
