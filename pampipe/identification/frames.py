"""The tables of an identification besides its long one, as rows of plain dicts (issue 42, item 2).

Read from the ``identify --json`` document only, so ``IdentifyResult.coefficients()`` and ``.tests_frame()``
show
the numbers of ``--json``; columns carry their unit in their name (``value_MPa``, ``rmse_N``)."""

from __future__ import annotations

from collections.abc import Mapping


def coefficient_rows(doc: Mapping) -> list[dict]:
    """One row per fitted moduli coefficient (``theta.axial.a0``: block ``theta``, stress ``axial``, term
    ``a``, power 0 of E_k = Σ_j (a_kj + b_kj P/P_ref) ε_k^j, docs/physics.md §4), with its value, standard
    deviation and 95 % interval in MPa (None where the data do not determine it), ``determined`` and
    ``at_bound``. Calibrated geometry entries (``geometry.*``) are not coefficients: they are in
    ``to_dict()["geometry"]``."""
    u = doc["uncertainty"]
    rows = []
    for i, name in enumerate(u["parameters"]):
        block, stress, term = name.split(".", 2)
        if block == "geometry":
            continue
        low, high = u["interval_95"][i]
        rows.append({"coefficient": name, "block": block, "stress": stress, "term": term[0],
                     "power": int(term[1:]), "value_MPa": u["values"][i], "std_MPa": u["std"][i],
                     "low_MPa": low, "high_MPa": high, "determined": u["determined"][i],
                     "at_bound": u["at_bound"][i]})
    return rows


def test_rows(doc: Mapping) -> list[dict]:
    """One row per test: its kind, protocol, points, RMSE [N], slack and excluded rows, and from the
    fit-quality check its noise floor [N], RMSE over floor, runs z, lag-1 autocorrelation and whether it
    is structured."""
    quality = {q["test"]: q for q in ((doc["fit"].get("quality") or {}).get("tests") or [])}
    rows = []
    for test in doc["fit"]["tests"]:
        q = quality.get(test["name"], {})
        rows.append({"test": test["name"], "kind": test["kind"], "protocol": test["protocol"],
                     "points": test["points"], "rmse_N": test["rmse_N"], "slack_rows": test["slack_rows"],
                     "excluded_rows": test["excluded_rows"], "noise_floor_N": q.get("floor_N"),
                     "rmse_over_floor": q.get("rmse_over_floor"), "runs_z": q.get("runs_z"),
                     "lag1_autocorrelation": q.get("lag1_autocorrelation"),
                     "structured": q.get("structured")})
    return rows
