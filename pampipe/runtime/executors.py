"""One way to run independent tasks: a ``concurrent.futures`` executor, serial, local processes or Dask.

:func:`executor` opens the executor a command asked for, :func:`run_all` maps a function over
tasks and returns the results in task order, so a sweep gives the same answer on any executor
when each task is deterministic (its own seed, plain data in and out). Used by ``design``'s
multi-start; any other sweep (e.g. a Monte Carlo check) can use it the same way.

* serial (the default): tasks run one after the other in this process;
* ``workers=N``: N local processes (``spawn``, so no CasADi state is inherited through fork);
* ``scheduler=ADDRESS``: a Dask cluster, ``distributed.Client(ADDRESS).get_executor()``; Dask is an
  optional extra, ``pip install pampipe[dask]``.

Tasks and results must pickle: CasADi SX does not, so a worker receives numbers and builds its own
CasADi functions (cached per process).
"""

from __future__ import annotations

import multiprocessing
import signal
import socket
from collections.abc import Callable, Iterable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, BrokenExecutor, Executor, Future, ProcessPoolExecutor, wait
from contextlib import contextmanager

from pampipe.errors import InputError, SolverError
from pampipe.runtime import progress


class SerialExecutor(Executor):
    """An executor that runs each task at submission, in the calling process."""

    def submit(self, fn, /, *args, **kwargs) -> Future:
        future: Future = Future()
        try:
            future.set_result(fn(*args, **kwargs))
        except BaseException as exc:  # handed to the caller through the future, as any executor does
            future.set_exception(exc)
        return future


@contextmanager
def executor(*, workers: int | None = None, scheduler: str | None = None) -> Iterator[Executor]:
    """The executor for ``workers`` local processes or the Dask ``scheduler`` address (serial if neither)."""
    if workers is not None and scheduler is not None:
        raise InputError("--workers and --scheduler: give one of them, not both (--workers N runs on N "
                         "local processes, --scheduler ADDRESS on a Dask cluster).")
    if scheduler is not None:
        with _dask(scheduler) as pool:
            yield pool
    elif workers is not None and workers > 1:
        _quiet_resource_tracker()
        pool = ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("spawn"),
                                   initializer=_worker_ignores_signals)
        try:
            yield pool
        except BaseException:  # an error or Ctrl-C: stop the workers now, wait for nothing queued
            _stop(pool)
            raise
        pool.shutdown()  # the workers joined
        _stop_resource_tracker()
    else:
        if workers is not None and workers < 1:
            raise InputError(f"--workers: {workers} must be at least 1.")
        yield SerialExecutor()


def _worker_ignores_signals() -> None:
    """A worker leaves Ctrl-C and SIGTERM to the command (which stops the workers): a terminal's Ctrl-C
    reaches the whole process group, and a worker interrupted on its own prints its traceback."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_IGN)


def _quiet_resource_tracker() -> None:
    """Start multiprocessing's resource tracker with its stderr on /dev/null. An interrupt can land
    between a semaphore's unlink and its unregistering; the tracker then warns of a "leaked semaphore"
    that no longer exists, in lines after the command's one-line message."""
    import os
    from multiprocessing import resource_tracker

    null, saved = os.open(os.devnull, os.O_WRONLY), os.dup(2)
    os.dup2(null, 2)
    try:
        resource_tracker.ensure_running()
    finally:
        os.dup2(saved, 2)
        os.close(saved)
        os.close(null)


def _stop_resource_tracker() -> None:
    """End multiprocessing's resource tracker (started for the pool's semaphores) and wait for it: left
    running, it outlives the command for a moment, a process of pampipe's after pampipe exited. The
    next pool starts another. Not after an interrupt: the killed workers' semaphores are still to be
    finalized at exit, and a tracker ended before them would have unlinked them first (tracebacks)."""
    from multiprocessing import resource_tracker

    stop = getattr(resource_tracker._resource_tracker, "_stop", None)  # CPython ≥ 3.8; private
    if stop is not None:
        stop()


def _stop(pool: ProcessPoolExecutor) -> None:
    """Cancel the queued tasks and kill the workers, then let the pool's threads end (no orphan, no hang).

    ``shutdown(wait=False)`` forgets the pool's manager thread, which goes on to reap the killed workers
    itself; it is joined here, or a worker it reaped is still listed as a live child when the block ends
    (seen in CI: the two threads' waitpid race, and the loser's join returns without marking it ended)."""
    processes = list((getattr(pool, "_processes", None) or {}).values())
    manager = getattr(pool, "_executor_manager_thread", None)  # private, CPython >= 3.9
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        if process.is_alive():
            process.kill()
    if manager is not None:
        manager.join(timeout=60.0)
    for process in processes:  # SIGKILL ends it; the join reaps it (1 s was too short on a busy machine)
        process.join(timeout=60.0)
    pool.shutdown(wait=True)


def run_all(fn: Callable, tasks: Iterable, pool: Executor, *, what: str | None = "tasks") -> list:
    """[fn(task) for task in tasks] computed on ``pool``, in task order (the first error is raised);
    each finished task is counted in :mod:`pampipe.runtime.progress` as one of ``what`` (None: not counted).

    A worker process that dies (killed, out of memory) is a :class:`SolverError` (exit 3).
    """
    if isinstance(pool, SerialExecutor):
        tasks = list(tasks)
        results = []
        for task in tasks:
            results.append(fn(task))
            if what:
                progress.count(what, len(results), len(tasks))
        return results
    try:
        futures: Sequence[Future] = [pool.submit(fn, task) for task in tasks]
        waiting, done = set(futures), 0
        while waiting:
            finished, waiting = wait(waiting, return_when=FIRST_COMPLETED)
            for future in finished:
                future.result()  # the first error, at once
            done += len(finished)
            if what:
                progress.count(what, done, len(futures))
        return [f.result() for f in futures]
    except BrokenExecutor as exc:
        raise SolverError(f"a worker process stopped before finishing its task ({exc}); run again, or "
                          "without --workers.", status="worker_died") from None


def _check_reachable(address: str) -> None:
    """InputError unless ``address`` names a host and port (``tcp://host:port``, ``host:port``) that
    accepts a connection, checked before a Dask ``Client`` is made: a Client that fails to connect is
    closed by the garbage collector, which prints a traceback 20 s after the message."""
    from distributed.comm.addressing import parse_address, parse_host_port

    scheme, location = parse_address(address)
    try:
        host, port = parse_host_port(location)
    except ValueError:
        host = port = None
    if not host or not port:
        raise InputError(f"--scheduler {address!r}: not an address of a Dask scheduler; give its host and "
                         "port, e.g. tcp://127.0.0.1:8786.")
    if scheme in ("tcp", "tls"):
        try:
            socket.create_connection((host, port), timeout=10).close()
        except OSError as exc:
            why = exc.strerror or exc
            raise InputError(f"--scheduler {address}: cannot reach a Dask scheduler there ({why}); give its "
                             "address, e.g. tcp://127.0.0.1:8786.") from None


@contextmanager
def _dask(address: str) -> Iterator[Executor]:
    try:
        from distributed import Client
    except ImportError:
        raise InputError(f"--scheduler {address}: Dask is not installed; install the optional extra with "
                         "`pip install pampipe[dask]`, or use --workers N for local processes.") from None
    _check_reachable(address)
    try:
        client = Client(address, timeout=10, set_as_default=False)
    except (OSError, TimeoutError, ValueError) as exc:
        raise InputError(f"--scheduler {address}: cannot reach a Dask scheduler there ({exc}); give its "
                         "address, e.g. tcp://127.0.0.1:8786.") from None
    try:
        with client.get_executor(pure=False) as pool:
            yield pool
    finally:
        client.close()
