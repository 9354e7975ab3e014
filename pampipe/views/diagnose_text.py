"""The text report of `pampipe diagnose`: the baseline against each test's noise floor, the selection steps,
the verdict with the effects' parameters, RMSE before and after, and where structure remains
(docs/commands.md §10); the slip tests' part when there are any."""

from __future__ import annotations

from pampipe.diagnosis import structure
from pampipe.diagnosis.candidates import GEOMETRY, candidate, describe
from pampipe.model.effects import LIBRARY
from pampipe.units.display import counted, scaled
from pampipe.views.tables import table


def _parameters(summary) -> str:
    """The effects' parameters with their joint 95 % intervals, in display units."""
    cells = []
    for name in summary.effects:
        for p in candidate(name).parameters:
            shown, factor = scaled(p.unit)  # the display units of --units
            value = summary.parameters[name][p.name] / p.scale * factor
            unit = "" if p.unit == "-" else f" {shown}"
            band = summary.intervals.get(name, {}).get(p.name, (float("nan"),) * 2)
            low, high = (v / p.scale * factor for v in band)
            cells.append(f"{name}.{p.name} = {value:.4g}{unit} [{low:.4g}, {high:.4g}]")
    return "; ".join(cells) or "-"


#: Check names of :mod:`pampipe.diagnosis.structure` that an effect's ``signature`` may go by.
ALIASES = {"length": ("length", "stroke_ends"), "contact": ("contact", "axial_load")}


def _strongest(check) -> str:
    """The check that rejects most strongly, and the library effects whose signature it is."""
    name, p = min(check.p_values().items(), key=lambda item: item[1])
    names = ALIASES.get(name, (name,))
    hints = [e.name for e in LIBRARY.values() if e.signature in names]
    shown = f"p = {p:.2g}" if p > 0 else "p < 1e-300"
    return f"{name} ({shown})" + (f" -> {', '.join(hints)}" if hints else "")


def _percent(share: float) -> str:
    return f"{round(share, 2) + 0.0:.0%}"  # + 0.0: no "-0%" for a round-off below zero


def _span(low: float, high: float, scale: float, digits: int) -> str:
    return f"{low * scale:.{digits}f}-{high * scale:.{digits}f}"


def result_text(result) -> str:
    """The report of `diagnose` (``str(result)``), with the slip tests' when there are any."""
    return report(result) if result.slip is None else report(result) + "\n" + result.slip.report()


def report(result) -> str:
    """The human-readable report: noise floors and checks, the steps, the verdict, before/after."""
    base, chosen = result.baseline, result.chosen
    checks_before = result.baseline_model.assessment.tests
    checks_after = result.chosen_model.assessment.tests
    cells = result.cells
    parts = [f"{result.source}: {cells.rows:,} rows in {counted(len(base.tests), 'test')}, reduced to "
             f"{cells.size:,} "
             f"cells; baseline = shared moduli ({result.baseline_source}), sum of test RMSE "
             f"{base.sum_rmse:.4g} N"]
    rows = []
    for t, floor, check in zip(base.tests, result.noise, checks_before, strict=True):
        interval = floor.interval
        band = "-" if interval is None else _span(*interval, 1.0, 2)
        rows.append((t.name, t.points, floor.sigma, band, f"{floor.method} ({floor.dof:.0f} dof)", t.rmse,
                     t.rmse / floor.sigma, check.at_noise, "-" if check.at_noise else _strongest(check)))
    parts.append("Baseline against the noise floor of each test (checks at family level "
                 f"{structure.ALPHA:.0%}, Bonferroni):\n" + table(
        ["test", "points", "floor [N]", "95 % [N]", "floor from", "RMSE [N]", "RMSE/floor", "at noise",
         "strongest structure"], rows))
    notes = [f"  {f.test}: {f.note}" for f in result.noise if f.note]
    if notes:
        parts.append("Noise-floor notes:\n" + "\n".join(notes))
    for step in result.steps:
        if not step.trials:
            continue
        title = {"add": f"added {step.effect}", "remove": f"removed {step.effect}",
                 "keep": "every effect kept", "stop": "no addition clears the margins"}[step.action]
        parts.append(f"Step {step.number} ({step.wall_time:.1f} s): {title}; model: "
                     f"{' + '.join(step.effects) or 'baseline'}\n" + table(
            ["effect", "dBIC", "CV ratio", "where share", "where focus", "eligible", "note", "time [s]"],
            [(t.effect, t.delta_bic, "-" if t.cv_ratio is None else f"{t.cv_ratio:.3f}",
              _percent(t.where_share) if step.action in ("add", "stop") else "-",
              _percent(t.where_focus) if step.action in ("add", "stop") else "-", t.eligible, t.note or "-",
              t.wall_time) for t in step.trials]))
    verdict = result.verdict
    decision = [f"Verdict: {verdict.verdict}. {verdict.reason}."]
    if chosen.effects:
        named = f"named: {' + '.join(result.selected_effects) or 'none on its own'}; "
        decision.append(f"  refitted: {' + '.join(chosen.effects)} ({named}parameters, joint 95 % "
                        f"intervals: {_parameters(chosen)})")
        for name in result.selected_effects:
            decision.append(f"  {name}: {candidate(name).summary}")
    for name in chosen.effects:
        if name in GEOMETRY:
            decision.append(f"  {name}: {describe(name, chosen.parameters[name], result.pam.geometry)}")
    for group in verdict.indistinguishable:
        decision.append(f"  indistinguishable: {' or '.join(group)} (these tests cannot tell them apart)")
    if result.ties:
        decision.append(f"  -o writes the refit with {' + '.join(result.written.effects) or 'no effect'}: no "
                        "member of a tie as the muscle's physics; the file names each tie "
                        "(effects.indistinguishable) and the test that would separate it")
    if verdict.undetermined:
        decision.append("  undetermined (interval spans the allowed range): "
                        + ", ".join(verdict.undetermined))
    for caution in verdict.cautions:
        decision.append(f"  caution: {caution}")
    for c in result.confounded:
        text = f"  caution: {c['effect']} and {c['with']} explain the data almost equally (confounded)"
        if c["separate_by"]:
            sep = c["separate_by"]
            text += (f"; {sep['experiment']} would separate them (predictions differ by "
                     f"{sep['max_difference_N']:.3g} N, {sep['share']:.0%} of the effects' size in the data, "
                     f"{sep['ratio']:.3g}x the noise floor)")
        decision.append(text)
    if verdict.probes_removed > 0:
        force, k = scaled("N")  # sums of squared residuals, in the display unit of force squared
        decision.append(f"  on the tests that held the residual, the library removes "
                        f"{verdict.library_removed * k**2:.4g} {force}^2 and generic probes "
                        f"{verdict.probes_removed * k**2:.4g} {force}^2")
    parts.append("\n".join(decision))
    parts.append(_rmse_table(result, checks_after))
    if verdict.remaining:
        parts.append("Where structured residual remains:\n" + table(
            ["test", "signature", "p", "P [kPa]", "L [mm]", "cells", "rows", "mean [N]"],
            [(w.test, w.signature, f"{w.p_value:.2g}", _span(*w.pressure, 1e-3, 0),
              "-" if w.length is None else _span(*w.length, 1e3, 1), w.cells, w.rows, w.mean_residual)
             for w in verdict.remaining]))
    timings = result.timings
    parts.append("Time: " + ", ".join(f"{k.removesuffix('_wall_time_s')} {v:.1f} s"
                                      for k, v in timings.items()))
    return "\n\n".join(parts)


def _rmse_table(result, checks_after) -> str:
    """RMSE per test before and after, with the protocol read, the floor and the verdict at the noise."""
    rows = [(t.name, d.protocol, t.rmse, a.rmse, f.sigma, a.rmse / f.sigma, c.at_noise)
            for t, d, a, f, c in zip(result.baseline.tests, result.data.tests, result.chosen.tests,
                                     result.noise, checks_after, strict=True)]
    return ("RMSE per test, before and after (protocol: as read from the data, or as the file states):\n"
            + table(["test", "protocol", "before [N]", "after [N]", "floor [N]", "after/floor",
                     "at noise after"], rows)
            + f"\nimprovement (1 - after/before, sum of test RMSE): {result.improvement:.1%}")
