"""The anchoring law of one mission as a CasADi function of the section: what the C code computes.

For segment i (rear to front) and a section of inner diameter D, incline φ, wall friction μ and
payload m [kg], with the mission's robot, safety factor SF, load path κ and tether drag built in:

    W_i = g(M|sin φ| + μ cos φ (M − m_i)) + F_tether,   M = Σm_j + m    (pampipe.model.no_slip)
    P_i = Muscle.closed_form_pressure(D, W_i, κ, μ, SF)                 (docs/physics.md §8.3)

the same calls `plan` makes, on CasADi symbols instead of numbers. With ``--confidence C`` each P_i gains
a margin ΔP_i [Pa] (:func:`confidence_margins`): the largest P_C − P_nominal that `plan --confidence C`
needs for segment i over the mission's sections, so that the law plans at C there. The reasons follow `plan`'s
order (docs/physics.md §8.4): no wall friction, then a pipe not wider than a muscle at rest, then a
pipe the braid cannot fill, then a pressure above the supply (inf included).

Every argument comes from a live sensor on the robot, so each is checked first (:data:`DOMAIN`):
0 < D ≤ 10 m, |φ| ≤ π/2, 0 ≤ μ ≤ 10 and 0 ≤ m ≤ 10⁵ kg, the ranges a mission file allows, each
finite; anything else (NaN and ±inf included) is ``BAD_ARGUMENT``. Outside |φ| ≤ π/2 the load
formula is wrong (cos φ < 0 makes the sliding term negative), so the law never answers there.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import IntEnum

import casadi as ca
import numpy as np

from pampipe.errors import InputError
from pampipe.model import no_slip
from pampipe.model.braid import diameter_at_length
from pampipe.model.effects import LIBRARY
from pampipe.planning.feasibility import pressure_limits
from pampipe.planning.problem import mission_muscles
from pampipe.units.quantities import real_number

INPUTS = ("inner_diameter_m", "incline_rad", "friction", "payload_kg")

#: The range of each argument, inclusive unless ``open`` says so: (low, high, open_low) in SI. The
#: bounds are those a mission file accepts (pampipe.io.mission_schema); π/2 is the double nearest to it.
#: Friction below this is no friction (reason 3): a sliding load μ·g·M this small underflows to
#: subnormal floats, where the law's arithmetic no longer holds. No wall is this slippery.
FRICTION_MIN = 1e-6
DOMAIN = {"inner_diameter_m": (0.0, 10.0, True), "incline_rad": (-math.pi / 2, math.pi / 2, False),
          "friction": (0.0, 10.0, False), "payload_kg": (0.0, 1e5, False)}


def in_domain(*arguments) -> bool:
    """True if (D, φ, μ, m) are real numbers (:func:`pampipe.units.quantities.real_number`: numpy, Decimal,
    Fraction
    too), finite and within :data:`DOMAIN` (NaN is not)."""
    for value, (low, high, open_low) in zip(arguments, DOMAIN.values(), strict=True):
        try:
            value = real_number(value)
        except InputError:  # beyond the float range
            return False
        if value is None or not (low < value <= high if open_low else low <= value <= high):
            return False
    return True


class Reason(IntEnum):
    """Return codes of ``pampipe_required_pressure`` (docs/commands.md §9; 5 is an addition)."""

    OK = 0
    NARROW = 1  # the pipe is not wider than a muscle at rest
    WIDE = 2  # the pipe is wider than the braid can fill
    NO_FRICTION = 3  # no wall friction (below FRICTION_MIN)
    ABOVE_SUPPLY = 4  # a segment needs more than the supply (or no pressure up to 100 MPa holds)
    BAD_ARGUMENT = 5  # an argument outside DOMAIN: NaN, infinite, or out of its range


@dataclass(frozen=True)
class Law:
    """The mission's anchoring law: the SX function and the constants of the reason checks (SI)."""

    function: ca.Function  # (D, φ, μ, m) -> P_1..P_n [Pa], inf where the closed form does not hold
    segments: tuple[str, ...]
    masses: tuple[float, ...]  # [kg]
    rest_diameters: tuple[float, ...]  # D₀ per segment [m]
    largest_diameters: tuple[float, ...]  # D(B/√3) per segment, or D at its max_contraction if less [m]
    supply_pressure: float  # [Pa]
    safety_factor: float
    load_path: str
    kappa: float
    tether_drag: float  # [N]
    payload: float  # the mission's payload [kg]
    effects: dict  # segment name -> {effect: {parameter: SI value}} of its PAM
    pressure_limits: tuple[float, ...] = ()  # per segment [Pa]: the supply, or its max_pressure if lower
    confidence: float | None = None  # C of the margins (None: the nominal law)
    margins: tuple[float, ...] = ()  # ΔP_i [Pa] added to each segment's pressure (empty: none)
    samples: int | None = None  # the draws the margins were sampled with (None: the default)

    @property
    def limits(self) -> np.ndarray:
        """Each segment's pressure limit [Pa] (the supply where none is given)."""
        return np.array(self.pressure_limits or (self.supply_pressure,) * len(self.segments), dtype=float)

    @property
    def narrowest(self) -> float:
        """Pipes up to this diameter [m] are too narrow for some muscle (reason 1)."""
        return max(self.rest_diameters)

    @property
    def widest(self) -> float:
        """Pipes from this diameter [m] on are too wide for some braid (reason 2)."""
        return min(self.largest_diameters)

    def evaluate(self, diameter: float, incline: float, friction: float, payload: float):
        """(reason, pressures [Pa]) in Python, as the C function answers (NaN where it writes NaN).

        Anything but four real numbers within :data:`DOMAIN` is ``BAD_ARGUMENT``, as in C.
        """
        nan = np.full(len(self.segments), np.nan)
        if not in_domain(diameter, incline, friction, payload):
            return Reason.BAD_ARGUMENT, nan
        diameter, incline, friction, payload = map(real_number, (diameter, incline, friction, payload))
        if not friction >= FRICTION_MIN:
            return Reason.NO_FRICTION, nan
        if diameter <= self.narrowest:
            return Reason.NARROW, nan
        if diameter >= self.widest:
            return Reason.WIDE, nan
        pressure = np.array([float(p) for p in self.function(diameter, incline, friction, payload)])
        return (Reason.OK if np.all(pressure <= self.limits) else Reason.ABOVE_SUPPLY), pressure


def confidence_margins(mission, confidence: float, **sampling) -> tuple[float, ...]:
    """ΔP_i [Pa] per segment: the largest P_C − P_nominal of `plan --confidence C` over the sections
    where the segment plans (0 where none does); ``sampling``: ``samples``/``seed`` of the plan."""
    from pampipe.planning.planner import plan_mission

    plan = plan_mission(mission, confidence=confidence, **sampling)
    a = plan.arrays
    with np.errstate(invalid="ignore"):
        finite = np.isfinite(a.pressure) & np.isfinite(a.nominal_pressure)
        gap = np.where(finite, a.pressure - a.nominal_pressure, -np.inf)
    return tuple(float(max(g, 0.0)) for g in np.max(gap, axis=0))


def mission_law(mission, *, confidence: float | None = None, margins: tuple[float, ...] = (),
                samples: int | None = None) -> Law:
    """Build the anchoring law of ``mission`` (InputError if a PAM's effects have no closed form), with
    ``margins`` [Pa] per segment added at ``confidence`` (see :func:`confidence_margins`; ``samples``
    its draws, when given)."""
    muscles = mission_muscles(mission)
    refused = [(seg, name, why) for seg, m in zip(mission.segments, muscles, strict=True)
               for name, why in m.closed_form_refusals().items()]
    if refused:
        seg, name, why = refused[0]
        raise InputError(
            f"{mission.source}: robot segment {seg.name} (PAM '{seg.pam.name}'): the effect '{name}' cannot "
            f"be exported to C: {why}. `pampipe plan` handles it by bisection on the model, but the exported "
            "law is the closed form. Export with a PAM without this effect (e.g. the file `pampipe identify` "
            "wrote), or with one whose effects are among "
            f"{', '.join(name for name, e in LIBRARY.items() if not e.no_closed_form)}.")
    d, incline, friction, payload = (ca.SX.sym(name) for name in INPUTS)
    total = sum(seg.mass for seg in mission.segments) + payload
    outputs = []
    for i, (seg, muscle) in enumerate(zip(mission.segments, muscles, strict=True)):
        load = no_slip.anchor_load(total, seg.mass, incline, friction, mission.tether_drag)
        pressure = muscle.closed_form_pressure(d, load, kappa=mission.kappa, friction=friction,
                                               safety_factor=mission.safety_factor)
        outputs.append(pressure + margins[i] if margins else pressure)
    function = ca.Function("pampipe_required_pressure", [d, incline, friction, payload], ca.cse(outputs),
                           list(INPUTS), [f"pressure_{i}" for i in range(len(outputs))])
    geometry = [seg.pam.geometry for seg in mission.segments]
    return Law(function, tuple(seg.name for seg in mission.segments),
               tuple(seg.mass for seg in mission.segments),
               tuple(g.initial_diameter for g in geometry),
               tuple(_widest(seg.pam) for seg in mission.segments),
               mission.supply_pressure, mission.safety_factor, mission.load_path, mission.kappa,
               mission.tether_drag, mission.payload,
               {seg.name: seg.pam.effects for seg in mission.segments if seg.pam.effects},
               tuple(float(v) for v in pressure_limits(mission)), confidence=confidence,
               margins=tuple(margins), samples=samples)


def _widest(pam) -> float:
    """The widest bore [m] a muscle may anchor in: D(B/√3), or where it reaches its rated max_contraction."""
    g = pam.geometry
    if pam.max_contraction is None:
        return g.largest_diameter
    return min(g.largest_diameter, float(diameter_at_length((1 - pam.max_contraction) * g.initial_length, g)))
