"""The commands that write files, as functions (docs/commands.md §11.1): `route` (a mission file through a
network), `synth` (a synthetic experiment) and `example` (a bundled problem copied). Each returns a
:class:`CommandResult`: the command's ``--json`` document and its text report; the command line calls them.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import partial

from pampipe.api import arguments as arg
from pampipe.errors import InputError
from pampipe.results import notebook


def _text():
    return _rendered


def _plot():
    from pampipe.views.plots.route import plot_command

    return plot_command


def _rendered(result: CommandResult) -> str:
    return result.render()


@notebook(headline=("command",), plot=_plot, text=_text)
@dataclass(frozen=True)
class CommandResult:
    """The outcome of a command that writes files (route, synth, example): its ``--json`` document
    (``to_dict()``) and its text report (``str()``, ``to_text(units)``; ``render()`` writes it)."""

    command: str
    document: dict
    render: Callable[[], str] = field(repr=False, compare=False)

    def to_dict(self) -> dict:
        return {"command": self.command, **self.document}

    @property
    def text(self) -> str:
        """The text report in the units of :func:`pampipe.set_units`."""
        return self.to_text()


def route(network: str | os.PathLike, *, from_node: str, to_node: str, friction=None, template=None,
          min_bore=None, max_bore=None, output=None, force: bool = False, **unexpected) -> CommandResult:
    """The shortest path through a water network as mission sections (`pampipe route`): ``network`` a name
    shipped with wntr or an EPANET .inp file; ``output`` a mission file to write (an existing one only with
    ``force``), ``template`` the mission whose other keys it copies; ``friction``, ``min_bore`` and
    ``max_bore`` numbers in SI or unit strings (``"3 in"``)."""
    from pampipe.io.network_mission import network_mission
    from pampipe.views.route_text import route_text

    arg.no_other(route, unexpected)
    found = network_mission(
        str(network), str(from_node), str(to_node), friction=arg.si(friction, "dimensionless", "friction"),
        template=arg.path(template, "template"), min_bore=arg.si(min_bore, "length", "min_bore"),
        max_bore=arg.si(max_bore, "length", "max_bore"), output=arg.path(output, "output"),
        force=arg.flag(force, "force"))
    return CommandResult("route", found.as_document(), partial(route_text, found))


def synth(out_dir: str | os.PathLike, *, pam=None, name: str = "experiment", seed: int = 0, force_noise=2.0,
          pressure_noise=0.0, points_per_leg: int = 50, cycles: int = 3, radial_points: int = 40,
          slip_pipe=None, friction=0.3, load_coupling=1.0, slip_scatter=0.03, stick_slip: bool = False,
          slip_pressure=None, held_trial=None, pipe_material: str | None = None, slip_only: bool = False,
          force: bool = False, held_lengths: int = 0, **unexpected) -> CommandResult:
    """Write a synthetic experiment (YAML + CSV) of the known moduli of ``pam`` (default: the bundled
    paper-radial-pam.yaml) into ``out_dir`` (`pampipe synth`); ``to_dict()["experiment"]`` is the file to
    pass to :func:`pampipe.identify`. The paper's protocol: ``cycles`` axial cycles of ``points_per_leg``
    samples per leg (with ``held_lengths`` N > 0 instead N held lengths, the pressure ramped up and down at
    each, ``points_per_leg`` samples per ramp: a force map), ``radial_points`` per radial level, Gaussian
    ``force_noise`` and ``pressure_noise`` (SI or unit strings, ``"2 N"``) from ``seed``. With ``slip_pipe``
    (bores) also slip tests of ``friction``, ``load_coupling``, ``slip_scatter`` at ``slip_pressure``
    (default 250 to 600 kPa), ``held_trial`` (1-based) never slipping; ``slip_only`` writes those alone.
    Existing files are replaced only with ``force``."""
    from pampipe.identification.noise import MOST_HELD_LENGTHS
    from pampipe.io import bundled
    from pampipe.io.csvfile import check_rows
    from pampipe.io.pam_schema import load_pam
    from pampipe.io.pamfile import write_experiment
    from pampipe.model.domain import check_kind
    from pampipe.simulation.synthetic import Protocol, synthetic_tests
    from pampipe.views.synth_text import synth_text

    arg.no_other(synth, unexpected)
    seed = arg.whole(seed, "seed", least=0)
    force_noise, pressure_noise = arg.si(force_noise, "force", "force_noise"), arg.si(
        pressure_noise, "pressure", "pressure_noise")
    protocol = Protocol(cycles=arg.whole(cycles, "cycles", least=1),
                        points_per_leg=arg.whole(points_per_leg, "points_per_leg", least=1),
                        held_lengths=arg.whole(held_lengths, "held_lengths", least=0),
                        radial_points=arg.whole(radial_points, "radial_points", least=1),
                        force_noise=force_noise, pressure_noise=pressure_noise)
    rows = {"axial": (protocol.held_lengths or len(protocol.pressures)) * protocol.cycles * 2
            * protocol.points_per_leg,
            "radial": len(protocol.radial_pressures) * protocol.radial_points}
    for kind, count in rows.items():
        check_rows(count, where=f"synth: the {kind} test's",
                   advice="lower --cycles, --points-per-leg or --radial-points")
    if protocol.held_lengths > MOST_HELD_LENGTHS:
        raise InputError(f"held_lengths: {protocol.held_lengths} is not allowed; give 0 (the paper's "
                         f"length cycles) to {MOST_HELD_LENGTHS} (identify reads more lengths as a sweep).")
    if force_noise < 0 or pressure_noise < 0:
        raise InputError("--force-noise and --pressure-noise must not be negative.")
    if not isinstance(name, str) or not name or "/" in name or name.startswith("."):
        raise InputError(f"--name: {name!r} must be a plain file name.")
    pam_file = arg.path(pam, "pam") or bundled.default_pam()
    muscle = load_pam(pam_file)
    check_kind(muscle.geometry, extensile=False, where=f"--pam {pam_file}",
               role="a synthetic experiment (axial and radial tests of an anchoring muscle)")
    slip = _slip_protocol(slip_pipe, friction, load_coupling, slip_scatter,
                          arg.flag(stick_slip, "stick_slip"), slip_pressure, held_trial, pipe_material)
    slip_only = arg.flag(slip_only, "slip_only")
    if slip_only and slip is None:
        raise InputError("--slip-only writes slip tests only: give at least one --slip-pipe, e.g. '3 in'.")
    tests, notes = synthetic_tests(muscle, protocol, seed=seed, slip=slip, slip_only=slip_only,
                                   where=str(pam_file))
    target = write_experiment(arg.path(out_dir, "out_dir"), name, muscle, tests, comments=notes,
                              overwrite=arg.flag(force, "force"), inputs=[pam_file], with_moduli=slip_only)
    document = {"experiment": str(target), "seed": seed, "force_noise_N": force_noise,
                "pressure_noise_Pa": pressure_noise, "pam": muscle.name,
                "true_moduli_MPa": [v / 1e6 for v in muscle.moduli.as_vector()]}
    if slip is not None:
        document["slip"] = {"friction": slip.friction, "load_coupling": slip.load_coupling,
                            "scatter": slip.scatter, "stick_slip": slip.stick_slip,
                            "pipe_diameters_m": list(slip.pipes)}
    return CommandResult("synth", document, partial(synth_text, document))


def _slip_protocol(pipes, friction, load_coupling, scatter, stick_slip: bool, pressures, held, material):
    """The slip tests asked for (None without ``pipes``), their values checked."""
    from pampipe.slip.synthetic_trials import SlipProtocol

    bores = arg.si(pipes, "length", "slip_pipe")
    if bores in (None, []):
        return None
    friction = arg.si(friction, "dimensionless", "friction")
    load_coupling = arg.si(load_coupling, "dimensionless", "load_coupling")
    scatter = arg.si(scatter, "dimensionless", "slip_scatter")
    checks = (("--friction", friction, 0 < friction <= 5, "in (0, 5]"),
              ("--load-coupling", load_coupling, 0 <= load_coupling <= 3, "in [0, 3]"),
              ("--slip-scatter", scatter, 0 <= scatter <= 1, "in [0, 1] (0 to 100 %)"))
    for flag, value, ok, allowed in checks:
        if not ok:
            raise InputError(f"{flag}: {value:g} is outside the allowed range {allowed}.")
    given = arg.si(pressures, "pressure", "slip_pressure")
    pressures = SlipProtocol(()).pressures if given in (None, []) else tuple(arg.as_list(given))
    if any(p <= 0 for p in pressures):
        raise InputError("--slip-pressure: each trial pressure must be above 0 (the muscle must grip).")
    held = () if held is None else tuple(arg.whole(n, "held_trial", least=1) for n in arg.as_list(held))
    return SlipProtocol(tuple(arg.as_list(bores)), friction, load_coupling, scatter, stick_slip, pressures,
                        pipe_material=material, held=held)


def example(name: str | None = None, out_dir: str | os.PathLike | None = None, *,
            force: bool = False) -> CommandResult:
    """Copy a bundled problem (and the files it uses) into ``out_dir`` (`pampipe example`); without a
    name, ``to_dict()["examples"]`` lists them."""
    from pampipe.io import bundled
    from pampipe.views.example_text import copied_text, listing_text

    if name is None:
        listing = bundled.catalogue()
        return CommandResult("example", {"examples": listing}, partial(listing_text, listing))
    if out_dir is None:
        raise InputError(f"example {name}: give the folder to copy into, e.g. "
                         f"`pampipe example {name} my-{name}`.")
    name = str(name)
    kind, files, unchanged = bundled.copy_example(name, arg.path(out_dir, "out_dir"),
                                                  overwrite=arg.flag(force, "force"))
    return CommandResult("example", {"example": name, "kind": kind, "files": [str(p) for p in files],
                                     "unchanged": [str(p) for p in unchanged]},
                         partial(copied_text, kind, files, unchanged))
