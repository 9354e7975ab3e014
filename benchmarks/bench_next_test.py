"""Does `next-test` pick the test that fixes the plan? (issue 36, the study)

Truth known independently of the ranking. For each of ``--muscles`` tested muscles (the paper's radial-test
muscle with its geometry drawn from the stated tolerance, as in benchmarks/bench_coverage.py):

1. axial-only synthetic data of the true muscle (one cycle per level, 2 N noise), fitted by ``identify`` from
   the stated geometry: the PAM a lab has before its next test;
2. the demo climb up an untested 76.2 mm riser (``unit: tested``) planned at C = 0.95: exit 3 or a pressure;
3. ``next-test`` on a menu of radial tests (six bores × two loads, one hour each, so that the linearised pick
   and the D-optimal pick are both per unit cost): its top test and the D-optimal pick, each with its
   predicted planned pressure;
4. each of the two tests RUN on the true muscle (synthesised from it), added to the axial data, refitted
   (the braid angle calibrated, as a radial test allows) and the mission planned again at 0.95: the realised
   J as next-test counts it (the stated sds of the geometry the fit did not calibrate included) and the plan
   `plan --confidence` itself gives (it draws no geometry for a tested muscle), its exit 3, whether that plan
   holds (P ≥ the true muscle's least holding pressure, the closed form) and its P / P_true; and the J of
   the refit's estimate with the uncertainty the linearised criterion predicted (what the truth moved).

Printed per muscle and in total: exit 3 before and after, P / P_true after the top test and after the
D-optimal pick, the predicted and the realised drop of each (drop = today's plan on the prior − the plan
after), and whether the top test's realised drop beats the D-optimal pick's. Then the timing of the
linearised ranking of 20 candidates at 10⁴ draws.

Exit-3 starts (``--open-width W``): each axial fit with hoop.a0 listed as undetermined over ±W MPa
(:func:`opened`), so that today's plan stops; the drop is then from today's plan on that prior.

    .venv/bin/python benchmarks/bench_next_test.py [--muscles 4] [--seed 1] [--samples 10000] [--open-width 2]
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from benchmarks.bench_coverage import FRICTION, RISER, drawn_around, least, stated_muscle  # noqa: E402
from pampipe.identification import identify  # noqa: E402
from pampipe.identification.options import FitOptions  # noqa: E402
from pampipe.io.mission_schema import load_mission  # noqa: E402
from pampipe.model import no_slip as slip  # noqa: E402
from pampipe.model.uncertainty import UndeterminedDirection  # noqa: E402
from pampipe.nexttest.information import fisher  # noqa: E402
from pampipe.nexttest.posterior import planned_uncertainty, posterior  # noqa: E402
from pampipe.nexttest.ranking import Planner, rank_menu  # noqa: E402
from pampipe.simulation.synthetic import Protocol, generate  # noqa: E402
from pampipe.specs.experiment import ExperimentData, make_test_data  # noqa: E402
from pampipe.specs.menu import DEFAULT_LEVELS, MenuTest, pressure_levels  # noqa: E402

PROBLEMS = ROOT / "problems"
LEVEL = 0.95
BORES = (0.0635, 0.0700, 0.0762, 0.0825, 0.0889, 0.1016)  # [m]
LOADS = (0.0, 1024.74)  # [N]


def menu() -> tuple[MenuTest, ...]:
    levels = pressure_levels(*DEFAULT_LEVELS)
    return tuple(MenuTest("radial", 3600.0, levels, pipe_diameter=d, axial_load=w, entry=k)
                 for k, (d, w) in enumerate((d, w) for d in BORES for w in LOADS))


def mission_for(pam, riser: float):
    """The demo climb's riser (76.2 mm for the paper's muscle), every segment the tested muscle ``pam``."""
    mission = load_mission(PROBLEMS / "missions" / "vertical-climb-3in.yaml")
    route = tuple(dataclasses.replace(s, diameter=riser, diameter_low=riser, diameter_high=riser,
                                      friction=FRICTION, incline=math.pi / 2) for s in mission.route[:1])
    segments = tuple(dataclasses.replace(s, pam=pam, pam_file=None, unit="tested") for s in mission.segments)
    return dataclasses.replace(mission, route=route, segments=segments)


def fit(stated, tests, calibrate=()):
    base = dataclasses.replace(stated, moduli=None, covariance=None)
    result = identify(ExperimentData(PROBLEMS / "generated.yaml", base, tuple(tests), {}),
                      FitOptions(calibrate=calibrate))
    return dataclasses.replace(result.fitted_pam(base), geometry_sd=dict(stated.geometry_sd))


def realised(stated, truth, axial, test, seed: int, samples: int, riser: float, predicted):
    """(J [Pa] as next-test counts it, plan stops, the pressure `plan --confidence` itself gives [Pa]: inf
    where it stops, J [Pa] of the refit's estimate with the ``predicted`` uncertainty) after running ``test``
    on the true muscle and refitting. The last splits the miss: predicted → it is where the estimate moved
    (the truth), it → realised is the refit's own uncertainty against the linearised Σ₁."""
    protocol = Protocol(pipes=(test.pipe_diameter,), loads=(test.axial_load,),
                        radial_pressures=tuple(test.pressures))
    radial = [make_test_data(spec, cols) for spec, cols in generate(truth, protocol, seed=seed)[1:]]
    pam = fit(stated, [*axial, *radial], calibrate=("braid_angle",))
    planner = Planner(mission_for(pam, riser), pam, None, LEVEL, samples=samples)
    value, stops = planner.refitted(pam)
    own = planner.plan(pam.uncertainty)
    moved = planner.value(planner.plan(predicted))[0]
    return value, stops, math.inf if stops else planner.value(own)[0], moved


def opened(pam, width: float):
    """The PAM with hoop.a0 (the level of the hoop law, what a radial test pins) listed as undetermined over
    ±``width`` [MPa] and its variance along it removed: a fit that leaves the contact force open, so that
    `plan` stops (exit 3), as tests/support/open_direction.py builds it for the paper's muscle."""
    u = pam.uncertainty
    vector = np.array([name == "hoop.a0" for name in u.names], dtype=float)
    keep = np.eye(vector.size) - np.outer(vector, vector)
    direction = UndeterminedDirection(vector, width, {}, "a radial test")
    return pam.with_uncertainty(dataclasses.replace(u, covariance=keep @ u.covariance @ keep,
                                                    undetermined=(*u.undetermined, direction)))


def trial(k: int, seed: int, samples: int, open_width: float = 0.0) -> dict:
    """One true muscle ``k`` (module docstring); ``open_width`` > 0: an exit-3 start (:func:`opened`)."""
    stated = stated_muscle(1.0, 1.0)
    rng = np.random.default_rng([seed, 1000, 1000, k])  # bench_coverage's truths
    truth = drawn_around(stated, stated.geometry_sd, rng)
    riser = RISER * stated.geometry.initial_diameter
    axial = [make_test_data(spec, cols) for spec, cols in generate(truth, Protocol(pipes=(), cycles=1),
                                                                    seed=seed * 1000 + k)]
    pam = fit(stated, axial)
    if open_width > 0:
        pam = opened(pam, open_width)
    mission = mission_for(pam, riser)
    seg = mission.segments[0]
    load = slip.anchor_load(sum(s.mass for s in mission.segments) + mission.payload, seg.mass, math.pi / 2,
                            FRICTION, mission.tether_drag)
    true = least(truth, riser, load, mission)
    planner = Planner(mission, pam, None, LEVEL, samples=samples)
    started = time.perf_counter()
    ranking = rank_menu(planner, menu())
    ranked_in = time.perf_counter() - started
    now = ranking.current.pressure
    out = {"k": k, "true": true, "now": now, "stops_now": ranking.current.stops,
           "undetermined": ranking.current.left_open, "rank_s": ranked_in}
    for name, outcome in (("top", ranking.ranked[0]), ("d", ranking.d_optimal)):
        test = outcome.tests[0]
        u = planner.uncertainty
        predicted = planned_uncertainty(u, posterior(u, fisher(planner.muscle, u, test)), on_prior=True)
        value, stops, own, moved = realised(stated, truth, axial, test, seed * 7919 + k, samples, riser,
                                            predicted)
        out[name] = {"test": test.describe(), "predicted": outcome.pressure, "realised": value,
                     "moved": moved, "stops": stops, "held": own >= true, "ratio": own / true,
                     "counted_ratio": value / true,
                     "predicted_drop": now - outcome.pressure, "realised_drop": now - value}
    return out


def timing(samples: int) -> tuple[float, float]:
    """(wall, CPU) seconds to rank 20 radial candidates (10 bores × 2 loads) on the paper fit at ``samples``
    draws (the CPU time of this process: what the ranking costs on a machine shared with others)."""
    from pampipe.io.pam_schema import load_pam

    pam_file = PROBLEMS / "pams" / "paper-radial-pam-uncertain.yaml"
    levels = pressure_levels(*DEFAULT_LEVELS)
    tests = tuple(MenuTest("radial", 3600.0, levels, pipe_diameter=d, axial_load=w, entry=i)
                  for i, (d, w) in enumerate((d, w) for d in np.linspace(0.060, 0.110, 10) for w in LOADS))
    started, cpu = time.perf_counter(), time.process_time()
    planner = Planner(load_mission(PROBLEMS / "missions" / "riser-uncertain-friction.yaml"),
                      load_pam(pam_file), pam_file, LEVEL, samples=samples)
    rank_menu(planner, tests)
    return time.perf_counter() - started, time.process_time() - cpu


def _mean(rows: list[dict], key: str) -> str:
    return f"{statistics.fmean(r[key] for r in rows) / 1e3:.1f}" if rows else "nan"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--muscles", type=int, default=4)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--samples", type=int, default=10_000)
    parser.add_argument("--open-width", type=float, default=0.0,
                        help="MPa: > 0 starts each muscle at exit 3, hoop.a0 open over ± this (opened())")
    args = parser.parse_args(argv)
    rows = []
    for k in range(args.muscles):
        r = trial(k, args.seed, args.samples, args.open_width)
        rows.append(r)
        top, d = r["top"], r["d"]
        print(f"muscle {k}: P_true {r['true'] / 1e3:.1f} kPa; today {r['now'] / 1e3:.1f} kPa on the prior, "
              f"{r['undetermined']} undetermined, exit 3: {r['stops_now']}; ranked in {r['rank_s']:.1f} s",
              flush=True)
        for name, x in (("top", top), ("D-opt", d)):
            print(f"  {name:5s} {x['test']:26s} predicted {x['predicted'] / 1e3:7.1f} realised "
                  f"{x['realised'] / 1e3:7.1f} kPa (/P_true {x['counted_ratio']:.3f}); plan's own P/P_true "
                  f"{x['ratio']:.3f} held {x['held']} exit 3 "
                  f"{x['stops']}  drop predicted {x['predicted_drop'] / 1e3:.1f} realised "
                  f"{x['realised_drop'] / 1e3:.1f} kPa; the refit's estimate with the predicted uncertainty "
                  f"{x['moved'] / 1e3:.1f} kPa", flush=True)
    tops = [r["top"] for r in rows]
    beats = sum(r["top"]["realised_drop"] >= r["d"]["realised_drop"] for r in rows)
    finite = [t for t in tops if t["realised_drop"] != 0 and math.isfinite(t["realised_drop"])
              and math.isfinite(t["predicted_drop"])]
    errors = [abs(t["predicted_drop"] - t["realised_drop"]) / abs(t["realised_drop"]) for t in finite]
    ratios = [t["predicted_drop"] / t["realised_drop"] for t in finite]
    print(f"\nexit 3 before: {sum(r['stops_now'] for r in rows)} of {len(rows)}; after the top test: "
          f"{sum(t['stops'] for t in tops)}; held after: {sum(t['held'] for t in tops)} of {len(rows)}; "
          f"P/P_true after: median {statistics.median(t['ratio'] for t in tops):.3f}, "
          f"max {max(t['ratio'] for t in tops):.3f}")
    print(f"top test's realised drop >= the D-optimal pick's: {beats} of {len(rows)}; "
          f"|predicted - realised| / realised drop, median: "
          f"{statistics.median(errors) if errors else float('nan'):.3f}; predicted / realised drop, median "
          f"{statistics.median(ratios) if ratios else float('nan'):.3f} "
          f"({', '.join(f'{r:.2f}' for r in ratios)}); mean drop predicted {_mean(finite, 'predicted_drop')} "
          f"kPa, realised {_mean(finite, 'realised_drop')} kPa")
    wall, cpu = timing(args.samples)
    print(f"ranking 20 candidates at {args.samples} draws: {wall:.1f} s wall, {cpu:.1f} s CPU")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
