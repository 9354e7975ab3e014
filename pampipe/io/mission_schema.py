"""The mission file (docs/formats.md §4): :func:`load_mission`.

A well-formed file is read by its quick check (:data:`pampipe.io.quick_schemas.MISSION`); any other is
validated by its strict pydantic schema (:mod:`.mission_model`, imported only then), so that a problem
raises :class:`InputError` naming the file, the key, the value and what is allowed. The robot's PAM files
are read too (:mod:`.pam_schema`), the route is listed or taken from a pipe network (:mod:`.routes`), and
the measured wall contact of the PAM files is checked to agree where the mission uses it.
"""

from __future__ import annotations

from pathlib import Path

from pampipe.errors import InputError
from pampipe.io.distinct_sections import DistinctSections, distinct_sections
from pampipe.io.field_rules import relative
from pampipe.io.file_units import read_units
from pampipe.io.pam_schema import resolve_pam
from pampipe.io.plausible import unit_slips
from pampipe.io.quick_check import Fallback
from pampipe.io.quick_schemas import MISSION
from pampipe.io.routes import elbow_radius, listed_route, network_route
from pampipe.model.domain import check_kind
from pampipe.runtime.collector import paused
from pampipe.specs.mission import Mission, Segment, Steering
from pampipe.specs.tether import Compressor, Hose, Tether

#: The safety factor of a mission that gives none, and what the commands say about it.
DEFAULT_SAFETY_FACTOR = 1.0
NO_SAFETY_FACTOR = ("the mission gives no safety_factor, so 1 is used: the plan holds exactly the load, with "
                    "no margin for friction, load or model error; write e.g. 'safety_factor: 1.5'.")


def load_mission(path: str | Path, *, raw: dict | None = None) -> Mission:
    """Read and validate a mission file and the PAM files it names.

    ``raw``: the file's content as a mapping instead; relative paths resolve beside ``path``.
    """
    path = Path(path)
    # a long route is millions of acyclic objects (pampipe.runtime.collector)
    with paused(), read_units(path, raw, what="mission file") as content:
        return _load_mission(path, content)


def _load_mission(path: Path, content: dict) -> Mission:
    schema, distinct = _validated(path, content)
    segments = tuple(Segment(s.name, resolve_pam(path, s.pam, f"robot.segments[{i}].pam"), s.mass,
                             relative(path, s.pam) if isinstance(s.pam, str) else None, s.unit)
                     for i, s in enumerate(schema.robot.segments))
    if len({s.name for s in segments}) != len(segments):
        raise InputError(f"{path}: robot.segments: segment names must be unique, got "
                         f"{[s.name for s in segments]}.")
    masses = {f"robot.segments[{i}].mass": s.mass for i, s in enumerate(segments)}
    warnings = tuple(f"{path}: {slip}" for slip in unit_slips(schema.supply_pressure, masses,
                                                               schema.robot.payload))
    safety_factor = schema.safety_factor
    if safety_factor is None:
        safety_factor, warnings = DEFAULT_SAFETY_FACTOR, (*warnings, f"{path}: {NO_SAFETY_FACTOR}")
    for i, seg in enumerate(segments):
        try:
            check_kind(seg.pam.geometry, extensile=False, where=f"robot.segments[{i}].pam",
                       role="an anchoring segment")
        except InputError as exc:
            raise InputError(f"{path}: {exc}") from None
    steering = _steering(path, schema.robot.steering)
    elbow = elbow_radius(path, schema.elbow_radius, "elbow_radius")
    grip = MeasuredGrip(path, segments)
    if not isinstance(schema.route, list):  # a path through a network
        route = network_route(path, schema.route, segments, grip.friction, elbow=elbow)
        sections = [("route", schema.route.friction, schema.route.pipe_material)]
    else:
        route = listed_route(path, schema.route, grip.friction, elbow=elbow, distinct=distinct)
        sections = _sections(schema.route, distinct)
    warnings += grip.material_warnings(sections) + grip.effective_warning(schema.load_path is not None)
    load_path, kappa, kappa_sd = schema.load_path or "through_anchor", None, 0.0
    if schema.load_path is None and grip.coupling() is not None:
        load_path, (kappa, kappa_sd) = "from_pam", grip.coupling()
    return Mission(path, segments, schema.robot.payload, schema.supply_pressure, safety_factor,
                   load_path, schema.tether_drag, route, dict(schema.gait or {}), warnings,
                   kappa_sd=kappa_sd, load_coupling=kappa, steering=steering, bend_model=schema.bend_model,
                   joint_angle=schema.robot.joint_angle, tether=build_tether(schema.tether))


def _validated(path: Path, content: dict):
    """The mission validated (a :class:`~pampipe.io.quick_check.Record` of the quick check, or a
    ``MissionSchema`` of the schema) and, for a long listed route, where its sections lie among the distinct
    ones that were validated (:mod:`pampipe.io.distinct_sections`); a problem is found and told by
    validating the whole file with the schema, as for a short route."""
    distinct = distinct_sections(content.get("route")) if isinstance(content, dict) else None
    shown = content if distinct is None else {**content, "route": distinct.distinct(content["route"])}
    try:
        return MISSION(shown), distinct
    except Fallback:
        pass
    from pampipe.io.mission_model import MissionSchema
    from pampipe.specs.schema import validate

    if distinct is not None:
        try:
            return validate(path, MissionSchema, shown), distinct
        except InputError:
            pass  # validated whole below: the message names the section and its place
    return validate(path, MissionSchema, content), None


def _sections(route: list, distinct: DistinctSections | None) -> list[tuple]:
    """(where, friction, pipe material) of the sections whose measured friction may not fit their pipe
    (:meth:`MeasuredGrip.material_warnings`), in travel order: every section of a route given whole; of a
    long one, the places of the distinct sections that name a material and give no friction."""
    if distinct is None:
        return [(f"route[{i}] ({s.name})", s.friction, s.pipe_material) for i, s in enumerate(route)]
    warned = {k for k, s in enumerate(route)
              if s.friction in (None, "from_pam") and s.pipe_material is not None}
    if not warned:
        return []
    return [(f"route[{i}] ({distinct.names[i]})", route[k].friction, route[k].pipe_material)
            for i, k in enumerate(distinct.index.tolist()) if k in warned]


def _steering(path: Path, schema) -> Steering | None:
    """The steering module of ``robot.steering``: its PAM must be extensile."""
    if schema is None:
        return None
    pam = resolve_pam(path, schema.pam, "robot.steering.pam")
    try:
        check_kind(pam.geometry, extensile=True, where="robot.steering.pam", role="a steering PAM")
    except InputError as exc:
        raise InputError(f"{path}: {exc}") from None
    return Steering(pam, schema.count, schema.radius,
                    relative(path, schema.pam) if isinstance(schema.pam, str) else None)


def build_tether(schema) -> Tether | None:
    """The SI :class:`Tether` of a validated ``tether:`` block (None stays None)."""
    if schema is None:
        return None
    friction, sd = ((schema.friction.value, schema.friction.sd)
                    if hasattr(schema.friction, "sd") else (schema.friction, 0.0))
    hose = None if schema.hose is None else Hose(schema.hose.inner_diameter, schema.hose.roughness)
    compressor = None if schema.compressor is None else Compressor(schema.compressor.free_air_delivery)
    return Tether(schema.weight, friction, schema.back_tension, schema.length, sd, hose, compressor)


class MeasuredGrip:
    """The robot's measured wall contact (the PAM files' ``contact:`` blocks), checked to agree when used."""

    def __init__(self, path: Path, segments):
        self.path, self.segments, self.used = path, segments, False

    def _common(self, what: str, where: str, value):
        values = {seg.name: value(seg.pam.grip) if seg.pam.grip is not None else None
                  for seg in self.segments}
        missing = [name for name, v in values.items() if v is None]
        if missing and what == "friction":
            raise InputError(f"{self.path}: {where}: the friction is taken from the PAM files (from_pam "
                             f"or absent), and the PAM of segment(s) {', '.join(missing)} has no contact: "
                             "block; run `pampipe identify` on a slip test (kind: slip) with -o, or give the "
                             "friction, e.g. 'friction: 0.3'.")
        if missing:
            return None
        if len(set(values.values())) > 1:
            shown = ", ".join(f"{name}: {v}" for name, v in values.items())
            raise InputError(f"{self.path}: {where}: the segments' PAM files measured different {what} "
                             f"({shown}); one section has one {what}: give it in the mission, or use PAM "
                             "files that agree.")
        return next(iter(values.values()))

    def friction(self, where: str) -> tuple[float, float]:
        """(μ, σ_μ) of every segment's PAM (they must agree)."""
        self.used = True
        return self._common("friction", where, lambda g: (g.friction, g.friction_sd))

    def effective_warning(self, kappa_given: bool) -> tuple[str, ...]:
        """What a measured friction means when its slip tests did not determine κ (one bore)."""
        grip = self.segments[0].pam.grip
        if not self.used or grip is None or grip.load_coupling is not None:
            return ()
        bores = ", ".join(f"{d * 1e3:.4g} mm" for d in grip.tested_diameters) or "the tested bore"
        path = "the load path" if kappa_given else "load_path through_anchor (kappa = 1, the default)"
        return (f"{self.path}: the PAM's friction {grip.friction:.4g} is the effective friction mu/(1 + "
                f"kappa*mu*pi*A) of slip tests at {bores} only (kappa not determined); with {path} the "
                "plan is conservative for any kappa in [0, 1] (docs/physics.md §13.3); slip tests at a "
                "second bore would give mu and kappa.",)

    def coupling(self) -> tuple[float, float] | None:
        """(κ, σ_κ) when every segment's PAM measured the same κ, else None."""
        if any(seg.pam.grip is None or seg.pam.grip.load_coupling is None for seg in self.segments):
            return None
        return self._common("load_coupling", "load_path", lambda g: (g.load_coupling, g.load_coupling_sd))

    def material_warnings(self, sections) -> tuple[str, ...]:
        """A warning for each section using the measured friction on another pipe material than tested."""
        out = []
        for where, friction, material in sections:
            if friction not in (None, "from_pam") or material is None:
                continue
            tested = {seg.pam.grip.pipe_material for seg in self.segments if seg.pam.grip is not None}
            if tested != {material}:
                shown = ", ".join(sorted(t or "an unnamed material" for t in tested))
                out.append(f"{self.path}: {where}: the friction comes from slip tests on {shown}, and this "
                           f"section's pipe is {material}: friction differs between materials; test a "
                           f"{material} pipe or give the friction.")
        return tuple(out)
