"""The executor helper (pampipe.runtime.executors) and issue 16's reproducibility: serial, 2 local workers
and a
Dask LocalCluster give byte-identical `design --reproducible` JSON."""

from __future__ import annotations

import dataclasses
import os
import subprocess
import sys
from concurrent.futures import Executor, Future

import pytest

from pampipe.design import solve_inventory
from pampipe.errors import InputError
from pampipe.io.inventory_file import load_inventory
from pampipe.runtime.executors import SerialExecutor, executor, run_all
from tests.support.problems import PROBLEMS, ROOT

RISER = PROBLEMS / "inventories" / "riser.yaml"
PLANT = PROBLEMS / "inventories" / "plant.yaml"


def _square(x):
    return x * x


def _fail(x):
    raise ValueError(f"task {x} failed")


def test_run_all_keeps_task_order_on_every_local_executor():
    for workers in (None, 1, 2):
        with executor(workers=workers) as pool:
            assert run_all(_square, range(7), pool) == [0, 1, 4, 9, 16, 25, 36]


def _processes_marked(mark: str) -> list[str]:
    """Command lines of the processes whose environment holds R39_MARK=``mark`` (Linux /proc)."""
    found = []
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            with open(f"/proc/{pid}/environ", "rb") as environ, open(f"/proc/{pid}/cmdline", "rb") as cmd:
                if f"R39_MARK={mark}".encode() in environ.read().split(b"\0"):
                    found.append(cmd.read().replace(b"\0", b" ").decode(errors="replace"))
        except OSError:  # ended meanwhile, or not ours to read
            continue
    return found


def test_a_pool_leaves_no_process_behind():
    """After the pool's block: no worker and no resource tracker is left (after an error: no worker)."""
    from multiprocessing import active_children, resource_tracker

    with executor(workers=2) as pool:
        assert run_all(_square, range(3), pool) == [0, 1, 4]
    assert active_children() == []
    assert resource_tracker._resource_tracker._pid is None  # ended and waited for
    with pytest.raises(ValueError, match="failed"), executor(workers=2) as pool:
        run_all(_fail, range(3), pool)
    assert active_children() == []


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="lists processes through /proc")
def test_plan_with_two_workers_leaves_no_process_behind_at_exit():
    mark = f"{os.getpid()}-workers"
    mission = PROBLEMS / "missions" / "riser-uncertain-friction.yaml"
    out = subprocess.run([sys.executable, "-m", "pampipe", "plan", str(mission), "--confidence", "0.95",
                          "--samples", "400", "--workers", "2"], capture_output=True, text=True, cwd=ROOT,
                         env={**os.environ, "R39_MARK": mark}, timeout=300)
    assert out.returncode == 0, out.stderr
    assert _processes_marked(mark) == []


def test_the_process_check_can_fail():
    mark = f"{os.getpid()}-sleeper"
    sleeper = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"],
                               env={**os.environ, "R39_MARK": mark})
    try:
        assert len(_processes_marked(mark)) == 1
    finally:
        sleeper.kill()
        sleeper.wait()


def test_errors_reach_the_caller():
    with pytest.raises(ValueError, match="task 3 failed"):
        run_all(_fail, [3], SerialExecutor())


@pytest.mark.parametrize(("options", "words"), [({"workers": 0}, "at least 1"),
                                                ({"workers": 2, "scheduler": "tcp://x:1"}, "not both")])
def test_bad_executor_options_are_input_errors(options, words):
    with pytest.raises(InputError, match=words), executor(**options):
        pass


class _LateFuture(Future):
    """A future whose done-callbacks wait for its executor's shutdown, as a process pool or Dask may run them
    (in the executor's own thread) after the caller's ``result()`` has returned."""

    def __init__(self, late: list):
        super().__init__()
        self._late = late

    def add_done_callback(self, fn):
        self._late.append(lambda: fn(self))


class _LateCallbacks(Executor):
    """Runs each task at submission; its future's done-callbacks only at shutdown."""

    def __init__(self):
        self.late: list = []

    def submit(self, fn, /, *args, **kwargs) -> Future:
        future = _LateFuture(self.late)
        future.set_result(fn(*args, **kwargs))
        return future

    def shutdown(self, wait=True, *, cancel_futures=False):
        for call in self.late:
            call()


def test_the_solver_tally_counts_finished_tasks_not_callbacks():
    """`nlp_solves` and `iterations` cannot depend on when an executor runs its done-callbacks (issue 16):
    with every callback held back until after the design, the tally still counts each start once, and
    the iterations are the sum over the starts' own records."""
    inventory = load_inventory(RISER)
    inventory = dataclasses.replace(inventory, space=dataclasses.replace(inventory.space, starts=6))
    assert inventory.space.objective.value == "max_pressure"  # one multi-start, no second run
    pool = _LateCallbacks()
    result = solve_inventory(inventory, pool=pool)
    pool.shutdown()
    runs = result.as_document()["starts"]["runs"]
    assert result.solves == len(runs) == 6
    assert result.iterations == sum(r["iterations"] for r in runs) > 0


def _design(inventory, starts: int, *extra: str) -> bytes:
    env = dict(os.environ, OMP_NUM_THREADS="1")
    out = subprocess.run([sys.executable, "-m", "pampipe", "design", str(inventory), "--json",
                          "--reproducible", "--starts", str(starts), *extra], capture_output=True, cwd=ROOT,
                         env=env, timeout=600)
    assert out.returncode == 0, out.stderr.decode()
    return out.stdout


def _identical(inventory, starts: int = 6):
    distributed = pytest.importorskip("distributed")
    serial = _design(inventory, starts)
    assert b'"wall_time_s": 0.0' in serial  # --reproducible zeroes the timings, nothing else differs
    assert serial == _design(inventory, starts, "--workers", "2")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                  host="127.0.0.1") as cluster:
        assert serial == _design(inventory, starts, "--scheduler", cluster.scheduler_address)


def test_serial_two_workers_and_dask_give_byte_identical_json():
    """Each start is a deterministic task (its own Latin-hypercube point, plain data in and out), and the
    best is chosen by (objective, start index): the executor cannot change the document. Four starts:
    two per worker, so the order they finish in can differ from the order of the starts (the slow test
    below has six, on two sizes)."""
    _identical(RISER, starts=4)


@pytest.mark.slow
def test_byte_identical_json_with_sizes():
    """The same with two sizes: interval checks, enumeration and refits all run on the executor."""
    _identical(PLANT)


@pytest.mark.slow
def test_an_unreachable_scheduler_is_an_input_error():
    """distributed retries until its 10 s connection timeout, hence slow."""
    pytest.importorskip("distributed")
    out = subprocess.run([sys.executable, "-m", "pampipe", "design", str(PLANT), "--scheduler",
                          "tcp://127.0.0.1:9"], capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert out.returncode == 2, out.stderr
    assert "cannot reach a Dask scheduler" in out.stderr and "Traceback" not in out.stderr


@pytest.mark.parametrize("address", ["", "bogus", "tcp://", "tcp://127.0.0.1:1"])
def test_a_bad_scheduler_address_makes_no_client(address, monkeypatch):
    """Issue 38: `--scheduler ''` printed a distributed `Client.__del__` traceback 20 s after the message (the
    half-made Client closed by the garbage collector): the address is checked before any Client is made."""
    distributed = pytest.importorskip("distributed")
    monkeypatch.setattr(distributed, "Client", lambda *a, **k: pytest.fail("a Client was made"))
    with pytest.raises(InputError, match="--scheduler"), executor(scheduler=address):
        pass
