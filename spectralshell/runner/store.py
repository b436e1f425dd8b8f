"""Sweep results as a labelled ``xarray.Dataset``, and their stores: Zarr (written chunk by
chunk, resumable) and NetCDF (written at the end).

Variables (dimensions: the grid axes, 'kind' included):

* ``tau_min``: smallest marginal tau <= tau_max; NaN where ``has_tau`` is false (no
  instability there, or the point not computed);
* ``has_tau``: a marginal tau <= tau_max exists;
* ``error_estimate``: the solver's error estimate of tau_min (0 where there is none);
* ``n_temporal``: the final temporal truncation N;
* ``complete_to``: no real tau below it was missed (at most tau_max): an empty point
  (``has_tau`` false) claims "no tau" only up to it; one below its bound (tau_max, or the
  smallest tau_min of the other kinds there) is uncertified -- the zero count could not prove
  it (:func:`spectralshell.results.maps.uncertified`);
* ``computed``: the point has been solved (false only in an interrupted store);

and, for a model with spatial modes (the cochlea):

* ``n_spatial``: the number M of spatial modes of the values (the finer M of the last pair
  compared where M is refined per point; 1 for a single spatial_mode);
* ``spatial_converged``: the refinement in M met tol_spatial (false: it reached M = 512 first,
  and the values are those at M = 512, or stopped where an empty answer of its last pair could
  not be proved; always true with n_spatial given);

and, for the sphere with a non-uniform kappa:

* ``l_max``: the degree truncation of the values;
* ``critical_l``, ``critical_k``, ``critical_share``: the mode (l, k) with the largest share of
  the critical mode's squared displacement norm, and that share (0 where has_tau is false).

A Zarr store (format 2, consolidated metadata) is created whole -- metadata, coordinates and
fill values -- in a hidden directory that is then renamed into place, so it is always readable.
Each finished chunk is written as one Zarr chunk per variable, its ``computed`` flags last, then
its completion record (:mod:`.integrity`): reading a store back (:func:`open_sweep`, or a
rerun), a chunk counts as finished only if its record matches the values read, so that
missing, unreadable or foreign chunk files are found, never served. Only one process writes a
store at a time (:mod:`.lock`).

Stores written before ``complete_to`` existed (before certified empty answers) lack it, and
their empty points were never proved: their finished chunks, verified against their own
records, are ``outdated`` -- reading such a store (:func:`open_sweep`, ``plot``) refuses it in
one line that says so, and a rerun adds ``complete_to`` to the store, recomputes those chunks
and reports them as such (``SweepRun.outdated``), not as damage.
Likewise for a sweep that refines M per point (the cochlea without n_spatial): each chunk's
record (a NetCDF file's digest) names the stopping rule of that refinement
(:func:`~spectralshell.runner.solve.spatial_rule`: for a minimum-tau map also the basis of its
blocks), and the intact chunks of another rule, or of none (written before records named it:
the pair rule, which two coarse M agreeing by chance could pass; or, for a minimum-tau map,
before its natural-mode basis), are ``outdated``: refused on reading, recomputed on a rerun,
never mixed with this rule's values.
Stores written before tau_min was NaN where there is none hold tau_max there; they verify as
written (the records digest the stored bytes), reading them (:func:`open_sweep`, a rerun) gives
NaN there (:func:`without_tau_as_nan`), and a rerun rewrites those chunks (values and records)
and tau_min's note, so that the resumed store holds one convention.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import threading
import uuid
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from .._validate import require_writable_directory
from .._version import stamp
from ..errors import ParameterError, StoreDamaged
from ..params.sweep_grid import LONG_NAMES, VARIABLE_LONG_NAMES, SweepSpec, sweep_spec
from .integrity import (DECODE_ERRORS, census, dataset_digest, read_records, read_variable,
                        record_path, stated_rule, write_record)
from .layout import Chunk, chunk_key, chunks, region, store_chunks
from .solve import NONUNIFORM_VARIABLES, SPATIAL_VARIABLES, VARIABLES, spatial_rule, variables

#: Every variable a store may hold, in the order a loaded Dataset lists them.
KNOWN_VARIABLES = {**VARIABLES, **SPATIAL_VARIABLES, **NONUNIFORM_VARIABLES,
                   "computed": np.bool_}
SUFFIXES = (".zarr", ".nc")
#: Why the chunks of a store without ``complete_to`` are recomputed (module notes).
OUTDATED = ("written before certified empty answers (no complete_to: its empty points were never "
            "proved)")
#: Why the chunks whose records name another stopping rule of the refinement in M are.
OUTDATED_RULE = ("written under an earlier stopping rule of the refinement in M (the pair M/2, M "
                 "alone, which two coarse M agreeing by chance could pass; or, for a minimum-tau "
                 "map, cosine-mode blocks at every point)")
_VAR_ATTRS = {
    "tau_min": {"long_name": VARIABLE_LONG_NAMES["tau_min"], "units": "1",
                "note": "NaN where has_tau is false"},
    "has_tau": {"long_name": VARIABLE_LONG_NAMES["has_tau"]},
    "error_estimate": {"long_name": VARIABLE_LONG_NAMES["error_estimate"], "units": "1",
                       "note": "0 where has_tau is false"},
    "n_temporal": {"long_name": VARIABLE_LONG_NAMES["n_temporal"]},
    "complete_to": {"long_name": VARIABLE_LONG_NAMES["complete_to"], "units": "1",
                    "note": "at most tau_max; where has_tau is false and complete_to is below "
                            "the point's bound the empty answer is uncertified"},
    "n_spatial": {"long_name": VARIABLE_LONG_NAMES["n_spatial"]},
    "spatial_converged": {"long_name": "tau_min converged to tol_spatial in M (false: M = 512 "
                                       "reached first; values at M = 512)"},
    "computed": {"long_name": "point solved (false only in an interrupted store)"},
    **{name: {"long_name": VARIABLE_LONG_NAMES[name]} for name in NONUNIFORM_VARIABLES},
}


def stored_variables(spec: SweepSpec) -> dict[str, type]:
    """Variables of a sweep's store and their dtypes: the solved ones and ``computed``."""
    return {**variables(spec), "computed": np.bool_}


def empty_arrays(spec: SweepSpec) -> dict[str, np.ndarray]:
    """Result arrays before any point is solved (tau_min NaN, everything else 0/false)."""
    out = {name: np.zeros(spec.shape, dtype=dtype) for name, dtype in stored_variables(spec).items()}
    out["tau_min"][...] = np.nan
    return out


def without_tau_as_nan(arrays: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """``arrays`` with tau_min NaN wherever has_tau is false (where a store written by an
    earlier version holds tau_max)."""
    return {**arrays, "tau_min": np.where(arrays["has_tau"], arrays["tau_min"], np.nan)}


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
            **({"spatial_rule": spatial_rule(spec)} if spec.refines_spatial else {}),
            "line_axis": "" if spec.line_axis is None else spec.dims[spec.line_axis],
            "conventions": "K(t) = kappa (1 + 2 tau sin t), forcing period 2 pi; harmonic "
                           "gamma = 0, subharmonic gamma = i/2"}


def to_dataset(spec: SweepSpec, arrays: dict[str, np.ndarray],
               attrs: dict[str, Any] | None = None) -> xr.Dataset:
    """The labelled Dataset of a sweep's arrays (coordinates with units; ``attrs``, by default
    the provenance of this process)."""
    coords = {}
    for a in spec.axes:
        meta = {"long_name": LONG_NAMES.get(a.name, a.name), "spacing": a.spacing}
        if a.units:
            meta["units"] = a.units
        coords[a.name] = xr.Variable((a.name,), np.array(a.values), meta)
    data = {name: xr.Variable(spec.dims, arrays[name], _VAR_ATTRS[name])
            for name in stored_variables(spec)}
    return xr.Dataset(data, coords=coords, attrs=provenance(spec) if attrs is None else attrs)


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


def _open_netcdf(path: Path, name: str) -> xr.Dataset:
    try:
        return xr.open_dataset(path)
    except Exception as exc:  # noqa: BLE001 - any unreadable file
        raise _unreadable(path, name, exc) from None


def _unreadable(path: Path, name: str, exc: Exception) -> ParameterError:
    return ParameterError(f"{name} = {str(path)!r} exists and is not a readable spectralshell "
                          f"sweep ({type(exc).__name__}): choose another path")


def _other_scene(path: Path, found: str | None, spec: SweepSpec) -> ParameterError:
    what = f"a different sweep (scene hash {found})" if found else "no spectralshell sweep"
    return ParameterError(f"out = {str(path)!r} holds {what}, not this scene (hash "
                          f"{spec.digest}): choose another out= or delete it; sweeps are never "
                          "mixed")


@dataclass(frozen=True, eq=False)
class StoredSweep:
    """A store's contents as read back: ``arrays`` of every stored variable (the values of
    finished chunks, those of :func:`empty_arrays` elsewhere; ``computed`` true exactly on
    finished chunks), its ``attrs``, the ``damaged`` chunks (numbers), the coordinates
    whose stored values differ from the scene's, the finished chunks stored with tau_max
    where there is no tau (``legacy``: written before NaN was), and, in a store written
    before ``complete_to`` existed, the chunks with a completion record, and in a store of a
    sweep refining M the chunks whose records name an earlier stopping rule (``outdated``, why
    in ``outdated_why``: none of their values is kept, and a rerun recomputes them)."""

    arrays: dict[str, np.ndarray]
    attrs: dict[str, Any]
    damaged: frozenset[int] = frozenset()
    coordinates: tuple[str, ...] = ()
    legacy: frozenset[int] = frozenset()
    outdated: frozenset[int] = frozenset()
    outdated_why: str = OUTDATED

    def damage(self, spec: SweepSpec) -> str:
        """'3 of 8 chunks missing, unreadable or altered[, coordinates kappa]' ('' if none)."""
        parts = []
        if self.damaged:
            parts.append(f"{len(self.damaged)} of {len(chunks(spec))} chunks missing, "
                         "unreadable or altered since they were written")
        if self.coordinates:
            parts.append(f"coordinates {', '.join(self.coordinates)} altered")
        return "; ".join(parts)


def _stored_spec(path: Path, attrs: dict[str, Any]) -> SweepSpec:
    """The SweepSpec of a store's own scene (attrs 'scene'), checked against its hash."""
    try:
        spec = sweep_spec(json.loads(attrs["scene"]))
    except (KeyError, TypeError, ValueError):
        raise ParameterError(f"sweep = {str(path)!r} is invalid: not a spectralshell sweep (no "
                             "valid scene in its attributes)") from None
    if spec.digest != attrs.get("scene_hash"):
        raise ParameterError(f"sweep = {str(path)!r} is invalid: its scene hashes to "
                             f"{spec.digest}, its attributes say {attrs.get('scene_hash')} "
                             "(altered, or written by another spectralshell version)")
    return spec


def _coordinate_intact(group, axis) -> bool:
    try:
        return np.array_equal(group[axis.name][...], np.array(axis.values))
    except (KeyError, *DECODE_ERRORS):
        return False


def read_zarr(path: Path, spec: SweepSpec | None = None) -> tuple[SweepSpec, StoredSweep]:
    """Read a Zarr sweep store and verify every chunk against its completion record (records
    first: a chunk a running writer finishes meanwhile reads as unfinished, not as damaged).
    Without ``spec``, the store's own scene is used; with it, the store must hold that scene.
    A store of the scene written before ``complete_to`` existed keeps nothing: its recorded
    chunks are ``outdated`` (module notes); so are the intact chunks whose records name an
    earlier stopping rule of the refinement in M (:func:`~.integrity.census`).

    Raises
    ------
    ParameterError : not a readable spectralshell store, another scene, or variables of the
        wrong shape or chunking.
    """
    import zarr

    name = "sweep" if spec is None else "out"
    try:  # each array's own metadata, and the consolidated copy that other readers use
        group = zarr.open_group(str(path), mode="r", use_consolidated=False)
        attrs = dict(group.attrs)
        zarr.open_consolidated(str(path), mode="r")
    except Exception as exc:  # noqa: BLE001 - any unreadable metadata
        raise _unreadable(path, name, exc) from None
    if spec is None:
        spec = _stored_spec(path, attrs)
    elif attrs.get("scene_hash") != spec.digest:
        raise _other_scene(path, attrs.get("scene_hash"), spec)
    wanted = stored_variables(spec)
    try:
        found = {v: group[v] for v in wanted if v in group}
    except Exception as exc:  # noqa: BLE001 - an array's metadata unreadable
        raise _unreadable(path, name, exc) from None
    records = read_records(path)
    if [v for v in wanted if v not in found] == ["complete_to"] and holds_records_of(path, spec):
        return spec, StoredSweep(empty_arrays(spec), attrs, outdated=frozenset(
            c.index for c in chunks(spec) if chunk_key(spec, c) in records))
    if len(found) < len(wanted) or any(a.shape != spec.shape or a.chunks != store_chunks(spec)
                                       for a in found.values()):
        raise ParameterError(f"{name} = {str(path)!r} is a damaged store (variables missing, or "
                             "of the wrong shape): delete it and rerun")
    arrays, unreadable = {}, frozenset()
    for variable, dtype in wanted.items():
        arrays[variable], bad = read_variable(found[variable], spec, dtype)
        unreadable |= bad
    state = census(spec, arrays, unreadable, records)
    done = np.zeros(spec.shape, dtype=bool)
    for chunk in chunks(spec):
        if chunk.index in state.finished:
            done[region(spec, chunk)] = True
    empty = empty_arrays(spec)
    stored = {v: np.where(done, values, empty[v]) for v, values in arrays.items()}
    old = ~stored["has_tau"] & ~np.isnan(stored["tau_min"])
    legacy = frozenset(c.index for c in chunks(spec) if old[region(spec, c)].any())
    coordinates = tuple(a.name for a in spec.axes if not _coordinate_intact(group, a))
    return spec, StoredSweep(without_tau_as_nan(stored), attrs, state.damaged, coordinates,
                             legacy, state.outdated, OUTDATED_RULE)


def load_existing(path: Path, spec: SweepSpec) -> StoredSweep | None:
    """What an existing store of the same scene holds (None if there is no store); a Zarr
    store's chunks are verified (:func:`read_zarr`), and one written before ``complete_to``
    existed gets it (:func:`restore_metadata`).

    Raises
    ------
    ParameterError : the path holds another scene's sweep or something else.
    """
    if not path.exists():
        return None
    if path.suffix == ".zarr":
        try:
            stored = read_zarr(path, spec)[1]
        except ParameterError:
            if not restore_metadata(path, spec):
                raise
            return read_zarr(path, spec)[1]
        if stored.outdated_why == OUTDATED and stored.outdated:  # no complete_to: add it
            restore_metadata(path, spec)  # (ZarrStore.repair then removes the outdated chunks)
        return stored
    with _open_netcdf(path, "out") as ds:
        found = ds.attrs.get("scene_hash")
        if found != spec.digest:
            raise _other_scene(path, found, spec)
        arrays = _netcdf_arrays(ds, spec, spatial_rule(spec))
        every = frozenset(c.index for c in chunks(spec))
        if arrays is None and _of_earlier_rule(ds, spec):  # recomputed, and the file replaced
            return StoredSweep(empty_arrays(spec), dict(ds.attrs), outdated=every,
                               outdated_why=OUTDATED_RULE)
        if arrays is None:  # damaged: every chunk is recomputed, and the file replaced
            return StoredSweep(empty_arrays(spec), dict(ds.attrs), every)
        return StoredSweep(arrays, dict(ds.attrs))


def _netcdf_arrays(ds: xr.Dataset, spec: SweepSpec,
                   rule: str | None) -> dict[str, np.ndarray] | None:
    """The stored variables of a NetCDF sweep of ``spec``, or None when they are missing, have
    other dimensions or coordinates, or differ from their digest (attrs ``data_sha256``) with
    the stopping ``rule`` of a refinement in M (:func:`~.integrity.dataset_digest`)."""
    wanted = stored_variables(spec)
    if any(v not in ds for v in wanted) or tuple(ds["tau_min"].dims) != spec.dims:
        return None
    try:
        arrays = {name: np.asarray(ds[name].values, dtype=dtype) for name, dtype in wanted.items()}
    except (*DECODE_ERRORS, TypeError):
        return None
    if any(not np.array_equal(ds[a.name].values, np.array(a.values)) for a in spec.axes):
        return None
    if ds.attrs.get("data_sha256") != dataset_digest(spec, arrays, rule):
        return None
    return without_tau_as_nan(arrays)


def _of_earlier_rule(ds: xr.Dataset, spec: SweepSpec) -> bool:
    """Whether a NetCDF sweep that refines M was written, intact, under another stopping rule
    of the refinement (attrs ``spatial_rule``; none before files named it)."""
    rule = stated_rule(ds.attrs)
    return (spec.refines_spatial and rule != spatial_rule(spec)
            and _netcdf_arrays(ds, spec, rule) is not None)


#: Zarr (format 2) metadata files of a store and of each of its arrays.
GROUP_METADATA = (".zgroup", ".zattrs", ".zmetadata")
ARRAY_METADATA = (".zarray", ".zattrs")


def holds_records_of(path: Path, spec: SweepSpec) -> bool:
    """Whether the store at ``path`` has a completion record of ``spec``'s scene (the store
    is this sweep's, whatever its metadata now says)."""
    for text in read_records(path).values():
        try:
            if json.loads(text).get("scene_hash") == spec.digest:
                return True
        except (ValueError, AttributeError):
            continue
    return False


def restore_metadata(path: Path, spec: SweepSpec) -> bool:
    """Rewrite the metadata of a Zarr store of ``spec``'s scene (group and array metadata, and
    the coordinates) from the scene, keeping its chunk files and completion records, which the
    next read verifies: a store whose ``.zattrs``, ``.zmetadata`` or ``.zarray`` files were
    damaged is repaired by a rerun. Returns False, touching nothing, when the store holds no
    record of this scene (it is not this sweep's)."""
    if not path.is_dir() or not holds_records_of(path, spec):
        return False
    fresh = path.parent / f".metadata-{uuid.uuid4().hex[:8]}-{path.name}"
    try:
        ZarrStore.create(fresh, spec)
        for name in GROUP_METADATA:
            _replace(fresh / name, path / name)
        axes = {a.name for a in spec.axes}
        for name in stored_variables(spec):
            (path / name).mkdir(exist_ok=True)
            for meta in ARRAY_METADATA:
                _replace(fresh / name / meta, path / name / meta)
        for name in axes:  # coordinates: small, and wholly the scene's
            _remove(path / name)
            shutil.copytree(fresh / name, path / name)
    finally:
        shutil.rmtree(fresh, ignore_errors=True)
    return True


def _replace(source: Path, target: Path) -> None:
    """Copy the file ``source`` over ``target`` (whatever ``target`` became), or remove
    ``target`` if there is no ``source``."""
    _remove(target)
    if source.exists():
        shutil.copy2(source, target)


class ZarrStore:
    """A sweep's Zarr store, open for writing finished chunks."""

    def __init__(self, path: Path, spec: SweepSpec):
        import zarr

        self.path = path
        self.spec = spec
        self._group = zarr.open_group(str(path), mode="r+")
        self._dtypes = stored_variables(spec)
        self._arrays = {name: self._group[name] for name in self._dtypes}

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

    def write(self, chunk: Chunk, block: dict[str, np.ndarray]) -> None:
        """Write one finished chunk (``block``: its solved variables): the variables, then its
        ``computed`` flags, then its completion record; a Ctrl-C arriving meanwhile takes effect
        once the chunk is written (:func:`_sigint_deferred`)."""
        where = region(self.spec, chunk)
        full = {**block, "computed": np.ones(block["tau_min"].shape, dtype=bool)}
        values = {name: np.asarray(full[name], dtype=dtype) for name, dtype in self._dtypes.items()}
        with _sigint_deferred():
            for name, array in self._arrays.items():
                array[where] = values[name]
            write_record(self.path, self.spec, chunk, values)

    def repair(self, stored: StoredSweep) -> None:
        """Prepare a store read back as ``stored`` for a rerun: remove the temporary files of
        writes a killed writer left, rewrite the altered coordinates from the scene, remove
        the damaged and outdated chunks' files and records (whatever they became: a directory or
        a link is never written through), so that they are recomputed, and rewrite the chunks of the
        tau_max convention with NaN (:meth:`migrate`)."""
        for leftover in self.path.glob("*/*.partial"):
            _remove(leftover)
        for axis in self.spec.axes:
            if axis.name in stored.coordinates:
                self._group[axis.name][...] = np.array(axis.values)
        for chunk in chunks(self.spec):
            if chunk.index in stored.damaged | stored.outdated:
                _remove(record_path(self.path, self.spec, chunk))
                for name in self._arrays:
                    _remove(self.path / name / chunk_key(self.spec, chunk))
        self.migrate(stored)

    def migrate(self, stored: StoredSweep) -> None:
        """Rewrite the ``legacy`` chunks of ``stored`` (tau_max where there is no tau) with its
        values, NaN there, and their records; give tau_min the note of this convention."""
        if not stored.legacy:
            return
        import zarr

        for chunk in chunks(self.spec):
            if chunk.index in stored.legacy:
                where = region(self.spec, chunk)
                self.write(chunk, {name: stored.arrays[name][where] for name in self._arrays
                                   if name != "computed"})
        self._arrays["tau_min"].attrs.update(_VAR_ATTRS["tau_min"])
        with warnings.catch_warnings():  # the records' directory is not a Zarr node: expected
            warnings.filterwarnings("ignore", "Object at .chunks is not recognized")
            zarr.consolidate_metadata(str(self.path), zarr_format=2)


def _remove(path: Path) -> None:
    """Remove a file, link or directory tree, if there is one."""
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path)
    else:
        path.unlink(missing_ok=True)


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


def write_netcdf(spec: SweepSpec, arrays: dict[str, np.ndarray], path: Path) -> None:
    """Write the sweep as NetCDF, with the digest of its values (:func:`dataset_digest`), via
    a temporary file in the same directory (never a partial file)."""
    ds = to_dataset(spec, arrays)
    ds.attrs["data_sha256"] = dataset_digest(spec, {n: arrays[n] for n in stored_variables(spec)},
                                          spatial_rule(spec))
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
    """Load a stored sweep (.zarr or .nc) into memory; a Zarr store's chunks are verified
    first, and unfinished ones read as not ``computed``.

    Raises
    ------
    ParameterError : no such store, or not a spectralshell sweep.
    StoreDamaged : chunks of the Zarr store are missing, unreadable or altered (rerunning the
        sweep into it recomputes exactly those), or it was written before ``complete_to``
        existed or, refining M, under an earlier stopping rule of that refinement (rerunning
        recomputes those chunks).
    """
    path = Path(path)
    if not path.exists():
        raise ParameterError(f"sweep = {str(path)!r} is invalid: no such file or store")
    if path.suffix == ".zarr":
        try:
            spec, stored = read_zarr(path)
        except ParameterError as exc:
            if read_records(path):  # a sweep's store, its metadata damaged
                raise StoreDamaged(f"sweep = {str(path)!r} is damaged: its metadata cannot be "
                                   f"read ({exc}); rerun its sweep with out={str(path)!r} to "
                                   "rebuild it (finished chunks are kept)") from None
            raise
        if stored.outdated:
            raise StoreDamaged(f"sweep = {str(path)!r} was {stored.outdated_why}; rerun its "
                               f"sweep with out={str(path)!r} to recompute its "
                               f"{len(stored.outdated)} finished chunks")
        damage = stored.damage(spec)
        if damage:
            raise StoreDamaged(f"sweep = {str(path)!r} is damaged: {damage}; rerun its sweep "
                               f"with out={str(path)!r} to recompute exactly those")
        return to_dataset(spec, stored.arrays, stored.attrs)
    with _open_netcdf(path, "sweep") as ds:
        if "scene_hash" not in ds.attrs or "tau_min" not in ds:
            raise ParameterError(f"sweep = {str(path)!r} is invalid: not a spectralshell sweep")
        spec = _stored_spec(path, dict(ds.attrs))
        arrays = _netcdf_arrays(ds, spec, spatial_rule(spec))
        if arrays is None and _of_earlier_rule(ds, spec):
            raise StoreDamaged(f"sweep = {str(path)!r} was {OUTDATED_RULE}; rerun its sweep "
                               f"with out={str(path)!r} to recompute it")
        if arrays is None:
            raise StoreDamaged(f"sweep = {str(path)!r} is damaged: its variables, dimensions, "
                               "coordinates or values differ from what was written (data_sha256);"
                               f" rerun its sweep with out={str(path)!r} to recompute it")
        order = [v for v in KNOWN_VARIABLES if v in ds]
        order += [v for v in ds.data_vars if v not in KNOWN_VARIABLES]
        out = ds[order].load()
        out["tau_min"] = out["tau_min"].copy(data=arrays["tau_min"])
        out["tau_min"].attrs.update(_VAR_ATTRS["tau_min"])
        return out
