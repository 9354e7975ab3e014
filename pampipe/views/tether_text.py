"""The tether's lines of the `plan` and `rehearse` reports: tension per section and the reach
(docs/physics.md §16)."""

from __future__ import annotations

import numpy as np

from pampipe.views.tables import table


def tether_text(plan, rows: np.ndarray) -> str:
    """The tension at the entry and the end of each listed section (``rows``), then the reach."""
    t = plan.tether
    names = plan.arrays.route.name
    body = table(["section", "T_in [N]", "T_out [N]", "carried [N]"],
                 [(names[s], float(t.tension_in[s]), float(t.tension_out[s]), float(t.largest[s]))
                  for s in rows.tolist()])
    head = ("tether tension (T_in after the previous bend, T_out before the section's own bend; each anchor "
            "carries the largest on top of W):")
    return "\n".join([head, body, t.reach.sentence()])
