"""Floquet characteristic exponents gamma at a given forcing amplitude tau (Hill's method).

For a model with polynomial D(s) = sum_j s^j D_j (invertible leading D_p), write (1) of
:mod:`spectralshell.models.base` as a first-order system y' = (C_0 + 2 sin(t) C_1) y with
y = (u, u', ..., u^{(p-1)}) (companion form). Inserting y = exp(gamma t) sum_k y_k exp(i k t)
(thesis (2.4)-(2.5)) gives the standard eigenproblem, for k = -N..N,

    gamma y_k = (C_0 - i k I) y_k - i tau C_1 (y_{k-1} - y_{k+1}).

Its eigenvalues are gamma + i l for every integer l; the representative of each exponent is the
eigenvalue whose eigenvector is centred at k = 0 (smallest |Fourier centroid|), which is also the
best-resolved copy; a candidate that differs from one already chosen by a non-zero multiple of i
is skipped (two copies of one exponent can tie in centroid when Im gamma = 1/2). Exponents are returned with Im gamma folded into (-1/2, 1/2] and sorted by
decreasing Re gamma (the growth rate per unit time); multipliers are exp(2 pi gamma).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.linalg as sla

from ..errors import ConvergenceError
from ..models.base import HillSystem
from ..results.records import Exponents
from .marginal import coarser

N_MAX = 200
SIZE_MAX = 6000  # largest dense companion-form eigenproblem attempted
EPS = np.finfo(float).eps
#: The rounding floor of the exponents is ROUNDING eps max |eigenvalue| (:func:`_exponents_at`).
ROUNDING = 8.0


def companion(system: HillSystem) -> tuple[np.ndarray, np.ndarray]:
    """C_0 and C_1 of the first-order form y' = (C_0 + 2 sin(t) C_1) y of a polynomial model."""
    if system.polynomial is None:
        raise NotImplementedError(
            f"Floquet exponents need a polynomial D(s); model {system.name!r} does not provide one")
    coeffs = [np.asarray(c, dtype=float) for c in system.polynomial]
    p, b = len(coeffs) - 1, system.block_size
    lead = np.linalg.inv(coeffs[-1])
    C0 = np.zeros((p * b, p * b))
    C0[: (p - 1) * b, b:] = np.eye((p - 1) * b)
    for j in range(p):
        C0[(p - 1) * b:, j * b:(j + 1) * b] = -lead @ coeffs[j]
    C1 = np.zeros_like(C0)
    C1[(p - 1) * b:, :b] = -lead @ np.asarray(system.forcing, dtype=float)
    return C0, C1


def fold(gamma: np.ndarray) -> np.ndarray:
    """Im gamma into (-1/2, 1/2]; within 1e-12 of -1/2 counts as +1/2 (a subharmonic exponent)."""
    imag = gamma.imag - np.ceil(gamma.imag - 0.5)
    imag = np.where(np.abs(imag + 0.5) <= 1e-12, 0.5, imag)
    return gamma.real + 1j * imag


def _exponents_at(system: HillSystem, tau: float, n: int) -> tuple[np.ndarray, float]:
    """(exponents of the truncation N = ``n``, their rounding floor ROUNDING eps max |eigenvalue|:
    LAPACK's eig has backward error ~ eps ||H||, so no exponent is known better than that in
    absolute terms however the truncation converges; under strong damping nu the eigenvalues
    span |gamma| ~ kappa / nu .. nu and the small ones drown in it)."""
    C0, C1 = companion(system)
    d = C0.shape[0]
    if d * (2 * n + 1) > SIZE_MAX:  # dense eig with vectors: memory ~ size^2, time ~ size^3
        raise ConvergenceError(f"Floquet exponents at n_temporal={n} need a dense eigenproblem of size "
                               f"{d * (2 * n + 1)} (limit {SIZE_MAX}): lower n_temporal, kappa or |tau|, "
                               "or use fewer spatial modes")
    k = np.arange(-n, n + 1)
    H = np.kron(np.eye(len(k)), C0) - 1j * np.kron(np.diag(k), np.eye(d))
    S = np.diag(np.ones(len(k) - 1), -1) - np.diag(np.ones(len(k) - 1), 1)
    H = H - 1j * tau * np.kron(S, C1)
    values, vectors = sla.eig(H)
    weights = np.abs(vectors.reshape(len(k), d, -1)) ** 2
    weights = weights.sum(axis=1)
    centroid = (k[:, None] * weights).sum(axis=0) / weights.sum(axis=0)
    chosen: list[complex] = []
    for i in np.argsort(np.abs(centroid), kind="stable"):
        g = values[i]
        shift = [c.imag - g.imag for c in chosen if abs(c.real - g.real) <= 1e-8 * max(1, abs(g))]
        if any(abs(x - round(x)) <= 1e-8 and round(x) != 0 for x in shift):
            continue  # a copy gamma + i l of an exponent already chosen
        chosen.append(g)
        if len(chosen) == d:
            break
    gamma = fold(np.array(chosen))
    floor = ROUNDING * EPS * float(np.max(np.abs(values)))
    return gamma[np.lexsort((gamma.imag, -gamma.real))], floor


def first_truncation(system: HillSystem, tau: float) -> int:
    """The first truncation N tried: the resonant index, widened by the forcing's reach
    2 |tau| sqrt(max |G|), plus 8."""
    return int(np.ceil(system.n_resonant + 2 * abs(tau) * np.sqrt(abs(system.forcing).max()))) + 8


def _unresolvable(tol: float, floor: float) -> ConvergenceError:
    return ConvergenceError(
        f"Floquet exponents cannot be resolved to tol={tol:g} here: rounding limits them to "
        f"+-{floor:.2g} (the Hill eigenproblem's eigenvalues reach |gamma| = "
        f"{floor / (ROUNDING * EPS):.3g}, e.g. under strong damping nu); relax tol= to at least "
        f"{floor:.2g}")


def distance(a: np.ndarray, b: np.ndarray) -> float:
    """Largest distance from a point of ``a`` to the nearest of ``b``, modulo i (0 for an empty
    ``a``, inf for an empty ``b``)."""
    if not a.size or not b.size:
        return 0.0 if not a.size else math.inf
    diff = a[:, None] - b[None, :]
    diff = diff.real + 1j * (diff.imag - np.round(diff.imag))
    return float(np.max(np.min(np.abs(diff), axis=1)))


def floquet_exponents(system: HillSystem, tau: float, *, tol: float = 1e-10,
                      n_temporal: int | None = None) -> Exponents:
    """Characteristic exponents gamma of the model at forcing amplitude ``tau``.

    Notes
    -----
    Hill's method on the companion form (module docstring); thesis (2.3)-(2.5) for the Mathieu
    equation. With ``n_temporal=None`` the truncation grows until the exponents change by less
    than ``tol``.

    Raises
    ------
    ConvergenceError : not converged by N = 200.
    NotImplementedError : the model's D(s) is not a matrix polynomial.
    """
    start = first_truncation(system, tau)
    if n_temporal is not None:
        n_prev = coarser(n_temporal)
        gamma, floor = _exponents_at(system, tau, n_temporal)
        change = distance(gamma, _exponents_at(system, tau, n_prev)[0])
        return Exponents(gamma=gamma, n_temporal=n_temporal, error_estimate=max(change, floor))
    if start >= N_MAX:  # the resonant Fourier index alone exceeds the limit: nothing to converge
        raise ConvergenceError(f"Floquet exponents need a truncation above n_temporal={N_MAX} here "
                               f"(resonant Fourier index ~{start - 8}): lower kappa or |tau|")
    n = start
    previous, floor = _exponents_at(system, tau, n)
    if floor >= tol:
        raise _unresolvable(tol, floor)
    while n < N_MAX:
        n = min(n + max(6, n // 2), N_MAX)
        gamma, floor = _exponents_at(system, tau, n)
        change = distance(gamma, previous)
        if change < tol and floor < tol:
            return Exponents(gamma=gamma, n_temporal=n, error_estimate=max(change, floor))
        if floor >= tol:
            raise _unresolvable(tol, floor)
        previous = gamma
    raise ConvergenceError(f"Floquet exponents did not converge to tol={tol:g} by n_temporal={N_MAX} "
                           f"(last change {change:.3g}); relax tol=")
