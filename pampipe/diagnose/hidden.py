"""Synthetic experiments with one effect hidden in them (the test bench of `diagnose`).

The protocol is the paper's (:mod:`pampipe.synth`): isobaric axial cycles from L₀ to L_free(P) at
69…689 kPa, and split-pipe tests with and without the 1024.74 N hanging load. To let the effects
that act only on the pipe tests be told apart, the hidden-effect protocol adds a third pipe
(3.25 in) between the paper's 3 in and 3.5 in: with two pipes, wall friction (one slope factor
per pipe) and contact stiffening (two modulus increments) fit each other's slopes exactly.

Generation: :func:`pampipe.synth.generate` gives the rows and the noise (force noise σ_F, no
pressure noise, so the recorded pressure is the regulated one); the hidden effect is then added
as F_effect(row) − F_baseline(row), both from :mod:`pampipe.model.effects` at the recorded rows.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from pampipe.experiment import ExperimentData, make_test_data
from pampipe.model.effects import get_effect
from pampipe.model.muscle import Muscle
from pampipe.model.pam import Pam
from pampipe.synth import PAPER_LOAD, Protocol, generate

#: Realistic magnitudes (SI) at which each effect is hidden; see the module docstring of
#: :mod:`pampipe.model.effects` for the meaning of each parameter.
MAGNITUDES: dict[str, dict[str, float]] = {
    "braid_friction": {"f0": 6.0, "f1": 15e-6},  # 6 N + 15 N/MPa: ±16 N at 689 kPa
    "braid_extensibility": {"compliance": 0.2e-6},  # 0.2 /MN: 0.08 % fibre strain at 4 kN
    "end_effects": {"volume_taper": 0.01, "end_length": 0.1},  # ends ≈ 1 mm shorter per 10 mm of D − D₀
    "contact_stiffening": {"axial_increment": 0.3e6, "hoop_increment": 0.5e6},  # MPa per MPa
    "pressure_offset": {"offset": 8e3},  # 8 kPa (the paper quotes 28-35 kPa of pressure noise)
    "axial_preload": {"preload": 40.0},  # rope, clamp and fitting weight
    "wall_friction": {"lock": 0.005},  # λμ_w: 1.7 % of μ_w = 0.3 locked in
}

#: Pipes of the hidden-effect protocol [m]: the paper's 3 in and 3.5 in plus 3.25 in.
PIPES = (0.0762, 0.08255, 0.0889)


def hidden_protocol(*, force_noise: float = 2.0, cycles: int = 2, points_per_leg: int = 30,
                    radial_points: int = 10) -> Protocol:
    """The paper's protocol, three pipes, fewer samples per leg (fast refits), no pressure noise."""
    return Protocol(cycles=cycles, points_per_leg=points_per_leg, pipes=PIPES, loads=(0.0, PAPER_LOAD),
                    radial_points=radial_points, force_noise=force_noise, pressure_noise=0.0)


def hidden_experiment(pam: Pam, effect: str | None, *, seed: int, protocol: Protocol | None = None,
                      values: dict[str, float] | None = None, source: Path | None = None) -> ExperimentData:
    """An :class:`ExperimentData` generated from ``pam`` with ``effect`` hidden (None: clean)."""
    protocol = protocol or hidden_protocol()
    if protocol.pressure_noise:
        raise ValueError("hidden effects need pressure_noise = 0 (the effect is added at the "
                         "recorded pressure)")
    active = {} if effect is None else {effect: dict(MAGNITUDES[effect] if values is None else values)}
    if effect is not None:
        get_effect(effect)  # unknown names fail here
    base = Muscle.from_pam(replace(pam, effects=None))
    hidden = Muscle.from_pam(replace(pam, effects=active or None))
    tests = []
    for spec, columns in generate(replace(pam, effects=None), protocol, seed=seed):
        test = make_test_data(spec, columns)
        if active:
            if spec.kind == "axial":
                leg = test.leg.astype(float)
                delta = (hidden.axial_force(test.pressure, test.length, leg=leg)
                         - base.axial_force(test.pressure, test.length, leg=leg))
            else:
                args = (test.pressure, spec.pipe_diameter, spec.axial_load)
                delta = hidden.radial_force(*args) - base.radial_force(*args)
            test = replace(test, force=test.force + np.asarray(delta, dtype=float))
        tests.append(test)
    bare = replace(pam, moduli=None, covariance=None)
    return ExperimentData(source or Path(f"<hidden {effect or 'none'} seed {seed}>"), bare, tuple(tests), {})


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
                "Generated by pampipe.diagnose.hidden.hidden_tests from the paper's radial-test muscle",
                f"with its demo moduli (seed {seed}, force noise {protocol.force_noise:g} N).",
                f"Try: pampipe diagnose problems/experiments/{name}.yaml --plots /tmp/d"]
    tests = []
    for test in data.tests:
        columns = {"time": test.time, "pressure": test.pressure, "force": test.force}
        if test.kind == "axial":
            columns["length"] = test.length
        tests.append((test.spec, columns))
    return tests, comments
