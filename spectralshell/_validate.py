"""Argument validators with one message format (a leaf module).

Each validator returns the cleaned value or raises :class:`~spectralshell.errors.ParameterError`
with the message ``"<name> = <value> is invalid: must be <allowed range>"``.
"""

from __future__ import annotations

import math
import numbers
import os
import uuid
from collections.abc import Iterable
from pathlib import Path

from .errors import ParameterError

SHOWN = 80


def invalid(name: str, value: object, allowed: str) -> ParameterError:
    """The error for ``name`` = ``value`` outside ``allowed``, on one line: a value whose repr is
    longer than SHOWN characters is cut there."""
    shown = repr(value).replace("\n", " ")
    if len(shown) > SHOWN:
        shown = f"{shown[:SHOWN]}... ({len(shown)} characters)"
    return ParameterError(f"{name} = {shown} is invalid: must be {allowed}")


def require_real(name: str, value: object) -> float:
    """Return ``value`` as a finite float."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        if isinstance(value, str):
            try:
                value = float(value)
            except ValueError:
                raise invalid(name, value, "a finite real number") from None
        else:
            raise invalid(name, value, "a finite real number")
    value = float(value)
    if not math.isfinite(value):
        raise invalid(name, value, "a finite real number")
    return value


def require_nonnegative(name: str, value: object) -> float:
    """Return ``value`` as a finite float >= 0."""
    v = require_real(name, value)
    if v < 0:
        raise invalid(name, value, "a finite real number >= 0")
    return v


def require_positive(name: str, value: object) -> float:
    """Return ``value`` as a finite float > 0."""
    v = require_real(name, value)
    if v <= 0:
        raise invalid(name, value, "a finite real number > 0")
    return v


def require_int_in_range(name: str, value: object, lo: int, hi: int | None = None) -> int:
    """Return ``value`` as an int with ``lo <= value <= hi`` (``hi=None``: no upper bound)."""
    if isinstance(value, bool):
        raise invalid(name, value, _int_range(lo, hi))
    if isinstance(value, numbers.Integral):
        v = int(value)
    elif isinstance(value, numbers.Real) and float(value).is_integer():
        v = int(value)
    elif isinstance(value, str) and value.strip().lstrip("+-").isdigit():
        v = int(value)
    else:
        raise invalid(name, value, _int_range(lo, hi))
    if v < lo or (hi is not None and v > hi):
        raise invalid(name, value, _int_range(lo, hi))
    return v


def _int_range(lo: int, hi: int | None) -> str:
    return f"an integer >= {lo}" if hi is None else f"an integer in [{lo}, {hi}]"


def require_choice(name: str, value: object, choices: Iterable[str]) -> str:
    """Return ``value`` as a plain str if it is one of ``choices`` (a str subclass such as
    numpy's str_ comes back as str, so that messages and results print it plainly)."""
    choices = tuple(choices)
    if not isinstance(value, str) or value not in choices:
        raise invalid(name, value, "one of " + ", ".join(repr(c) for c in choices))
    return str(value)


def require_writable_directory(name: str, value: object, directory: Path) -> None:
    """Check that new files can be made in ``directory`` (where output ``name`` = ``value``
    goes), by making and removing a probe file: os.access alone says yes where files cannot be
    made (e.g. /proc, or any directory as root)."""
    if not directory.is_dir() or not os.access(directory, os.W_OK):
        raise ParameterError(f"{name} = {str(value)!r} is not writable: directory "
                             f"{str(directory)!r} does not exist or is read-only")
    probe = directory / f".probe-{uuid.uuid4().hex[:8]}"
    try:
        probe.touch(exist_ok=False)
        probe.unlink()
    except OSError as exc:
        raise ParameterError(f"{name} = {str(value)!r} is not writable: directory "
                             f"{str(directory)!r} refuses new files ({exc.strerror})") from None
