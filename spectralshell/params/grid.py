"""Parameter ranges: 'start:stop:num' strings or {start, stop, num} tables -> 1-D grids."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from .._validate import parse_int, parse_real, require_int_in_range, require_real
from ..errors import ParameterError
from .limits import check_points


def parse_range(name: str, spec: object, max_points: int | None = None) -> np.ndarray:
    """Evenly spaced grid from ``"start:stop:num"``, ``{start, stop, num}`` or a single number.

    Raises
    ------
    ParameterError : malformed, empty (num < 1) or reversed (stop < start) range, or num above
        the points limit (``max_points``, :data:`spectralshell.params.limits.POINTS`), refused
        before any array is made.
    """
    if isinstance(spec, str):
        parts = spec.split(":")
        if len(parts) == 1:
            return np.array([require_real(name, parse_real(name, spec))])
        if len(parts) != 3:
            raise ParameterError(f"{name} = {spec!r} is invalid: must be START:STOP:NUM, e.g. 0:3:301")
        start, stop = (parse_real(name, p) for p in parts[:2])
        num = parse_int(f"{name} num", parts[2])
    elif isinstance(spec, Mapping):
        unknown = set(spec) - {"start", "stop", "num"}
        if unknown or not {"start", "stop", "num"} <= set(spec):
            raise ParameterError(f"{name} = {dict(spec)!r} is invalid: must be a table with keys "
                                 "start, stop, num")
        start, stop, num = spec["start"], spec["stop"], spec["num"]
    else:
        return np.array([require_real(name, spec)])
    start, stop = require_real(f"{name} start", start), require_real(f"{name} stop", stop)
    num = require_int_in_range(f"{name} num", num, 1)
    check_points(f"{name} = {spec!r}", num, max_points)
    if stop < start:
        raise ParameterError(f"{name} = {spec!r} is invalid: stop must be >= start (empty range)")
    if num > 1 and stop == start:
        raise ParameterError(f"{name} = {spec!r} is invalid: a range of {num} points needs stop > start")
    return np.linspace(start, stop, num)


def parse_int_range(name: str, spec: object, bounds: tuple[int, int | None] = (0, None),
                    max_points: int | None = None) -> list[int]:
    """Integers from ``"lo:hi"`` (inclusive), a single integer, or a list of integers, each in
    ``bounds`` = (lowest, highest or None) (e.g. a model's degrees m, from
    :func:`spectralshell.params.registry.int_bounds`).

    Raises
    ------
    ParameterError : malformed, non-integer or reversed range, a value outside ``bounds``, or
        more values than the points limit (``max_points``); a range "lo:hi" is checked on its
        ends, before its values are made.
    """
    if isinstance(spec, str) and ":" in spec:
        parts = spec.split(":")
        if len(parts) != 2:
            raise ParameterError(f"{name} = {spec!r} is invalid: must be LO:HI, e.g. 2:6")
        lo, hi = (require_int_in_range(name, parse_int(name, p), *bounds) for p in parts)
        if hi < lo:
            raise ParameterError(f"{name} = {spec!r} is invalid: HI must be >= LO (empty range)")
        check_points(f"{name} = {spec!r}", hi - lo + 1, max_points)
        return list(range(lo, hi + 1))
    if isinstance(spec, (list, tuple)):
        if not spec:
            raise ParameterError(f"{name} = [] is invalid: must be a non-empty list of integers")
        check_points(f"{name} (a list)", len(spec), max_points)
        return [require_int_in_range(name, v, *bounds) for v in spec]
    if isinstance(spec, str):
        spec = parse_int(name, spec)
    return [require_int_in_range(name, spec, *bounds)]
