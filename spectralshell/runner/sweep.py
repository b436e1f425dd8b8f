"""The sweep runner: plan the chunks, skip the finished ones, dispatch the rest, store results."""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures.process import BrokenProcessPool
from contextlib import nullcontext
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import xarray as xr

from ..errors import SweepInterrupted, UncertifiedWarning
from ..params.sweep_grid import SweepSpec, sweep_spec
from ..results.maps import uncertified, uncertified_note
from .engine import run_tasks
from .executors import check_executor, open_pool
from .integrity import read_records
from .layout import Chunk, block_shape, chunk_key, chunks, region
from .lock import writer_lock
from .progress import progress_bar
from .solve import ChunkResult, SweepError, solve_chunks, solve_points
from .store import (StoredSweep, ZarrStore, check_out, empty_arrays, load_existing, to_dataset,
                    write_netcdf)

IN_FLIGHT_PER_SLOT = 2  # tasks submitted per executor slot: keeps every worker busy
#: Compute seconds aimed at per task once chunk costs are measured: a Dask task costs ~10 ms of
#: dispatch (validation/bench_sweep.py), ~0.5 % of this; the progress bar still moves about
#: every TASK_SECONDS / slots.
TASK_SECONDS = 2.0


def _in_flight(pool) -> int:
    """Tasks kept submitted: one for the serial executor (it runs a task at submit), else two
    per slot, so that a worker never waits for the next task."""
    return 1 if pool.name == "serial" else IN_FLIGHT_PER_SLOT * pool.slots


def batches(todo: Sequence[Chunk], chunk_seconds: Callable[[], float | None],
            slots: int) -> Iterator[tuple[Chunk, ...]]:
    """The chunks to compute, in order, cut into consecutive runs, one run per task.

    A run is one chunk while ``chunk_seconds()`` (the mean compute time of the last finished
    chunks, read as each task is submitted) is None, then as many chunks as fill TASK_SECONDS,
    but never more than the remaining chunks / (IN_FLIGHT_PER_SLOT x ``slots``), so that the
    last tasks stay short and every slot keeps work to the end. Batching leaves the numbers unchanged (each
    chunk is solved on its own, :func:`~spectralshell.runner.solve.solve_chunks`) and the store
    layout too (it depends on the scene only); it cuts the per-task dispatch cost of cheap
    chunks (Mathieu points, ~0.5 ms each) on a Dask cluster.
    """
    start = 0
    while start < len(todo):
        cost = chunk_seconds()
        size = 1
        if cost:
            share = (len(todo) - start) // (IN_FLIGHT_PER_SLOT * slots)
            size = max(1, min(math.ceil(TASK_SECONDS / cost), share))
        yield tuple(todo[start:start + size])
        start += size


def dispatch(pool, spec: SweepSpec, todo: Sequence[Chunk],
             record: Callable[[Chunk, ChunkResult], None]) -> None:
    """Solve the chunks ``todo`` on an open pool, in :func:`batches`, and call
    ``record(chunk, result)`` in this process for each finished chunk (in completion order; the
    chunks a failing task finished before the error are recorded too, then the error is
    raised)."""
    recent: list[float] = []  # compute seconds of the last finished chunks

    def finished(task: tuple, results: list[ChunkResult]) -> None:
        for chunk, result in zip(task[1], results):
            recent.append(result.seconds)
            del recent[:-IN_FLIGHT_PER_SLOT * pool.slots]
            record(chunk, result)

    def chunk_seconds() -> float | None:
        return sum(recent) / len(recent) if recent else None

    run_tasks(pool.executor, solve_chunks,
              ((spec, batch) for batch in batches(todo, chunk_seconds, pool.slots)),
              in_flight=_in_flight(pool), on_result=finished)


@dataclass(frozen=True, kw_only=True, eq=False)
class SweepRun:
    """A finished sweep: its Dataset, and how many grid points there are, were computed now,
    and were skipped (already in the store); the store path and the wall time in seconds.

    damaged : points computed now because their chunk in the store was missing, unreadable or
        altered (counted in ``computed``).

    uncertified : points with no tau found whose emptiness the zero count could not prove
        (:func:`~spectralshell.results.maps.uncertified`; stored, never as "none").
    compute_seconds : summed in-worker compute time of the chunks computed now.
    continued, fallbacks : kind solves accepted from the neighbour's truncation / not.
    """

    dataset: xr.Dataset
    points: int
    computed: int
    skipped: int
    out: str | None
    seconds: float
    damaged: int = 0
    uncertified: int = 0
    compute_seconds: float = 0.0
    chunks: int = 0
    continued: int = 0
    fallbacks: int = 0
    executor: str = ""

    def summary(self) -> dict[str, Any]:
        """The JSON summary ``{"points", "computed", "skipped", "damaged", "uncertified", "out",
        "seconds"}``."""
        return {"points": self.points, "computed": self.computed, "skipped": self.skipped,
                "damaged": self.damaged, "uncertified": self.uncertified, "out": self.out,
                "seconds": round(self.seconds, 3)}

    def uncertified_note(self) -> str:
        """One line on the uncertified points and what to change ('' when there are none)."""
        if not self.uncertified:
            return ""
        return uncertified_note(self.uncertified, self.points,
                                float(self.dataset.attrs.get("tau_max", 0.5)))


def _spec(scene) -> SweepSpec:
    return scene if isinstance(scene, SweepSpec) else sweep_spec(scene)


def _crash() -> SweepError:
    return SweepError("a worker process died (killed, or out of memory): finished chunks are "
                      "kept in the store; rerun the same command to resume")


def _interrupted(spec: SweepSpec, path: Path | None,
                 stored: StoredSweep | None) -> SweepInterrupted:
    """What a Ctrl-C leaves: the points in the store (a Zarr store keeps every chunk with a
    completion record, a NetCDF file only what it held before this run)."""
    if path is None:
        kept = 0
    elif path.suffix == ".zarr":
        records = read_records(path)
        kept = sum(math.prod(block_shape(spec, c)) for c in chunks(spec)
                   if chunk_key(spec, c) in records)
    else:
        kept = 0 if stored is None else int(stored.arrays["computed"].sum())
    return SweepInterrupted(kept, spec.size, None if path is None else str(path))


def run_sweep(scene, *, executor: str = "processes", workers: int | None = None,
              scheduler: str | None = None, out: str | Path | None = None,
              progress: bool = False,
              on_chunk: Callable[[int, ChunkResult], None] | None = None) -> SweepRun:
    """Run a sweep scene (path, TOML string, dict or SweepSpec) and return a :class:`SweepRun`.

    Parameters
    ----------
    executor : 'serial', 'processes' (default) or 'dask'.
    workers : processes (default: every core) or LocalCluster workers.
    scheduler : with 'dask': 'local' (a LocalCluster, the default) or 'tcp://HOST:PORT'.
    out : '*.zarr' (written chunk by chunk; rerunning resumes, and recomputes chunks found
        missing, unreadable or altered) or '*.nc' (written at the end); None keeps the results
        in memory only. One process at a time writes an ``out``.
    progress : a progress bar (points/s, ETA) on stderr.
    on_chunk : test hook, called as ``on_chunk(n_finished, result)`` after each chunk is stored.

    Raises
    ------
    ParameterError : invalid scene, executor arguments or output; a store of another scene.
    StoreBusy : another process is writing ``out``.
    BackendUnavailable : executor 'dask' without the extra.
    ConvergenceError, SweepError : a point failed (named with its parameters) or a worker died;
        chunks finished before are kept in the store.
    SweepInterrupted : Ctrl-C (a KeyboardInterrupt); it counts the points kept in the store.
    """
    t0 = time.perf_counter()
    spec = _spec(scene)
    executor, workers, scheduler = check_executor(executor, workers, scheduler)
    path = check_out(out)
    with nullcontext() if path is None else writer_lock(path):
        return _run(spec, path, executor=executor, workers=workers, scheduler=scheduler,
                    progress=progress, on_chunk=on_chunk, t0=t0)


def _run(spec: SweepSpec, path: Path | None, *, executor: str, workers: int | None,
         scheduler: str | None, progress: bool,
         on_chunk: Callable[[int, ChunkResult], None] | None, t0: float) -> SweepRun:
    """:func:`run_sweep` once its arguments are checked and ``path`` is locked."""
    stored = load_existing(path, spec) if path is not None else None
    if stored is not None and path.suffix == ".zarr":
        ZarrStore(path, spec).repair(stored)
    arrays = empty_arrays(spec) if stored is None else stored.arrays
    plan = chunks(spec)
    todo = [c for c in plan if not arrays["computed"][region(spec, c)].all()]
    n_todo = sum(int(arrays["computed"][region(spec, c)].size) for c in todo)
    damaged = sum(int(arrays["computed"][region(spec, c)].size) for c in plan
                  if c.index in stored.damaged) if stored is not None else 0
    stats = {"chunks": 0, "seconds": 0.0, "continued": 0, "fallbacks": 0}
    used = "none (nothing to compute)"
    store = None
    if todo:
        bar = progress_bar(n_todo, "sweep", "pt", progress)

        def record(chunk: Chunk, result: ChunkResult) -> None:
            where = region(spec, chunk)
            for name, block in result.arrays.items():
                arrays[name][where] = block
            arrays["computed"][where] = True
            if store is not None:
                store.write(chunk, result.arrays)
            stats["chunks"] += 1
            stats["seconds"] += result.seconds
            stats["continued"] += result.continued
            stats["fallbacks"] += result.fallbacks
            bar.update(int(result.arrays["tau_min"].size))
            if on_chunk is not None:
                on_chunk(stats["chunks"], result)

        try:
            with open_pool(executor, workers=workers, scheduler=scheduler,
                           max_tasks=len(todo)) as pool:
                if path is not None and path.suffix == ".zarr":
                    store = ZarrStore(path, spec) if path.exists() else ZarrStore.create(path, spec)
                used = pool.description
                bar.set_description(f"sweep [{pool.name}]")
                dispatch(pool, spec, todo, record)
        except KeyboardInterrupt:
            raise _interrupted(spec, path, stored) from None
        except BrokenProcessPool:
            raise _crash() from None
        except Exception as exc:
            if type(exc).__name__ == "KilledWorker":  # Dask gave up after repeated worker deaths
                raise _crash() from None
            raise
        finally:
            bar.close()
    ds = to_dataset(spec, arrays)
    if path is not None and path.suffix == ".nc" and todo:
        write_netcdf(spec, arrays, path)
    return SweepRun(dataset=ds, points=spec.size, computed=n_todo, skipped=spec.size - n_todo,
                    damaged=damaged, uncertified=int(uncertified(ds).sum()),
                    out=None if path is None else str(path),
                    seconds=time.perf_counter() - t0,
                    compute_seconds=stats["seconds"], chunks=stats["chunks"],
                    continued=stats["continued"], fallbacks=stats["fallbacks"], executor=used)


def sweep(scene, *, executor: str = "processes", workers: int | None = None,
          scheduler: str | None = None, out: str | Path | None = None,
          progress: bool = False) -> xr.Dataset:
    """Run a parameter sweep and return its labelled ``xarray.Dataset``.

    ``scene`` is a path, a TOML string or a dict with model, ask = ["tau_min"], [params] and a
    [grid] (see :mod:`spectralshell.params.sweep_grid`). The result has the grid parameters as
    coordinates (units in attrs), variables tau_min, has_tau, error_estimate, n_temporal and
    computed (and, for a model with spatial modes, n_spatial and spatial_converged), and
    provenance attrs. Every executor gives the same numbers. With ``out`` a .zarr
    store is written chunk by chunk and a rerun computes only the missing points; a .nc file is
    written at the end. See :func:`run_sweep` for the parameters and errors.

    Points with no tau found whose emptiness the zero count could not prove are kept and
    marked (``complete_to`` below the bound, :func:`~spectralshell.results.maps.uncertified`),
    and an :class:`~spectralshell.errors.UncertifiedWarning` counts them (:func:`flagged`).
    """
    return flagged(run_sweep(scene, executor=executor, workers=workers, scheduler=scheduler,
                             out=out, progress=progress))


def flagged(run: SweepRun) -> xr.Dataset:
    """The Dataset of ``run``, after an UncertifiedWarning when it holds uncertified points
    (the API's flag: the work is kept, in the store too; the CLI exits 1 instead)."""
    if run.uncertified:
        warnings.warn(run.uncertified_note(), UncertifiedWarning, stacklevel=3)
    return run.dataset


def sweep_summary(scene, *, executor: str = "processes", workers: int | None = None,
                  scheduler: str | None = None, out: str | Path | None = None,
                  progress: bool = False) -> dict[str, Any]:
    """Run a sweep (as :func:`run_sweep`) and return the CLI's JSON summary
    ``{"points": N, "computed": n, "skipped": k, "damaged": d, "out": "PATH", "seconds": t}``."""
    return run_sweep(scene, executor=executor, workers=workers, scheduler=scheduler, out=out,
                     progress=progress).summary()


def _point_chunks(points: Sequence, size: int) -> list[tuple[int, list]]:
    return [(i, list(points[i:i + size])) for i in range(0, len(points), size)]


def map_points(factory, points: Sequence, kinds: tuple[str, ...], *, executor: str = "processes",
               workers: int | None = None, scheduler: str | None = None, chunk: int = 32,
               progress: bool = False, desc: str = "points", **options: Any) -> list[dict]:
    """Full ``marginal_tau`` of each kind at every point, through any executor, in point order:
    ``factory(point)`` (picklable) gives the Hill system; ``options`` go to ``marginal_tau``.

    The general form of :func:`spectralshell.solvers.tongues.sweep` (same rows, same numbers),
    for callers that need every marginal tau rather than a stored Dataset.
    """
    executor, workers, scheduler = check_executor(executor, workers, scheduler)
    points = list(points)
    tasks = [(factory, block, tuple(kinds), dict(options))
             for _, block in _point_chunks(points, chunk)]
    starts = {id(t): i * chunk for i, t in enumerate(tasks)}
    rows: list = [None] * len(points)
    bar = progress_bar(len(points), desc, "pt", progress)

    def record(task: tuple, result: list) -> None:
        start = starts[id(task)]
        rows[start:start + len(result)] = result
        bar.update(len(result))

    try:
        with open_pool(executor, workers=workers, scheduler=scheduler,
                       max_tasks=len(tasks)) as pool:
            run_tasks(pool.executor, solve_points, tasks,
                      in_flight=_in_flight(pool), on_result=record)
    finally:
        bar.close()
    return rows
