"""Every plot is fit to print: labelled axes with units, no legend entry without a drawn artist (issue 26),
and --plot-format writes the format asked for."""

from __future__ import annotations

import re
import subprocess
import sys

import numpy as np
import pytest

import pampipe
from pampipe.views.tables import capture
from tests.support.problems import PROBLEMS, ROOT

UNIT = re.compile(r"\[[^\]]+\]|\(network units\)")


def _figures(draw, *args) -> list:
    with capture() as figures:
        draw(*args, None)
    assert figures
    return figures


def _drawn(artist) -> bool:
    """The artist shows something: a line with a finite point, a patch, a non-empty collection."""
    from matplotlib.collections import Collection
    from matplotlib.lines import Line2D

    if isinstance(artist, Line2D):
        x, y = (np.asarray(v, dtype=float) for v in artist.get_data())
        return bool(np.any(np.isfinite(x) & np.isfinite(y)))
    if isinstance(artist, Collection):
        return len(artist.get_paths()) > 0
    return artist.get_visible()


def check(fig) -> None:
    panels = [ax for ax in fig.axes if ax.get_label() != "<colorbar>"]
    for ax in panels:
        title = ax.get_title() or fig.texts
        assert UNIT.search(ax.get_ylabel()), (title, ax.get_ylabel())
        handles, labels = ax.get_legend_handles_labels()
        for artist, label in zip(handles, labels, strict=True):
            assert _drawn(artist), f"{title}: legend entry {label!r} has nothing drawn"
    assert any(UNIT.search(ax.get_xlabel()) for ax in panels), [ax.get_xlabel() for ax in panels]


@pytest.fixture(scope="module")
def plan():
    return pampipe.plan(PROBLEMS / "missions" / "vertical-climb-3in.yaml", payload="3 kg")


def test_plan_plots(plan):
    from pampipe.views.plots.plan import plot_plan

    for fig in _figures(plot_plan, plan):
        check(fig)


def test_plan_draws_identical_segments_as_one_line(plan):
    """The three PAMs of the demo share their pressures: one line, named after all three."""
    fig = plan.plot()
    labels = fig.axes[0].get_legend_handles_labels()[1]
    planned = [label for label in labels if "planned pressure" in label]
    assert planned == ["PAM1, PAM2, PAM3: planned pressure"]
    assert "red band" not in fig.axes[0].get_title()


def test_required_pressure_axis_shows_the_step_between_sections(plan):
    """The step from the riser to the run (about 122 -> 167 kPa, docs/workflows.md §1.4) fills the axis; the
    689 kPa supply, far above, is named on the plot instead of squashing the axis to 0-700 kPa (issue 42)."""
    ax = plan.plot().axes[0]
    low, high = ax.get_ylim()
    stairs = [p for p in ax.patches if "planned pressure" in str(p.get_label())]
    values = stairs[0].get_data().values
    assert high - low < 2 * (values.max() - values.min())
    assert low < values.min() and values.max() < high < 689
    assert any("supply pressure 689 kPa" in text.get_text() for text in ax.texts)


def test_network_route_plots_and_colour_span():
    from pampipe.views.plots.plan import plot_plan

    plan = pampipe.plan(PROBLEMS / "missions" / "ky4-route.yaml")
    figures = _figures(plot_plan, plan)
    for fig in figures:
        check(fig)
    bars = [image for fig in figures for ax in fig.axes for image in ax.collections
            if image.get_array() is not None and ax.get_label() != "<colorbar>"]
    for image in bars:
        low, high = image.get_clim()
        assert high - low >= 0.05 * plan.supply_pressure / 1e3 - 1e-9
    # issue 42: the network map's coordinates carry no 1e6 offset and its grey is in the legend; the bend's
    # axes name their quantity
    by_title = {fig.axes[0].get_title().split(":")[0]: fig for fig in figures}
    network = next(fig for title, fig in by_title.items() if title.startswith("network"))
    network.canvas.draw()
    ax = network.axes[0]
    assert ax.xaxis.get_offset_text().get_text() == "" and ax.yaxis.get_offset_text().get_text() == ""
    assert "pipe not planned (off the route)" in ax.get_legend_handles_labels()[1]
    bend = next(fig for title, fig in by_title.items() if title.startswith("tightest bend"))
    assert "centre of curvature [m]" in bend.axes[0].get_xlabel()


def test_tornado_shows_every_segment_with_labels_off_the_planned_line():
    from pampipe.views.plots.tornado import plot_tornado

    plan = pampipe.plan(PROBLEMS / "missions" / "riser-uncertain-friction.yaml", confidence=0.95)
    (fig,) = _figures(lambda p, folder: plot_tornado(p, folder, "kPa", 1e3), plan)
    assert len(fig.axes) == 3  # PAM1, PAM2, PAM3 of the section with the largest pressure
    for ax in fig.axes:
        planned = next(line.get_xdata()[0] for line in ax.lines if line.get_linestyle() == "--")
        assert ax.texts and all(text.xy[0] >= planned - 1e-9 for text in ax.texts)


def test_simulate_and_gait_plots():
    from pampipe.views.plots.gait import plot_report
    from pampipe.views.plots.simulate import plot_simulation

    pam = PROBLEMS / "pams" / "paper-radial-pam.yaml"
    simulation = pampipe.simulate(pam, pipe_diameter=["3 in", "3.5 in"])
    for fig in _figures(plot_simulation, simulation):
        check(fig)
    space_time = 0
    for fig in _figures(plot_report, pampipe.gait(PROBLEMS / "missions" / "vertical-climb-3in.yaml")):
        check(fig)
        fig.canvas.draw()
        for ax in fig.axes:  # issue 42: a space-time diagram's legends sit beside the curves, not on them
            legend = ax.get_legend()
            if legend is not None and ax.get_ylabel().startswith(("position along", "displacement since")):
                box, frame = legend.get_window_extent(), ax.get_window_extent()
                assert box.x0 >= frame.x1 - 1
                space_time += 1
    assert space_time == 2


@pytest.mark.parametrize("kind", ["svg", "pdf"])
def test_plot_format(kind, tmp_path):
    pam = PROBLEMS / "pams" / "paper-radial-pam.yaml"
    out = subprocess.run([sys.executable, "-m", "pampipe", "simulate", str(pam), "--pipe-diameter", "3 in",
                          "--plots", str(tmp_path), "--plot-format", kind],
                         capture_output=True, text=True, cwd=ROOT, timeout=300)
    assert out.returncode == 0, out.stderr
    written = sorted(p.name for p in tmp_path.iterdir())
    names = ("radial_force", "free_contraction", "amplification")
    assert written == sorted(f"{name}.{kind}" for name in names)
    head = (tmp_path / f"radial_force.{kind}").read_bytes()[:5]
    assert head == (b"<?xml" if kind == "svg" else b"%PDF-")


def test_a_figure_legend_is_shown_in_the_users_units():
    """A legend of the whole figure (the Drucker map's, below the axes) is converted like the axes' own;
    the control: the axis legend next to it."""
    from matplotlib.figure import Figure

    from pampipe.units.display import shown_in
    from pampipe.views.plots.display_units import localize_figure

    fig = Figure()
    ax = fig.add_subplot()
    ax.plot([0, 1], [0, 1], label="exact minimum 0.00263 MPa (axial)")
    ax.legend()
    fig.legend(loc="outside lower center")
    with shown_in("us"):
        localize_figure(fig)
    texts = [t.get_text() for legend in (ax.get_legend(), *fig.legends) for t in legend.get_texts()]
    assert texts == ["exact minimum 0.381 psi (axial)"] * 2, texts


def test_a_log_axis_gets_decades_of_the_users_unit():
    """Under us, a log axis in N is ticked at 1, 10, 100 lbf (not at N decades relabelled 2.248, 22.48)."""
    from matplotlib.figure import Figure

    from pampipe.units.display import shown_in
    from pampipe.views.plots.display_units import localize_figure

    fig = Figure()
    ax = fig.add_subplot()
    ax.semilogy([0, 1], [5.0, 5000.0])
    ax.set_ylabel("holding capacity [N]")
    with shown_in("us"):
        localize_figure(fig)
    lbf = 4.4482216152605  # N
    ticks = [t * (1 / lbf) for t in ax.yaxis.get_major_locator().tick_values(5.0, 5000.0)]
    inside = [t for t in ticks if 5.0 / lbf <= t <= 5000.0 / lbf]
    assert inside and all(abs(t - round(t)) < 1e-9 and str(round(t)).strip("0") == "1" for t in inside), ticks


def test_the_simulation_plots_draw_the_models_numbers():
    """What radial_force.png and free_contraction.png draw, read from the figure (issue 40): the radial
    force curve of each bore is F_r of the muscle at the plotted pressures (Muscle.radial_force, no load),
    the dotted line stands at the published anchoring pressures (117.0 kPa in 3 in, 165.0 kPa in 3.5 in,
    docs/physics.md §7), the legend names the bores in mm, and the axes cover the drawn data."""
    from pampipe.io.pam_schema import load_pam
    from pampipe.model.muscle import Muscle
    from pampipe.views.plots.simulate import plot_simulation

    pam = PROBLEMS / "pams" / "paper-radial-pam.yaml"
    muscle = Muscle.from_pam(load_pam(pam))
    simulation = pampipe.simulate(pam, pipe_diameter=["3 in", "3.5 in"])
    radial, contraction, _ = _figures(plot_simulation, simulation)
    ax = radial.axes[0]
    curves = [line for line in ax.get_lines() if line.get_linestyle() == "-" and line.get_label()[0] != "_"]
    assert [line.get_label().split(",")[0] for line in curves] == ["D_p = 76.2 mm", "D_p = 88.9 mm"]
    for line, bore in zip(curves, (0.0762, 0.0889), strict=True):
        x, y = (np.asarray(v, dtype=float) for v in line.get_data())
        assert x.size > 10
        np.testing.assert_allclose(y, muscle.radial_force(x * 1e3, bore, 0.0), rtol=1e-9, atol=1e-9)
        low, high = ax.get_xlim()
        assert low <= x.min() and x.max() <= high
    anchoring = sorted(line.get_xdata()[0] for line in ax.get_lines() if line.get_linestyle() == ":")
    np.testing.assert_allclose(anchoring, [117.0, 165.0], atol=0.5)
    assert "[kPa]" in ax.get_xlabel() and "[N]" in ax.get_ylabel()
    assert contraction.axes and contraction.axes[0].get_lines()


def test_design_starts_show_round_off_as_one_value():
    """The riser's 16 starts reach one optimum to within IPOPT's tolerance: drawn as one value in a 2 %
    window, not as a spread of 1e-6 Pa; no shading is promised when no start failed (issue 42)."""
    from pampipe.views.plots.design import plot_design

    result = pampipe.design_inventory(PROBLEMS / "inventories" / "riser.yaml")
    ax = _figures(plot_design, result)[-1].axes[0]
    values = {float(v) for c in ax.collections for v in c.get_offsets()[:, 1]}
    assert len(values) == 1
    low, high = ax.get_ylim()
    (value,) = values
    assert high - low == pytest.approx(0.02 * value, rel=1e-6)
    assert "shaded" not in ax.get_xlabel()
