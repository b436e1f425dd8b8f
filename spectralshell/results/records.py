"""Record types: the plain values that solvers return and results hold, and their JSON form.

A leaf module: it imports numpy and the standard library only, so that every stage may import it
(the solvers construct these records, :mod:`spectralshell.results` stores them) and it imports
no stage. Each record is a frozen dataclass whose fields are JSON values, numpy arrays, complex
numbers, tuples or other dataclasses; :func:`encode` and :func:`decode` give such values a JSON
form that comes back unchanged (arrays keep dtype and shape), which :meth:`Record.to_dict` and
:meth:`spectralshell.results.base.Result.save` use.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

#: The key that marks a tagged JSON object: {TYPE: "ndarray" | "complex" | "tuple" | "float" |
#: the name of a dataclass, ...}.
TYPE = "__type__"


def encode(value: Any) -> Any:
    """``value`` as JSON data (strict: no NaN or Infinity literals). Lists, str-keyed dicts,
    str, bool, int, None and finite floats stay as they are; numpy scalars become Python ones;
    arrays, complex numbers, tuples, non-finite floats and dataclasses become objects tagged with
    their type (:data:`TYPE`), a dataclass with its name and every field."""
    if isinstance(value, np.generic):
        value = value.item()
    if value is None or isinstance(value, (bool, int, str)):
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else {TYPE: "float", "value": repr(value)}
    if isinstance(value, complex):
        return {TYPE: "complex", "re": encode(value.real), "im": encode(value.imag)}
    if isinstance(value, np.ndarray):
        flat = value.ravel()
        data = ({"re": encode(flat.real.tolist()), "im": encode(flat.imag.tolist())}
                if value.dtype.kind == "c" else {"data": encode(flat.tolist())})
        return {TYPE: "ndarray", "dtype": value.dtype.str, "shape": list(value.shape), **data}
    if isinstance(value, (list, tuple)):
        items = [encode(v) for v in value]
        return items if isinstance(value, list) else {TYPE: "tuple", "items": items}
    if isinstance(value, dict):
        if TYPE in value or not all(isinstance(k, str) for k in value):
            raise TypeError(f"a dict with keys {list(value)!r} has no JSON form here: keys must "
                            f"be strings other than {TYPE!r}")
        return {k: encode(v) for k, v in value.items()}
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {TYPE: type(value).__name__, **fields_of(value)}
    raise TypeError(f"a {type(value).__name__} has no JSON form here")


def decode(data: Any, types: Mapping[str, type]) -> Any:
    """The value that :func:`encode` turned into ``data``; ``types`` maps the name of each
    dataclass that may occur to the class. Raises KeyError, TypeError or ValueError on data that
    :func:`encode` cannot have written."""
    if isinstance(data, list):
        return [decode(v, types) for v in data]
    if not isinstance(data, dict):
        return data
    tag = data.get(TYPE)
    if tag is None:
        return {k: decode(v, types) for k, v in data.items()}
    if tag == "float":
        return float(data["value"])
    if tag == "complex":
        return complex(decode(data["re"], types), decode(data["im"], types))
    if tag == "tuple":
        return tuple(decode(v, types) for v in data["items"])
    if tag == "ndarray":
        dtype, shape = np.dtype(data["dtype"]), tuple(data["shape"])
        if dtype.kind != "c":
            return np.array(decode(data["data"], types), dtype=dtype).reshape(shape)
        out = np.empty(math.prod(shape), dtype=dtype)
        out.real, out.imag = decode(data["re"], types), decode(data["im"], types)
        return out.reshape(shape)
    if tag not in types:
        raise ValueError(f"unknown type {tag!r}: expected one of {', '.join(types)}")
    return build(types[tag], {k: v for k, v in data.items() if k != TYPE}, types)


def fields_of(obj: Any) -> dict[str, Any]:
    """Every field of the dataclass instance ``obj``, encoded (:func:`encode`)."""
    return {f.name: encode(getattr(obj, f.name)) for f in dataclasses.fields(obj)}


def build(cls: type, data: Mapping[str, Any], types: Mapping[str, type]) -> Any:
    """The dataclass ``cls`` from the fields :func:`fields_of` wrote (decoded with ``types``)."""
    return cls(**{k: decode(v, types) for k, v in data.items()})


class Record:
    """Mixin of the record types: their JSON form, field by field, and back."""

    def to_dict(self) -> dict[str, Any]:
        """Every field as JSON data (:func:`encode`); :meth:`from_dict` inverts it."""
        return fields_of(self)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]):
        """The record whose :meth:`to_dict` is ``data``."""
        return build(cls, data, RECORDS)


@dataclass(frozen=True, kw_only=True, eq=False)
class MarginalTau(Record):
    """Marginal amplitudes of one Floquet kind.

    Attributes
    ----------
    kind : 'harmonic' or 'subharmonic'.
    tau : ascending real tau >= 0 at the final truncation that reappear at the previous one to
        within max(tol, error_estimate) * max(1, tau).
    tau_min : smallest such tau (None if there is none).
    n_temporal : final truncation N.
    n_previous : the truncation it was compared with.
    error_estimate : max(``|tau_min(N) - tau_min(previous N)|``, spread of a reported tau = 0,
        8 eps max(1, tau_min)) (None if there is no tau_min).
    method : 'structured', 'krylov', 'shift-invert' or 'qz' (the fallback), at the final
        truncation.
    complete_to : ``tau`` is complete up to this value: every real tau <= complete_to (and
        <= tau_max) of both truncations was computed, and beyond it none was looked for; inf
        when both were solved completely (dense), else the smaller Krylov radius.
    empty_proved : no tau <= tau_max at either truncation, and that proved by the argument
        principle's zero count (or the disk bound that implies it) at both: by the solve's
        own path or by ``certify_empty`` (:func:`~spectralshell.solvers.marginal.marginal_tau`);
        False otherwise (an empty answer may still be proved by other means, see complete_to).
    count_failed : the solve walked the zero count of one of the pair's truncations at
        tau_max and it could not prove that truncation empty: a later proof of the empty answer
        at the same tau_max (:func:`~spectralshell.solvers.marginal.certify_empty_answer`)
        fails the same way, and is not walked again.
    """

    kind: str
    tau: np.ndarray
    tau_min: float | None
    n_temporal: int
    n_previous: int
    error_estimate: float | None
    method: str
    complete_to: float = np.inf
    empty_proved: bool = False
    count_failed: bool = False

    def unproved_empty(self, cap: float) -> bool:
        """No tau found, and their absence not proved up to ``cap`` (complete_to below it: the
        zero count could not prove the empty answer; issue 23): never to be read as "none"."""
        return self.tau_min is None and self.complete_to < cap


@dataclass(frozen=True, kw_only=True, eq=False)
class Tip(Record):
    """Minimum (kappa, tau) of one finger of an Ince-Strutt diagram.

    kappa_error : width of the final bracket of the root of d tau / d kappa.
    tau_error : the Floquet error estimate of tau at the tip.
    """

    kind: str
    kappa: float
    tau: float
    kappa_error: float
    tau_error: float


@dataclass(frozen=True, kw_only=True, eq=False)
class Boundary(Record):
    """One traced boundary curve of an Ince-Strutt diagram: vertices (kappa[i], tau[i]) in
    order along the curve, each a marginal tau of ``kind`` from the point solver (or a finger
    tip), so that the unstable region of the kind lies on one side (see
    :func:`spectralshell.solvers.tongues.link_boundaries`)."""

    kind: str
    kappa: np.ndarray
    tau: np.ndarray


@dataclass(frozen=True, kw_only=True, eq=False)
class Exponents(Record):
    """Floquet exponents of one model at one tau.

    Attributes
    ----------
    gamma : complex exponents, Im in (-1/2, 1/2], sorted by decreasing Re.
    n_temporal : truncation N (Fourier indices -N..N).
    error_estimate : max |change| of the exponents between N and the previous truncation.
    complete_in : (lo, hi): every exponent with lo < Re gamma <= hi is listed, proved by a count
        (models with a non-polynomial D(s); the fluid's continuous spectrum on the negative
        real axis excluded); None where every exponent of the truncation is listed (Hill's
        companion form).
    """

    gamma: np.ndarray
    n_temporal: int
    error_estimate: float
    complete_in: tuple[float, float] | None = None


@dataclass(frozen=True, kw_only=True, eq=False)
class ModeRoots(Record):
    """Natural modes of one system, least damped first.

    Attributes
    ----------
    x : roots in the system's variable (complex; for the sphere beta).
    gamma : gamma = to_gamma(x), Im gamma >= 0, sorted by decreasing Re gamma.
    error_estimate : absolute error bound of each gamma.
    principal_sheet : margin > error (a resolved, genuine mode).
    on_cut : |margin| <= error (sheet not resolved at this precision).
    precision : digits of the mpmath polish, or None (double precision).
    gamma_digits : with precision, (Re, Im) of each gamma as decimal strings of that many digits.
    double_error : with precision, |gamma_double - gamma_polished| of each mode.
    evaluations : residual evaluations in double precision (all seeds tried).
    seeds_tried : number of seeds drawn.
    uncounted : None, or (count-driven search) True for each mode met between the counting
        region and the branch cut, outside the argument-principle count (the others are exactly
        the counted roots, one of each conjugate pair).
    """

    x: np.ndarray
    gamma: np.ndarray
    error_estimate: np.ndarray
    principal_sheet: np.ndarray
    on_cut: np.ndarray
    precision: int | None
    gamma_digits: tuple[tuple[str, str], ...] | None
    double_error: np.ndarray | None
    evaluations: int
    seeds_tried: int
    uncounted: np.ndarray | None = None


@dataclass(frozen=True, kw_only=True)
class RateFit(Record):
    """Dominant growth rate (Re gamma) and angular frequency of a signal, with error estimate.

    multiplier : exp(gamma h) (unforced, h the sample spacing) or the Floquet multiplier
    exp(gamma T) (forced). window : the fitted time interval. rank : exponentials fitted.
    """

    growth_rate: float
    frequency: float
    multiplier: complex
    error_estimate: float
    window: tuple[float, float]
    rank: int


@dataclass(frozen=True, eq=False)
class ContinuedModes(Record):
    """Natural modes of a mode family, least damped first (Im gamma >= 0).

    gamma, error : the modes gamma = unit * gamma_scale * s and their error estimates.
    on_cut : the mode lies on the branch cut within its error.
    digits : with ``precision``, (Re, Im) of each gamma as decimal strings, else None.
    double_error : with ``precision``, |double - polished| of each gamma, else None.
    warnings : lost branches, merged branches, a failed completeness count, modes on the cut.
    """

    gamma: np.ndarray
    error: np.ndarray
    on_cut: np.ndarray
    digits: tuple[tuple[str, str], ...] | None
    double_error: np.ndarray | None
    warnings: tuple[str, ...]



#: Every record type by name (what :func:`decode` accepts for them).
RECORDS: dict[str, type] = {cls.__name__: cls for cls in (MarginalTau, Tip, Boundary, Exponents,
                                                          ModeRoots, RateFit, ContinuedModes)}
