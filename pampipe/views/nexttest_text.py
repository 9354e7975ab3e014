"""Text report of `pampipe next-test`: today's plan, the ranked tests, the D-optimal pick."""

from __future__ import annotations

import math

from pampipe.views.tables import table


def _kpa(value) -> str:
    return "-" if value is None else f"{value / 1e3:.1f}"


def result_text(result) -> str:
    """The report of a :class:`pampipe.nexttest.result.NextTest` (read from its document)."""
    doc = result.to_dict()
    current = doc["current"]
    what = "largest planned pressure" if doc["objective"] == "pressure" else "air-weighted planned pressure"
    lines = [f"next test for {doc['mission']} with {doc['pam']} (menu {doc['menu']}): {what} at confidence "
             f"{doc['confidence']:g}, {doc['samples']} seeded draws (seed {doc['seed']})",
             f"today: {_kpa(current['pressure_Pa'])} kPa"
             + (" (on the prior along the undetermined directions)" if current["undetermined"] else "")
             + (f"; {current['undetermined']} undetermined direction(s)" if current["undetermined"] else "")
             + ("; plan stops (exit 3)" if current["exit_3"] else "")]
    rows = []
    for k, c in enumerate(doc["ranked"], start=1):
        p = c["predicted"]
        checked = c.get("checked")
        rows.append([k, c["label"], f"{c['cost_s'] / 3600:.3g}", _kpa(p["pressure_Pa"]),
                     _kpa(p["pressure_sd_Pa"]), _kpa(p["drop_Pa"]),
                     "-" if p["drop_per_hour_Pa"] is None else f"{p['drop_per_hour_Pa'] / 1e3:.3g}",
                     p["closes_undetermined"], "yes" if p["exit_3"] else "no",
                     "-" if checked is None else _kpa(checked["pressure_Pa"])])
    lines.append(table(["rank", "test", "cost [h]", "P after [kPa]", "sd [kPa]", "drop [kPa]",
                        "drop/h [kPa]", "closes", "exit 3", "checked [kPa]"], rows))
    d = doc["d_optimal"]
    p = d["predicted"]
    gain = p["information_gain"]
    lines.append(f"D-optimal pick (largest log det gain per hour; {gain:.3g} nats): {d['label']}: "
                 f"{_kpa(p['pressure_Pa'])} kPa after it (drop {_kpa(p['drop_Pa'])} kPa)"
                 + ("" if d["label"] == doc["ranked"][0]["label"] else
                    "; it buys information about parameters the plan does not depend on as much"))
    lines.append("P after: the planned pressure predicted after the test (linearised: its Fisher information "
                 "added to the fit's; sd: the Monte Carlo spread of the quantile, or, checked, over truths "
                 "drawn from the posterior); closes: undetermined directions it determines.")
    if math.isfinite(result.wall_time) and result.command:
        lines.append(f"again: {result.command}")
    return "\n".join(lines)
