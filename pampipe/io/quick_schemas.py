"""The quick check's shapes of the PAM and mission files (:mod:`.quick_check`; docs/formats.md §2, §4), and
the checks of a whole block that the schema classes share with them.

Each :class:`~pampipe.io.quick_check.Shape` mirrors the strict schema class of the same name
(:mod:`.pam_model`, :mod:`.mission_model`, :mod:`.tether_schema`) key for key, with the same rules
(:mod:`.field_rules`); ``tests/io/test_quick_schemas.py`` checks that both give the same objects on every
bundled file and that the quick check hands every broken one to the schema.
"""

from __future__ import annotations

import math

from pampipe.io import field_rules as rules
from pampipe.io.quick_check import (
    REQUIRED,
    Shape,
    anything,
    finite_number,
    keyed,
    listed,
    literal,
    mapping_or,
    optional,
    quantity,
    scalar,
    text,
    then,
    whole,
)
from pampipe.units.quantities import to_si


# ---------------------------------------------------------------------------- checks of a whole block
def one_angle(geometry) -> None:
    """A PAM's ``geometry:`` gives exactly one of its two braid angles."""
    given = [geometry.braid_angle_from_transverse is not None, geometry.braid_angle_from_axis is not None]
    if sum(given) != 1:
        raise ValueError("give exactly one of braid_angle_from_transverse (the paper's convention, "
                         "e.g. '65.92 deg') or braid_angle_from_axis (e.g. '24.08 deg'); "
                         f"{'both were' if all(given) else 'neither was'} given")


def same_length(law) -> None:
    """A law's ``a`` and ``b`` have as many coefficients."""
    if len(law.a) != len(law.b):
        raise ValueError(f"'a' has {len(law.a)} coefficients and 'b' has {len(law.b)}; "
                         "they must have the same length (degree + 1)")


def consistent_moduli(moduli) -> None:
    """``moduli.unit`` is a pressure unit; the axial, hoop (and contact) laws are of one degree."""
    to_si(f"1 {moduli.unit}", "pressure", where=f"unit {moduli.unit!r}")
    sizes = {len(moduli.axial.a), len(moduli.hoop.a)}
    if moduli.contact is not None:
        sizes |= {len(moduli.contact.axial.a), len(moduli.contact.hoop.a)}
    if len(sizes) != 1:
        raise ValueError("axial, hoop (and contact) laws must have the same number of coefficients")


def three_segments(segments: list) -> list:
    """A robot has exactly 3 segments."""
    if len(segments) != 3:
        raise ValueError(f"needs exactly 3 segments (rear to front), got {len(segments)}")
    return segments


# ---------------------------------------------------------------------------- the PAM file
_TEXT = text()
_NAME = text(min_length=1)
_MATERIAL = optional(text(min_length=1, max_length=100))
_LENGTH = quantity(rules.LENGTH)
_ANGLE = quantity(rules.ANGLE)
_FRICTION = quantity(rules.FRICTION)
_COEFFICIENTS = listed(finite_number, 1, 8)
_UNCERTAIN_LENGTH = Shape("UncertainLength", {"value": (_LENGTH, REQUIRED),
                                              "sd": (quantity(rules.LENGTH_SD), REQUIRED)})
_UNCERTAIN_ANGLE = Shape("UncertainAngle", {"value": (_ANGLE, REQUIRED),
                                            "sd": (quantity(rules.ANGLE_SD), REQUIRED)})
_GEOMETRY = Shape("GeometrySchema", {
    "initial_length": (mapping_or(_UNCERTAIN_LENGTH, _LENGTH), REQUIRED),
    "initial_diameter": (mapping_or(_UNCERTAIN_LENGTH, _LENGTH), REQUIRED),
    "braid_angle_from_transverse": (optional(mapping_or(_UNCERTAIN_ANGLE, _ANGLE)), None),
    "braid_angle_from_axis": (optional(mapping_or(_UNCERTAIN_ANGLE, _ANGLE)), None),
    "bladder_thickness": (mapping_or(_UNCERTAIN_LENGTH, _LENGTH), REQUIRED),
    "wall": (literal("thick", "thin"), "thick"),
    "fitting_length": (quantity(rules.LENGTH_SD), 0.0)}, after=one_angle)
_LAW = Shape("LawSchema", {"a": (_COEFFICIENTS, REQUIRED), "b": (_COEFFICIENTS, REQUIRED)},
             after=same_length)
_CONTACT = Shape("ContactSchema", {"axial": (_LAW, REQUIRED), "hoop": (_LAW, REQUIRED)})
_MODULI = Shape("ModuliSchema", {
    "unit": (_TEXT, "MPa"), "reference_pressure": (quantity(rules.REFERENCE_PRESSURE), 1e6),
    "axial": (_LAW, REQUIRED), "hoop": (_LAW, REQUIRED), "contact": (optional(_CONTACT), None)},
    after=consistent_moduli)
_UNDETERMINED = Shape("UndeterminedSchema", {
    "direction": (keyed(finite_number, min_length=1), REQUIRED),
    "scale": (quantity(rules.DIRECTION_SCALE), 1.0), "moves": (keyed(finite_number), {}),
    "test": (_TEXT, "")})
_UNCERTAINTY = Shape("UncertaintySchema", {
    "unit": (_TEXT, "MPa"), "parameters": (optional(listed(_TEXT, 1, 64)), None),
    "covariance": (listed(listed(finite_number)), REQUIRED),
    "model_error": (quantity(rules.NON_NEGATIVE_FORCE), 0.0),
    "model_error_dof": (optional(whole(ge=1)), None), "undetermined": (listed(_UNDETERMINED, 0, 64), []),
    "prior_determined": (listed(_UNDETERMINED, 0, 64), [])})
_MEASURED = Shape("MeasuredValue", {"value": (_FRICTION, REQUIRED), "sd": (_FRICTION, 0.0)})
_GRIP = Shape("GripSchema", {
    "friction": (_MEASURED, REQUIRED), "load_coupling": (optional(_MEASURED), None),
    "pipe_material": (_MATERIAL, None), "tested_pipe_diameters": (optional(listed(_LENGTH, 0, 100)), None)})
PAM = Shape("PamSchema", {
    "name": (_NAME, REQUIRED), "geometry": (_GEOMETRY, REQUIRED), "moduli": (optional(_MODULI), None),
    "uncertainty": (optional(_UNCERTAINTY), None), "effects": (optional(keyed(keyed(anything))), None),
    "contact": (optional(_GRIP), None), "max_pressure": (optional(quantity(rules.POSITIVE_PRESSURE)), None),
    "max_contraction": (optional(quantity(rules.CONTRACTION)), None)})

# ---------------------------------------------------------------------------- the mission file
_MASS = quantity(rules.MASS)
_PAM_REF = mapping_or(PAM, _TEXT)
_RADIUS = optional(scalar(str, float, int))
_SEGMENT = Shape("SegmentSchema", {"name": (_NAME, REQUIRED), "pam": (_PAM_REF, REQUIRED),
                                   "mass": (_MASS, REQUIRED), "unit": (literal("tested", "lot"), "lot")})
_STEERING = Shape("SteeringSchema", {"pam": (_PAM_REF, REQUIRED), "count": (literal(3), 3),
                                     "radius": (_LENGTH, REQUIRED)})
_ROBOT = Shape("RobotSchema", {
    "segments": (then(listed(_SEGMENT), three_segments), REQUIRED), "payload": (_MASS, 0.0),
    "steering": (optional(_STEERING), None), "joint_angle": (optional(quantity(rules.JOINT_ANGLE)), None)})
_BEND = Shape("BendSchema", {"angle": (quantity(rules.BEND_ANGLE), REQUIRED), "radius": (_RADIUS, None),
                             "direction": (quantity(rules.BEND_DIRECTION), math.pi)})
_UNCERTAIN_FRICTION = Shape("UncertainFriction", {"value": (_FRICTION, REQUIRED), "sd": (_FRICTION, 0.0)})


def _section_friction(value):
    """``from_pam``, a friction, ``{value, sd}`` or absent (None)."""
    if value is None or (type(value) is str and value == "from_pam"):
        return value
    return mapping_or(_UNCERTAIN_FRICTION, _FRICTION)(value)


SECTION = Shape("SectionSchema", {
    "name": (_NAME, REQUIRED), "length": (quantity(rules.ROUTE_LENGTH), REQUIRED),
    "inner_diameter": (anything, REQUIRED), "incline": (quantity(rules.INCLINE), 0.0),
    "friction": (_section_friction, None), "pipe_material": (_MATERIAL, None),
    "bend": (optional(_BEND), None)})
_NODE = optional(scalar(str, int))
_NETWORK_ROUTE = Shape("NetworkRouteSchema", {
    "network": (_NAME, REQUIRED), "from_node": (_NODE, None), "to_node": (_NODE, None),
    "friction": (_section_friction, None), "tolerance": (_RADIUS, None), "sd": (_RADIUS, None),
    "pipe_material": (_MATERIAL, None)}, aliases={"from_node": "from", "to_node": "to"})
_TETHER = Shape("TetherSchema", {
    "weight": (then(quantity(rules.weight), rules.weight_range), REQUIRED),
    "friction": (mapping_or(Shape("UncertainTetherFriction", {"value": (_FRICTION, REQUIRED),
                                                              "sd": (_FRICTION, 0.0)}), _FRICTION), REQUIRED),
    "back_tension": (quantity(rules.NON_NEGATIVE_FORCE), 0.0),
    "length": (quantity(rules.TETHER_LENGTH), REQUIRED),
    "hose": (optional(Shape("HoseSchema", {"inner_diameter": (quantity(rules.HOSE_BORE), REQUIRED),
                                           "roughness": (quantity(rules.ROUGHNESS), 1.5e-6)})), None),
    "compressor": (optional(Shape("CompressorSchema", {
        "free_air_delivery": (quantity(rules.FREE_AIR_DELIVERY), REQUIRED)})), None)})


def _route(value):
    """A list of at least one section, or a path through a network."""
    return listed(SECTION, min_length=1)(value) if isinstance(value, list) else _NETWORK_ROUTE(value)


MISSION = Shape("MissionSchema", {
    "robot": (_ROBOT, REQUIRED), "supply_pressure": (quantity(rules.POSITIVE_PRESSURE), REQUIRED),
    "safety_factor": (optional(quantity(rules.SAFETY_FACTOR)), None),
    "load_path": (optional(literal("through_anchor", "distributed", "none")), None),
    "tether_drag": (quantity(rules.NON_NEGATIVE_FORCE), 0.0), "route": (_route, REQUIRED),
    "gait": (optional(keyed(anything)), None), "elbow_radius": (scalar(str, float, int), "1.5 D"),
    "bend_model": (literal("rigid", "flexible"), "rigid"), "tether": (optional(_TETHER), None)})
