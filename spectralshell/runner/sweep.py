"""The sweep runner: plan the chunks, skip the finished ones, dispatch the rest, store results."""

from __future__ import annotations

import functools
import itertools
import math
import time
import warnings
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures.process import BrokenProcessPool
from contextlib import nullcontext
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from ..errors import SweepInterrupted, UncertifiedWarning
from ..params.limits import SECONDS
from ..params.sweep_grid import SweepSpec, sweep_spec
from ..results.maps import uncertified, uncertified_note
from .engine import run_tasks
from .executors import check_executor, open_pool
from .integrity import read_records
from .layout import Chunk, block_shape, chunk_key, chunks, region
from .lock import writer_lock
from .progress import progress_bar
from ..solvers.cost import CostEstimate, duration, spatial_cost
from .solve import ChunkResult, SweepError, solve_chunks, solve_points, spatial_system
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
    outdated : points computed now because their chunks in the store were written before
        ``complete_to`` existed (:data:`~spectralshell.runner.store.OUTDATED`) or under an
        earlier stopping rule of the refinement in M (``OUTDATED_RULE``); counted in
        ``computed``, not in ``damaged``.

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
    outdated: int = 0
    uncertified: int = 0
    compute_seconds: float = 0.0
    chunks: int = 0
    continued: int = 0
    fallbacks: int = 0
    executor: str = ""

    def summary(self) -> dict[str, Any]:
        """The JSON summary ``{"points", "computed", "skipped", "damaged", "outdated",
        "uncertified", "out", "seconds"}``."""
        return {"points": self.points, "computed": self.computed, "skipped": self.skipped,
                "damaged": self.damaged, "outdated": self.outdated,
                "uncertified": self.uncertified, "out": self.out,
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


#: Values per real axis at which a sweep with spatial modes is priced (:func:`sweep_cost`; the
#: ends included): at most PRICE_SAMPLES ** axes points, each the HillSystems of the first
#: window of the refinement in M (M = 16, 24, 32).
PRICE_SAMPLES = 5


def sweep_cost(spec: SweepSpec, points: int) -> tuple[float, CostEstimate] | None:
    """(estimated seconds of work, the dearest sampled point's estimate) of ``points`` points
    of a sweep of a model with spatial modes (the cochlea; None for other sweeps, whose points
    are cheap, and for a single spatial mode): the mean least price of a point
    (:func:`~spectralshell.solvers.cost.spatial_cost`, the kinds and the certificate of an
    empty answer included) over a sub-grid of up to PRICE_SAMPLES values of each axis, ends
    included, times ``points``. Only the work the refinement in M must do is priced (its
    first pair; the values at larger M are not known before), the dense price of each
    truncation: what a point may cost (solvers/cost.py)."""
    fixed = dict(spec.fixed)
    if not spec.spatial or "spatial_mode" in fixed or "spatial_mode" in spec.dims:
        return None
    axes = [a for a in spec.axes if a.name != "kind"]
    picks = [[a.values[i] for i in np.unique(np.linspace(0, len(a.values) - 1, min(
        len(a.values), PRICE_SAMPLES)).round().astype(int))] for a in axes]
    estimates = []
    for values in itertools.product(*picks):
        params = spec.params_at(dict(zip((a.name for a in axes), values)))
        n_spatial = params.pop("n_spatial", None)
        estimates.append(spatial_cost(functools.partial(spatial_system, spec.model, params),
                                      spec.kinds, n_spatial=n_spatial,
                                      n_temporal=spec.options.n_temporal, upper=False))
    mean = sum(e.seconds for e in estimates) / len(estimates)
    return mean * points / len(spec.kinds), max(estimates, key=lambda e: e.seconds)


def priced_sweep(spec: SweepSpec, points: int, max_seconds: float | None) -> str:
    """Refuse (ParameterError, before any work) a sweep whose ``points`` still to compute are
    estimated above the limit on seconds (:func:`sweep_cost`); else the estimate in words for
    the progress bar ('' where the sweep is not priced)."""
    priced = sweep_cost(spec, points)
    if priced is None:
        return ""
    seconds, dearest = priced
    what = (f"sweep of {points // len(spec.kinds)} {spec.model} points (dearest sampled: "
            f"{dearest.describe()})")
    SECONDS.check(what, seconds, max_seconds, "fix the truncations with n_spatial and "
                  "tau_min.n_temporal")
    return f"about {duration(seconds)} of work"


def run_sweep(scene, *, executor: str = "processes", workers: int | None = None,
              scheduler: str | None = None, out: str | Path | None = None,
              progress: bool = False, max_seconds: float | None = None,
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
    progress : a progress bar (points/s, ETA) on stderr; for a model with spatial modes its
        label states the estimated work (:func:`sweep_cost`).
    max_seconds : raise the limit on the estimated seconds of work of a sweep of a model with
        spatial modes (default :data:`spectralshell.params.limits.SECONDS`, 600 s, or
        $SPECTRALSHELL_MAX_SECONDS): the points still to compute are priced before any work
        (:func:`priced_sweep`) and refused above it.
    on_chunk : test hook, called as ``on_chunk(n_finished, result)`` after each chunk is stored.

    Raises
    ------
    ParameterError : invalid scene, executor arguments or output; a store of another scene;
        an estimated cost above the limit (before any work).
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
                    progress=progress, on_chunk=on_chunk, t0=t0, max_seconds=max_seconds)


def _points(spec: SweepSpec, which: frozenset[int]) -> int:
    """The number of points in the chunks numbered ``which``."""
    return sum(math.prod(block_shape(spec, c)) for c in chunks(spec) if c.index in which)


def _run(spec: SweepSpec, path: Path | None, *, executor: str, workers: int | None,
         scheduler: str | None, progress: bool,
         on_chunk: Callable[[int, ChunkResult], None] | None, t0: float,
         max_seconds: float | None = None) -> SweepRun:
    """:func:`run_sweep` once its arguments are checked and ``path`` is locked."""
    stored = load_existing(path, spec) if path is not None else None
    if stored is not None and path.suffix == ".zarr":
        ZarrStore(path, spec).repair(stored)
    arrays = empty_arrays(spec) if stored is None else stored.arrays
    plan = chunks(spec)
    todo = [c for c in plan if not arrays["computed"][region(spec, c)].all()]
    n_todo = sum(int(arrays["computed"][region(spec, c)].size) for c in todo)
    damaged = 0 if stored is None else _points(spec, stored.damaged)
    outdated = 0 if stored is None else _points(spec, stored.outdated)
    stats = {"chunks": 0, "seconds": 0.0, "continued": 0, "fallbacks": 0}
    used = "none (nothing to compute)"
    store = None
    if todo:
        estimate = priced_sweep(spec, n_todo, max_seconds)
        label = f"sweep ({estimate})" if estimate else "sweep"
        bar = progress_bar(n_todo, label, "pt", progress)

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
                bar.set_description(f"{label} [{pool.name}]")
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
                    damaged=damaged, outdated=outdated, uncertified=int(uncertified(ds).sum()),
                    out=None if path is None else str(path),
                    seconds=time.perf_counter() - t0,
                    compute_seconds=stats["seconds"], chunks=stats["chunks"],
                    continued=stats["continued"], fallbacks=stats["fallbacks"], executor=used)


def sweep(scene, *, executor: str = "processes", workers: int | None = None,
          scheduler: str | None = None, out: str | Path | None = None,
          progress: bool = False, max_seconds: float | None = None) -> xr.Dataset:
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
                             out=out, progress=progress, max_seconds=max_seconds))


def flagged(run: SweepRun) -> xr.Dataset:
    """The Dataset of ``run``, after an UncertifiedWarning when it holds uncertified points
    (the API's flag: the work is kept, in the store too; the CLI exits 1 instead)."""
    if run.uncertified:
        warnings.warn(run.uncertified_note(), UncertifiedWarning, stacklevel=3)
    return run.dataset


def sweep_summary(scene, *, executor: str = "processes", workers: int | None = None,
                  scheduler: str | None = None, out: str | Path | None = None,
                  progress: bool = False, max_seconds: float | None = None) -> dict[str, Any]:
    """Run a sweep (as :func:`run_sweep`) and return the CLI's JSON summary
    ``{"points": N, "computed": n, "skipped": k, "damaged": d, "outdated": o, "uncertified": u,
    "out": "PATH", "seconds": t}`` (:meth:`SweepRun.summary`)."""
    return run_sweep(scene, executor=executor, workers=workers, scheduler=scheduler, out=out,
                     progress=progress, max_seconds=max_seconds).summary()


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
