"""Sweep results as a labelled ``xarray.Dataset``, and their stores: Zarr (written chunk by
chunk, resumable) and NetCDF (written at the end).

Variables (dimensions: the grid axes, 'kind' included), NaN-free:

* ``tau_min``: smallest marginal tau <= tau_max; equals tau_max where ``has_tau`` is false;
* ``has_tau``: a marginal tau <= tau_max exists;
* ``error_estimate``: the solver's error estimate of tau_min (0 where there is none);
* ``n_temporal``: the final temporal truncation N;
* ``computed``: the point has been solved (false only in an interrupted store);

and, for a model with spatial modes (the cochlea):

* ``n_spatial``: the number M of spatial modes of the values (the finer M of the last pair
  compared where M is refined per point; 1 for a single spatial_mode);
* ``spatial_converged``: the refinement in M met tol_spatial (false: it reached M = 512 first,
  and the values are those at M = 512; always true with n_spatial given).

A Zarr store (format 2, consolidated metadata) is created whole -- metadata, coordinates and
fill values -- in a hidden directory that is then renamed into place, so it is always readable.
Each finished chunk is written as one Zarr chunk per variable (each an atomic file write), its
``computed`` flags last: a chunk counts as finished only once all its variables are on disk.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import threading
import uuid
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from .._validate import require_writable_directory
from .._version import stamp
from ..errors import ParameterError
from ..params.sweep_grid import LONG_NAMES, SweepSpec
from .layout import store_chunks
from .solve import SPATIAL_VARIABLES, VARIABLES, variables

#: Every variable a store may hold, in the order a loaded Dataset lists them.
KNOWN_VARIABLES = {**VARIABLES, **SPATIAL_VARIABLES, "computed": np.bool_}
SUFFIXES = (".zarr", ".nc")
_VAR_ATTRS = {
    "tau_min": {"long_name": "smallest marginal forcing amplitude tau <= tau_max", "units": "1",
                "note": "equals tau_max where has_tau is false"},
    "has_tau": {"long_name": "a marginal tau <= tau_max exists"},
    "error_estimate": {"long_name": "Floquet error estimate of tau_min", "units": "1",
                       "note": "0 where has_tau is false"},
    "n_temporal": {"long_name": "final temporal truncation N"},
    "n_spatial": {"long_name": "number of spatial modes M of the values"},
    "spatial_converged": {"long_name": "tau_min converged to tol_spatial in M (false: M = 512 "
                                       "reached first; values at M = 512)"},
    "computed": {"long_name": "point solved (false only in an interrupted store)"},
}


def stored_variables(spec: SweepSpec) -> dict[str, type]:
    """Variables of a sweep's store and their dtypes: the solved ones and ``computed``."""
    return {**variables(spec), "computed": np.bool_}


def empty_arrays(spec: SweepSpec) -> dict[str, np.ndarray]:
    """Result arrays before any point is solved (tau_min = tau_max, everything else 0/false)."""
    out = {name: np.zeros(spec.shape, dtype=dtype) for name, dtype in stored_variables(spec).items()}
    out["tau_min"][...] = spec.options.tau_max
    return out


def provenance(spec: SweepSpec) -> dict[str, Any]:
    """Dataset attributes: package and library versions (JSON, of the process that created the
    store), the scene as given (JSON: ``ss.sweep(json.loads(
    ds.attrs["scene"]))`` reruns it), its canonical form and hash, the solver options."""
    canonical = spec.canonical()
    software = stamp()  # NetCDF attributes are flat: the libraries as JSON
    return {"title": f"spectralshell sweep: {spec.model}, ask {', '.join(spec.ask)}",
            **software, "libraries": json.dumps(software["libraries"], sort_keys=True),
            "model": spec.model,
            "scene": spec.source or json.dumps(canonical, sort_keys=True),
            "scene_canonical": json.dumps(canonical, sort_keys=True), "scene_hash": spec.digest,
            "params": json.dumps(dict(spec.fixed)),
            "solver_options": json.dumps(canonical["options"], sort_keys=True),
            "tau_max": spec.options.tau_max, "chunk": spec.chunk,
            "line_axis": "" if spec.line_axis is None else spec.dims[spec.line_axis],
            "conventions": "K(t) = kappa (1 + 2 tau sin t), forcing period 2 pi; harmonic "
                           "gamma = 0, subharmonic gamma = i/2"}


def to_dataset(spec: SweepSpec, arrays: dict[str, np.ndarray]) -> xr.Dataset:
    """The labelled Dataset of a sweep's arrays (coordinates with units, provenance attrs)."""
    coords = {}
    for a in spec.axes:
        attrs = {"long_name": LONG_NAMES.get(a.name, a.name), "spacing": a.spacing}
        if a.units:
            attrs["units"] = a.units
        coords[a.name] = xr.Variable((a.name,), np.array(a.values), attrs)
    data = {name: xr.Variable(spec.dims, arrays[name], _VAR_ATTRS[name])
            for name in stored_variables(spec)}
    return xr.Dataset(data, coords=coords, attrs=provenance(spec))


def check_out(out: str | os.PathLike | None) -> Path | None:
    """Validated output path (.zarr or .nc in a writable directory), before anything runs.

    Raises
    ------
    ParameterError : wrong suffix, missing or read-only directory, or a path of the wrong type.
    """
    if out is None:
        return None
    path = Path(out)
    if path.suffix not in SUFFIXES:
        raise ParameterError(f"out = {str(out)!r} is invalid: must end in .zarr (written chunk by "
                             "chunk, resumable) or .nc (NetCDF, written at the end)")
    require_writable_directory("out", out, path.resolve().parent)
    if path.exists() and (path.is_dir() != (path.suffix == ".zarr")):
        raise ParameterError(f"out = {str(out)!r} is invalid: it exists and is not a "
                             f"{'directory' if path.suffix == '.zarr' else 'file'}")
    if path.suffix == ".zarr" and path.exists() and not os.access(path, os.W_OK):
        raise ParameterError(f"out = {str(out)!r} is not writable: read-only")
    return path


def _open(path: Path) -> xr.Dataset:
    try:
        if path.suffix == ".zarr":
            return xr.open_zarr(path)
        return xr.open_dataset(path)
    except Exception as exc:  # noqa: BLE001 - any unreadable file
        raise ParameterError(f"out = {str(path)!r} exists and is not a readable spectralshell "
                             f"sweep ({type(exc).__name__}): choose another path") from None


def load_existing(path: Path, spec: SweepSpec) -> dict[str, np.ndarray] | None:
    """Arrays of an existing store of the same scene (None if there is no store).

    Raises
    ------
    ParameterError : the path holds another scene's sweep or something else.
    """
    if not path.exists():
        return None
    with _open(path) as ds:
        found = ds.attrs.get("scene_hash")
        if found != spec.digest:
            what = f"a different sweep (scene hash {found})" if found else "no spectralshell sweep"
            raise ParameterError(f"out = {str(path)!r} holds {what}, not this scene (hash "
                                 f"{spec.digest}): choose another --out or delete it; sweeps "
                                 "are never mixed")
        wanted = stored_variables(spec)
        missing = [v for v in wanted if v not in ds]
        if missing or tuple(ds["tau_min"].dims) != spec.dims:
            raise ParameterError(f"out = {str(path)!r} is a damaged store (variables or "
                                 "dimensions missing): delete it and rerun")
        return {name: np.asarray(ds[name].values, dtype=dtype) for name, dtype in wanted.items()}


class ZarrStore:
    """A sweep's Zarr store, open for writing finished chunks."""

    def __init__(self, path: Path, spec: SweepSpec):
        import zarr

        self.path = path
        group = zarr.open_group(str(path), mode="r+")
        self._names = tuple(variables(spec))
        self._arrays = {name: group[name] for name in stored_variables(spec)}

    @classmethod
    def create(cls, path: Path, spec: SweepSpec) -> "ZarrStore":
        """Write a new store (metadata, coordinates, fill values) and open it."""
        ds = to_dataset(spec, empty_arrays(spec))
        chunks = store_chunks(spec)
        encoding = {name: {"chunks": chunks} for name in stored_variables(spec)}
        tmp = path.parent / f".partial-{uuid.uuid4().hex[:8]}-{path.name}"
        try:
            ds.to_zarr(tmp, mode="w-", encoding=encoding, zarr_format=2, consolidated=True)
            os.rename(tmp, path)
        except OSError as exc:  # permission, or a directory that refuses files (e.g. /proc)
            raise ParameterError(f"out = {str(path)!r} is not writable: {exc}") from None
        finally:
            if tmp.exists():
                shutil.rmtree(tmp, ignore_errors=True)
        return cls(path, spec)

    def write(self, where: tuple[slice, ...], block: dict[str, np.ndarray]) -> None:
        """Write one finished chunk: the variables, then its ``computed`` flags; a Ctrl-C
        arriving meanwhile takes effect once the chunk is written (:func:`_sigint_deferred`)."""
        with _sigint_deferred():
            for name in self._names:
                self._arrays[name][where] = block[name]
            self._arrays["computed"][where] = np.ones(block["tau_min"].shape, dtype=bool)


@contextmanager
def _sigint_deferred() -> Iterator[None]:
    """Hold back SIGINT (Ctrl-C) until the block is done, then deliver it to the previous
    handler (KeyboardInterrupt by default). A KeyboardInterrupt inside a Zarr write leaves the
    write's I/O tasks pending in Zarr's event-loop thread, which then prints "Task was destroyed
    but it is pending!" at exit; the chunk itself would stay unflagged. Main thread only (the only
    one that may set signal handlers)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    received: list[int] = []
    previous = signal.signal(signal.SIGINT, lambda signum, _frame: received.append(signum))
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
        if received:
            if callable(previous):
                previous(signal.SIGINT, None)
            elif previous != signal.SIG_IGN:
                raise KeyboardInterrupt


def write_netcdf(ds: xr.Dataset, path: Path) -> None:
    """Write ``ds`` as NetCDF via a temporary file in the same directory (never a partial file)."""
    tmp = path.parent / f".partial-{uuid.uuid4().hex[:8]}-{path.name}"
    try:
        ds.to_netcdf(tmp)
        os.replace(tmp, path)
    except OSError as exc:
        raise ParameterError(f"out = {str(path)!r} is not writable: {exc}") from None
    finally:
        if tmp.exists():
            tmp.unlink()


def open_sweep(path: str | os.PathLike) -> xr.Dataset:
    """Load a stored sweep (.zarr or .nc) into memory.

    Raises
    ------
    ParameterError : no such store, or not a spectralshell sweep.
    """
    path = Path(path)
    if not path.exists():
        raise ParameterError(f"sweep = {str(path)!r} is invalid: no such file or store")
    with _open(path) as ds:
        if "scene_hash" not in ds.attrs or "tau_min" not in ds:
            raise ParameterError(f"sweep = {str(path)!r} is invalid: not a spectralshell sweep")
        order = [v for v in KNOWN_VARIABLES if v in ds]
        order += [v for v in ds.data_vars if v not in KNOWN_VARIABLES]
        return ds[order].load()
