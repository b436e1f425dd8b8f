"""Argument validators with one message format (a leaf module).

Each validator returns the cleaned value or raises :class:`~spectralshell.errors.ParameterError`
with the message ``"<name> = <value> is invalid: must be <allowed range>"``.

Validators are strict about types: a number must be a number, so a scene's ``num = "6"`` is
refused where an integer is expected. Command-line text is read by :func:`parse_real` and
:func:`parse_int` first, and the parameter's validator then checks the number.

Every real input has magnitude 0 or within [``REAL_MIN``, ``REAL_MAX``] = [1e-100, 1e100]: any
product or quotient of three such numbers (a parameter squared times another, kappa / nu^2, a
Fourier index squared times a parameter) is then a normal double, |x| in [1e-300, 1e300], so the
numerics of a valid input neither overflow nor underflow to 0.
"""

from __future__ import annotations

import numbers
import os
import stat
import uuid
from collections.abc import Iterable, Sequence
from pathlib import Path

from .errors import ParameterError

#: Longest repr of a value shown in a message.
SHOWN = 80
#: Largest magnitude of a real input (see the module docstring).
REAL_MAX = 1e100
#: Smallest non-zero magnitude of a real input (see the module docstring).
REAL_MIN = 1e-100


def invalid(name: str, value: object, allowed: str) -> ParameterError:
    """The error for ``name`` = ``value`` outside ``allowed``, on one line: a value whose repr is
    longer than SHOWN characters is cut there; a numpy scalar is shown as the Python number it
    holds (0.5, not np.float64(0.5))."""
    if isinstance(value, numbers.Number) and hasattr(value, "item"):
        value = value.item()
    shown = repr(value).replace("\n", " ")
    if len(shown) > SHOWN:
        shown = f"{shown[:SHOWN]}... ({len(shown)} characters)"
    return ParameterError(f"{name} = {shown} is invalid: must be {allowed}")


def _real(name: str, value: object, allowed: str) -> float:
    """``value`` as a float of magnitude 0 or in [REAL_MIN, REAL_MAX] (no str, no bool)."""
    if isinstance(value, float):  # float and its subclasses (numpy's float64): no ABC lookup
        v = float(value)
    elif isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise invalid(name, value, allowed)
    else:
        try:
            v = float(value)
        except OverflowError:  # an int or a Fraction beyond the float range
            raise invalid(name, value, allowed) from None
    if not (v == 0.0 or REAL_MIN <= abs(v) <= REAL_MAX):  # also refuses nan and inf
        raise invalid(name, value, allowed)
    return v + 0.0  # -0.0 becomes 0.0


#: The allowed ranges of :func:`require_real`, :func:`require_nonnegative` and
#: :func:`require_positive` as their messages state them (formatted once: a sweep validates
#: the parameters of every point).
REAL_ALLOWED = f"a finite real number, 0 or of magnitude in [{REAL_MIN:g}, {REAL_MAX:g}]"
NONNEGATIVE_ALLOWED = f"a finite real number >= 0: 0 or in [{REAL_MIN:g}, {REAL_MAX:g}]"
POSITIVE_ALLOWED = f"a finite real number > 0, in [{REAL_MIN:g}, {REAL_MAX:g}]"


def require_real(name: str, value: object) -> float:
    """Return ``value`` as a float of magnitude 0 or in [REAL_MIN, REAL_MAX]."""
    return _real(name, value, REAL_ALLOWED)


def require_nonnegative(name: str, value: object) -> float:
    """Return ``value`` as a float, 0 or in [REAL_MIN, REAL_MAX]."""
    v = _real(name, value, NONNEGATIVE_ALLOWED)
    if v < 0:
        raise invalid(name, value, NONNEGATIVE_ALLOWED)
    return v


def require_positive(name: str, value: object) -> float:
    """Return ``value`` as a float in [REAL_MIN, REAL_MAX]."""
    v = _real(name, value, POSITIVE_ALLOWED)
    if v <= 0:
        raise invalid(name, value, POSITIVE_ALLOWED)
    return v


def require_int_in_range(name: str, value: object, lo: int, hi: int | None = None) -> int:
    """Return ``value`` (an integer, or an integral float; no str, no bool) as an int with
    ``lo <= value <= hi`` (``hi=None``: no upper bound)."""
    if isinstance(value, bool):
        v = None
    elif type(value) is int or isinstance(value, numbers.Integral):
        v = int(value)
    elif isinstance(value, numbers.Real) and float(value).is_integer():
        v = int(value)
    else:
        v = None
    if v is None or v < lo or (hi is not None and v > hi):
        raise invalid(name, value, f"an integer >= {lo}" if hi is None else
                      f"an integer in [{lo}, {hi}]")
    return v


def parse_real(name: str, text: str) -> float:
    """The number written in ``text`` (command-line input); the parameter's validator checks
    its range."""
    try:
        return float(text)
    except ValueError:
        raise invalid(name, text, "a finite real number") from None


def parse_int(name: str, text: str) -> int | float:
    """The integer written in ``text`` (command-line input; '3.0' and '1e3' are read as numbers
    and checked by the parameter's validator)."""
    for convert in (int, float):
        try:
            return convert(text)
        except ValueError:
            pass
    raise invalid(name, text, "an integer")


def require_choice(name: str, value: object, choices: Iterable[str]) -> str:
    """Return ``value`` as a plain str if it is one of ``choices`` (a str subclass such as
    numpy's str_ comes back as str, so that messages and results print it plainly)."""
    choices = tuple(choices)
    if not isinstance(value, str) or value not in choices:
        raise invalid(name, value, "one of " + ", ".join(repr(c) for c in choices))
    return str(value)


def require_choices(name: str, value: object, choices: Iterable[str]) -> tuple[str, ...]:
    """Return ``value``, a non-empty list of ``choices``, as a tuple without repeats (a single
    str is refused: a list is expected)."""
    choices = tuple(choices)
    if not isinstance(value, (list, tuple)) or not value:
        raise invalid(name, value, "a non-empty list of " + ", ".join(repr(c) for c in choices))
    return tuple(dict.fromkeys(require_choice(name, v, choices) for v in value))


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


_NOT_REGULAR = ((stat.S_ISDIR, "a directory"), (stat.S_ISCHR, "a device"),
                (stat.S_ISBLK, "a device"),
                (stat.S_ISFIFO, "a FIFO"), (stat.S_ISSOCK, "a socket"))


def require_output_file(name: str, value: object, suffixes: Sequence[str]) -> Path:
    """Return the output file ``name`` = ``value`` as a Path if it can be written: an existing
    regular file (it will be replaced) or a new one, named with one of ``suffixes`` (e.g.
    ('.png',)), in a directory that exists and accepts new files."""
    if not isinstance(value, (str, os.PathLike)) or not str(value):
        raise invalid(name, value, "a file name")
    path = Path(value)
    try:
        mode = path.stat().st_mode
    except FileNotFoundError:
        mode = None
    except OSError as exc:
        raise ParameterError(f"{name} = {str(value)!r} is not writable: {exc.strerror}") from None
    for test, kind in _NOT_REGULAR:
        if mode is not None and test(mode):
            raise ParameterError(f"{name} = {str(value)!r} is invalid: it is {kind}; must be a "
                                 "regular file (new, or an existing one to replace)")
    if path.suffix.lower() not in suffixes:
        raise invalid(name, str(value), "a file name ending in " + " or ".join(suffixes))
    require_writable_directory(name, value, path.resolve().parent)
    return path
