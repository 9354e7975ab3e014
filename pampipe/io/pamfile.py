"""A :class:`~pampipe.model.pam.Pam` → PAM file (docs/formats.md §2), and experiment files.

Numbers are written at full precision (shortest round-trip floats) in the units of the format:
lengths in mm, angles in deg, moduli in MPa, effect parameters in their display units.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from pampipe.io import yamlwrite
from pampipe.io.csvfile import write_csv
from pampipe.io.files import check_not_input, check_overwrite
from pampipe.model.effects import get_effect
from pampipe.model.pam import TIES, Pam
from pampipe.model.uncertainty import GEOMETRY_NAMES, ParameterUncertainty
from pampipe.specs.experiment import TestSpec

MPA = 1e6


def _quantity(value: float, unit: str) -> str:
    return f"{float(value)!r} {unit}"


def geometry_document(pam: Pam) -> dict:
    """The ``geometry:`` block (braid angle from the axis); an entry with a stated sd is ``{value, sd}``."""
    g, sd = pam.geometry, pam.geometry_sd
    doc = {"initial_length": _entry(g.initial_length * 1e3, sd.get("initial_length"), "mm", 1e3),
           "initial_diameter": _entry(g.initial_diameter * 1e3, sd.get("initial_diameter"), "mm", 1e3),
           "braid_angle_from_axis": _entry(math.degrees(g.braid_angle), sd.get("braid_angle"), "deg",
                                           math.degrees(1.0)),
           "bladder_thickness": _entry(g.bladder_thickness * 1e3, sd.get("bladder_thickness"), "mm", 1e3),
           "wall": g.wall}
    if pam.fitting_length:
        doc["fitting_length"] = _quantity(pam.fitting_length * 1e3, "mm")
    return doc


def _entry(value: float, sd: float | None, unit: str, factor: float):
    """A geometry entry shown in ``unit``: a quantity, or ``{value, sd}`` when an sd [SI] is stated."""
    if sd is None:
        return _quantity(value, unit)
    return {"value": _quantity(value, unit), "sd": _quantity(sd * factor, unit)}


def _law(vector: np.ndarray, k: int, block: int) -> dict:
    values = np.asarray(vector, dtype=float) / MPA
    return {"a": [float(v) for v in values[2 * block * k:(2 * block + 1) * k]],
            "b": [float(v) for v in values[(2 * block + 1) * k:(2 * block + 2) * k]]}


def pam_document(pam: Pam, *, with_moduli: bool = True) -> dict:
    """The PAM file of ``pam`` as a dict: name, geometry, limits and (if any) moduli, uncertainty, effects."""
    doc: dict = {"name": pam.name, "geometry": geometry_document(pam)}
    if pam.max_pressure is not None:
        doc["max_pressure"] = _quantity(pam.max_pressure / 1e3, "kPa")
    if pam.max_contraction is not None:
        doc["max_contraction"] = float(pam.max_contraction)  # a fraction (25 % is 0.25)
    m = pam.moduli
    if m is None or not with_moduli:
        return doc
    k = m.degree + 1
    theta = m.as_vector()
    doc["moduli"] = {"unit": "MPa", "reference_pressure": _quantity(m.reference_pressure / 1e3, "kPa"),
                     "axial": _law(theta, k, 0), "hoop": _law(theta, k, 1)}
    if m.contact is not None:
        contact = m.contact_vector()
        doc["moduli"]["contact"] = {"axial": _law(contact, k, 0), "hoop": _law(contact, k, 1)}
    uncertainty = pam.uncertainty
    if uncertainty is None and pam.covariance is not None:
        uncertainty = ParameterUncertainty.moduli_only(pam.covariance, degree=m.degree)
    if uncertainty is not None:
        doc["uncertainty"] = uncertainty_document(uncertainty)
    if pam.effects or pam.ties:
        doc["effects"] = {name: _effect_values(name, values) for name, values in (pam.effects or {}).items()}
        if pam.ties:
            doc["effects"][TIES] = dict(pam.ties)
    doc.update(_grip_document(pam))
    return doc


def _grip_document(pam: Pam) -> dict:
    """``{contact: {friction, load_coupling, pipe_material, tested_pipe_diameters}}`` (empty without grip)."""
    g = pam.grip
    if g is None:
        return {}
    block: dict = {"friction": {"value": float(g.friction), "sd": float(g.friction_sd)},
                   "load_coupling": None if g.load_coupling is None else
                   {"value": float(g.load_coupling), "sd": float(g.load_coupling_sd)}}
    if g.pipe_material is not None:
        block["pipe_material"] = g.pipe_material
    if g.tested_diameters:
        block["tested_pipe_diameters"] = [f"{d * 1e3:.9g} mm" for d in g.tested_diameters]
    return {"contact": block}
def uncertainty_document(u: ParameterUncertainty) -> dict:
    """The ``uncertainty:`` block: moduli rows in MPa, geometry rows in SI (m, rad), model error in N."""
    row_scale = np.array([1.0 if name in GEOMETRY_NAMES else MPA for name in u.names])
    cov = u.covariance / np.outer(row_scale, row_scale)
    doc = {"unit": "MPa", "parameters": list(u.names), "covariance": [[float(v) for v in row] for row in cov],
           "model_error": _quantity(u.model_error, "N")}
    if u.model_error_dof is not None:
        doc["model_error_dof"] = int(u.model_error_dof)
    for key, directions in (("undetermined", u.undetermined), ("prior_determined", u.prior_determined)):
        if directions:
            doc[key] = [{"direction": {name: float(w) for name, w in zip(u.names, d.vector, strict=True)
                                       if w != 0},
                         "scale": float(d.scale), "moves": {k: float(v) for k, v in d.moves.items()},
                         **({"test": d.test} if d.test else {})}
                        for d in directions]
    return doc


def _effect_values(name: str, values: dict) -> dict:
    out = {}
    for p in get_effect(name).parameters:
        if p.name in values:
            shown = float(values[p.name] / p.scale)
            out[p.name] = shown if p.unit == "-" else _quantity(shown, p.unit)
    return out


def write_pam(target: Path, pam: Pam, *, comments: Sequence[str] = ()) -> None:
    """Write ``pam`` as a PAM file, atomically (the caller checks ``target`` is not an input)."""
    yamlwrite.write(target, pam_document(pam), comments=comments)


def write_experiment(out_dir: Path, name: str, pam: Pam, tests: Sequence[tuple[TestSpec, dict]], *,
                     comments: Sequence[str] = (), overwrite: bool = False,
                     inputs: Sequence[Path] = (), with_moduli: bool = False) -> Path:
    """Write ``out_dir/<name>.yaml`` (the PAM inline, without moduli) and ``out_dir/data/<name>/*.csv``.

    ``tests`` pairs each test's spec with its SI columns (``time``, ``pressure``, ``force`` and,
    for axial tests, ``length``; slip tests: ``axial_load`` and ``displacement``, not ``force``);
    ``with_moduli`` writes the PAM's moduli too (an experiment of slip tests only needs them). Returns
    the YAML path. Before anything is written: existing files
    are replaced only with ``overwrite`` (``--force``), and ``inputs`` (the PAM file read) never.
    """
    out_dir = Path(out_dir)
    target = out_dir / f"{name}.yaml"
    csvs = [out_dir / "data" / name / f"{spec.name}.csv" for spec, _ in tests]
    for path in (target, *csvs):
        check_not_input(path, inputs, option="synth")
    check_overwrite((target, *csvs), force=overwrite)
    entries = []
    for (spec, columns), csv in zip(tests, csvs, strict=True):
        write_csv(csv, columns)
        entry = {"name": spec.name, "kind": spec.kind, "data": csv.relative_to(out_dir).as_posix()}
        if spec.kind == "radial":
            entry["pipe_diameter"] = _quantity(spec.pipe_diameter * 1e3, "mm")
            entry["axial_load"] = _quantity(spec.axial_load, "N")
        if spec.kind == "slip":
            entry["pipe_diameter"] = _quantity(spec.pipe_diameter * 1e3, "mm")
            if spec.pipe_material is not None:
                entry["pipe_material"] = spec.pipe_material
        entries.append(entry)
    yamlwrite.write(target, {"pam": pam_document(pam, with_moduli=with_moduli), "tests": entries},
                    comments=comments)
    return target
