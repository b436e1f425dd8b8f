"""Eigenvalues of a nonlinear matrix function: det T(s) = 0 (natural modes of block models).

Model-agnostic: the solver sees callables T(s) -> (b, b) and T'(s) -> (b, b), analytic in a
region, and starting points; never the physics. It serves models whose unforced operator D(s) of
:mod:`spectralshell.models.base` is a matrix with non-polynomial (e.g. square-root) dependence on
s, where neither a linearisation nor a scalar dispersion relation is available.

Method
------
Newton's method on f(s) = det T(s) in the trace form f/f' = 1/tr(T(s)^{-1} T'(s)) (Lancaster),
which needs no determinant (no overflow for large b) and converges quadratically to simple
eigenvalues. Roots already found are deflated implicitly: the step uses
tr(T^{-1} T') - sum_j 1/(s - s_j), the logarithmic derivative of f(s) / prod(s - s_j), so a
seed near a found root is driven to a new one or fails. A converged s is accepted only if T(s) is
singular to working accuracy: its smallest singular value is below ``SINGULAR_RTOL`` times its
largest; the right singular vector is the mode shape. The error estimate is the last Newton step
(floored at 64 eps |s|).

Completeness
------------
:func:`count_in_contour` counts the eigenvalues inside a closed polygon by the argument principle,
(1/(2 pi i)) oint tr(T^{-1} T') ds, by Gauss-Legendre quadrature on each edge, doubling the nodes
until two successive values agree to 1e-2 and lie within 1e-2 of an integer. Comparing it with the
roots found inside says whether the seeds found every eigenvalue there. The contour must avoid
eigenvalues and branch cuts of T.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass

import numpy as np

from ..errors import ConvergenceError

SINGULAR_RTOL = 1e-10
DUPLICATE_RTOL = 1e-8
_FLOOR = 64 * np.finfo(float).eps

Matrix = Callable[[complex], np.ndarray]


@dataclass(frozen=True, kw_only=True, eq=False)
class NonlinearEigenvalues:
    """Eigenvalues s of det T(s) = 0 found from the seeds, in the order found.

    Attributes
    ----------
    values : complex eigenvalues.
    error_estimate : last Newton step of each (>= 64 eps |s|).
    vectors : (b, count) right null vectors of T(s) (unit 2-norm).
    singular_ratio : sigma_min / sigma_max of T at each eigenvalue (<= SINGULAR_RTOL).
    seeds_tried, failed : seeds drawn and seeds that did not give a new eigenvalue.
    """

    values: np.ndarray
    error_estimate: np.ndarray
    vectors: np.ndarray
    singular_ratio: np.ndarray
    seeds_tried: int
    failed: int


def _log_derivative(T: Matrix, dT: Matrix, s: complex) -> complex:
    return complex(np.trace(np.linalg.solve(T(s), dT(s))))


def singular_ratio(T: Matrix, s: complex) -> float:
    """sigma_min / sigma_max of T(s): <= SINGULAR_RTOL at an eigenvalue (to working accuracy)."""
    sv = np.linalg.svd(T(s), compute_uv=False)
    return float(sv[-1] / sv[0])


def newton(T: Matrix, dT: Matrix, s: complex, *, known: Iterable[complex] = (), tol: float = 1e-13,
           max_iter: int = 60) -> tuple[complex, float] | None:
    """Newton's method on det T from s, deflating ``known`` roots; (root, last step) or None.

    The step is capped at |s|/2 + 1 (a trust region against jumps far from the seed).
    """
    known = np.asarray(list(known), dtype=complex)
    previous = np.inf
    for _ in range(max_iter):
        try:
            g = _log_derivative(T, dT, s)
        except np.linalg.LinAlgError:
            return s, _FLOOR * max(abs(s), 1.0)  # exactly singular: s is a root
        if known.size:
            g -= np.sum(1.0 / (s - known))
        if g == 0 or not np.isfinite(g):
            return None
        step = 1.0 / g
        cap = 0.5 * abs(s) + 1.0
        if abs(step) > cap:
            step *= cap / abs(step)
        s = s - step
        size = abs(step)
        if size <= tol * max(abs(s), 1.0) or (size >= previous and size <= 1e-9 * max(abs(s), 1.0)):
            return s, max(size, _FLOOR * abs(s))
        previous = size
    return None


def nonlinear_eigenvalues(T: Matrix, dT: Matrix, seeds: Iterable[complex], *, tol: float = 1e-13,
                          max_iter: int = 60, accept: Callable[[complex], bool] | None = None,
                          max_roots: int | None = None) -> NonlinearEigenvalues:
    """Eigenvalues of T(s) from the seeds, each verified by the smallest singular value.

    Parameters
    ----------
    T, dT : the matrix function and its derivative, (b, b) complex for complex s.
    seeds : starting points, best first.
    accept : optional filter of converged roots (e.g. a physical sheet or half plane).
    max_roots : stop after this many roots.
    """
    found, errors, vectors, ratios = [], [], [], []
    tried = failed = 0
    for seed in seeds:
        if max_roots is not None and len(found) >= max_roots:
            break
        tried += 1
        out = newton(T, dT, complex(seed), known=found, tol=tol, max_iter=max_iter)
        if out is None:
            failed += 1
            continue
        s, err = out
        if any(abs(s - r) <= DUPLICATE_RTOL * max(abs(s), 1.0) for r in found) or \
                (accept is not None and not accept(s)):
            failed += 1
            continue
        _, sv, vh = np.linalg.svd(T(s))
        ratio = sv[-1] / sv[0]
        if ratio > SINGULAR_RTOL:
            failed += 1
            continue
        found.append(s)
        errors.append(err)
        vectors.append(vh[-1].conj())
        ratios.append(ratio)
    b = np.asarray(T(complex(1j))).shape[0] if not vectors else len(vectors[0])
    return NonlinearEigenvalues(values=np.array(found, dtype=complex), error_estimate=np.array(errors),
                                vectors=np.array(vectors, dtype=complex).T.reshape(b, len(found)),
                                singular_ratio=np.array(ratios), seeds_tried=tried, failed=failed)


def count_in_contour(T: Matrix, dT: Matrix, vertices: Iterable[complex], *, n_start: int = 16,
                     n_max: int = 4096) -> int:
    """Number of eigenvalues (with multiplicity) inside the closed polygon ``vertices``
    (counter-clockwise) by the argument principle (module notes).

    Raises
    ------
    ConvergenceError : the quadrature did not settle on an integer by ``n_max`` nodes per edge
        (an eigenvalue or branch point on or very near the contour).
    """
    v = np.asarray(list(vertices), dtype=complex)
    edges = list(zip(v, np.roll(v, -1)))
    n, previous = n_start, None
    while n <= n_max:
        x, w = np.polynomial.legendre.leggauss(n)
        total = 0j
        for a, b in edges:
            half = (b - a) / 2
            total += sum(wi * half * _log_derivative(T, dT, (a + b) / 2 + half * xi) for xi, wi in zip(x, w))
        value = total / (2j * np.pi)
        if previous is not None and abs(value - previous) < 1e-2 and abs(value.real - round(value.real)) < 1e-2:
            return int(round(value.real))
        previous, n = value, 2 * n
    raise ConvergenceError(f"the argument-principle count did not settle by {n_max} nodes per edge "
                           f"(last value {previous:.6g}): move the contour away from eigenvalues "
                           "and branch cuts")


def continue_roots(family: Callable[[float], tuple[Matrix, Matrix]], start: float, stop: float,
                   roots: Iterable[complex], *, first_ratio: float = 1.5, min_ratio: float = 1e-6,
                   max_move: float = 0.25, tol: float = 1e-13) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Follow each eigenvalue of T(s; p) from p = ``start`` (where ``roots`` are its eigenvalues)
    to p = ``stop`` > start > 0, in geometric steps with step control.

    A step p -> p r is accepted when Newton's method (at most 12 iterations, from the linear
    extrapolation of the last two points) converges and the root moves by at most ``max_move``
    times its distance to the nearest other branch; otherwise r -> sqrt(r). A branch whose ratio
    falls below 1 + ``min_ratio`` is abandoned (a fold, a collision or a branch cut).

    Every branch is then polished by a full Newton solve at ``stop``. Returns (roots at ``stop``,
    last Newton steps, ok): ``ok`` is False for an abandoned branch (its root is then the last
    accepted value, at a smaller p) or for two branches that meet.
    """
    current = np.array(list(roots), dtype=complex)
    steps = np.full(current.shape, _FLOOR)
    ok = np.ones(current.shape, dtype=bool)
    for i in range(current.size):
        p, ratio, s, slope = start, first_ratio, current[i], 0j
        while p < stop:
            q = min(p * ratio, stop)
            others = np.delete(current, i)
            guard = np.min(np.abs(others - s)) if others.size else abs(s) + 1.0
            T, dT = family(q)
            out = newton(T, dT, s + slope * np.log(q / p), tol=tol, max_iter=12)
            if out is not None and abs(out[0] - s) <= max_move * guard:
                slope = (out[0] - s) / np.log(q / p)
                s, steps[i], p = out[0], out[1], q
                ratio = min(ratio ** 1.5, 10.0)
                continue
            ratio = np.sqrt(ratio)
            if ratio < 1.0 + min_ratio:
                ok[i] = False
                break
        current[i] = s
    T, dT = family(stop)
    for i in np.flatnonzero(ok):  # polish at ``stop``: merged branches then coincide to rounding
        out = newton(T, dT, current[i], tol=tol)
        if out is None:
            ok[i] = False
        else:
            current[i], steps[i] = out
    for i in range(current.size):
        for j in range(i):
            if ok[i] and ok[j] and abs(current[i] - current[j]) <= DUPLICATE_RTOL * max(abs(current[i]), 1.0):
                ok[i] = ok[j] = False
    return current, steps, ok
