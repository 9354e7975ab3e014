"""The candidates table of a diagnosis, as rows of plain dicts (issue 42, item 2).

Read from the ``diagnose --json`` document only, so ``DiagnoseResult.candidates()`` shows the numbers of
``--json``; columns carry their unit in their name (``sum_rmse_N``, ``wall_time_s``).
"""

from __future__ import annotations

from collections.abc import Mapping


def candidate_rows(doc: Mapping) -> list[dict]:
    """One row per effect tried in the first step of the selection (docs/commands.md §6), in the
    report's order: ΔBIC against the baseline, the cross-validated RMSE ratio (None: not
    cross-validated), where the gain falls (shares as fractions), whether it is eligible and why not, and
    the refit's summed test RMSE [N], cross-validated RMSE [N] and wall time [s]."""
    fits = {c["effect"]: c for c in doc.get("candidates", [])}
    trials = doc["steps"][0]["trials"] if doc.get("steps") else []
    rows = []
    for trial in trials:
        fit = fits.get(trial["effect"], {})
        rows.append({"effect": trial["effect"], "delta_bic": trial["delta_bic"],
                     "cv_ratio": trial["cv_ratio"], "where_share": trial["where_share"],
                     "where_focus": trial["where_focus"], "eligible": trial["eligible"],
                     "note": trial["note"],
                     "sum_rmse_N": fit.get("sum_rmse_N"), "cv_rmse_N": fit.get("cv_rmse_N"),
                     "wall_time_s": trial["wall_time_s"]})
    return rows
