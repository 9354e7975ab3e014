"""Synthetic experiments that follow the paper's test protocol, from known moduli (for tests and demos).

Protocol (the paper's Sections 3-4, as far as the text describes it):

* **axial test:** at each pressure 69…689 kPa (10 psi steps) the muscle is cycled ``cycles`` times
  between its blocked length L₀ and its free-contraction length L_free(P): a shortening leg
  L₀ → L_free then a lengthening leg L_free → L₀, ``points_per_leg`` samples each, linear in L;
* **radial tests:** the muscle is inflated inside split pipes of 76.2 mm and 88.9 mm, without and
  with a 1024.74 N hanging axial load; at each pressure level (0 and 69…689 kPa)
  ``radial_points`` samples of the split-pipe force are recorded (zero below anchoring).

Noise: the recorded force is the model force + N(0, σ_F²); the recorded pressure is the regulated
pressure + N(0, σ_P²) while the force is computed at the regulated pressure (sensor noise).
Lengths are exact (displacement-controlled test machine). Time advances by ``sample_time`` per row.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pampipe.errors import InputError
from pampipe.experiment import TestSpec
from pampipe.io.files import atomic_write, atomic_write_text
from pampipe.model import forces
from pampipe.model.functions import free_length
from pampipe.model.pam import Pam
from pampipe.simulate import PAPER_PRESSURES, require_moduli

#: The paper's pipes [m] and hanging load [N].
PAPER_PIPES = (0.0762, 0.0889)
PAPER_LOAD = 1024.74


@dataclass(frozen=True)
class Protocol:
    """What to generate (SI). The defaults give 3000 axial and 1760 radial rows."""

    pressures: tuple[float, ...] = PAPER_PRESSURES  # axial levels [Pa]
    cycles: int = 3
    points_per_leg: int = 50
    pipes: tuple[float, ...] = PAPER_PIPES  # [m]
    loads: tuple[float, ...] = (0.0, PAPER_LOAD)  # [N]
    radial_pressures: tuple[float, ...] = (0.0, *PAPER_PRESSURES)  # [Pa]
    radial_points: int = 40
    force_noise: float = 2.0  # σ_F [N]
    pressure_noise: float = 0.0  # σ_P [Pa]
    sample_time: float = 0.1  # [s]


def generate(pam: Pam, protocol: Protocol = Protocol(), *, seed: int = 0
             ) -> list[tuple[TestSpec, dict[str, np.ndarray]]]:
    """[(test spec, SI columns)] for one axial test and one radial test per (pipe, load)."""
    require_moduli(pam, source="synth")
    rng = np.random.default_rng(seed)
    geometry, theta = pam.geometry, pam.moduli.as_vector()
    pref, contact = pam.moduli.reference_pressure, pam.moduli.contact_vector()
    contact = contact if np.any(contact) else None
    tests = [(TestSpec("axial", "axial", Path("data/axial.csv"), None, 0.0),
              _axial(pam, protocol, rng))]
    for pipe in protocol.pipes:
        for load in protocol.loads:
            name = f"radial-{pipe * 1e3:.1f}mm-{load:.0f}N"
            pressure = np.repeat(np.asarray(protocol.radial_pressures, dtype=float), protocol.radial_points)
            force = forces.radial_force(pressure, pipe, geometry, theta, pref, load, contact)
            tests.append((TestSpec(name, "radial", Path(f"data/{name}.csv"), pipe, load),
                          _noisy(pressure, np.asarray(force, dtype=float), None, protocol, rng)))
    return tests


def _axial(pam: Pam, protocol: Protocol, rng) -> dict[str, np.ndarray]:
    geometry, theta = pam.geometry, pam.moduli.as_vector()
    pref = pam.moduli.reference_pressure
    levels = np.asarray(protocol.pressures, dtype=float)
    shortest = free_length(levels, geometry, theta, pref)
    m = protocol.points_per_leg
    parts_p, parts_l = [], []
    for pressure, low in zip(levels, shortest, strict=True):
        shorten = np.linspace(geometry.initial_length, low, m, endpoint=False)
        lengthen = np.linspace(low, geometry.initial_length, m, endpoint=False)
        path = np.tile(np.concatenate([shorten, lengthen]), protocol.cycles)
        parts_l.append(path)
        parts_p.append(np.full(path.size, pressure))
    pressure, length = np.concatenate(parts_p), np.concatenate(parts_l)
    force = np.asarray(forces.axial_force(pressure, length, geometry, theta, pref), dtype=float)
    return _noisy(pressure, force, length, protocol, rng)


def _noisy(pressure, force, length, protocol: Protocol, rng) -> dict[str, np.ndarray]:
    columns = {"time": np.arange(pressure.size) * protocol.sample_time,
               "pressure": pressure + protocol.pressure_noise * rng.standard_normal(pressure.size),
               "force": force + protocol.force_noise * rng.standard_normal(pressure.size)}
    if length is not None:
        columns["length"] = length
    return columns


def write_csv(path: Path, columns: dict[str, np.ndarray]) -> None:
    """Write SI columns as CSV in lab units (kPa, mm, N, s), atomically."""
    units = {"time": ("s", 1.0, "%.3f"), "pressure": ("kPa", 1e-3, "%.4f"),
             "length": ("mm", 1e3, "%.5f"), "force": ("N", 1.0, "%.4f")}
    order = [name for name in ("time", "pressure", "length", "force") if name in columns]
    header = ",".join(f"{name} [{units[name][0]}]" for name in order)
    table = np.column_stack([columns[name] * units[name][1] for name in order])
    fmt = [units[name][2] for name in order]
    atomic_write(path, lambda tmp: np.savetxt(tmp, table, delimiter=",", fmt=fmt, header=header,
                                              comments=""))


def write_experiment(out_dir: Path, pam: Pam, *, name: str = "experiment", protocol: Protocol = Protocol(),
                     seed: int = 0, overwrite: bool = False) -> Path:
    """Write ``out_dir/<name>.yaml`` and ``out_dir/data/<name>/*.csv``; return the YAML path.

    The PAM geometry is written inline (without moduli: those are what ``identify`` finds); the
    generating moduli are recorded in a comment.
    """
    out_dir = Path(out_dir)
    target = out_dir / f"{name}.yaml"
    if target.exists() and not overwrite:
        raise InputError(f"{target}: already exists; choose another folder or name, or pass --force.")
    tests = generate(pam, protocol, seed=seed)
    lines = [f"# Synthetic experiment generated by `pampipe synth` (seed {seed}) following the paper's",
             f"# protocol; force noise {protocol.force_noise:.4g} N, pressure noise "
             f"{protocol.pressure_noise / 1e3:.4g} kPa (standard deviations).",
             f"# Generating moduli [MPa], theta = [axial.a, axial.b, hoop.a, hoop.b]: "
             f"{_mpa_list(pam.moduli.as_vector())}"]
    if pam.moduli.contact is not None:
        lines.append(f"# Generating contact increments [MPa]: {_mpa_list(pam.moduli.contact_vector())}")
    g = pam.geometry
    lines += ["pam:", f"  name: {pam.name}", "  geometry:",
              f"    initial_length: {g.initial_length * 1e3:.6g} mm",
              f"    initial_diameter: {g.initial_diameter * 1e3:.6g} mm",
              f"    braid_angle_from_axis: {np.degrees(g.braid_angle):.8g} deg",
              f"    bladder_thickness: {g.bladder_thickness * 1e3:.6g} mm",
              f"    wall: {g.wall}", "tests:"]
    for spec, columns in tests:
        csv = Path("data") / name / f"{spec.name}.csv"
        write_csv(out_dir / csv, columns)
        lines += [f"  - name: {spec.name}", f"    kind: {spec.kind}", f"    data: {csv.as_posix()}"]
        if spec.kind == "radial":
            lines += [f"    pipe_diameter: {spec.pipe_diameter * 1e3:.6g} mm",
                      f"    axial_load: {spec.axial_load:.6g} N"]
    atomic_write_text(target, "\n".join(lines) + "\n")
    return target


def _mpa_list(theta) -> str:
    return "[" + ", ".join(f"{v / 1e6:.6g}" for v in theta) + "]"
