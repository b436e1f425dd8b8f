"""Stage 6, the computations: a model's Floquet boundaries, diagrams, maps, exponents, natural
modes, responses and time stepping, from parameters to result objects (``runner.floquet``,
``runner.modes``, ``runner.response``, ``runner.simulate``, ``runner.lp``); the one owner of
solving a point (``runner.solve``); and the sweep runner -- plan a grid's chunks, run them on
serial, process or Dask executors (one ``concurrent.futures.Executor`` interface), and keep
labelled, resumable results (``xarray`` Datasets in Zarr or NetCDF stores).

Public functions: :func:`sweep` (-> Dataset), :func:`run_sweep` (-> SweepRun with counts),
:func:`sweep_summary` (the CLI's JSON summary), :func:`open_sweep` (load a store) and
:func:`map_points` (every marginal tau at arbitrary points, through any executor).
"""

from .executors import CONNECT_TIMEOUT, EXECUTORS, SerialExecutor, open_pool
from .solve import SweepError
from .store import open_sweep
from .sweep import SweepRun, map_points, run_sweep, sweep, sweep_summary

__all__ = ["sweep", "run_sweep", "sweep_summary", "open_sweep", "map_points", "SweepRun",
           "SweepError", "SerialExecutor", "open_pool", "EXECUTORS", "CONNECT_TIMEOUT"]
