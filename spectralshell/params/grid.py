"""Parameter ranges: 'start:stop:num' strings or {start, stop, num} tables -> 1-D grids."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from .._validate import require_int_in_range, require_real
from ..errors import ParameterError


def parse_range(name: str, spec: object) -> np.ndarray:
    """Evenly spaced grid from ``"start:stop:num"``, ``{start, stop, num}`` or a single number.

    Raises
    ------
    ParameterError : malformed, empty (num < 1) or reversed (stop < start) range.
    """
    if isinstance(spec, str):
        parts = spec.split(":")
        if len(parts) == 1:
            return np.array([require_real(name, parts[0])])
        if len(parts) != 3:
            raise ParameterError(f"{name} = {spec!r} is invalid: must be START:STOP:NUM, e.g. 0:3:301")
        start, stop, num = parts
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
    if stop < start:
        raise ParameterError(f"{name} = {spec!r} is invalid: stop must be >= start (empty range)")
    if num > 1 and stop == start:
        raise ParameterError(f"{name} = {spec!r} is invalid: a range of {num} points needs stop > start")
    return np.linspace(start, stop, num)
