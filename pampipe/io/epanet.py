"""EPANET water networks (.inp files, and those shipped with wntr) read into a
:class:`pampipe.specs.network.Network` (docs/commands.md §7).

A node's elevation is the junction's or tank's elevation (a tank's bottom) or the reservoir's head [m];
node coordinates and pipe vertices give the plan points of the bends (NaN where the file has none). wntr
takes about 2 s to import, so it is imported only when a network is read.
"""

from __future__ import annotations

import difflib
import math
import os
from pathlib import Path

import numpy as np

from pampipe.errors import InputError
from pampipe.io.paths import read_bounded
from pampipe.specs.network import Network


def load_network(network: str | Path, *, base: Path | None = None) -> Network:
    """Read a network shipped with wntr (``Net1``, ``Net3``, ``ky4``, ...) or an EPANET ``.inp`` file.

    A value ending in ``.inp`` or containing a ``/`` is a file, relative to ``base`` (e.g. the mission's
    folder) when given; any other value names a shipped network.
    """
    import wntr
    from wntr.library import model_library

    text = str(network)
    if text.lower().endswith(".inp") or "/" in text or isinstance(network, Path):
        path = Path(text) if base is None or Path(text).is_absolute() else Path(base) / text
        if not os.path.exists(path):
            raise InputError(f"network {text}: file {path} not found (a network is the name of one shipped "
                             f"with wntr, {', '.join(sorted(model_library.model_name_list))}, or an "
                             "EPANET .inp file).")
        _check_unique_ids(path, read_bounded(path, what="EPANET .inp file", limit=INP_LIMIT))
        name = path.stem
    elif text in model_library.model_name_list:
        path, name = Path(model_library.get_filepath(text)), text
    else:
        shipped = sorted(model_library.model_name_list)
        near = difflib.get_close_matches(text, shipped, n=3, cutoff=0.3)
        hint = f"did you mean {' or '.join(near)}? " if near else ""
        raise InputError(f"network {text!r}: no network of that name ships with wntr; {hint}shipped: "
                         f"{', '.join(shipped)}; or give the path of an EPANET .inp file.")
    try:
        model = wntr.network.WaterNetworkModel(str(path))
    except Exception as exc:  # wntr raises many types for unreadable or malformed files
        raise InputError(f"network {path}: cannot read it as an EPANET .inp file ({exc}).") from None
    return _columns(model, name, path)


#: Largest .inp file read [bytes].
INP_LIMIT = 1 << 29
#: The sections of an .inp file whose first field is an id: (namespace, what a row defines). Links
#: (pipes, pumps, valves) share one namespace, nodes (junctions, reservoirs, tanks) another.
_ID_SECTIONS = {"PIPES": ("link", "pipe"), "PUMPS": ("link", "pump"), "VALVES": ("link", "valve"),
                "JUNCTIONS": ("node", "junction"), "RESERVOIRS": ("node", "reservoir"),
                "TANKS": ("node", "tank")}


def _check_unique_ids(path: Path, raw: bytes) -> None:
    """Refuse an .inp file that defines one pipe (or node) id twice: wntr would keep only the last."""
    seen: dict[tuple[str, str], tuple[int, str]] = {}
    section = None
    for number, line in enumerate(raw.decode("utf-8", "replace").splitlines(), start=1):
        fields = line.split(";", 1)[0].split()
        if not fields:
            continue
        if fields[0].startswith("["):
            section = _ID_SECTIONS.get(fields[0].strip("[]").upper())
        elif section is not None:
            (space, what), key = section, (section[0], fields[0])
            if key in seen:
                first, before = seen[key]
                raise InputError(f"network {path}: line {number} defines the {what} id {fields[0]!r}, which "
                                 f"line {first} already gives to a {before}; every {space} needs its own id "
                                 "(wntr would silently keep only the last).")
            seen[key] = number, what


def _columns(model, name: str, source: Path) -> Network:
    """The wntr model's nodes and pipes as arrays."""
    node_ids, elevation, xy = [], [], []
    for node_id, node in model.nodes():
        node_ids.append(node_id)
        elevation.append(node.base_head if node.node_type == "Reservoir" else node.elevation)
        # wntr keeps the default coordinates as the list [0, 0] and those read from the file as a tuple
        xy.append(node.coordinates if isinstance(node.coordinates, tuple) else (math.nan, math.nan))
    index = {node_id: i for i, node_id in enumerate(node_ids)}
    xy = np.array(xy, dtype=float).reshape(-1, 2)
    pipes = list(model.pipes())
    start = np.array([index[p.start_node_name] for _, p in pipes], dtype=np.int64)
    end = np.array([index[p.end_node_name] for _, p in pipes], dtype=np.int64)
    after_start, before_end = xy[end].copy(), xy[start].copy()
    for i, (_, pipe) in enumerate(pipes):
        if pipe.vertices:
            after_start[i], before_end[i] = pipe.vertices[0], pipe.vertices[-1]
    net = Network(name, source, np.array(node_ids, dtype=str), np.array(elevation, dtype=float), xy,
                  np.array([pipe_id for pipe_id, _ in pipes], dtype=str), start, end,
                  np.array([p.length for _, p in pipes], dtype=float),
                  np.array([p.diameter for _, p in pipes], dtype=float), after_start, before_end,
                  model.num_pumps + model.num_valves)
    for values, what in ((net.length, "length"), (net.diameter, "diameter")):
        bad = ~(np.isfinite(values) & (values > 0))
        if bad.any():
            raise InputError(f"network {source}: pipe {net.pipe_ids[bad][0]} has {what} {values[bad][0]!r}; "
                             f"every pipe {what} must be positive ({int(bad.sum())} pipes are not).")
    if not np.isfinite(net.elevation).all():
        raise InputError(f"network {source}: node {net.node_ids[~np.isfinite(net.elevation)][0]} has no "
                         "finite elevation.")
    return net
