"""A long ``route:`` list validated once per distinct section, then expanded back to every place (issue 39).

A long route repeats a few lengths, bores, inclines and frictions (the 10⁵ sections of
``benchmarks/bench_big_mission.py`` hold 1,260 distinct ones). Whether a section is valid, and what it
validates to, depends on its own keys and values only, and on its name only in that the name must be
non-empty text (names are checked to be unique over the whole list by
:func:`pampipe.io.routes.listed_route`). So the list is validated as its distinct sections (each taken, with
its own name, at its first place) and the route's columns are expanded back by
:attr:`DistinctSections.index`.

Two sections are the same if they are written the same as Python literals (``repr``) without their names:
the same keys in the same order with the same values of the same types (YAML's text, numbers, booleans,
nothing, lists and mappings: ``1``, ``1.0`` and ``true`` differ, and so do ``0.0`` and ``-0.0``). Not taken
this way (None): a list shorter than :data:`SHORTEST`, a section that is not a mapping or whose name is
not non-empty text, and a section with a ``bend`` (its radius depends on the next section's bore). When the
distinct sections fail validation, the caller validates the whole list again, so that the message names
the section and its place exactly as before.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Routes with fewer sections are validated section by section (the saving is below a millisecond).
SHORTEST = 256


@dataclass(frozen=True)
class DistinctSections:
    """Where each section of a long route lies among its distinct sections."""

    names: list[str]  # every section's name, in travel order
    first: list[int]  # the place of each distinct section's first occurrence (ascending)
    index: np.ndarray  # (n,) intp: the distinct section at each place

    def distinct(self, route: list) -> list:
        """The distinct sections of ``route`` (the list this was found in), in order of first occurrence."""
        return [route[i] for i in self.first]


def distinct_sections(route) -> DistinctSections | None:
    """The distinct sections of ``route`` (a list of mappings as read from YAML), or None (see above)."""
    if type(route) is not list or len(route) < SHORTEST:
        return None
    seen: dict[str, int] = {}
    first: list[int] = []
    index: list[int] = []
    names: list[str] = []
    for place, section in enumerate(route):
        if type(section) is not dict:
            return None
        name = section.get("name")
        if type(name) is not str or not name or "bend" in section:
            return None
        rest = section.copy()
        del rest["name"]
        key = repr(rest)  # YAML's values written as literals: the same text only for the same values
        found = seen.get(key)
        if found is None:
            found = seen[key] = len(first)
            first.append(place)
        index.append(found)
        names.append(name)
    return DistinctSections(names, first, np.array(index, dtype=np.intp))
