"""Global calibration: the calibrated fit solved from many starting geometries with one NLP
(docs/commands.md §3.4).

Starts: the braid angle is first screened at :data:`SCREENED` evenly spread points of its range (the
other calibrated entries at their stated values) by the moduli's linear least squares at each
geometry, without IPOPT; the lowest local minima of that profile (at most :data:`LOCAL`) are starts,
and so are the stated geometry, the braid angle of the blocked-force check at the stated L₀
(:mod:`.geometry`) and the (α₀, L₀) of the force slopes (:mod:`.seeds`), each clipped into the
bounds; a start closer than :data:`START_SAME` to an earlier one is dropped. From each start IPOPT
fits the moduli and the geometry together. Every start uses the same built NLP: only x₀ and the data
in the parameter vector (slack flags, Drucker rows) differ.

Minima: the solutions sorted by their sum of squares, merged when their geometries agree within
:data:`SAME`. ``reached_best`` counts the starts that ended in the best; a *runner-up* is another
minimum whose RMSE is within :data:`CLOSE` × the best's but whose geometry is far from it (braid
angle more than 1°, rest length more than 0.5 %, wall thickness more than 25 % apart): the data do
not clearly prefer one geometry.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from pampipe.errors import SolverError

#: Braid angles screened (evenly spread over the range) by the moduli's linear fit at that geometry.
SCREENED = 12
#: IPOPT starts from at most this many local minima of the screened profile.
LOCAL = 3
#: Solutions closer than this are one minimum (x units: deg, mm, mm).
SAME = {"braid_angle": 0.05, "initial_length": 0.05, "bladder_thickness": 0.01}
#: Starts closer than this to an earlier start are not run (they would end in the same minimum).
START_SAME = {"braid_angle": 0.5, "initial_length": 0.5, "bladder_thickness": 0.05}
#: The start tried where every other start failed: the stated geometry with the moduli fitted there, a
#: converged point (the other starts take the moduli's bounded linear least squares, which can sit on
#: the bounds where IPOPT's step fails: seed 1, trial 13 of benchmarks/bench_coverage.py).
FALLBACK = "the stated geometry's fit (every other start failed)"
#: A runner-up's RMSE is at most this multiple of the best's.
CLOSE = 1.25
#: Far in geometry: braid angle [deg], relative rest length, relative wall thickness.
FAR = {"braid_angle": 1.0, "initial_length": 0.005, "bladder_thickness": 0.25}
#: Units of the calibrated entries in x, for the report.
UNITS = {"braid_angle": "deg", "initial_length": "mm", "bladder_thickness": "mm"}


@dataclass(frozen=True)
class Minimum:
    """One local minimum: its geometry (x units, in calibration order), sum of squares and RMSE, and
    the starts that ended in it."""

    geometry: tuple[float, ...]
    sse: float  # [N²]
    rmse: float  # [N]
    starts: tuple[str, ...]

    def as_document(self, calibrate) -> dict:
        doc = {"rmse_N": self.rmse, "sse_N2": self.sse, "starts": len(self.starts),
               "from": list(self.starts)}
        for name, value in zip(calibrate, self.geometry, strict=True):
            doc["braid_angle_from_axis_deg" if name == "braid_angle" else f"{name}_m"] = \
                value if name == "braid_angle" else value * 1e-3
        return doc


@dataclass(frozen=True)
class Search:
    """The outcome of the multi-start: the starts tried and the minima found (best first)."""

    calibrate: tuple[str, ...]
    starts: tuple[tuple[str, tuple[float, ...]], ...]  # (label, geometry in x units)
    minima: tuple[Minimum, ...]
    failed: tuple[str, ...]  # starts whose solve failed
    seed: object | None  # :class:`.seeds.Seed` or None
    screened: int = 0  # braid angles screened without IPOPT

    @property
    def best(self) -> Minimum:
        return self.minima[0]

    @property
    def reached_best(self) -> int:
        return len(self.best.starts)

    def runner_ups(self) -> list[Minimum]:
        """Minima close to the best in cost but far from it in geometry."""
        return [m for m in self.minima[1:] if m.rmse <= CLOSE * self.best.rmse and _far(self.calibrate,
                                                                                         m, self.best)]

    def as_document(self) -> dict:
        return {"starts": len(self.starts), "reached_best": self.reached_best, "failed": len(self.failed),
                "screened": self.screened,
                "best": self.best.as_document(self.calibrate),
                "runner_up_minima": [m.as_document(self.calibrate) for m in self.runner_ups()],
                "minima": [m.as_document(self.calibrate) for m in self.minima],
                "start_points": [{"from": label, **dict(zip(self.calibrate, x, strict=True))}
                                 for label, x in self.starts],
                "close_rmse_factor": CLOSE,
                "seed_from_force_slopes": None if self.seed is None else self.seed.as_document()}

    def describe(self) -> list[str]:
        """Report lines: starts, how many reached the best, runner-ups."""
        def where(m: Minimum) -> str:
            pairs = zip(self.calibrate, m.geometry, strict=True)
            return ", ".join(f"{name} {value:.5g} {UNITS[name]}" for name, value in pairs)

        count = len(self.starts)
        lines = [f"global calibration: {count} start{'s' if count != 1 else ''}"
                 + (f" (after screening {self.screened} braid angles)" if self.screened else "")
                 + f", {self.reached_best} reached the best "
                 f"(RMSE {self.best.rmse:.4g} N at {where(self.best)})"
                 + (f", {len(self.failed)} failed" if self.failed else "")
                 + (f"; {len(self.minima) - 1} other local minim{'a' if len(self.minima) > 2 else 'um'}"
                    if len(self.minima) > 1 else "")]
        runners = self.runner_ups()
        lines.append("runner-up minima close in cost but far in geometry: "
                     + ("none" if not runners else "; ".join(f"RMSE {m.rmse:.4g} N at {where(m)} "
                                                             f"({len(m.starts)} starts)" for m in runners)))
        return lines


def start_points(calibrate, lower, upper, stated_x, extra, screen: Callable
                 ) -> tuple[list[tuple[str, np.ndarray]], int]:
    """(label, geometry x) of every IPOPT start, and how many grid points were screened.

    The braid angle at :data:`SCREENED` evenly spread points of its range (other entries stated) is
    screened by ``screen(x) -> SSE`` (the moduli's linear least squares at that geometry, no IPOPT);
    the :data:`LOCAL` lowest local minima of that profile become starts, then ``extra`` (label, x or
    None: the data's seeds). Starts closer than :data:`START_SAME` to an earlier one are dropped."""
    lower, upper = np.asarray(lower, float), np.asarray(upper, float)
    inside = lower + 1e-6 * (upper - lower), upper - 1e-6 * (upper - lower)
    out, screened = [], 0
    if "braid_angle" in calibrate:
        k = list(calibrate).index("braid_angle")
        grid = []
        for j in range(SCREENED):
            x = np.clip(np.array(stated_x, float), *inside)
            x[k] = lower[k] + (j + 0.5) / SCREENED * (upper[k] - lower[k])
            grid.append(x)
        profile = np.array([screen(x) for x in grid])
        screened = len(grid)
        padded = np.concatenate([[np.inf], profile, [np.inf]])
        minima = [j for j in range(screened) if padded[j + 1] <= padded[j] and padded[j + 1] <= padded[j + 2]]
        for j in sorted(minima, key=lambda j: profile[j])[:LOCAL]:
            out.append((f"braid angle {grid[j][k]:.3g} deg (screened)", grid[j]))
    out += [(label, np.asarray(x, float)) for label, x in extra if x is not None]
    kept = []
    for label, x in out:
        x = np.clip(x, *inside)
        if not any(_close(calibrate, x, y, START_SAME) for _, y in kept):
            kept.append((label, x))
    return kept, screened


def search(run: Callable, starts, calibrate, rows: int, seed=None, screened: int = 0, fallback=None):
    """Run ``run(x_geometry) -> (payload, sse, fitted geometry x)`` from every start; returns
    (:class:`Search`, the best start's payload). A start whose solve fails is counted, not fatal.
    Where every start fails, ``fallback`` (label, geometry x, ``() -> run's answer``: in a calibrated
    fit the moduli fitted at the stated geometry as the start, :data:`FALLBACK`) is run and listed among
    the starts; where it fails too (or there is none) the first failure is raised."""
    results, failed, errors = [], [], []
    tried = list(starts)

    def attempt(label, go):
        try:
            payload, sse, fitted = go()
        except SolverError as error:
            failed.append(label)
            errors.append(error)
            return
        results.append((float(sse), np.asarray(fitted, float), label, payload))

    for label, x in starts:
        attempt(label, lambda x=x: run(x))
    if not results and fallback is not None:
        tried.append(fallback[:2])
        attempt(fallback[0], fallback[2])
    if not results:
        raise errors[0]
    results.sort(key=lambda item: item[0])
    minima: list[list] = []  # [sse, geometry, labels]
    for sse, fitted, label, _ in results:
        for minimum in minima:
            if _same(calibrate, fitted, minimum[1]):
                minimum[2].append(label)
                break
        else:
            minima.append([sse, fitted, [label]])
    found = tuple(Minimum(tuple(float(v) for v in g), s, math.sqrt(s / max(rows, 1)), tuple(labels))
                  for s, g, labels in minima)
    report = Search(tuple(calibrate), tuple((label, tuple(float(v) for v in x)) for label, x in tried),
                    found, tuple(failed), seed, screened)
    return report, results[0][3]


def _same(calibrate, a, b) -> bool:
    return _close(calibrate, a, b, SAME)


def _close(calibrate, a, b, tolerance) -> bool:
    return all(abs(u - v) <= tolerance[name] for name, u, v in zip(calibrate, a, b, strict=True))


def _far(calibrate, a: Minimum, b: Minimum) -> bool:
    for name, u, v in zip(calibrate, a.geometry, b.geometry, strict=True):
        gap = abs(u - v) if name == "braid_angle" else abs(u - v) / max(abs(v), 1e-12)
        if gap > FAR[name]:
            return True
    return False
