"""Slip onset in one trial: where the displacement departs from its elastic trend (docs/physics.md §13.2).

While the muscle sticks, the displacement follows the load elastically, d ≈ a + b·F. The trend is fitted
over the first half of the load's rise; its noise σ_d is 1.4826·MAD of those residuals (floored at
10⁻⁹ m). The onset is the first row from which the residual r = d − (a + bF) stays above
T = max(:data:`THRESHOLD`·σ_d, :data:`ELASTIC_SHARE`·b·ΔF) (ΔF the load's rise) to the end of the
trial: a slip shifts the muscle for good, stick-slip included (each stick re-loads from the shifted
position). The slip load is the largest load before the onset
(the static peak; the load may fall once the muscle moves), the pressure the one at that peak.

Confidence: Φ((r̃ − T)/σ_d) with r̃ the median departure after the onset (0.5 at the threshold, 0.98 two
σ_d above). A trial that never departs is censored: the muscle held every load of the trial, so its largest
load is a lower bound of the slip load, with confidence Φ((T − r_max)/σ_d), r_max its largest residual.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: Departure from the elastic trend, in noise standard deviations, that counts as slip.
THRESHOLD = 6.0
#: Share of the trial's load rise over which the elastic trend is fitted.
TREND_SHARE = 0.5
#: Departure, as a share of the elastic displacement over the whole rise, below which it is not slip (a
#: mildly non-linear elastic trend curves away from the fitted line by a few per cent).
ELASTIC_SHARE = 0.05


@dataclass(frozen=True)
class Trial:
    """One trial's detected slip (SI). ``censored``: no slip, ``slip_load`` is then the largest load held.

    ``onset_row`` is the row (in the test's time order) of the first slipped sample (None if censored),
    ``peak_row`` the row of ``slip_load``; ``load_rate`` [N/s] the mean rate of the elastic rise;
    ``compliance`` b [m/N] and ``noise`` σ_d [m] of the elastic trend.
    """

    test: str
    index: int  # 0-based trial number in its test
    pipe_diameter: float  # [m]
    pressure: float  # [Pa] at the slip (or at the largest load held)
    slip_load: float  # [N]
    censored: bool
    confidence: float
    onset_row: int | None
    peak_row: int
    first_row: int
    end_row: int
    load_rate: float  # [N/s]
    compliance: float  # [m/N]
    noise: float  # [m]
    departure: float  # median residual after the onset (largest residual if censored) [m]
    onset_time: float | None = None  # [s] of the first slipped sample (None if censored)


def detect(test: str, index: int, pipe_diameter: float, time, pressure, load, displacement,
           first_row: int = 0) -> Trial:
    """The :class:`Trial` of one trial's rows (time order). Arrays in SI; ``first_row`` offsets rows."""
    time, pressure, load, displacement = (np.asarray(v, dtype=float)
                                          for v in (time, pressure, load, displacement))
    top = int(np.argmax(load))
    low = float(np.min(load[:top + 1]))
    begin = int(np.flatnonzero(load[:top + 1] <= low + 0.02 * (load[top] - low))[-1])
    if begin:  # the rest before the rise may belong to the previous trial (re-seated, re-zeroed): drop it
        time, pressure = time[begin:], pressure[begin:]
        load, displacement = load[begin:], displacement[begin:]
        first_row, top = first_row + begin, top - begin
    start = load[0]
    rise = load[top] - start
    window = np.flatnonzero(load[:top + 1] <= start + TREND_SHARE * rise)
    if window.size < 4:
        window = np.arange(min(4, top + 1))
    slope, intercept = _line(load[window], displacement[window])
    residual = displacement - (intercept + slope * load)
    noise = max(1.4826 * float(np.median(np.abs(residual[window] - np.median(residual[window])))), 1e-9)
    # a mildly non-linear elastic trend curves away from the line by a few per cent: that is no slip
    threshold = max(THRESHOLD * noise, ELASTIC_SHARE * abs(slope) * rise)
    above = residual > threshold
    stays = np.flip(np.logical_and.accumulate(np.flip(above)))  # above from here to the end
    stays[window] = False  # never inside the fitted window
    onset = int(np.argmax(stays)) if stays.any() else None
    span = time[window[-1]] - time[window[0]]
    rate = (load[window[-1]] - load[window[0]]) / span if span > 0 else math.nan
    if onset is None:
        peak = top
        largest = float(np.max(residual))
        return Trial(test, index, pipe_diameter, float(pressure[peak]), float(load[peak]), True,
                     _phi((threshold - largest) / noise), None, first_row + peak, first_row,
                     first_row + load.size, rate, slope, noise, largest)
    peak = int(np.argmax(load[:onset])) if onset > 0 else 0
    departure = float(np.median(residual[onset:]))
    return Trial(test, index, pipe_diameter, float(pressure[peak]), float(load[peak]), False,
                 _phi((departure - threshold) / noise), first_row + onset, first_row + peak, first_row,
                 first_row + load.size, rate, slope, noise, departure, float(time[onset]))


def _line(x: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    """(slope, intercept) of the least-squares line y = intercept + slope·x (slope 0 if x is constant)."""
    if np.ptp(x) <= 0:
        return 0.0, float(np.mean(y))
    slope, intercept = np.polyfit(x, y, 1)
    return float(slope), float(intercept)


def _phi(z: float) -> float:
    """Standard normal CDF Φ(z)."""
    return 0.5 * math.erfc(-z / math.sqrt(2.0))
