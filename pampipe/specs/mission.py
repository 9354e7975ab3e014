"""A mission as frozen SI objects: the robot's segments and the route's pipe sections (docs/formats.md §4).

No I/O here: :func:`pampipe.io.load_mission` builds these from a mission file, and the Python API
(:mod:`pampipe.api`) from a dict. The route is columnar (:class:`Route`, one array per field), so that
10⁵ sections cost a few arrays, not 10⁵ objects; ``route[i]`` builds one :class:`Section` on demand.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any

import numpy as np

from pampipe.model.pam import Pam
from pampipe.specs.tether import Tether

#: κ of the no-slip condition for each load path (docs/physics.md §8).
LOAD_PATH_KAPPA = {"through_anchor": 1.0, "distributed": 0.5, "none": 0.0}


@dataclass(frozen=True)
class Segment:
    """One segment of the robot (rear to front): its muscle and its mass.

    ``unit`` says which muscle it carries: ``"tested"``, the very muscle its PAM file was fitted to, or
    ``"lot"``, another muscle of the same lot (docs/physics.md §15: what `plan --confidence` draws).
    """

    name: str
    pam: Pam
    mass: float  # [kg]
    pam_file: Path | None = None  # the PAM file it names (None for an inline PAM)
    unit: str = "lot"  # "tested" | "lot"


@dataclass(frozen=True)
class Steering:
    """The steering module (docs/physics.md §14.4): ``count`` extensile PAMs in parallel at ``radius`` [m]
    from the module's axis, evenly spaced (PAM k at 2π(k − 1)/count)."""

    pam: Pam
    count: int
    radius: float  # [m]
    pam_file: Path | None = None


@dataclass(frozen=True)
class Section:
    """One pipe section of the route, in travel order (SI).

    The bore may take any value in [``diameter_low``, ``diameter_high``] (both default to ``diameter``,
    the nominal bore); ``diameter_sd`` is its standard deviation for confidence plans, ``label`` what the
    user wrote (``"NPS 3 Sch 40 (ASME B36.10M) ± 1 mm"``).
    """

    name: str
    length: float  # [m]
    diameter: float  # nominal inner diameter [m]
    incline: float  # [rad] above horizontal, along travel
    friction: float  # braid-wall Coulomb coefficient
    friction_sd: float  # its standard deviation (0 = known exactly)
    diameter_low: float | None = None  # [m] smallest bore (None: the nominal)
    diameter_high: float | None = None  # [m] largest bore (None: the nominal)
    diameter_sd: float = 0.0  # [m]
    label: str = ""

    def __post_init__(self):
        for key in ("diameter_low", "diameter_high"):
            if getattr(self, key) is None:
                object.__setattr__(self, key, self.diameter)


@dataclass(frozen=True, eq=False)
class NetworkRoute:
    """Where a route came from when it was read from a pipe network (docs/commands.md §7).

    ``network`` is the :class:`pampipe.specs.network.Network` (node coordinates and elevations, for plots and
    reports); ``entry``/``exit`` index its nodes for each section, in travel order; ``bend`` [rad] is the
    plan-view deflection at the joint with the previous pipe (NaN: first pipe or no coordinates);
    ``whole`` is True when the route is every pipe of the network (``from``/``to`` not given).
    """

    network: Any
    from_node: str | None
    to_node: str | None
    entry: np.ndarray  # (n,) node index
    exit: np.ndarray  # (n,) node index
    bend: np.ndarray  # (n,) [rad]
    clipped: np.ndarray  # (n,) bool: |Δz| > length, incline taken as ±90°
    whole: bool
    excluded: int = 0  # pipes left out of the route search (the robot cannot pass them)

    def subset(self, index) -> NetworkRoute:
        return NetworkRoute(self.network, self.from_node, self.to_node, self.entry[index], self.exit[index],
                            self.bend[index], self.clipped[index], self.whole, self.excluded)


_COLUMNS = ("length", "diameter", "incline", "friction", "friction_sd", "diameter_low", "diameter_high",
            "diameter_sd")


@dataclass(frozen=True, eq=False)
class Route:
    """The route's sections as columns (SI), in travel order; ``route[i]`` is a :class:`Section`.

    ``label`` holds what the user wrote for each bore (None: the bore in mm); ``origin`` the network the
    route was read from, if any; ``bend_*`` the elbow at the end of each section (None: a route without
    bends), its ``bend_direction`` measured in the steering module from PAM 1 toward PAM 2.
    """

    name: np.ndarray  # (n,) str
    length: np.ndarray  # [m]
    diameter: np.ndarray  # nominal bore [m]
    incline: np.ndarray  # [rad]
    friction: np.ndarray
    friction_sd: np.ndarray
    diameter_low: np.ndarray  # [m]
    diameter_high: np.ndarray  # [m]
    diameter_sd: np.ndarray  # [m]
    label: np.ndarray | None = None  # (n,) str
    origin: NetworkRoute | None = field(default=None, repr=False)
    bend_angle: np.ndarray | None = None  # (n,) [rad] of the elbow at the end of each section (0: none)
    bend_radius: np.ndarray | None = None  # (n,) [m] its centreline radius (NaN: none)
    bend_direction: np.ndarray | None = None  # (n,) [rad] the turn's direction in the steering module
    bend_radius_assumed: np.ndarray | None = None  # (n,) bool: the bend gives no radius (elbow_radius taken)

    @classmethod
    def from_sections(cls, sections) -> Route:
        """The columns of a sequence of :class:`Section` objects."""
        sections = tuple(sections)
        columns = {key: np.fromiter((getattr(s, key) for s in sections), dtype=float, count=len(sections))
                   for key in _COLUMNS}
        labels = [s.label for s in sections]
        return cls(np.array([s.name for s in sections], dtype=str), **columns,
                   label=np.array(labels, dtype=str) if any(labels) else None)

    def __len__(self) -> int:
        return len(self.name)

    def __iter__(self):
        return (self[i] for i in range(len(self)))

    def __getitem__(self, index):
        if isinstance(index, slice | np.ndarray | list):
            return self.subset(index)
        i = range(len(self))[index]
        return Section(str(self.name[i]), *(float(getattr(self, key)[i]) for key in _COLUMNS),
                       label=self.section_label(i))

    def subset(self, index) -> Route:
        """The sections at ``index`` (a slice, an index array or a boolean mask), as a Route."""
        columns = {f.name: getattr(self, f.name) for f in fields(self)}
        for key, value in columns.items():
            if isinstance(value, np.ndarray) and value.shape[:1] == (len(self),):
                columns[key] = value[index]
        if self.origin is not None:
            columns["origin"] = self.origin.subset(index)
        return Route(**columns)

    @property
    def toleranced(self) -> np.ndarray:
        """True where the bore is a range rather than one value."""
        return self.diameter_high > self.diameter_low

    def section_label(self, i: int) -> str:
        """What the user wrote for the bore of section ``i`` (or the bore in mm)."""
        if self.label is not None and self.label[i]:
            return str(self.label[i])
        return f"{self.diameter[i] * 1e3:.6g} mm"

    def section_labels(self, rows: slice) -> list[str]:
        """:meth:`section_label` of each of the sections ``rows``."""
        diameters = self.diameter[rows].tolist()
        given = [""] * len(diameters) if self.label is None else self.label[rows].tolist()
        if all(given):
            return given
        worded: dict[float, str] = {}  # a route repeats its bores
        return [g or worded.get(d) or worded.setdefault(d, f"{d * 1e3:.6g} mm")
                for g, d in zip(given, diameters, strict=True)]

    def elevation_profile(self) -> tuple[np.ndarray, np.ndarray]:
        """(distance along the route [m], elevation [m]) at the n + 1 section ends.

        From the network's node elevations for a network route, else the sum of ℓ·sin(incline) from 0.
        """
        distance = np.concatenate([[0.0], np.cumsum(self.length)])
        if self.origin is not None and not self.origin.whole:
            z = self.origin.network.elevation
            return distance, np.concatenate([z[self.origin.entry[:1]], z[self.origin.exit]])
        return distance, np.concatenate([[0.0], np.cumsum(self.length * np.sin(self.incline))])


@dataclass(frozen=True)
class Mission:
    """The robot, its supply and safety factor, and the route (SI). ``source`` names where it came from.

    ``route`` may be given as a sequence of :class:`Section` objects; it is stored as a :class:`Route`.
    ``warnings`` are sentences about the file that the commands print (e.g. a defaulted safety factor).
    """

    source: Path
    segments: tuple[Segment, ...]
    payload: float  # [kg]
    supply_pressure: float  # [Pa] gauge
    safety_factor: float
    load_path: str
    tether_drag: float  # [N]
    route: Route
    gait: dict[str, Any]
    warnings: tuple[str, ...] = ()
    kappa_sd: float = 0.0  # standard deviation of κ (sampled by confidence plans when > 0)
    load_coupling: float | None = None  # κ measured in slip tests (load_path "from_pam"); None: load_path's
    steering: Steering | None = None
    bend_model: str = "rigid"  # rigid | flexible (docs/physics.md §14)
    joint_angle: float | None = None  # [rad] the largest angle a joint between segments allows (None: free)
    tether: Tether | None = None  # the tether dragged behind (docs/physics.md §16; None: tether_drag only)

    def __post_init__(self):
        if not isinstance(self.route, Route):
            object.__setattr__(self, "route", Route.from_sections(self.route))

    @property
    def input_files(self) -> list[Path]:
        """Every file the mission reads: itself, the PAM files its segments name and its network file."""
        files = [self.source, *(seg.pam_file for seg in self.segments if seg.pam_file is not None)]
        if self.steering is not None and self.steering.pam_file is not None:
            files.append(self.steering.pam_file)
        origin = self.route.origin
        if origin is not None and origin.network.source is not None:
            files.append(Path(origin.network.source))
        return files

    @property
    def kappa(self) -> float:
        """κ of the no-slip condition (docs/physics.md §8): measured, or that of the load path."""
        if self.load_coupling is not None:
            return self.load_coupling
        return LOAD_PATH_KAPPA[self.load_path]

    @property
    def passable_bores(self) -> tuple[float, float]:
        """(D_low, D_high) [m]: the robot passes bores wider than its widest muscle at rest and anchors in
        bores narrower than the least D(B/√3) its braids open to (docs/physics.md §2)."""
        return (max(seg.pam.geometry.initial_diameter for seg in self.segments),
                min(seg.pam.geometry.largest_diameter for seg in self.segments))
