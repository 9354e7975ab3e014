"""What an HTML report opens with (issue 42, item 3): the verdict, the headline numbers and the inputs.

Read from the command's JSON document (SI) and its text report; the values are written in the metric
units of the text (kPa, mm, m, N) so that :func:`pampipe.units.display.localize` shows them in the
user's units, as it does every other line of the report.
"""

from __future__ import annotations

from collections.abc import Mapping

#: How a text report's verdict line starts, per command (the last matching line is the verdict).
VERDICT_STARTS = ("feasible", "infeasible", "not feasible", "completed", "the robot stops", "Verdict:",
                  "fit: ", "pampipe plan: no solution")

#: The JSON unit suffixes shown in the report, as (suffix, metric unit, factor from SI); longest first.
SUFFIXES = (("_m3_per_s", "L/min", 6e4), ("_m3", "L", 1e3), ("_Pa", "kPa", 1e-3), ("_kg", "kg", 1.0),
            ("_N", "N", 1.0), ("_deg", "deg", 1.0), ("_s", "s", 1.0), ("_m", "m", 1.0))
#: Lengths shown in mm (bores, muscles) rather than m (pipes, routes).
SHORT = ("diameter", "bore", "thickness", "stride")


def verdict(text: str) -> str:
    """The verdict line of a command's text report (its last line that states one), else its last line."""
    lines = [line.strip() for line in text.splitlines() if line.strip()]
    found = [line for line in lines if line.startswith(VERDICT_STARTS)]
    return found[-1] if found else (lines[-1] if lines else "")


def quantity(key: str, value) -> tuple[str, str]:
    """(readable name, value with its metric unit) of one JSON key: ``supply_pressure_Pa`` →
    (``supply pressure``, ``689 kPa``); ``section_inner_diameter_m`` → (``section inner diameter``,
    ``76.2 mm``); keys without a unit suffix keep their value."""
    end = next((e for e in ("_low", "_high") if key.endswith(e)), "")
    key = key[: len(key) - len(end)]
    name, unit, scale = key, "", 1.0
    for suffix, metric, factor in SUFFIXES:
        if key.endswith(suffix):
            name, unit, scale = key[: -len(suffix)], metric, factor
            if metric == "m" and any(word in key for word in SHORT):
                unit, scale = "mm", 1e3
            break
    readable = (name + end).replace(".", " ").replace("_", " ").strip()
    return readable, _value(value, unit, scale)


def _value(value, unit: str, scale: float) -> str:
    if isinstance(value, bool) or value is None:
        return {True: "yes", False: "no", None: "-"}[value]
    if isinstance(value, int | float):
        text = f"{value * scale:.4g}"
        return f"{text} {unit}" if unit else text
    return str(value)


def headline(command: str, document: Mapping) -> list[tuple[str, str]]:
    """The numbers a reader looks for first: the largest pressure and where, the reach, the holding
    (or completion) probability for plan and rehearse; the fit's RMSE, its ratio to the noise floor
    and the determined combinations for identify; the verdict's effects and the improvement for
    diagnose."""
    rows: list[tuple[str, str]] = []
    if command in ("plan", "rehearse"):
        rows += _pressures(document)
        reach = document.get("reach") or {}
        if reach.get("distance_m") is not None:
            where = f" (in {reach['section']})" if reach.get("section") else ""
            rows.append(("reach", f"{reach['distance_m']:.4g} m{where}"))
        if command == "rehearse":
            hours = f"{document['time_s'] / 3600:.3g} h" if document.get("time_s") is not None else "-"
            rows += [("walked", _value(document.get("walked_m"), "m", 1.0)), ("time", hours),
                     ("free air", _value(document.get("free_air_m3"), "L", 1e3))]
            if document.get("completion_probability") is not None:
                rows.append(("completion probability", f"{document['completion_probability']:.3f}"))
    elif command == "identify":
        fit, u = document.get("fit", {}), document.get("uncertainty", {})
        rows.append(("RMSE", _value(fit.get("rmse_N"), "N", 1.0)))
        quality = fit.get("quality") or {}
        if quality.get("rmse_over_floor") is not None:
            rows.append(("RMSE / noise floor (worst test)", f"{quality['rmse_over_floor']:.3g}"))
        if u.get("parameters"):
            rows.append(("determined combinations", f"{u.get('rank')} of {len(u['parameters'])}"))
    elif command == "diagnose":
        selected = document.get("selected", {})
        rows.append(("verdict", str(document.get("verdict"))))
        rows.append(("effects", ", ".join(selected.get("effects") or []) or "none"))
        if document.get("improvement") is not None:
            rows.append(("improvement", f"{100 * document['improvement']:.1f} %"))
    return rows


def _pressures(document: Mapping) -> list[tuple[str, str]]:
    """The largest planned pressure and where, and the lowest holding probability (plan --confidence)."""
    segments = [(section.get("name"), segment) for section in document.get("sections") or []
                for segment in section.get("segments") or []]
    rows = []
    planned = [(s["pressure_Pa"], name, s.get("name")) for name, s in segments
               if s.get("pressure_Pa") is not None]
    if planned:
        pressure, section, segment = max(planned, key=lambda item: item[0])
        rows.append(("largest pressure", f"{pressure / 1e3:.4g} kPa ({segment} in {section})"))
    probabilities = [s["holding_probability"] for _, s in segments
                     if s.get("holding_probability") is not None]
    if probabilities:
        rows.append(("holding probability (lowest)", f"{min(probabilities):.3f}"))
    return rows


def settings(document: Mapping) -> list[tuple[str, str]]:
    """The document's own scalar inputs and settings (supply, payload, safety factor, …) as (name, value),
    timings and verdict flags left out."""
    skip = ("wall_time", "feasible", "completed", "success", "status", "improvement", "verdict", "reason",
            "time_s", "walked_m", "free_air", "completion_probability", "largest_tension")
    return [quantity(key, value) for key, value in document.items()
            if (value is None or isinstance(value, str | bool | int | float)) and not key.startswith(skip)
            and value is not None]


def report_inputs(command: str, document: Mapping) -> list[tuple[str, str]]:
    """The settings a report rests on: the document's own inputs; identify's and diagnose's from their fit
    and data blocks."""
    if command == "identify":
        fit = document.get("fit", {})
        keys = ("objective", "mode", "degree", "points", "slack", "slack_rows", "excluded_rows")
        return settings({"experiment": document.get("experiment"), **{k: fit.get(k) for k in keys}})
    if command == "diagnose":
        return settings({"experiment": document.get("source"), **(document.get("cells") or {})})
    return settings(document)
