"""Route.section_labels: each section's bore as the user wrote it, or in mm (as Route.section_label)."""

from __future__ import annotations

from pampipe.specs.mission import Route, Section

BORES = [(0.0762, "3 in"), (0.08, ""), (0.0779272, ""), (0.08, "80 mm"), (0.1, "")]


def test_section_labels_are_the_labels_one_by_one():
    route = Route.from_sections(Section(f"s{i}", 1.0, d, 0.0, 0.3, 0.0, label=label)
                                for i, (d, label) in enumerate(BORES))
    for rows in (slice(0, 5), slice(1, 4), slice(2, 2)):
        assert route.section_labels(rows) == [route.section_label(i) for i in range(5)[rows]]
    assert route.section_labels(slice(0, 3)) == ["3 in", "80 mm", "77.9272 mm"]
    bare = Route.from_sections([Section(name, 1.0, 0.05, 0.0, 0.3, 0.0) for name in "ab"])
    assert bare.label is None and bare.section_labels(slice(None)) == ["50 mm", "50 mm"]
