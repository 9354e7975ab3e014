"""The inventory file of `pampipe design` (docs/commands.md §8): a strict schema → :class:`Inventory`.

```yaml
material: ../pams/paper-radial-pam.yaml   # a PAM whose moduli and bladder thickness are the material
robot: {segments: [0.4 kg, 0.4 kg, 0.4 kg], payload: 2 kg}   # masses rear to front (or {name, mass})
supply_pressure: 689 kPa
safety_factor: 1.5
load_path: through_anchor
pipes:                                    # a list of pipes, or {network: ky4, friction: 0.3}
  - {name: riser, inner_diameter: 3 in, incline: 90 deg, friction: 0.3, length: 120 m}
design:
  initial_length: [200 mm, 400 mm]
  initial_diameter: [30 mm, 70 mm]
  braid_angle_from_axis: [15 deg, 35 deg] # or braid_angle_from_transverse: [55 deg, 75 deg]
  clearance: 2 mm
  objective: max_pressure                 # max_pressure | air | speed
```

A pipe's ``inner_diameter`` is a length or a standard size with an optional tolerance, as a route
section's (:func:`pampipe.specs.pipes.bore`). ``{network: NAME, friction: MU}`` takes every pipe of an
EPANET network (:func:`pampipe.specs.network.whole_network`), optionally only those with ``min_bore`` ≤
bore ≤ ``max_bore``.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Literal

import numpy as np
from pydantic import Field, model_validator

from pampipe.errors import InputError
from pampipe.io.file_units import read_units
from pampipe.io.pam_model import PamSchema
from pampipe.io.pam_schema import build_pam, load_pam
from pampipe.specs.inventory import DesignSpace, Inventory, Objective, Pipes
from pampipe.specs.pipes import bore
from pampipe.specs.schema import Strict, quantity, validate

Length = quantity("length", gt=0, le=10.0, unit="m")
PipeLength = quantity("length", gt=0, le=1e7, unit="m")
Mass = quantity("mass", ge=0, le=1e5, unit="kg")
Angle = quantity("angle", gt=0, lt=math.pi / 2, unit="rad")
Incline = quantity("angle", ge=-math.pi / 2, le=math.pi / 2, unit="rad")
Friction = quantity("dimensionless", ge=0, le=10)
#: Largest braid angle from the axis of a contractile muscle: arctan √2 = 54.7356° (docs/physics.md §2).
CONTRACTILE = math.atan(math.sqrt(2))


class SegmentMass(Strict):
    name: str = Field(min_length=1)
    mass: Mass


class RobotSchema(Strict):
    segments: list[Mass | SegmentMass] = Field(min_length=3, max_length=3)
    payload: Mass = 0.0


class PipeSchema(Strict):
    name: str = Field(min_length=1)
    inner_diameter: Any  # a length or a standard size, read by pampipe.specs.pipes.bore
    length: PipeLength
    incline: Incline = 0.0
    friction: Friction


class NetworkSchema(Strict):
    network: str = Field(min_length=1)
    friction: Friction
    min_bore: Length | None = None
    max_bore: Length | None = None


class DesignSchema(Strict):
    initial_length: list[Length] = Field(min_length=2, max_length=2)
    initial_diameter: list[Length] = Field(min_length=2, max_length=2)
    braid_angle_from_axis: list[Angle] | None = Field(default=None, min_length=2, max_length=2)
    braid_angle_from_transverse: list[Angle] | None = Field(default=None, min_length=2, max_length=2)
    clearance: quantity("length", ge=0, le=1.0, unit="m") = 2e-3
    contact_margin: quantity("dimensionless", ge=0, lt=1) = 0.05
    min_stride: quantity("length", ge=0, le=10.0, unit="m") = 0.0
    objective: Literal["max_pressure", "air", "speed"] = "max_pressure"
    sizes: int | None = Field(default=None, ge=1, le=20)
    starts: int = Field(default=16, ge=1, le=10000)
    seed: int = Field(default=0, ge=0)

    @model_validator(mode="after")
    def _bounds(self):
        given = [self.braid_angle_from_axis is not None, self.braid_angle_from_transverse is not None]
        if sum(given) != 1:
            raise ValueError("give exactly one of braid_angle_from_axis (e.g. [15 deg, 35 deg]) or "
                             "braid_angle_from_transverse (the paper's convention, e.g. [55 deg, 75 deg]); "
                             f"{'both were' if all(given) else 'neither was'} given")
        for key in ("initial_length", "initial_diameter", "braid_angle_from_axis",
                    "braid_angle_from_transverse"):
            pair = getattr(self, key)
            if pair is not None and pair[0] > pair[1]:
                raise ValueError(f"design.{key}: the lower bound {pair[0]:.6g} is above the upper bound "
                                 f"{pair[1]:.6g} (SI); give [lower, upper]")
        return self

    @property
    def angle(self) -> tuple[float, float]:
        """(α_lo, α_hi) [rad] from the axis."""
        if self.braid_angle_from_axis is not None:
            return tuple(self.braid_angle_from_axis)
        high, low = (math.pi / 2 - a for a in self.braid_angle_from_transverse)
        return low, high


class InventorySchema(Strict):
    material: str | PamSchema
    robot: RobotSchema
    supply_pressure: quantity("pressure", gt=0, le=1e8, unit="Pa")
    safety_factor: quantity("dimensionless", ge=1, le=100) = 1.0
    load_path: Literal["through_anchor", "distributed", "none"] = "through_anchor"
    tether_drag: quantity("force", ge=0, le=1e7, unit="N") = 0.0
    pipes: list[PipeSchema] | NetworkSchema
    design: DesignSchema


def load_inventory(path: str | Path, *, raw: dict | None = None) -> Inventory:
    """Read and validate an inventory file, the material PAM it names and the network it reads.

    ``raw``: the file's content as a mapping instead; relative paths resolve beside ``path``.
    """
    path = Path(path)
    with read_units(path, raw, what="inventory file") as content:
        return _load_inventory(path, content)


def _load_inventory(path: Path, content: dict) -> Inventory:
    schema = validate(path, InventorySchema, content)
    material, material_file = _material(path, schema.material)
    if material.moduli is None:
        raise InputError(f"{path}: material: the PAM '{material.name}' has no 'moduli:' block; the design "
                         "needs the bladder material's moduli (run `pampipe identify` first).")
    space = _space(path, schema.design, material)
    names, masses = [], []
    for i, seg in enumerate(schema.robot.segments):
        names.append(seg.name if isinstance(seg, SegmentMass) else f"PAM{i + 1}")
        masses.append(seg.mass if isinstance(seg, SegmentMass) else float(seg))
    if len(set(names)) != len(names):
        raise InputError(f"{path}: robot.segments: segment names must be unique, got {names}.")
    network = schema.pipes.network if isinstance(schema.pipes, NetworkSchema) else None
    pipes = _network_pipes(path, schema.pipes) if network else _listed_pipes(path, schema.pipes)
    return Inventory(path, material, tuple(names), tuple(masses), schema.robot.payload,
                     schema.supply_pressure, schema.safety_factor, schema.load_path, schema.tether_drag,
                     pipes, space, material_file=material_file, network=network)


def _material(path: Path, ref: str | PamSchema):
    if isinstance(ref, PamSchema):
        try:
            return build_pam(ref), None
        except (InputError, ValueError) as exc:
            raise InputError(f"{path}: material: {exc}") from None
    target = Path(ref).expanduser()
    target = target if target.is_absolute() else path.parent / target
    try:
        return load_pam(target), target
    except InputError as exc:
        raise InputError(f"{path}: material: {exc}") from None


def _space(path: Path, d: DesignSchema, material) -> DesignSpace:
    low, high = d.angle
    if high >= CONTRACTILE:
        raise InputError(f"{path}: design: the braid angle bound {math.degrees(high):.4g} deg from the axis "
                         f"is not below {math.degrees(CONTRACTILE):.4f} deg: the muscle would not contract. "
                         "Did you give angles from the transverse plane as braid_angle_from_axis?")
    thickness = material.geometry.bladder_thickness
    if d.initial_diameter[0] <= 2 * thickness:
        raise InputError(f"{path}: design.initial_diameter: the lower bound "
                         f"{d.initial_diameter[0] * 1e3:.4g} mm is not above twice the material's bladder "
                         f"thickness ({2 * thickness * 1e3:.4g} mm): the bladder would fill the braid. Raise "
                         "the bound.")
    return DesignSpace(tuple(d.initial_length), tuple(d.initial_diameter), (low, high), d.clearance,
                       d.contact_margin, d.min_stride, Objective(d.objective), d.sizes, d.starts, d.seed)


def _listed_pipes(path: Path, pipes: list[PipeSchema]) -> Pipes:
    if not pipes:
        raise InputError(f"{path}: pipes: the list is empty; give at least one pipe, or "
                         "{network: ky4, friction: 0.3}.")
    names = [p.name for p in pipes]
    if len(set(names)) != len(names):
        raise InputError(f"{path}: pipes: pipe names must be unique.")
    bores = []
    for i, p in enumerate(pipes):
        try:
            bores.append(bore(p.inner_diameter, where=f"pipes[{i}].inner_diameter"))
        except InputError as exc:
            raise InputError(f"{path}: {exc}") from None
    return Pipes(tuple(names), np.array([b.nominal for b in bores]), np.array([b.low for b in bores]),
                 np.array([b.high for b in bores]), np.array([p.length for p in pipes]),
                 np.array([p.incline for p in pipes]), np.array([p.friction for p in pipes]))


def _network_pipes(path: Path, spec: NetworkSchema) -> Pipes:
    from pampipe.io.epanet import load_network
    from pampipe.specs.network import whole_network

    try:
        sections = whole_network(load_network(spec.network, base=path.parent), friction=spec.friction)
    except InputError as exc:
        raise InputError(f"{path}: pipes.network: {exc}") from None
    keep = np.ones(len(sections), dtype=bool)
    if spec.min_bore is not None:
        keep &= sections.diameter >= spec.min_bore
    if spec.max_bore is not None:
        keep &= sections.diameter <= spec.max_bore
    if not keep.any():
        raise InputError(f"{path}: pipes: no pipe of network {spec.network} has a bore between min_bore and "
                         "max_bore.")
    d = sections.diameter[keep]
    return Pipes(tuple(str(n) for n in sections.name[keep]), d, d.copy(), d.copy(), sections.length[keep],
                 sections.incline[keep], sections.friction[keep])
