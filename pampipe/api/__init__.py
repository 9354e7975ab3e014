"""The Python API (docs/commands.md §11.1): every command as a function, for scripts and notebooks.

Each function takes a file path or a dict (the file's content; relative paths in it resolve
beside ``base``, the current folder by default), the same options as the command line — physical
values as numbers in SI or as unit strings (``payload="3 kg"``, ``pipe_diameter="3 in"``) — and
returns a result whose ``.to_dict()`` is the command's ``--json`` document::

    import pampipe
    plan = pampipe.plan("problems/missions/vertical-climb-3in.yaml", payload="3 kg")
    print(plan.sections[0].segments[0].pressure)          # Pa
    plan.to_dict()["feasible"]

The command-line interface is a thin layer over these functions. :mod:`pampipe.api.arguments` checks and
converts the arguments; :mod:`pampipe.api.files` holds the commands that write files (route, synth, example).
"""

from __future__ import annotations

import copy
import hashlib
import os
import pickle
import time
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from pampipe.api import arguments as arg
from pampipe.api.arguments import Source
from pampipe.api.files import CommandResult, example, route, synth
from pampipe.api.gait_report import GaitReport
from pampipe.units.quantities import show

if TYPE_CHECKING:  # the return types, for annotations only: importing them here would slow every command
    from pampipe.design.result import DesignResult
    from pampipe.diagnosis.result import DiagnoseResult
    from pampipe.export import Export
    from pampipe.identification.grip import GripResult
    from pampipe.identification.result import IdentifyResult
    from pampipe.model.pam import Pam
    from pampipe.nexttest.result import NextTest
    from pampipe.planning.result import MissionPlan
    from pampipe.rehearsal.result import Rehearsal
    from pampipe.simulation.anchored import ExtensionResult, SimulateResult
    from pampipe.specs.experiment import Experiment, ExperimentData
    from pampipe.specs.inventory import Inventory
    from pampipe.specs.mission import Mission

__all__ = ["CommandResult", "GaitReport", "Source", "design_inventory", "diagnose", "example",
           "export_mission", "extension", "gait", "identify", "load_experiment", "load_inventory",
           "load_mission", "load_pam", "next_test", "plan", "rehearse", "route", "save_pam", "set_units",
           "simulate", "synth"]

Progress = Callable[[str], None]


def load_pam(pam: Source, *, base=None, name: str = "pam") -> Pam:
    """A :class:`~pampipe.model.pam.Pam` from a PAM file or dict (docs/formats.md §2); a Pam passes
    (``name``: the option that gave it, for messages)."""
    from pampipe.io.pam_schema import load_pam as load
    from pampipe.model.pam import Pam

    if isinstance(pam, Pam):
        return pam
    path, raw = arg.source_file(pam, "PAM", base, name=name)
    return load(path, raw=raw)


def load_mission(mission: Source, *, base=None) -> Mission:
    """A :class:`~pampipe.specs.mission.Mission` from a mission file or dict (docs/formats.md §4) or itself.

    A file that loaded before and is unchanged, with every file it names, comes from the cache
    (:mod:`pampipe.io.validated`) without being parsed again."""
    from pampipe.io.validated import cached, keep
    from pampipe.specs.mission import Mission

    if isinstance(mission, Mission):
        return mission
    path, raw = arg.source_file(mission, "mission", base)
    if raw is None and (kept := cached("mission", path)) is not None:
        return kept  # read before, unchanged: no YAML parse, no schema library
    from pampipe.io.mission_schema import load_mission as load

    loaded = load(path, raw=raw)
    if raw is None:
        keep("mission", path, loaded, loaded.input_files)
    return loaded


def load_experiment(experiment: Source, *, base=None,
                    progress: Progress | None = None) -> tuple[Experiment, ExperimentData]:
    """(Experiment, ExperimentData): the experiment and its CSV data (docs/formats.md §3)."""
    from pampipe.io.csvfile import load_experiment_data
    from pampipe.io.experiment_schema import load_experiment as load

    path, raw = arg.source_file(experiment, "experiment", base)
    spec = load(path, raw=raw)
    return spec, load_experiment_data(spec, progress=progress)


def simulate(pam: Source, *, pipe_diameter, axial_load=0.0, pressure=None, paper_literal: bool = False,
             base=None) -> SimulateResult:
    """One muscle in one or more pipes under one or more axial loads (`pampipe simulate`).

    ``pipe_diameter`` and ``axial_load``: a value or a list; ``pressure``: a list (default: the
    paper's 69…689 kPa). Returns a :class:`pampipe.simulation.anchored.SimulateResult`.
    """
    from pampipe.errors import InputError
    from pampipe.simulation.anchored import PAPER_PRESSURES
    from pampipe.simulation.anchored import simulate as run

    paper_literal = arg.flag(paper_literal, "paper_literal")
    model = load_pam(pam, base=base)
    diameters = arg.as_list(arg.si(pipe_diameter, "length", "pipe_diameter"))
    loads = arg.as_list(arg.si(axial_load, "force", "axial_load"))
    pressures = arg.si(pressure, "pressure", "pressure") or list(PAPER_PRESSURES)
    try:
        return run(model, pipe_diameters=diameters, axial_loads=loads, pressures=arg.as_list(pressures),
                   paper_literal=paper_literal)
    except InputError as exc:
        source = pam if not isinstance(pam, Mapping) else "PAM"
        raise InputError(f"{source}: {exc}") from None


def extension(pam: Source, *, pressure=None, base=None) -> ExtensionResult:
    """An extensile PAM's free length against pressure (`pampipe simulate` without a pipe).

    Returns a :class:`pampipe.simulation.anchored.ExtensionResult`."""
    from pampipe.errors import InputError
    from pampipe.simulation.anchored import PAPER_PRESSURES
    from pampipe.simulation.anchored import extension as run

    model = load_pam(pam, base=base)
    source = pam if not isinstance(pam, Mapping) else "PAM"
    if not model.geometry.extensile:
        raise InputError(f"{source}: a contractile muscle is simulated in a pipe: give --pipe-diameter "
                         "(e.g. -d '3 in'); only an extensile muscle is simulated free, without a pipe.")
    pressures = arg.si(pressure, "pressure", "pressure") or list(PAPER_PRESSURES)
    try:
        return run(model, pressures=arg.as_list(pressures))
    except InputError as exc:
        raise InputError(f"{source}: {exc}") from None


def plan(mission: Source, *, payload=None, confidence: float | None = None, solver: str = "kkt",
         max_payload: bool = False, base=None, samples: int | None = None, seed: int | None = None,
         prior=None, workers: int | None = None, scheduler: str | None = None) -> MissionPlan:
    """The least anchoring pressure of every segment in every section (`pampipe plan`).

    With ``confidence`` C: ``samples`` draws seeded by ``seed`` (defaults of
    :mod:`pampipe.planning.confidence`), ``prior`` a PAM file (or :class:`~pampipe.model.pam.Pam`) whose
    uncertainty serves as prior along undetermined directions; the sampling runs on ``workers`` local
    processes or the Dask ``scheduler`` address, with the same result.
    Returns a :class:`pampipe.planning.MissionPlan` (``to_dict()``: the JSON document).
    """
    from pampipe.errors import InputError
    from pampipe.planning import plan_mission

    confidence = arg.probability(confidence)
    solver = arg.choice(solver, "solver", ("kkt", "ipopt"), optional=False)
    max_payload = arg.flag(max_payload, "max_payload")
    payload = arg.si(payload, "mass", "payload")
    if isinstance(payload, list):
        raise InputError("payload: give one mass, e.g. '3 kg', not a list.")
    workers, scheduler = arg.where(workers, scheduler)
    started = time.perf_counter()
    prior = None if prior is None else load_pam(prior, name="prior")
    result = plan_mission(load_mission(mission, base=base), payload=payload,
                          confidence=confidence, method=solver, with_max_payload=max_payload,
                          samples=samples, seed=seed, prior=prior, workers=workers, scheduler=scheduler)
    return result.timed(time.perf_counter() - started)


def gait(mission: Source, *, section: str | None = None, optimal: bool = False, base=None,
         progress: Progress | None = None) -> GaitReport:
    """The peristaltic schedule in one section; with ``optimal`` also the time-optimal gait (`gait`).

    The optimal gait is solved warm, from the last solution of the same structure (muscles' model
    structures, grid, valve) found by this process (:data:`_GAIT_WARM_STARTS`): the built OCP is reused
    and IPOPT starts at that optimum with its multipliers; another structure starts cold from the
    sequential schedule. ``result.optimal.solver["warm_start"]`` says which. The sequential
    schedule (the plan's thresholds and its simulation) is reused when the same mission, section and
    options come again, keyed by their whole content (:func:`_content_key`), never by identity.
    """
    from pampipe.errors import InputError
    from pampipe.locomotion import gait_options, optimal_gait, sequential_gait
    from pampipe.locomotion.optimal import problem_key

    optimal = arg.flag(optimal, "optimal")
    if section is not None and not isinstance(section, str):
        raise InputError(f"section: {show(section)} is not allowed; give a section's name.")
    model = load_mission(mission, base=base)
    options = gait_options(model.gait, source=model.source)
    content = _content_key(model, section, options)
    sequential = None if content is None else _GAIT_SEQUENTIAL.get(content)
    if sequential is None:
        sequential = sequential_gait(model, section, options=options)
    if content is not None:
        _keep(_GAIT_SEQUENTIAL, content, sequential)
    best = None
    if optimal:
        if progress is not None:
            progress("solving the time-optimal gait (CasADi/IPOPT) ...")
        key = problem_key(sequential.needs, options)
        best = optimal_gait(model, section, options=options, baseline=sequential,
                            warm_start=_GAIT_WARM_STARTS.get(key))
        _keep(_GAIT_WARM_STARTS, key, best.warm_start)
    sequential = copy.deepcopy(sequential, {id(sequential.needs): sequential.needs})  # the kept one stays
    bends = None
    if model.route.bend_angle is not None:
        from pampipe.bends.gait import route_time
        from pampipe.bends.plan import plan_bends

        bends = route_time(plan_bends(model)[0], float(model.route.length.sum()),
                           (best or sequential).speed)
    return GaitReport(sequential, best, bends)


def rehearse(mission: Source, *, optimal: bool = False, confidence: float | None = None,
             samples: int | None = None, seed: int | None = None, base=None,
             progress: Progress | None = None) -> Rehearsal:
    """The whole route in time (`pampipe rehearse`): per section the gait's cycles, time and free air, the
    tether, the supply hose and the compressor, the reach; with ``confidence`` C (``samples`` draws seeded by
    ``seed``) the chance of completing the route. Returns a :class:`pampipe.rehearsal.Rehearsal`
    (``to_dict()``: the JSON document)."""
    from pampipe.planning.confidence import DEFAULT_SAMPLES, DEFAULT_SEED
    from pampipe.rehearsal import rehearse_mission

    optimal = arg.flag(optimal, "optimal")
    confidence = arg.probability(confidence)
    samples = DEFAULT_SAMPLES if samples is None else arg.whole(samples, "samples", least=100)
    seed = DEFAULT_SEED if seed is None else arg.whole(seed, "seed", least=0)
    started = time.perf_counter()
    result = rehearse_mission(load_mission(mission, base=base), optimal=optimal, confidence=confidence,
                              samples=samples, seed=seed, progress=progress)
    return result.timed(time.perf_counter() - started)


def next_test(pam: Source, mission: Source, *, menu: Source, confidence: float = 0.95,
              objective: str = "pressure", pairs: bool = False, samples: int | None = None,
              seed: int | None = None, check: int = 0, truths: int | None = None,
              workers: int | None = None, scheduler: str | None = None, base=None) -> NextTest:
    """The test of ``menu`` (a MENU file or dict) that lowers ``mission``'s planned pressure at
    ``confidence`` most per unit cost, for the muscle of the PAM file ``pam`` (`pampipe next-test`): every
    test ranked by the linearised criterion (and, with ``pairs``, every pair), the D-optimal pick beside it,
    and the preposterior check of the top ``check`` over ``truths`` truths drawn from the fit (default 8) on
    ``workers`` processes or the Dask ``scheduler`` (the same numbers on each). Returns a
    :class:`pampipe.nexttest.result.NextTest` (``to_dict()``: the JSON document)."""
    from pampipe.io.menu_file import load_menu
    from pampipe.nexttest.preposterior import DEFAULT_TRUTHS
    from pampipe.nexttest.ranking import DEFAULT_DRAWS
    from pampipe.nexttest.workflow import next_test as rank
    from pampipe.planning.confidence import DEFAULT_SEED

    confidence = arg.number(confidence, "confidence", "give a probability in [0.5, 1), e.g. 0.95")
    objective = arg.choice(objective, "objective", ("pressure", "air"))
    pairs = arg.flag(pairs, "pairs")
    samples = DEFAULT_DRAWS if samples is None else arg.whole(samples, "samples", least=100)
    seed = DEFAULT_SEED if seed is None else arg.whole(seed, "seed", least=0)
    check = arg.whole(check, "check", least=0)
    truths = DEFAULT_TRUTHS if truths is None else arg.whole(truths, "truths", least=2)
    workers, scheduler = arg.where(workers, scheduler)
    started = time.perf_counter()
    path, raw = arg.source_file(pam, "PAM", base)
    model = load_pam(pam, base=base)
    planned = load_mission(mission, base=base)
    menu_path, menu_raw = arg.source_file(menu, "menu", base)
    chosen = load_menu(menu_path, model, pam_where=str(path), raw=menu_raw)
    result = rank(planned, model, None if raw is not None else path, chosen, confidence=confidence,
                  objective=objective, pairs=pairs, samples=samples, seed=seed, checks=check, truths=truths,
                  workers=workers, scheduler=scheduler)
    return result.timed(time.perf_counter() - started)


#: Structures whose last optimal-gait solution :func:`gait` keeps to start the next solve from (and
#: inputs whose sequential schedule it keeps).
WARM_STARTS_KEPT = 8
#: problem key (:func:`pampipe.locomotion.optimal.problem_key`) → its last WarmStart, oldest first.
_GAIT_WARM_STARTS: dict = {}
#: :func:`_content_key` of (mission, section, options) → its sequential GaitResult, oldest first.
_GAIT_SEQUENTIAL: dict = {}


def _content_key(*values) -> bytes | None:
    """A digest of the pickled ``values``: equal bytes rebuild equal objects, so a hit is never stale
    (equal content pickled differently is only a miss). None where they do not pickle (a mission built in
    Python around an object pickle refuses): nothing is then reused."""
    try:
        return hashlib.blake2b(pickle.dumps(values, protocol=pickle.HIGHEST_PROTOCOL)).digest()
    except (pickle.PicklingError, TypeError, AttributeError):
        return None


def _keep(store: dict, key, value) -> None:
    """Store ``value`` as the most recent entry; the least recent beyond :data:`WARM_STARTS_KEPT` goes."""
    store.pop(key, None)
    store[key] = value
    while len(store) > WARM_STARTS_KEPT:
        store.pop(next(iter(store)))


def identify(experiment: Source, *, mode: str | None = None, objective: str | None = None,
             degree: int | None = None, average_legs: bool | None = None, drucker: str | None = None,
             max_iterations: int | None = None, calibrate: Sequence[str] | None = None,
             slack: str | None = None, pipe_diameter=None, base=None,
             progress: Progress | None = None) -> IdentifyResult | GripResult:
    """Fit the bladder moduli (and the ``calibrate``d geometry) to an experiment (`pampipe identify`).

    Options override the experiment's ``fit:`` block; ``calibrate`` and ``pipe_diameter`` (a value or
    a list, unit strings accepted) add to it. Returns an :class:`pampipe.identification.IdentifyResult`; its
    ``fitted_pam(pam)`` is the muscle to write. With slip tests, ``result.slip`` is the
    :class:`pampipe.slip.SlipResult` (friction, load coupling, trials; ``to_dict()["slip"]``); an experiment
    of slip tests only returns a :class:`pampipe.identification.grip.GripResult` with the same ``slip``.
    """
    from pampipe.identification import identify as run
    from pampipe.identification.options import fit_options

    degree, max_iterations = arg.whole(degree, "degree"), arg.whole(max_iterations, "max_iterations")
    average_legs = None if average_legs is None else arg.flag(average_legs, "average_legs")
    calibrate = arg.names(calibrate, "calibrate")
    spec, data = load_experiment(experiment, base=base, progress=progress)
    diameters = arg.si(pipe_diameter, "length", "pipe_diameter")
    options = fit_options(spec.fit, {"mode": mode, "objective": objective, "degree": degree,
                                     "average_legs": average_legs, "drucker": drucker,
                                     "max_iterations": max_iterations, "slack": slack},
                          calibrate=tuple(calibrate or ()), source=spec.source,
                          pipe_diameters=[diameters] if isinstance(diameters, float) else diameters or ())
    result = run(data, options, progress=progress)  # the caller's callback hears every step of the fit
    object.__setattr__(result, "experiment_data", data)  # what result.plot() draws against
    object.__setattr__(result, "experiment_source", spec.source)  # what str(result) is headed by
    return result


def diagnose(experiment: Source, *, effect: Sequence[str] | None = None, folds: int | None = None,
             base=None, progress: Progress | None = None) -> DiagnoseResult:
    """Name the effect the model misses, refit with it, show the gap shrink (`pampipe diagnose`).

    Returns a :class:`pampipe.diagnosis.result.DiagnoseResult`; ``augmented_pam()`` is the muscle
    with its effects.
    """
    from pampipe.diagnosis.candidates import FOLDS
    from pampipe.diagnosis.workflow import diagnose as run

    folds = FOLDS if folds is None else arg.whole(folds, "folds", least=2)
    effect = arg.names(effect, "effect")
    _, data = load_experiment(experiment, base=base, progress=progress)
    return run(data, effects=list(effect) if effect else None, folds=folds, progress=progress)


def _relative(path: Path, folder: Path) -> str:
    """``path`` relative to ``folder`` with '/' separators (``../pams/x.yaml``), so that an export
    names its inputs the same on every machine; absolute only where no relative path exists
    (another drive)."""
    import os

    try:
        return Path(os.path.relpath(path.absolute(), folder.absolute())).as_posix()
    except ValueError:
        return path.absolute().as_posix()


def export_mission(mission: Source, *, sketch_name: str = "pampipe_example", base=None,
                   progress: Progress | None = None, confidence: float | None = None,
                   samples: int | None = None, seed: int | None = None) -> Export:
    """The mission's anchoring law and gait table as C texts (`pampipe export`; not ``pampipe.export``,
    the package that generates them). Returns a :class:`pampipe.export.Export`: ``files`` maps file
    names to texts, ``law.evaluate(...)`` answers as the C function does, ``to_dict()`` is the JSON.
    The header records the SHA-256 of every input file (none for a dict), each named relative to the
    mission's folder (the mission by its file name), so an export does not depend on where it ran.
    With ``confidence`` C the law adds, per segment, the margin `plan --confidence C` needs over the
    mission's sections (``samples`` draws seeded by ``seed``), stated in the header.
    """
    import hashlib

    from pampipe.errors import InputError
    from pampipe.export import Provenance, generate

    model = load_mission(mission, base=base)
    folder = Path(model.source).parent
    inputs = []
    for path in dict.fromkeys(Path(p) for p in model.input_files):
        if path.is_file():
            try:
                inputs.append((_relative(path, folder), hashlib.sha256(path.read_bytes()).hexdigest()))
            except OSError as exc:
                raise InputError(f"{path}: cannot read it to record its hash ({exc.strerror}).") from None
    confidence = arg.probability(confidence)
    samples, seed = arg.whole(samples, "samples", least=100), arg.whole(seed, "seed", least=0)
    sampling = {k: v for k, v in (("samples", samples), ("seed", seed)) if v is not None}
    provenance = Provenance(Path(model.source).name, tuple(inputs))
    return generate(model, provenance=provenance, sketch_name=sketch_name,
                    progress=progress, confidence=confidence, **sampling)


def load_inventory(inventory: Source, *, base=None) -> Inventory:
    """A :class:`~pampipe.specs.inventory.Inventory` from an inventory file or dict (docs/commands.md §8)."""
    from pampipe.io.inventory_file import load_inventory as load
    from pampipe.specs.inventory import Inventory

    if isinstance(inventory, Inventory):
        return inventory
    path, raw = arg.source_file(inventory, "inventory", base)
    return load(path, raw=raw)


def design_inventory(inventory: Source, *, objective: str | None = None, sizes: int | None = None,
           starts: int | None = None, seed: int | None = None, workers: int | None = None,
           scheduler: str | None = None, base=None) -> DesignResult:
    """The muscle geometry (or K sizes) for a pipe inventory (`pampipe design`; not ``pampipe.design``,
    which is the package of the science); the options override
    the file's ``design:`` block. Returns a :class:`pampipe.design.DesignResult` (``to_dict()``: the
    JSON document; ``feasible`` False names the binding constraint instead of raising)."""
    import dataclasses

    from pampipe.design import solve_inventory
    from pampipe.runtime.executors import executor
    from pampipe.specs.inventory import Objective

    starts, seed, sizes = arg.whole(starts, "starts", least=1), arg.whole(seed, "seed", least=0), arg.whole(
        sizes, "sizes", least=1)
    workers, scheduler = arg.where(workers, scheduler)
    model = load_inventory(inventory, base=base)
    overrides = {"starts": starts, "seed": seed, "sizes": sizes,
                 "objective": None if objective is None else arg.objective(objective, Objective)}
    space = dataclasses.replace(model.space, **{k: v for k, v in overrides.items() if v is not None})
    model = dataclasses.replace(model, space=space)
    with executor(workers=workers, scheduler=scheduler) as pool:
        return solve_inventory(model, pool=pool)


def save_pam(pam, path, *, force: bool = False, comments: Sequence[str] = ()) -> Path:
    """Write a PAM (a :class:`~pampipe.model.pam.Pam`, a PAM file or dict) as a PAM file at ``path``, as
    ``identify -o`` does: atomically (the old file or the new one, never half of one), never over an
    input of the PAM; an existing file is replaced only with ``force``. Returns the path.

    A fitted muscle is ``result.fitted_pam(pampipe.load_pam(...))`` of :func:`identify`, or
    ``result.augmented_pam()`` of :func:`diagnose`.
    """
    from pampipe.errors import InputError
    from pampipe.io.files import check_not_input
    from pampipe.io.pamfile import write_pam

    model = load_pam(pam)
    target = Path(path)
    if target.exists() and not force:
        raise InputError(f"save_pam: {target} exists; pass force=True to replace it.")
    check_not_input(target, [Path(pam)] if isinstance(pam, str | os.PathLike) else [], option="save_pam")
    write_pam(target, model, comments=[f"Written by pampipe.save_pam ({model.name})."])
    return target


def set_units(name: str) -> None:
    """Show results in ``name`` from now on, in this process: ``str(result)``, ``result.to_text()`` and
    ``result.plot()``; a preset (``"si"``, ``"metric"``, ``"us"``) or a pressure unit (``"psi"``). A
    command line run keeps its own --units; ``to_dict()`` and ``to_frame()`` stay SI."""
    from pampipe.units import display

    display.set_units(name)
