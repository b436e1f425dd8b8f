"""Stage 6, the computations: a model's Floquet boundaries, diagrams, maps, exponents, natural
modes, responses and time stepping, from parameters to result objects (``runner.floquet``,
``runner.modes``, ``runner.response``, ``runner.simulate``, ``runner.lp``); the one owner of
solving a point (``runner.solve``); and the sweep runner -- plan a grid's chunks, run them on
serial, process or Dask executors (one ``concurrent.futures.Executor`` interface), and keep
labelled, resumable results (``xarray`` Datasets in Zarr or NetCDF stores).

Public functions: :func:`sweep.sweep` (-> Dataset), :func:`run_sweep` (-> SweepRun with counts),
:func:`sweep_summary` (the CLI's JSON summary), :func:`open_sweep` (load a store) and
:func:`map_points` (every marginal tau at arbitrary points, through any executor).
"""

import importlib
from typing import Any

#: Public names and the module that defines each, imported on first use (the sweep's modules
#: bring xarray, ~0.3 s, which a single Floquet solve does not need).
_PUBLIC = {"run_sweep": "sweep", "sweep_summary": "sweep", "map_points": "sweep",
           "SweepRun": "sweep", "open_sweep": "store", "SweepError": "solve",
           "SerialExecutor": "executors", "open_pool": "executors", "EXECUTORS": "executors",
           "CONNECT_TIMEOUT": "executors"}

__all__ = sorted(_PUBLIC)


def __getattr__(name: str) -> Any:
    if name in _PUBLIC:
        return getattr(importlib.import_module(f".{_PUBLIC[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
