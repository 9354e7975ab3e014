"""planning/tension.py against the cable-pulling equations written out with plain floats (docs/physics.md
§16.1): T_out = max(0, T_in + w·ℓ·(μ_t·cos φ + sin φ)), T_in(next) = T_out·e^(μ_t·θ), T_in(first) = T₀; the
largest tension of a section max(T_in, T_out) added to tether_drag; the friction draws floored at 0. The
first target of ``make mutate`` for the module (the plan-level checks: tests/planning/test_tether.py)."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from pampipe.planning.sources import keyed_normal
from pampipe.planning.tension import drawn_drag, section_drag, tension_slope, tensions, tether_frictions

#: (length [m], incline [deg], bend at the end [deg]): a run, a riser, a drop that goes slack, a climb, a
#: gentle downhill that falls without going slack, a last run with no bend
SECTIONS = [(40.0, 0.0, 15.0), (12.0, 90.0, 90.0), (100.0, -60.0, 180.0), (30.0, 20.0, 45.0),
            (50.0, -25.0, 120.0), (300.0, 0.0, 0.0)]


def route(bends: bool = True):
    length, incline, bend = (np.array(c, dtype=float) for c in zip(*SECTIONS, strict=True))
    return SimpleNamespace(length=length, incline=np.radians(incline),
                           bend_angle=np.radians(bend) if bends else None)


def tether(friction=0.35, sd=0.0):
    return SimpleNamespace(weight=0.8, friction=friction, back_tension=5.0, friction_sd=sd)


def by_hand(w, mu, t0, bends=True):
    out, t = [], t0
    for length, incline, bend in SECTIONS:
        start = t
        phi = math.radians(incline)
        t = max(0.0, t + w * length * (mu * math.cos(phi) + math.sin(phi)))
        out.append((start, t))
        if bends:
            t *= math.exp(mu * math.radians(bend))
    return out


def test_tensions_follow_the_cable_pulling_equations():
    t_in, t_out = tensions(route(), tether())
    want = by_hand(0.8, 0.35, 5.0)
    assert want[2][1] == 0.0 and want[3][0] == 0.0 and 0 < want[4][1] < want[4][0]  # slack, then falling
    assert t_in == pytest.approx([a for a, _ in want], rel=1e-12, abs=1e-12)
    assert t_out == pytest.approx([b for _, b in want], rel=1e-12, abs=1e-12)
    no_bends = tensions(route(bends=False), tether())
    assert no_bends[1] == pytest.approx([b for _, b in by_hand(0.8, 0.35, 5.0, bends=False)], rel=1e-12)


def test_tension_slope_is_weight_times_friction_cos_plus_sin():
    k = tension_slope(route(), tether())
    assert k == pytest.approx([0.8 * (0.35 * math.cos(math.radians(phi)) + math.sin(math.radians(phi)))
                               for _, phi, _ in SECTIONS], rel=1e-12)
    assert tension_slope(route(), tether(), [0.1, 0.5]).shape == (6, 2)


def test_tensions_for_several_frictions_are_each_frictions_tensions():
    mu = np.array([0.0, 0.2, 0.6])
    t_in, t_out = tensions(route(), tether(), mu)
    assert t_in.shape == t_out.shape == (6, 3)
    for j, m in enumerate(mu):
        want = by_hand(0.8, m, 5.0)
        assert t_in[:, j] == pytest.approx([a for a, _ in want], rel=1e-12, abs=1e-12)
        assert t_out[:, j] == pytest.approx([b for _, b in want], rel=1e-12, abs=1e-12)


def test_section_drag_adds_the_largest_tension_of_each_section():
    want = by_hand(0.8, 0.35, 5.0)
    mission = SimpleNamespace(tether=tether(), tether_drag=3.0, route=route())
    assert section_drag(mission) == pytest.approx([3.0 + max(a, b) for a, b in want], rel=1e-12)
    assert section_drag(SimpleNamespace(tether=None, tether_drag=3.0, route=route())) == 3.0


def test_friction_draws_are_the_keyed_normal_stream_floored_at_zero():
    drawn = tether_frictions(tether(0.1, 0.2), 400, 7)
    normal = keyed_normal(7, "tether", (0.1, 0.2), 400)
    assert drawn == pytest.approx(np.maximum(0.1 + 0.2 * normal, 0.0), rel=1e-15)
    assert drawn.min() == 0.0 and (drawn == 0.0).sum() > 50  # a third of N(0.1, 0.2) is below 0


def test_drawn_drag_is_the_section_drag_of_each_draw():
    t = tether(0.3, 0.05)
    mission = SimpleNamespace(tether=t, tether_drag=2.0, route=route())
    drag = drawn_drag(mission, 5, 3)
    assert drag.shape == (6, 5)
    for j, m in enumerate(tether_frictions(t, 5, 3)):
        assert drag[:, j] == pytest.approx([2.0 + max(a, b) for a, b in by_hand(0.8, m, 5.0)], rel=1e-12)
    assert drawn_drag(SimpleNamespace(tether=tether(0.3, 0.0), tether_drag=2.0, route=route()), 5, 3) is None
    assert drawn_drag(SimpleNamespace(tether=None, tether_drag=2.0, route=route()), 5, 3) is None
