"""Completion records of a Zarr sweep store: which chunks are finished, and whether each one
still holds what was written.

Once every variable of a chunk is on disk (its ``computed`` flags last), its record
``.chunks/KEY.json`` is written (to a temporary name, then renamed, so it is whole or absent;
KEY names the chunk's Zarr files, e.g. ``0.3.0``). The record holds the scene hash, the chunk's
number, origin and length, for a sweep that refines M per point the name of the refinement's
stopping rule (:func:`~spectralshell.runner.solve.spatial_rule`), and a sha256
digest of those and of the chunk's values of every stored variable (name, dtype, shape and
bytes). Reading the store back, a chunk is

* finished: its record equals the one of the values decoded at the chunk's place;
* outdated: its record would be that, but names another stopping rule, or none (written before
  records named it): intact, but not this code's values;
* damaged: it has a record, but a chunk file is missing (Zarr reads the fill value), cannot be
  decoded, or holds other values -- e.g. another cell's file copied over it, or another
  store's record; identical bytes would verify, and are harmless;
* unfinished: it has no record (never written, interrupted, or its record removed).

A NetCDF sweep (written whole, at the end) carries one such digest of all its values and axes
in its attributes (:func:`dataset_digest`), checked on reading.

The digest detects accidents, not forgery: whoever rewrites a chunk and its record together
with this code makes a store that verifies.
"""

from __future__ import annotations

import hashlib
import json
import os
import uuid
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..params.sweep_grid import SweepSpec
from .layout import Chunk, chunk_key, chunks, region
from .solve import spatial_rule

RECORDS = ".chunks"  # directory of the completion records, inside the store
#: What decoding a damaged chunk file raises: blosc (RuntimeError), a buffer of the wrong size
#: or dtype (ValueError), an unreadable file (OSError).
DECODE_ERRORS = (RuntimeError, ValueError, OSError)


def _sha256(place: Mapping, block: Mapping[str, np.ndarray]) -> str:
    """sha256 of ``place`` (JSON) and of each array of ``block``: name, dtype, shape, bytes."""
    digest = hashlib.sha256(json.dumps(place, sort_keys=True).encode())
    for name, values in block.items():
        values = np.ascontiguousarray(values)
        digest.update(json.dumps([name, values.dtype.str, values.shape]).encode())
        digest.update(values.tobytes())
    return digest.hexdigest()


def record_text(spec: SweepSpec, chunk: Chunk, block: Mapping[str, np.ndarray],
                rule: str | None) -> str:
    """The completion record (JSON) of a chunk holding ``block`` (every stored variable, in
    the store's order and dtypes); where the sweep refines M per point it names the stopping
    ``rule`` of that refinement (None: a record of before records named it)."""
    place = _with_rule(spec, rule, {"scene_hash": spec.digest, "chunk": chunk.index,
                                    "origin": list(chunk.origin), "length": chunk.length})
    return json.dumps({**place, "sha256": _sha256(place, block)}, sort_keys=True)


def _with_rule(spec: SweepSpec, rule: str | None, place: dict) -> dict:
    """``place`` naming the stopping ``rule`` of the refinement in M where ``spec`` refines M
    (and ``rule`` is not None: a record or file of before they named it)."""
    return {**place, "spatial_rule": rule} if spec.refines_spatial and rule is not None else place


def stated_rule(fields: Mapping) -> str | None:
    """The stopping rule of the refinement in M that a record's or file's ``fields`` name (None:
    none, as before records named it, or not a string)."""
    rule = fields.get("spatial_rule")
    return rule if isinstance(rule, str) else None


def _rule_of(record: str) -> str | None:
    """:func:`stated_rule` of a record's text (None also when it is not a JSON object)."""
    try:
        fields = json.loads(record)
    except ValueError:
        return None
    return stated_rule(fields) if isinstance(fields, dict) else None


def dataset_digest(spec: SweepSpec, arrays: Mapping[str, np.ndarray],
                   rule: str | None) -> str:
    """sha256 of a whole sweep written at once (NetCDF): the scene hash, every axis's values,
    the stopping ``rule`` of a refinement in M (as in :func:`record_text`) and every stored
    variable (``arrays``, in the store's order and dtypes). Kept in the file's attributes
    (``data_sha256``, the rule as ``spatial_rule``) and checked when it is read back, as a Zarr
    chunk's record is."""
    place = _with_rule(spec, rule, {
        "scene_hash": spec.digest,
        "axes": [[a.name, [v.item() if hasattr(v, "item") else v for v in a.values]]
                 for a in spec.axes]})
    return _sha256(place, arrays)


def record_path(store: Path, spec: SweepSpec, chunk: Chunk) -> Path:
    """Where the chunk's completion record is: ``STORE/.chunks/KEY.json``."""
    return store / RECORDS / f"{chunk_key(spec, chunk)}.json"


def write_record(store: Path, spec: SweepSpec, chunk: Chunk,
                 block: Mapping[str, np.ndarray]) -> None:
    """Write the chunk's completion record into the store (whole or not at all)."""
    path = record_path(store, spec, chunk)
    path.parent.mkdir(exist_ok=True)
    tmp = path.parent / f"{uuid.uuid4().hex}.partial"  # named as Zarr names its temporary files
    tmp.write_text(record_text(spec, chunk, block, spatial_rule(spec)))
    os.replace(tmp, path)


def read_records(store: Path) -> dict[str, str]:
    """Completion records of a store by chunk key (text as stored; unreadable ones as '')."""
    folder = store / RECORDS
    if not folder.is_dir():
        return {}
    out = {}
    for path in folder.glob("*.json"):
        try:
            out[path.name.removesuffix(".json")] = path.read_text()
        except (OSError, UnicodeDecodeError):
            out[path.name.removesuffix(".json")] = ""
    return out


def read_variable(array, spec: SweepSpec, dtype: type) -> tuple[np.ndarray, frozenset[int]]:
    """Decoded values of a stored Zarr variable and the numbers of the chunks that could not be
    decoded (zero there): the whole array at once, chunk by chunk only if that fails."""
    try:
        return np.asarray(array[...], dtype=dtype), frozenset()
    except DECODE_ERRORS:
        pass
    values = np.zeros(spec.shape, dtype=dtype)
    bad = set()
    for chunk in chunks(spec):
        where = region(spec, chunk)
        try:
            values[where] = array[where]
        except DECODE_ERRORS:
            bad.add(chunk.index)
    return values, frozenset(bad)


@dataclass(frozen=True)
class Census:
    """The chunks of a store by state: ``finished``, ``damaged`` and ``outdated`` (chunk
    numbers); the others are unfinished."""

    finished: frozenset[int]
    damaged: frozenset[int]
    outdated: frozenset[int] = frozenset()


def census(spec: SweepSpec, arrays: Mapping[str, np.ndarray], unreadable: frozenset[int],
           records: Mapping[str, str]) -> Census:
    """Compare every chunk's values (``arrays``: every stored variable, decoded; ``unreadable``:
    chunks some variable could not be decoded) with its completion record."""
    finished, damaged, outdated = set(), set(), set()
    current = spatial_rule(spec)
    for chunk in chunks(spec):
        found = records.get(chunk_key(spec, chunk))
        if found is None:
            continue
        where = region(spec, chunk)
        block = {name: values[where] for name, values in arrays.items()}
        if chunk.index not in unreadable and found == record_text(spec, chunk, block, current):
            finished.add(chunk.index)
            continue
        rule = _rule_of(found)
        if spec.refines_spatial and rule != current and chunk.index not in unreadable and \
                found == record_text(spec, chunk, block, rule):
            outdated.add(chunk.index)
        else:
            damaged.add(chunk.index)
    return Census(frozenset(finished), frozenset(damaged), frozenset(outdated))
