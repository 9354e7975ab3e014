"""Synthetic lab data that mimic real protocols, generated from known parameters (for the tests).

Every force is computed from the baseline model (:class:`pampipe.model.muscle.Muscle` without
effects) of a *true* muscle; what real data add is written out here explicitly, not through the
effect library, so that the tests of the library check it against an independent statement:

* isometric ramps: lengths held, pressure ramped up and down; an optional pressure hysteresis
  F = F_ax − sgn(dP/dt)(h₀ + h₁P) (the venting leg above the filling leg); isometric steps: the same at
  repeated pressure set points (issue 41);
* force maps: a (P, L) grid where the muscle is slack (F_ax ≤ 0) records exactly 0 N;
* stepped isobaric cycles with pressure levels that may be close together;
* paper-style radial tests with one reading per pressure step;
* (issue 23) what real protocols add: ramp transients after every reversal, a ``state`` column coded
  1 = filling / 2 = venting, force maps at few pressures whose longest length stops short of L₀, and
  split-pipe tests that hold each pressure step for several readings; :func:`write_lab` writes them
  as a lab would (CSV in kPa, mm, N, s and an experiment file).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from pampipe.io import yamlwrite
from pampipe.io.pamfile import pam_document
from pampipe.model.effects import LIBRARY
from pampipe.model.muscle import Muscle
from pampipe.model.pam import Pam
from pampipe.specs.experiment import ExperimentData, TestSpec, make_test_data

DEG = np.pi / 180


def truth(pam: Pam) -> Muscle:
    return Muscle.from_pam(pam)


def isometric_ramps(muscle: Muscle, lengths, *, top=600e3, points=200, cycles=2, hysteresis=(0.0, 0.0),
                    noise=1.0, pressure_noise=0.0, transient=(0.0, 1.0), rng=None) -> dict[str, np.ndarray]:
    """Ramps 0 → ``top`` → 0 at each held length, ``points`` rows per leg; time advances 0.1 s a row.

    Where the muscle is slack (force ≤ 0: it cannot pull itself that short yet) the load cell reads
    0 N exactly. ``transient`` = (A [N], τ [s]): after every reversal the force lags its new leg by
    A·exp(−t/τ) (the gas and the bladder settling), −sgn(dP/dt)·A·e^(−t/τ). Returns SI columns and
    ``filling`` (+1 filling, −1 venting) as generated.
    """
    rng = rng or np.random.default_rng(0)
    step = top / points
    paths, signs = [], []
    for _ in range(len(lengths) * cycles):  # every ramp sampled at its own phase: no pressure repeats
        phase = rng.uniform(0.0, step)
        paths += [np.linspace(phase, top - step + phase, points), np.linspace(top - phase, phase, points)]
        signs += [np.ones(points), -np.ones(points)]
    path = np.concatenate(paths[:2 * cycles])
    pressure = np.concatenate(paths)
    filling = np.concatenate(signs)
    length = np.repeat(np.asarray(lengths, float), path.size)
    force = np.asarray(muscle.axial_force(pressure, length), float)
    force = force - filling * (hysteresis[0] + hysteresis[1] * pressure)
    since = 0.1 * np.tile(np.arange(points), pressure.size // points)  # [s] since the leg began
    force = force - filling * transient[0] * np.exp(-since / transient[1])
    force = np.where(force > 0, force + noise * rng.standard_normal(force.size), 0.0)  # slack: 0 N
    measured = pressure + pressure_noise * rng.standard_normal(pressure.size)
    return {"time": 0.1 * np.arange(force.size), "pressure": measured, "length": length, "force": force,
            "filling": filling}


def isometric_steps(muscle: Muscle, lengths, set_points, *, readings=5, cycles=2, hysteresis=(0.0, 0.0),
                     noise=2.0, pressure_noise=300.0, rng=None) -> dict[str, np.ndarray]:
    """Held lengths with repeated pressure set points (issue 41): at each length, ``cycles`` times up
    through ``set_points`` and back down, ``readings`` rows held at each; F = F_ax − sgn(dP/dt)(h₀ + h₁P)
    with the sign of the leg the set point was reached on. Time advances 0.1 s a row; 0 N where slack."""
    rng = rng or np.random.default_rng(0)
    up = np.asarray(set_points, float)
    leg_points = np.concatenate([up, up[::-1]])
    leg_signs = np.concatenate([np.ones(up.size), -np.ones(up.size)])
    pressure = np.repeat(np.tile(leg_points, cycles * len(lengths)), readings)
    filling = np.repeat(np.tile(leg_signs, cycles * len(lengths)), readings)
    length = np.repeat(np.asarray(lengths, float), leg_points.size * cycles * readings)
    force = np.asarray(muscle.axial_force(pressure, length), float)
    force = force - filling * (hysteresis[0] + hysteresis[1] * pressure)
    force = np.where(force > 0, force + noise * rng.standard_normal(force.size), 0.0)
    measured = pressure + pressure_noise * rng.standard_normal(pressure.size)
    return {"time": 0.1 * np.arange(force.size), "pressure": measured, "length": length, "force": force,
            "filling": filling}


def force_map(muscle: Muscle, pressures, lengths, *, noise=1.0, rng=None, order="pressure-major"
              ) -> dict[str, np.ndarray]:
    """One reading per (P, L) cell; 0 N exactly where the muscle is slack (F_ax ≤ 0).

    ``order``: ``pressure-major`` (all lengths at one pressure, then the next), ``length-major`` or
    ``shuffled`` (no time column: the rows carry no order).
    """
    rng = rng or np.random.default_rng(0)
    pp, ll = np.meshgrid(np.asarray(pressures, float), np.asarray(lengths, float), indexing="ij")
    model = np.asarray(muscle.axial_force(pp, ll), float)
    force = np.where(model > 0, model + noise * rng.standard_normal(model.shape), 0.0)
    k = np.arange(force.size)  # the same readings in every order
    if order == "length-major":
        k = k.reshape(pp.shape).T.ravel()
    elif order == "shuffled":
        k = rng.permutation(force.size)
    return {"pressure": pp.ravel()[k], "length": ll.ravel()[k], "force": force.ravel()[k]}


def stepped(muscle: Muscle, levels, *, points=60, noise=1.0, pressure_noise=500.0, rng=None
            ) -> dict[str, np.ndarray]:
    """Isobaric cycles L₀ → L_free(P) → L₀ at each pressure level, with regulator noise."""
    rng = rng or np.random.default_rng(0)
    g = muscle.geometry
    parts_p, parts_l = [], []
    for level, short in zip(levels, muscle.free_length(np.asarray(levels, float)), strict=True):
        path = np.concatenate([np.linspace(g.initial_length, short, points, endpoint=False),
                               np.linspace(short, g.initial_length, points, endpoint=False)])
        parts_l.append(path)
        parts_p.append(np.full(path.size, float(level)))
    pressure, length = np.concatenate(parts_p), np.concatenate(parts_l)
    force = np.asarray(muscle.axial_force(pressure, length), float) + noise * rng.standard_normal(length.size)
    return {"time": 0.1 * np.arange(length.size), "pressure": pressure + pressure_noise
            * rng.standard_normal(length.size), "length": length, "force": force}


def radial_steps(muscle: Muscle, pipe, *, load=0.0, readings=30, top=600e3, noise=1.0, rng=None
                 ) -> dict[str, np.ndarray]:
    """A paper-style radial test: ``readings`` pressure steps, one reading each."""
    rng = rng or np.random.default_rng(0)
    pressure = np.linspace(0.0, top, readings)
    force = np.asarray(muscle.radial_force(pressure, pipe, load), float)
    return {"pressure": pressure, "force": force + noise * rng.standard_normal(readings)}


def experiment(pam: Pam, tests, *, stated=None, fit=None) -> ExperimentData:
    """ExperimentData of (spec, columns) pairs; the fit sees ``stated`` geometry (default: the truth)."""
    geometry = stated or pam.geometry
    data = tuple(make_test_data(spec, {k: v for k, v in cols.items() if k != "filling"})
                 for spec, cols in tests)
    return ExperimentData(Path("lab.yaml"), Pam(pam.name, geometry), data, dict(fit or {}))


def axial(name="axial", **changes) -> TestSpec:
    return replace(TestSpec(name, "axial", Path(f"{name}.csv"), None, 0.0), **changes)


def radial(name, pipe, load=0.0) -> TestSpec:
    return TestSpec(name, "radial", Path(f"{name}.csv"), pipe, load)


def off_by(geometry, *, angle_deg=0.0, length_mm=0.0):
    """``geometry`` with the braid angle and the rest length shifted (a rough lab statement)."""
    return replace(geometry, braid_angle=geometry.braid_angle + angle_deg * DEG,
                   initial_length=geometry.initial_length + length_mm * 1e-3)


def state_coded(columns: dict[str, np.ndarray], *, filling=1, venting=2) -> dict[str, np.ndarray]:
    """The columns plus a lab's ``state`` column: ``filling`` on filling rows, ``venting`` on venting ones."""
    return {**columns, "state": np.where(columns["filling"] > 0, filling, venting).astype(float)}


def short_force_map(muscle: Muscle, *, pressures=(200e3, 400e3, 600e3), shortest=0.80, longest=0.987,
                    count=12, noise=1.0, rng=None) -> dict[str, np.ndarray]:
    """A lab's force map: few pressures, lengths from ``shortest`` to ``longest`` × L₀ (the rig
    stops short of the rest length), 0 N where slack."""
    l0 = muscle.geometry.initial_length
    return force_map(muscle, pressures, np.linspace(shortest * l0, longest * l0, count), noise=noise, rng=rng)


def split_pipe(muscle: Muscle, pipe, *, steps=12, readings=5, top=600e3, noise=1.0, rng=None
               ) -> dict[str, np.ndarray]:
    """A split-pipe radial test (the paper's rig): ``steps`` pressure steps up, each held for
    ``readings`` readings with the regulator's 1 kPa scatter; the pipe halves read 0 N until anchoring."""
    rng = rng or np.random.default_rng(0)
    pressure = np.repeat(np.linspace(top / steps, top, steps), readings) + 1e3 * rng.standard_normal(
        steps * readings)
    force = np.asarray(muscle.radial_force(pressure, pipe, 0.0), float)
    force = np.where(force > 0, force + noise * rng.standard_normal(force.size), 0.0)
    return {"time": 0.5 * np.arange(force.size), "pressure": pressure, "force": force}


#: CSV header of each column as a lab writes it: (header, factor from SI, format).
LAB_COLUMNS = {"time": ("time [s]", 1.0, "%.2f"), "pressure": ("pressure [kPa]", 1e-3, "%.4f"),
               "length": ("length [mm]", 1e3, "%.4f"), "force": ("force [N]", 1.0, "%.4f"),
               "state": ("state [-]", 1.0, "%d"), "direction": ("direction [-]", 1.0, "%d")}


def write_lab(folder: Path, pam: Pam, tests, *, fit=None) -> Path:
    """``folder/lab.yaml`` and one CSV per (spec, columns, extra) test, in lab units; ``extra`` is the
    test's entry beyond name/kind/data/pipe (e.g. a ``direction`` mapping). Returns the YAML path."""
    folder = Path(folder)
    entries = []
    for spec, columns, extra in tests:
        names = [n for n in LAB_COLUMNS if n in columns]
        table = np.column_stack([np.asarray(columns[n], float) * LAB_COLUMNS[n][1] for n in names])
        np.savetxt(folder / f"{spec.name}.csv", table, delimiter=",", comments="",
                   header=",".join(LAB_COLUMNS[n][0] for n in names), fmt=[LAB_COLUMNS[n][2] for n in names])
        entry = {"name": spec.name, "kind": spec.kind, "data": f"{spec.name}.csv", **(extra or {})}
        if spec.kind == "radial":
            entry["pipe_diameter"] = f"{spec.pipe_diameter * 1e3:.6g} mm"
        entries.append(entry)
    path = folder / "lab.yaml"
    yamlwrite.write(path, {"pam": pam_document(pam, with_moduli=False), "tests": entries,
                           **({"fit": fit} if fit else {})})
    return path


def refit_with_effect(geometry, test, theta0, effect: str | None) -> tuple[float, np.ndarray]:
    """Least squares of the degree-1 moduli θ (MPa), and of ``effect``'s parameters when given, through
    Muscle (scipy, row by row: independent of identify and diagnose), on the measured rows off the turning
    points of the pressure (there the direction is 0 and a band is undetermined).

    Returns (the RMSE [N], the effect's fitted parameters in their display scale).
    """
    from scipy.optimize import least_squares

    live = (test.force > 0) & (test.pressure_leg != 0)
    params = LIBRARY[effect].parameters if effect else ()

    def residual(z):
        effects = {effect: {p.name: z[8 + i] * p.scale for i, p in enumerate(params)}} if effect else None
        m = Muscle(geometry, z[:8] * 1e6, 1e6, effects=effects)
        model = m.axial_force(test.pressure, test.length, leg=test.leg, pressure_leg=test.pressure_leg)
        return np.asarray(model, float)[live] - test.force[live]

    z0 = np.concatenate([theta0, [p.null / p.scale for p in params]])
    lower = np.concatenate([np.full(8, -60.0), [p.lower / p.scale for p in params]])
    upper = np.concatenate([np.full(8, 60.0), [p.upper / p.scale for p in params]])
    fit = least_squares(residual, np.clip(z0, lower + 1e-9, upper - 1e-9), bounds=(lower, upper),
                        x_scale="jac")
    return float(np.sqrt(np.mean(fit.fun**2))), fit.x[8:]
