"""Synthetic experiments with effects hidden in them (the test bench of `diagnose`).

The protocol is the paper's (:mod:`pampipe.simulation.synthetic`): isobaric axial cycles from L₀ to L_free(P)
at
69…689 kPa, and split-pipe tests with and without the 1024.74 N hanging load. To let the effects
that act only on the pipe tests be told apart, the hidden-effect protocol adds a third pipe
(3.25 in) between the paper's 3 in and 3.5 in: with two pipes, wall friction (one slope factor
per pipe) and contact stiffening (two modulus increments) fit each other's slopes exactly.

Generation: :func:`pampipe.simulation.synthetic.generate` gives the rows and the white force noise σ_F (no
pressure noise, so the recorded pressure is the regulated one). Then each hidden effect adds its
force at the recorded rows:

* a *library* effect (:data:`MAGNITUDES`, any set of them at once): F_effects(row) − F_baseline(row),
  both through :class:`pampipe.model.muscle.Muscle`;
* an effect *outside the library* (:data:`FOREIGN`), which `diagnose` must not name:

  - ``first_cycle_softening`` (Mullins): in the first cycle at each pressure of the axial test the
    bladder is softer, its moduli scaled by (1 − δ);
  - ``viscous``: a damper F = c·dL/dt in the axial test;
  - ``sensor_drift``: a load cell that drifts by d·t within each test;
  - ``pressure_oscillation``: the regulated pressure oscillates, P = P_set + A sin(2πt/T), while the
    file records P_set;
  - ``ar1_noise``: the white force noise is replaced by AR(1) noise of the same standard deviation,
    e_i = φe_{i−1} + √(1 − φ²)σ_F w_i.

``scale`` multiplies every magnitude (the tuning and the test sets of the tests use different
scales and seeds).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from pampipe.model.effects import LIBRARY, get_effect
from pampipe.model.muscle import Muscle
from pampipe.model.pam import Geometry, Pam
from pampipe.simulation.synthetic import PAPER_LOAD, Protocol, generate
from pampipe.specs.experiment import ExperimentData, make_test_data

#: Realistic magnitudes (SI) at which each library effect is hidden; see the module docstring of
#: :mod:`pampipe.model.effects` for the meaning of each parameter.
MAGNITUDES: dict[str, dict[str, float]] = {
    "braid_friction": {"f0": 6.0, "f1": 15e-6},  # 6 N + 15 N/MPa: ±16 N at 689 kPa
    "braid_extensibility": {"compliance": 0.2e-6},  # 0.2 /MN: 0.08 % fibre strain at 4 kN
    "end_effects": {"volume_taper": 0.01, "end_length": 0.1},  # ends ≈ 1 mm shorter per 10 mm of D − D₀
    "contact_stiffening": {"axial_increment": 0.3e6, "hoop_increment": 0.5e6},  # MPa per MPa
    "pressure_offset": {"offset": 8e3},  # 8 kPa (the paper quotes 28-35 kPa of pressure noise)
    "axial_preload": {"preload": 40.0},  # rope, clamp and fitting weight
    "wall_friction": {"lock": 0.005},  # λμ_w: 1.7 % of μ_w = 0.3 locked in
    "prestrain": {"axial_prestrain": -0.004, "hoop_prestrain": 0.012},  # zero-strain length ≈ 1 mm off
}

#: Effects outside the library and their magnitudes (SI).
FOREIGN: dict[str, dict[str, float]] = {
    "first_cycle_softening": {"softening": 0.04},  # δ: first-cycle moduli 4 % lower
    "viscous": {"damping": 400.0},  # c [N s/m]: 8 N at 20 mm/s
    "sensor_drift": {"rate": 0.3},  # d [N/s]: 36 N over the 120 s axial test, 3 N over a radial test
    "pressure_oscillation": {"amplitude": 2e3, "period": 1.7},  # A [Pa], T [s]
    "ar1_noise": {"phi": 0.8},  # φ
}

#: Pipes of the hidden-effect protocol [m]: the paper's 3 in and 3.5 in plus 3.25 in.
PIPES = (0.0762, 0.08255, 0.0889)


def hidden_protocol(*, force_noise: float = 2.0, cycles: int = 2, points_per_leg: int = 30,
                    radial_points: int = 10) -> Protocol:
    """The paper's protocol, three pipes, fewer samples per leg (fast refits), no pressure noise."""
    return Protocol(cycles=cycles, points_per_leg=points_per_leg, pipes=PIPES, loads=(0.0, PAPER_LOAD),
                    radial_points=radial_points, force_noise=force_noise, pressure_noise=0.0)


def _names(effects) -> tuple[str, ...]:
    if effects is None:
        return ()
    names = (effects,) if isinstance(effects, str) else tuple(effects)
    for name in names:
        if name not in FOREIGN:
            get_effect(name)  # unknown names fail here
    return names


def hidden_experiment(pam: Pam, effects=None, *, seed: int, protocol: Protocol | None = None,
                      values: dict[str, float] | None = None, scale: float = 1.0,
                      source: Path | None = None, stated: Geometry | None = None) -> ExperimentData:
    """An :class:`ExperimentData` generated from ``pam`` with ``effects`` hidden (None: clean).

    ``effects`` is a name or a sequence of names of :data:`MAGNITUDES` or :data:`FOREIGN`;
    ``values`` overrides the magnitudes of a single library effect; ``scale`` multiplies all
    magnitudes (φ of ``ar1_noise`` and the oscillation period excepted). ``stated``: the geometry
    the experiment's PAM states (a mis-stated geometry; default: the true one, ``pam``'s).
    """
    protocol = protocol or hidden_protocol()
    if protocol.pressure_noise:
        raise ValueError("hidden effects need pressure_noise = 0 (the effect is added at the "
                         "recorded pressure)")
    names = _names(effects)
    library = {n: {k: v * scale for k, v in (values if values is not None and len(names) == 1
                                              else MAGNITUDES[n]).items()}
               for n in names if n in LIBRARY}
    foreign = {n: {k: (v if k in ("phi", "period") else v * scale) for k, v in FOREIGN[n].items()}
               for n in names if n in FOREIGN}
    clean = replace(pam, effects=None)
    base = Muscle.from_pam(clean)
    hidden = Muscle.from_pam(replace(pam, effects=library or None))
    ar1 = "ar1_noise" in foreign
    generated = generate(clean, replace(protocol, force_noise=0.0) if ar1 else protocol, seed=seed)
    rng = np.random.default_rng([seed, 1])
    tests = []
    for spec, columns in generated:
        test = make_test_data(spec, columns)
        force = test.force.copy()
        if library:
            force += _delta(hidden, base, test)
        for name, v in foreign.items():
            force += FOREIGN_FORCES[name](base, test, v, protocol, rng)
        tests.append(replace(test, force=force))
    label = "+".join(names) or "none"
    bare = replace(pam, moduli=None, covariance=None, uncertainty=None, geometry=stated or pam.geometry)
    return ExperimentData(source or Path(f"<hidden {label} seed {seed}>"), bare, tuple(tests), {})


def _delta(hidden: Muscle, base: Muscle, test, pressure=None) -> np.ndarray:
    """F_hidden − F_base at the test's rows (at ``pressure`` instead of the recorded one if given)."""
    pressure = test.pressure if pressure is None else pressure
    if test.kind == "axial":
        legs = {"leg": test.leg.astype(float),
                "pressure_leg": 0.0 if test.pressure_leg is None else test.pressure_leg.astype(float)}
        out = (hidden.axial_force(pressure, test.length, **legs)
               - base.axial_force(pressure, test.length, **legs))
    else:
        args = (test.spec.pipe_diameter, test.spec.axial_load)
        out = hidden.radial_force(pressure, *args) - base.radial_force(pressure, *args)
    return np.asarray(out, dtype=float)


def _first_cycle(base: Muscle, test, v, protocol, rng) -> np.ndarray:
    if test.kind != "axial":
        return np.zeros(test.points)
    soft = Muscle(base.geometry, np.asarray(base.theta) * (1 - v["softening"]), base.reference_pressure)
    return np.where(test.cycle == 0, _delta(soft, base, test), 0.0)


def _viscous(base: Muscle, test, v, protocol, rng) -> np.ndarray:
    if test.kind != "axial":
        return np.zeros(test.points)
    rate = np.zeros(test.points)
    for level in np.unique(test.level):
        rows = np.flatnonzero(test.level == level)
        if rows.size > 1:
            rate[rows] = np.gradient(test.length[rows], test.time[rows])
    return v["damping"] * rate


def _drift(base: Muscle, test, v, protocol, rng) -> np.ndarray:
    return v["rate"] * (test.time - test.time[0])


def _oscillation(base: Muscle, test, v, protocol, rng) -> np.ndarray:
    true = test.pressure + v["amplitude"] * np.sin(2 * np.pi * test.time / v["period"])
    if test.kind == "axial":
        return np.asarray(base.axial_force(true, test.length) - base.axial_force(test.pressure, test.length))
    args = (test.spec.pipe_diameter, test.spec.axial_load)
    return np.asarray(base.radial_force(true, *args) - base.radial_force(test.pressure, *args), dtype=float)


def _ar1(base: Muscle, test, v, protocol, rng) -> np.ndarray:
    phi, sigma = v["phi"], protocol.force_noise
    white = rng.standard_normal(test.points)
    out = np.empty(test.points)
    out[0] = sigma * white[0]
    for i in range(1, test.points):
        out[i] = phi * out[i - 1] + np.sqrt(1 - phi**2) * sigma * white[i]
    return out


FOREIGN_FORCES = {"first_cycle_softening": _first_cycle, "viscous": _viscous, "sensor_drift": _drift,
                  "pressure_oscillation": _oscillation, "ar1_noise": _ar1}


def hidden_tests(pam: Pam, effect: str, *, seed: int = 1, protocol: Protocol | None = None
                 ) -> tuple[list, list[str]]:
    """([(test spec, SI columns)], header comments) of a hidden-effect experiment, ready for
    :func:`pampipe.io.pamfile.write_experiment` (how ``problems/experiments/hidden-*.yaml`` are made)."""
    protocol = protocol or hidden_protocol()
    data = hidden_experiment(pam, effect, seed=seed, protocol=protocol)
    hidden = ", ".join(f"{p.name} = {MAGNITUDES[effect][p.name] / p.scale:g} {p.unit}"
                       for p in get_effect(effect).parameters if p.name in MAGNITUDES[effect])
    name = f"hidden-{effect.replace('_', '-')}"
    comments = [f"A synthetic experiment with one effect hidden in it: {effect} ({hidden}).",
                "Generated by pampipe.diagnosis.hidden.hidden_tests from the paper's radial-test muscle",
                f"with its demo moduli (seed {seed}, force noise {protocol.force_noise:g} N).",
                f"Try: pampipe diagnose problems/experiments/{name}.yaml --plots /tmp/d"]
    tests = []
    for test in data.tests:
        columns = {"time": test.time, "pressure": test.pressure, "force": test.force}
        if test.kind == "axial":
            columns["length"] = test.length
        tests.append((test.spec, columns))
    return tests, comments
