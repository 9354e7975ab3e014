"""The result of `pampipe gait` / :func:`pampipe.gait`: the sequential gait and the time-optimal one
(docs/commands.md §5.2); light to import (no numpy), so that ``import pampipe`` stays quick."""

from __future__ import annotations

from dataclasses import dataclass

from pampipe.results import notebook


def _plot():
    from pampipe.views.plots.gait import plot_report

    return plot_report


def _text():
    from pampipe.views.gait_text import result_text

    return result_text


@notebook(headline=("section", "cycle_time_s", "speed_gain"), plot=_plot, text=_text)
@dataclass(frozen=True)
class GaitReport:
    """The sequential gait and, if asked for, the time-optimal one; ``to_dict()`` is `gait --json`."""

    sequential: object  # pampipe.locomotion.GaitResult
    optimal: object | None = None
    bends: dict | None = None  # the route's bends: extra steering steps and time (pampipe.bends.gait)

    @property
    def results(self) -> tuple:
        return (self.sequential,) if self.optimal is None else (self.sequential, self.optimal)

    @property
    def speed_gain(self) -> float | None:
        """Relative speed gain of the optimal gait over the sequential one."""
        if self.optimal is None:
            return None
        return self.sequential.cycle_time / self.optimal.cycle_time - 1

    def to_dict(self) -> dict:
        if self.optimal is None:
            document = self.sequential.as_document()
        else:
            document = self.optimal.as_document()
            document["sequential"] = self.sequential.as_document()
            document["speed_gain"] = self.speed_gain
        if self.bends is not None:
            document["bends"] = self.bends
        return document

