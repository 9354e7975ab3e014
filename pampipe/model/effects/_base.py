"""The protocol of an effect (docs/physics.md §9): its parameters, the state its hooks see, and the hooks.

An effect is a small strategy object (in the style of pysindy's feature libraries): a name, named bounded
parameters with units and a null value, and one or more *hooks* that modify a stage of the forward model.
At its null value every hook is the identity, so the model reduces exactly to the baseline
(docs/physics.md §4-§7). Hooks work on floats, numpy arrays and CasADi symbols alike; parameter values are
SI (``values[name]``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar


@dataclass(frozen=True)
class Parameter:
    """One named parameter of an effect: display unit, SI bounds and null value.

    ``dimension`` is the :mod:`pampipe.units.quantities` dimension used to read it from a PAM file; ``scale``
    is the SI value of one display ``unit`` (the NLP works in display units, which are O(1)).
    ``fit_lower`` [SI] is the lower bound `diagnose` fits it within where the effect's physics fixes its sign
    (contact stiffening stiffens: its increments ≥ 0); None: ``lower``. A PAM file may still state any value
    in [``lower``, ``upper``].
    """

    name: str
    unit: str
    dimension: str
    scale: float
    lower: float
    upper: float
    null: float = 0.0
    description: str = ""
    fit_lower: float | None = None

    @property
    def fit_bounds(self) -> tuple[float, float]:
        """(low, high) [SI] of the parameter in `diagnose`'s refit: its physical sign kept."""
        return (self.lower if self.fit_lower is None else self.fit_lower), self.upper

    @property
    def json_key(self) -> str:
        """The JSON key with its SI unit suffix (docs/formats.md §1), e.g. ``f0_N``."""
        return f"{self.name}_{self.si_suffix}" if self.si_suffix else self.name

    @property
    def si_suffix(self) -> str:
        return {"force": "N", "pressure": "Pa", "area": "N_per_Pa", "compliance": "per_N",
                "dimensionless": ""}[self.dimension]


@dataclass(frozen=True)
class State:
    """What the hooks see at one evaluation point (SI): the muscle, its moduli and the test."""

    pressure: Any  # effective gauge pressure [Pa]
    length: Any  # [m]
    diameter: Any  # [m] (the pipe diameter when anchored)
    geometry: Any
    theta: Any  # moduli [Pa]
    reference_pressure: Any  # [Pa]
    axial_load: Any = 0.0  # effective F_a [N] (pipe tests)
    leg: Any = 0.0  # sign of the length rate: +1 lengthening, −1 shortening, 0 at rest
    in_pipe: bool = False
    pressure_leg: Any = 0.0  # sign of the pressure rate: +1 filling, −1 venting, 0 held


class Effect:
    """Base class: every hook is the identity, so a bare Effect is the baseline model.

    The hooks, by stage of the forward model (:mod:`pampipe.model.effects`): ``pressure`` (and its inverse
    ``pressure_inverse``), ``load``, ``braid_strain``, ``axial_increment``, ``radial_factor`` and
    ``radial_increment``; ``contact_increments`` gives the moduli increments Δθ of an anchored muscle.
    A hook that returns None adds nothing.
    """

    name: ClassVar[str] = ""
    section: ClassVar[str] = ""  # docs/physics.md section
    summary: ClassVar[str] = ""
    signature: ClassVar[str] = ""  # the residual signature (diagnose) that points to this effect
    parameters: ClassVar[tuple[Parameter, ...]] = ()
    tests: ClassVar[frozenset[str]] = frozenset({"axial", "radial"})  # test kinds it changes
    no_closed_form: ClassVar[str] = ""  # why the closed-form holding pressure cannot carry it ("" if it can)

    @property
    def null_values(self) -> dict[str, float]:
        return {p.name: p.null for p in self.parameters}

    def pressure(self, pressure, values):
        return pressure

    def pressure_inverse(self, pressure, values):
        """The measured pressure whose ``pressure`` hook gives ``pressure`` (closed-form effects)."""
        return pressure

    def contact_increments(self, size: int, values):
        """Δθ [Pa] (``size`` entries, ordered like θ) this effect adds once anchored; None if none."""
        return None

    def load(self, axial_load, values):
        return axial_load

    def braid_strain(self, tension, values):
        return None

    def axial_increment(self, state: State, values):
        return None

    def radial_factor(self, state: State, values):
        return None

    def radial_increment(self, state: State, values):
        return None
