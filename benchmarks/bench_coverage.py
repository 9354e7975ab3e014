"""Coverage of `plan --confidence`: do the plans hold on the muscles the robot carries? (issue 35, item 8)

Truth known independently of the planner. Each trial, for each muscle size and tolerance level:
1. the TESTED muscle: the stated geometry (the paper's radial-test muscle, or it scaled to another size)
   plus a draw from the stated tolerance (the sds below × the level), with the demo moduli;
2. synthetic tests of it (:mod:`pampipe.simulation.synthetic`, force noise 2 N): the axial test alone, and the
   axial test plus one radial test in a bore 1.556 D₀ (88.9 mm for the paper's muscle). The axial test
   (``--protocol``, :data:`AXIAL`) is ``held`` (the default: a force map, 8 held lengths, the pressure ramped
   at each) or ``sweep`` (the length cycled at each of the paper's 10 pressures), about 1000 rows each. The
   protocol sets the model error's degrees of freedom (its cross-validation holds out 4 pressure bands and
   each held length: ν = 11 held, 3 swept), so the plans' width depends on it;
3. ``identify`` on each, from the STATED geometry, calibrating where a radial test is the entries of
   ``--calibrate`` (:data:`CALIBRATABLE`; default :data:`DEFAULT_CALIBRATE`, the braid angle and the rest
   length, which the force map's zero-force edge pins and whose stated 1 mm sd otherwise reaches the plans as
   model error: docs/commands.md §4.5); the written PAM keeps the stated sd of every entry, the calibrated
   ones' too (the lot's tolerance: ``fitted_pam`` drops a calibrated entry's sd today, and a ``unit: lot``
   plan needs it);
4. ``plan --confidence C`` (C = 0.5, 0.9, 0.95, 0.99) of the demo climb (3 × 0.4 kg, 2 kg payload, SF 1.5)
   up a riser of bore 1.333 D₀ (76.2 mm: no test used it), every segment ``unit: tested``, then ``unit: lot``;
5. the judge, each muscle's closed-form least holding pressure in the riser
   (:meth:`Muscle.least_holding_pressure`): for ``tested`` the tested muscle's; for ``lot`` a SIBLING per
   segment, a fresh draw of the geometry from the stated tolerance around the tested muscle's (its moduli).

Printed for each (size, tolerance, data, unit, C): the trials planned, the share of segment plans that hold
(± its standard error, clustered by trial: the segments of a trial share one fit), the median and
90th-percentile overhead P_plan / P_true, the exit-3 rate (plans an undetermined direction stopped) and, per
data set, the fits IPOPT could not finish (no PAM, no plan).

    .venv/bin/python benchmarks/bench_coverage.py [--trials 30] [--seed 1] [--sizes 1,0.5] [--levels 0.5,1]
    .venv/bin/python benchmarks/bench_coverage.py --quick    # 6 trials, the paper's muscle, stated tolerance
    .venv/bin/python benchmarks/bench_coverage.py --fits FITS --sizes 1 --levels 1    # fits cached in FITS
    .venv/bin/python benchmarks/bench_coverage.py --fit-only --fits FITS --shard 0/2 ...  # trials 0, 2, 4, …

``--fits DIR`` keeps each fitted PAM as the PAM file ``identify -o`` would write (one per seed, trial, size,
level and data set; a fit IPOPT could not finish as a ``.failed`` file holding its message) and reuses it when
present: the truths are redrawn from the seed, so a change to planning is re-judged without refitting.
Delete the folder after a change to identification. ``--shard I/N`` runs only the trials k with k % N = I:
N ``--fit-only`` processes fill one folder in parallel, then one run without ``--shard`` judges them all.
"""

from __future__ import annotations

import argparse
import dataclasses
import functools
import math
import sys
import time
from pathlib import Path

import numpy as np
from scipy.special import ndtri, stdtrit

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from pampipe.errors import InputError, SolverError  # noqa: E402
from pampipe.identification import identify  # noqa: E402
from pampipe.identification.options import FitOptions  # noqa: E402
from pampipe.io.mission_schema import load_mission  # noqa: E402
from pampipe.io.pam_schema import load_pam  # noqa: E402
from pampipe.io.pamfile import write_pam  # noqa: E402
from pampipe.model import no_slip as slip  # noqa: E402
from pampipe.model.muscle import Muscle  # noqa: E402
from pampipe.model.pam import Pam  # noqa: E402
from pampipe.planning import plan_mission  # noqa: E402
from pampipe.simulation.synthetic import Protocol, generate  # noqa: E402
from pampipe.specs.experiment import ExperimentData, make_test_data  # noqa: E402

PROBLEMS = ROOT / "problems"
LEVELS = (0.5, 0.9, 0.95, 0.99)
UNITS = ("tested", "lot")
#: The stated tolerance of the PAM (one sd) at level 1: sizes the issue quotes as moving contact by 6-20 kPa.
TOLERANCE = {"initial_length": 1e-3, "initial_diameter": 0.5e-3, "braid_angle": math.radians(1.0),
             "bladder_thickness": 0.25e-3}
RISER = 76.2 / 57.15  # the planned bore / D₀: not tested
TESTED = 88.9 / 57.15  # the one radial test's bore / D₀
DATA_SETS = ("axial + radial", "axial only")
#: The axial test of each ``--protocol`` (one cycle): ``sweep`` cycles the length at each of the paper's 10
#: pressures, 2 × 50 rows each (1000 rows); ``held`` holds 8 lengths over the contraction range and ramps the
#: pressure at each, 2 × 62 rows (992 rows), as a lab's force map is recorded.
AXIAL = {"sweep": {"cycles": 1}, "held": {"cycles": 1, "held_lengths": 8, "points_per_leg": 62}}
PROTOCOLS = tuple(AXIAL)
#: The geometry entries ``identify`` can calibrate (docs/commands.md §3.3), in the order the cache names them;
#: D₀ cannot be.
CALIBRATABLE = ("braid_angle", "bladder_thickness", "initial_length")
DEFAULT_CALIBRATE = ("braid_angle", "initial_length")
#: The calibration whose cache names carry no suffix: the one from before ``--calibrate``, the angle alone.
UNNAMED_CALIBRATE = ("braid_angle",)
FRICTION = 0.3


def stated_muscle(size: float, level: float) -> Pam:
    """The paper's radial-test muscle, its lengths scaled by ``size``, stating the tolerance × ``level``."""
    pam = load_pam(PROBLEMS / "pams" / "paper-radial-pam.yaml")
    g = pam.geometry
    geometry = dataclasses.replace(g, initial_length=g.initial_length * size,
                                   initial_diameter=g.initial_diameter * size,
                                   bladder_thickness=g.bladder_thickness * size)
    sd = {k: v * level for k, v in TOLERANCE.items()}
    return dataclasses.replace(pam, geometry=geometry, geometry_sd=sd)


def drawn_around(pam: Pam, sd: dict, rng) -> Pam:
    """``pam`` with its geometry moved by a draw from the tolerance ``sd``."""
    g = pam.geometry
    values = {k: getattr(g, k) + rng.normal(0.0, s) for k, s in sd.items()}
    return dataclasses.replace(pam, geometry=dataclasses.replace(g, **values))


def fitted(stated: Pam, truth: Pam, protocol: Protocol, seed: int, calibrate: tuple[str, ...]) -> Pam:
    """identify on synthetic data of ``truth``, starting from the stated geometry; every stated sd kept."""
    tests = tuple(make_test_data(spec, cols) for spec, cols in generate(truth, protocol, seed=seed))
    base = dataclasses.replace(stated, moduli=None, covariance=None)
    data = ExperimentData(PROBLEMS / "generated.yaml", base, tests, {})
    result = identify(data, FitOptions(calibrate=calibrate))
    return dataclasses.replace(result.fitted_pam(base), geometry_sd=dict(stated.geometry_sd))


def cached_fit(fits: Path | None, key: str, fit) -> Pam | str:
    """The PAM ``fit()`` returns, or its :class:`SolverError` message; kept as ``fits/key.yaml`` (or
    ``fits/key.failed``) and read back from there when present (``fits`` None: no cache). A kept PAM that
    pampipe refuses to read (a calibrated value the stated sd puts across the domain's edge) is a failed fit
    too, with the reader's message."""
    if fits is None:
        try:
            return fit()
        except SolverError as exc:
            return str(exc)
    pam_file, failed_file = fits / f"{key}.yaml", fits / f"{key}.failed"
    if failed_file.exists():
        return failed_file.read_text()
    if not pam_file.exists():
        try:
            write_pam(pam_file, fit())
        except SolverError as exc:
            failed_file.write_text(str(exc))
            return str(exc)
    try:
        return load_pam(pam_file)
    except InputError as exc:
        return f"the fitted PAM is refused: {exc}"


def fit_key(seed: int, k: int, size: float, level: float, name: str, protocol: str = "held",
            calibrate: tuple[str, ...] = DEFAULT_CALIBRATE) -> str:
    """The cache name of one fit: ``seed1-trial13-size1-level1-radial-held`` (``sweep``: no suffix, the
    names of the caches made before ``--protocol``), then the calibrated entries where they are not
    :data:`UNNAMED_CALIBRATE` (the names made before ``--calibrate``): ``…-radial-held-cal-braid_angle-
    initial_length`` (the default), ``…-cal-none``. ``calibrate`` is what the fit calibrates (nothing
    without a radial test, so an axial-only fit is one whatever ``--calibrate`` says)."""
    data = "radial" if "radial" in name else "axial"
    suffix = "" if protocol == "sweep" else f"-{protocol}"
    if data == "radial" and tuple(calibrate) != UNNAMED_CALIBRATE:
        suffix += "-cal-" + ("-".join(calibrate) or "none")
    return f"seed{seed}-trial{k}-size{size:g}-level{level:g}-{data}{suffix}"


def calibration(names) -> tuple[str, ...]:
    """The ``--calibrate`` names once each, in the order of :data:`CALIBRATABLE` (None: the default)."""
    return DEFAULT_CALIBRATE if not names else tuple(n for n in CALIBRATABLE if n in names)


def least(pam: Pam, bore: float, load: float, mission) -> float:
    """The closed-form least holding pressure of ``pam`` [Pa] (inf where none holds)."""
    return float(Muscle.from_pam(pam).least_holding_pressure(
        bore, load, kappa=mission.kappa, friction=FRICTION, safety_factor=mission.safety_factor))


def plans(mission, pam: Pam, samples: int, seed: int, levels=LEVELS) -> dict:
    """{unit: {C: (pressures (segments,), stopped (segments,) bool)}}, the nominal pressures and, per unit and
    C, what each source adds alone to the first segment's C-quantile [Pa] (the planner's dominance table)."""
    out, alone, nominal = {}, {}, None
    for unit in UNITS:
        segments = tuple(dataclasses.replace(s, pam=pam, pam_file=None, unit=unit) for s in mission.segments)
        m = dataclasses.replace(mission, segments=segments)
        out[unit], alone[unit] = {}, {}
        for c in levels:
            plan = plan_mission(m, confidence=c, samples=samples, seed=seed)
            stopped = plan.uncertainty.stopped[0].copy()
            out[unit][c] = (plan.arrays.pressure[0].copy(), stopped)
            alone[unit][c] = {k: float(v[0][0]) for k, v in plan.uncertainty.shifts.items()}
            nominal = plan.arrays.nominal_pressure[0].copy()
    dof = getattr(pam.uncertainty, "model_error_dof", None)
    return {"plans": out, "nominal": nominal, "alone": alone, "model_error_dof": dof}


def trial(mission, size: float, level: float, k: int, seed: int, samples: int, data_sets=DATA_SETS,
          levels=LEVELS, fits: Path | None = None, protocol: str = "held",
          calibrate: tuple[str, ...] = DEFAULT_CALIBRATE) -> dict:
    """One tested muscle, its siblings, and the plans of each data set's fit (see the module docstring;
    ``protocol``: the axial test's, a key of :data:`AXIAL`; ``calibrate``: the geometry entries fitted where
    a radial test is)."""
    stated = stated_muscle(size, level)
    rng = np.random.default_rng([seed, int(size * 1000), int(level * 1000), k])
    truth = drawn_around(stated, stated.geometry_sd, rng)
    siblings = [drawn_around(truth, stated.geometry_sd, rng) for _ in mission.segments]
    riser = RISER * stated.geometry.initial_diameter
    seg = mission.segments[0]
    load = slip.anchor_load(sum(s.mass for s in mission.segments) + mission.payload, seg.mass, math.pi / 2,
                            FRICTION, mission.tether_drag)
    route = tuple(dataclasses.replace(s, diameter=riser, diameter_low=riser, diameter_high=riser,
                                      friction=FRICTION, incline=math.pi / 2) for s in mission.route)
    mission = dataclasses.replace(mission, route=route)  # a tuple of Sections: Mission makes the columns
    out = {"true": least(truth, riser, load, mission),
           "siblings": [least(s, riser, load, mission) for s in siblings], "data": {}, "trial": k}
    axial = AXIAL[protocol]
    protocols = {"axial + radial": Protocol(pipes=(TESTED * stated.geometry.initial_diameter,), loads=(0.0,),
                                            **axial),
                 "axial only": Protocol(pipes=(), **axial)}
    for name in data_sets:
        made = protocols[name]
        entries = tuple(calibrate) if made.pipes else ()
        pam = cached_fit(fits, fit_key(seed, k, size, level, name, protocol, entries),
                         functools.partial(fitted, stated, truth, made, seed * 1000 + k, entries))
        if isinstance(pam, str):  # no PAM, no plan: counted, not hidden
            out["data"][name] = {"failed": pam}
            continue
        out["data"][name] = plans(mission, pam, samples, seed=k, levels=levels)
    return out


def _judged(rows: list[dict], name: str, unit: str, c: float):
    """Per trial: (held (segments,) bool, overhead (segments,), stopped (segments,) bool) of the plans."""
    for r in rows:
        d = r["data"].get(name)
        if d is None or "failed" in d:
            continue
        pressure, stopped = d["plans"][unit][c]
        true = np.full(pressure.shape, r["true"]) if unit == "tested" else np.asarray(r["siblings"])
        if unit == "tested":  # one muscle: every tested segment is the same plan, judged once
            pressure, stopped, true = pressure[:1], stopped[:1], true[:1]
        yield pressure >= true, pressure / true, stopped


def summary(rows: list[dict]) -> list[tuple]:
    """Per data set, unit and C: plans, holds ± se, median and 90th-percentile overhead, exit-3 rate."""
    table = []
    for name in DATA_SETS:
        failed = sum(1 for r in rows if "failed" in r["data"].get(name, {}))
        if not any(name in r["data"] for r in rows):
            continue
        for unit in UNITS:
            for c in LEVELS:
                judged = list(_judged(rows, name, unit, c))
                if not judged:
                    continue
                shares, overheads, stops, plans_n = [], [], 0, 0
                for held, overhead, stopped in judged:
                    stops += int(stopped.any())
                    plans_n += 1
                    if stopped.any():
                        continue
                    shares.append(float(np.mean(held)))
                    overheads.extend(overhead.tolist())
                n_segments = len(overheads)
                if not shares:
                    table.append((name, unit, c, plans_n, "-", "-", "-", f"{stops / plans_n:.2f}", failed))
                    continue
                p = float(np.mean(shares))
                t = len(shares)
                cluster = math.sqrt(np.var(shares, ddof=1) / t) if t > 1 else 0.0
                se = max(cluster, 0.5 / n_segments)  # at p = 1 the error of n segments, not 0
                table.append((name, unit, c, t, f"{p:.3f} ± {se:.3f}", f"{np.median(overheads):.3f}",
                              f"{np.quantile(overheads, 0.9):.3f}", f"{stops / plans_n:.2f}", failed))
    return table


def decomposition(rows: list[dict], name: str = DATA_SETS[0], c: float = 0.95) -> list[str]:
    """Lines of where the ``unit: tested`` C-quantile above the nominal plan comes from, per trial: the true
    least pressure, the nominal plan, the plan, and what each source adds alone (moduli: the fit's posterior;
    model_error: the Student-t shift; prior: the undetermined directions), all over the nominal; then the
    independent check of the spread: the smallest factor λ on every trial's (P_C − P_nom) with which a
    share ≥ C of the trials hold (λ < 1: the plans are wider than the truths' scatter needs; λ > 1: narrower),
    and the median overhead P/P_true at that λ; and z = (P_true − P_nom)/(s/F₁), the truth's miss in model
    errors s (s/F₁ [Pa]: the model error's shift alone over the quantile it was drawn at, t_ν(C) or the
    normal's), whose RMS near 1 says s is the scale of what the plans meet."""
    lines, gaps, tops, zs = [], [], [], []
    for k, r in enumerate(rows):
        d = r["data"].get(name)
        if d is None or "failed" in d or c not in d["plans"]["tested"]:
            continue
        nominal = float(d["nominal"][0])
        planned = float(d["plans"]["tested"][c][0][0])
        alone = d["alone"]["tested"][c]
        gaps.append((r["true"] - nominal, planned - nominal, nominal, r["true"]))
        words = "  ".join(f"{s} +{v / nominal:.3%}" for s, v in sorted(alone.items()))
        dof = d.get("model_error_dof")
        quantile = float(stdtrit(dof, c)) if dof else float(ndtri(c))
        scale = alone.get("model_error", 0.0) / quantile  # s/F₁ [Pa]
        z = (r["true"] - nominal) / scale if scale > 0 else math.nan
        zs.append(z)
        lines.append(f"trial {r.get('trial', k)}: P_true/P_nom {r['true'] / nominal:.4f}  "
                     f"P_{c:g}/P_nom {planned / nominal:.4f}  z {z:+.2f} (nu {dof})  alone: {words}")
        tops.append(planned / nominal)
    if not gaps:
        return lines
    need, spread, nominal, true = (np.array(x) for x in zip(*gaps, strict=True))
    ratio = np.where(spread > 0, need / np.where(spread > 0, spread, 1.0), np.where(need <= 0, 0.0, np.inf))
    lam = float(np.quantile(ratio, c, method="inverted_cdf"))  # the least λ with a share ≥ c holding
    lines.append(f"{len(gaps)} plans: P_{c:g}/P_nom median {np.median(tops):.4f}; P_true/P_nom median "
                 f"{np.median(true / nominal):.4f}, sd {np.std(true / nominal, ddof=1):.4f}; "
                 f"least lambda holding {c:g} of the trials: {lam:.3f}, its median overhead "
                 f"{np.median((nominal + lam * spread) / true):.4f} (lambda 1: "
                 f"{np.median((nominal + spread) / true):.4f}); "
                 f"z RMS {math.sqrt(np.nanmean(np.square(zs))):.3f}")
    return lines


def run(trials: int, seed: int, samples: int = 4000, progress=None, data_sets=DATA_SETS, size: float = 1.0,
        level: float = 1.0, levels=LEVELS, fits: Path | None = None, protocol: str = "held",
        shard: tuple[int, int] = (0, 1), calibrate: tuple[str, ...] = DEFAULT_CALIBRATE) -> list[dict]:
    """``trials`` trials of one muscle size and tolerance level, planned at each C of ``levels`` (``fits``:
    the folder of cached fits, see the module docstring); of those, the trials k with k % N = I for
    ``shard`` = (I, N); ``calibrate``: the geometry entries fitted where a radial test is."""
    mission = load_mission(PROBLEMS / "missions" / "vertical-climb-3in.yaml")
    mission = dataclasses.replace(mission, route=mission.route[:1])
    rows = []
    index, count = shard
    for k in range(index, trials, count):
        rows.append(trial(mission, size, level, k, seed, samples, data_sets, levels, fits, protocol,
                          calibrate))
        if progress:
            progress(k, rows[-1])
    return rows


def shard_of(text: str) -> tuple[int, int]:
    """``I/N`` (0 ≤ I < N) as (I, N); anything else an argparse error (exit 2) naming what is allowed."""
    try:
        index, count = (int(x) for x in text.split("/"))
    except ValueError:
        index, count = -1, 0
    if not 0 <= index < count:
        raise argparse.ArgumentTypeError(f"{text!r}: give I/N with whole numbers 0 <= I < N, e.g. 0/2")
    return index, count


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=30)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--samples", type=int, default=4000)
    parser.add_argument("--sizes", default="1,0.5", help="muscle sizes, as factors of the paper's lengths")
    parser.add_argument("--levels", default="0.5,1", help="tolerance levels, as factors of the stated sds")
    parser.add_argument("--data", default="both", choices=("both", "radial", "axial"))
    parser.add_argument("--quick", action="store_true", help="6 trials, size 1, level 1")
    parser.add_argument("--fits", type=Path, help="folder of cached fitted PAMs (made if missing, reused)")
    parser.add_argument("--fit-only", action="store_true", help="fit (into --fits) and plan nothing")
    parser.add_argument("--protocol", default="held", choices=PROTOCOLS,
                        help="the axial test: held lengths, pressure ramped (a force map), or length sweeps")
    parser.add_argument("--shard", type=shard_of, default=(0, 1), metavar="I/N",
                        help="run only the trials k with k %% N == I (N processes in parallel)")
    parser.add_argument("--calibrate", action="append", choices=CALIBRATABLE, metavar="NAME",
                        help="a geometry entry identify fits where a radial test is (repeatable: "
                             f"{', '.join(CALIBRATABLE)}; default {', '.join(DEFAULT_CALIBRATE)})")
    parser.add_argument("--decompose", action="store_true",
                        help="also print, per trial, what each source adds to the tested C = 0.95 plan")
    args = parser.parse_args(argv)
    calibrate = calibration(args.calibrate)
    if args.quick:
        args.trials, args.sizes, args.levels = 6, "1", "1"
    data_sets = {"both": DATA_SETS, "radial": DATA_SETS[:1], "axial": DATA_SETS[1:]}[args.data]
    if args.fits:
        args.fits.mkdir(parents=True, exist_ok=True)
    if args.fit_only and not args.fits:
        parser.error("--fit-only needs --fits DIR")
    headers = ("data", "unit", "C", "plans", "holds (± se)", "median P/P_true", "p90 P/P_true", "exit 3",
               "fits failed")
    for size in (float(x) for x in args.sizes.split(",")):
        for level in (float(x) for x in args.levels.split(",")):
            started = time.perf_counter()

            def progress(k, row, size=size, level=level):
                words = [f"{n}: " + ("identify failed" if "failed" in d else
                                     f"tested {d['plans']['tested'][0.95][0][0] / 1e3:.1f} vs "
                                     f"{row['true'] / 1e3:.1f} kPa" if d["plans"]["tested"] else "fitted")
                         for n, d in row["data"].items()]
                print(f"  size {size:g} level {level:g} trial {k}: " + "; ".join(words), file=sys.stderr,
                      flush=True)

            rows = run(args.trials, args.seed, args.samples, progress, data_sets, size, level,
                       levels=() if args.fit_only else LEVELS, fits=args.fits, protocol=args.protocol,
                       shard=args.shard, calibrate=calibrate)
            if args.fit_only:
                continue
            d0 = 57.15 * size
            print(f"\ncoverage over {len(rows)} tested muscles (seed {args.seed}, {args.samples} draws, "
                  f"{args.protocol} axial protocol, calibrating {'+'.join(calibrate)} with radial data): "
                  f"D0 {d0:.4g} mm, riser {RISER * d0:.4g} mm (untested), radial test at {TESTED * d0:.4g} "
                  "mm; "
                  f"tolerance sd x {level:g}: L0 {level:g} mm, D0 {0.5 * level:g} mm, braid angle {level:g} "
                  f"deg, wall {0.25 * level:g} mm; {time.perf_counter() - started:.0f} s", flush=True)
            table = summary(rows)
            widths = [max(len(str(x)) for x in col) for col in zip(headers, *table, strict=True)]
            for line in (headers, *table):
                print("  ".join(str(x).rjust(w) for x, w in zip(line, widths, strict=True)), flush=True)
            if args.decompose:
                for name in data_sets:
                    print(f"\n{name}, unit: tested, C = 0.95, over the nominal plan:")
                    print("\n".join(decomposition(rows, name)), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
