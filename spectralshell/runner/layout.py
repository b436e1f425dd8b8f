"""Chunk layout of a sweep: which grid points each task solves, and where they go in the result.

A chunk is a run of at most ``spec.chunk`` consecutive points along the line axis (the last real
axis), at one value of every other axis, for all kinds. Lines longer than ``spec.chunk`` are cut
into equal pieces, so the chunks tile the grid regularly and each one is exactly one chunk of the
Zarr store. The layout depends only on the scene (never on the executor or the number of
workers): continuation restarts at a chunk's first point, so every executor gives the same numbers.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

from ..params.sweep_grid import SweepSpec


@dataclass(frozen=True)
class Chunk:
    """One task: grid index ``origin`` of its first point (0 on the kind axis) and the number
    ``length`` of points along the line axis."""

    index: int
    origin: tuple[int, ...]
    length: int


def line_length(spec: SweepSpec) -> int:
    """Points per chunk along the line axis: lines are cut into equal pieces <= spec.chunk."""
    axis = spec.line_axis
    if axis is None:
        return 1
    n = spec.shape[axis]
    return math.ceil(n / math.ceil(n / spec.chunk))


def store_chunks(spec: SweepSpec) -> tuple[int, ...]:
    """Chunk shape of the store's variables: 1 on the point axes, the chunk length on the line
    axis, every kind."""
    length = line_length(spec)
    return tuple(len(a.values) if a.name == "kind" else length if i == spec.line_axis else 1
                 for i, a in enumerate(spec.axes))


def chunks(spec: SweepSpec) -> list[Chunk]:
    """All chunks of the grid, in C order of the point axes (line pieces innermost)."""
    step = store_chunks(spec)
    ranges = [range(0, n, s) if i in spec.point_axes else range(1)
              for i, (n, s) in enumerate(zip(spec.shape, step))]
    line = spec.line_axis
    out = []
    for k, origin in enumerate(itertools.product(*ranges)):
        length = 1 if line is None else min(step[line], spec.shape[line] - origin[line])
        out.append(Chunk(index=k, origin=tuple(origin), length=length))
    return out


def region(spec: SweepSpec, chunk: Chunk) -> tuple[slice, ...]:
    """Index of the chunk's block in the full result arrays."""
    out = []
    for i, a in enumerate(spec.axes):
        if a.name == "kind":
            out.append(slice(None))
        elif i == spec.line_axis:
            out.append(slice(chunk.origin[i], chunk.origin[i] + chunk.length))
        else:
            out.append(slice(chunk.origin[i], chunk.origin[i] + 1))
    return tuple(out)


def block_shape(spec: SweepSpec, chunk: Chunk) -> tuple[int, ...]:
    """Shape of the chunk's block (1 on point axes, its length on the line axis, all kinds)."""
    return tuple(len(a.values) if a.name == "kind" else chunk.length if i == spec.line_axis else 1
                 for i, a in enumerate(spec.axes))


def chunk_points(spec: SweepSpec, chunk: Chunk) -> Iterator[tuple[int, dict[str, Any]]]:
    """(position j along the line, non-kind axis values) of each point of the chunk, in order."""
    for j in range(chunk.length):
        values = {}
        for i in spec.point_axes:
            offset = j if i == spec.line_axis else 0
            values[spec.axes[i].name] = spec.axes[i].values[chunk.origin[i] + offset]
        yield j, values


def block_index(spec: SweepSpec, j: int, kind_position: int) -> tuple[int, ...]:
    """Index in the chunk's block of point j along the line and kind number ``kind_position``."""
    at = [0] * len(spec.axes)
    if spec.line_axis is not None:
        at[spec.line_axis] = j
    at[spec.dims.index("kind")] = kind_position
    return tuple(at)


def chunk_key(spec: SweepSpec, chunk: Chunk) -> str:
    """Name of the chunk's Zarr chunk files ('0.3.0': block numbers along each axis)."""
    return ".".join(str(o // s) for o, s in zip(chunk.origin, store_chunks(spec)))
