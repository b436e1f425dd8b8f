"""Finite eigenvalues of a generalised eigenproblem s M v = L v, and its least-damped modes.

Model-agnostic: the solver sees two square matrices (dense or sparse), never the physics that
made them. Discretised differential operators with boundary rows give a singular M (a zero row
per algebraic condition), so the pencil has infinite eigenvalues; they are computed and dropped.

Method
------
1. Balance: scale every row of (L, M) by 1 / max(|L_i.|, |M_i.|) and then every column likewise
   (an equivalence transformation: eigenvalues are unchanged, eigenvectors are unscaled
   afterwards). Chebyshev rows differ by many orders of magnitude (boundary rows, nodes near a
   singular end, N^4 growth of second derivatives); without this the QZ backward error,
   eps ||L||, swamps the small rows (LAPACK's xGGEV only permutes).
2. Scale M by sigma = max|L_b| / max|M_b| so both matrices have unit size, and run QZ
   (``scipy.linalg.eig`` with ``homogeneous_eigvals=True``), giving pairs (alpha, beta) with
   s = sigma alpha / beta.
3. A pair with alpha = beta = 0 (both below 1e-13, the matrices having unit size) means a
   singular pencil (det(L - s M) = 0 for every s): an error. An eigenvalue is infinite when
   |beta| <= ``infinite_tol`` |alpha|, i.e. |s| >= sigma / infinite_tol: with both matrices of
   unit size, a genuine eigenvalue that large cannot be told from an infinite one in double
   precision.
4. Order by decreasing Re s; values whose real parts agree to ``TIE_RTOL`` |s| (the two of a
   conjugate pair, whose computed real parts differ by rounding) by decreasing Im s, so that
   the order does not depend on the last bits of QZ.

Least-damped modes
------------------
Truncated operators of unbounded or singular problems also have eigenvalues that do not belong to
the continuous problem: a discretised continuous spectrum, or spurious eigenvalues of the
truncation. Those move when the resolution changes, genuine ones converge. :func:`least_damped`
therefore takes the pencil at two resolutions, keeps the eigenvalues of the finer one with
Im s >= -1e-12 |s| (one per conjugate pair of a real pencil; an imaginary part within that
tolerance of 0 is set to 0), and accepts an eigenvalue only if the coarser
pencil has one within ``rtol`` |s|; its distance to that one is the reported error estimate (an
estimate of the coarse error, hence pessimistic for the fine one). :func:`least_damped` returns
the ``count`` accepted eigenvalues of largest Re s, :func:`converged_modes` all of them. A
complex pencil need not be conjugate-symmetric (e.g. complex scaling); its eigenvalues with
Im s < 0 are never returned, so build it such that the wanted ones have Im s >= 0.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from .._validate import require_int_in_range, require_positive
from ..errors import ConvergenceError, ParameterError

INFINITE_TOL = 1e-10
IMAG_TOL = 1e-12
SINGULAR_TOL = 1e-13
TIE_RTOL = 1e-10


@dataclass(frozen=True, kw_only=True, eq=False)
class Modes:
    """Least-damped eigenvalues of a pencil, checked between two resolutions.

    Attributes
    ----------
    values : (count,) complex eigenvalues s with Im s >= 0, by decreasing Re s.
    error_estimate : (count,) |s_fine - s_coarse| for each value.
    vectors : (n, count) eigenvectors of the fine pencil (unit 2-norm), or None.
    sizes : (fine size, coarse size) of the two pencils.
    rtol : the acceptance tolerance used.
    skipped : number of eigenvalues with larger Re s that were rejected as unconverged
        (discretised continuous spectrum or spurious).
    """

    values: np.ndarray
    error_estimate: np.ndarray
    vectors: np.ndarray | None
    sizes: tuple[int, int]
    rtol: float
    skipped: int


def _dense(A) -> np.ndarray:
    return A.toarray() if sp.issparse(A) else np.asarray(A)


def _check_pencil(L, M) -> tuple[np.ndarray, np.ndarray]:
    L, M = _dense(L), _dense(M)
    if L.ndim != 2 or L.shape[0] != L.shape[1] or L.shape != M.shape:
        raise ParameterError(f"(L, M) shapes = {L.shape}, {M.shape} are invalid: must be two "
                             "square matrices of equal size")
    if not (np.all(np.isfinite(L)) and np.all(np.isfinite(M))):
        raise ParameterError("(L, M) = matrices with NaN or inf entries are invalid: must be "
                             "finite")
    return L, M


def balance(L, M) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Row-then-column scaled (R L C, R M C) and the column scales C (diagonal), see step 1."""
    L, M = _check_pencil(L, M)
    row = np.maximum(np.abs(L).max(axis=1), np.abs(M).max(axis=1))
    if np.any(row == 0):
        raise ParameterError(f"(L, M) row {int(np.argmin(row))} is zero in both matrices: the "
                             "pencil is singular (must have no zero row pair)")
    L, M = L / row[:, None], M / row[:, None]
    col = np.maximum(np.abs(L).max(axis=0), np.abs(M).max(axis=0))
    if np.any(col == 0):
        raise ParameterError(f"(L, M) column {int(np.argmin(col))} is zero in both matrices: "
                             "the pencil is singular (must have no zero column pair)")
    return L / col, M / col, 1.0 / col


def finite_eigenvalues(L, M, *, vectors: bool = False, infinite_tol: float = INFINITE_TOL):
    """Finite eigenvalues s of s M v = L v, by decreasing Re s (see the module docstring).

    Returns
    -------
    values, or (values, vectors) with ``vectors=True`` (columns of unit 2-norm).

    Raises
    ------
    ParameterError : non-square, mismatched or non-finite matrices, a zero row or column pair.
    ConvergenceError : QZ failed, or the pencil is singular (an alpha = beta = 0 pair).
    """
    infinite_tol = require_positive("infinite_tol", infinite_tol)
    Lb, Mb, col = balance(L, M)
    norm_m = np.abs(Mb).max()
    if norm_m == 0:
        empty = np.zeros(0, complex)
        return (empty, np.zeros((Lb.shape[0], 0), complex)) if vectors else empty
    sigma = np.abs(Lb).max() / norm_m
    try:
        out = sla.eig(Lb, sigma * Mb, homogeneous_eigvals=True, right=vectors)
    except (np.linalg.LinAlgError, ValueError) as exc:
        raise ConvergenceError(f"QZ failed on the pencil of size {Lb.shape[0]}: {exc}") from None
    (alpha, beta), V = (out if vectors else (out, None))
    if np.any(np.maximum(np.abs(alpha), np.abs(beta)) < SINGULAR_TOL):
        raise ConvergenceError("the pencil (L, M) is singular to working precision: QZ found "
                               "alpha = beta = 0 (det(L - s M) vanishes for all s)")
    finite = np.abs(beta) > infinite_tol * np.abs(alpha)
    values = sigma * alpha[finite] / beta[finite]
    order = _decreasing_real_part(values)
    values = values[order]
    if not np.all(np.isfinite(values)):
        raise ConvergenceError("QZ returned non-finite eigenvalues")
    if not vectors:
        return values
    V = col[:, None] * V[:, finite][:, order]
    V = V / np.linalg.norm(V, axis=0)
    return values, V


def _decreasing_real_part(values: np.ndarray) -> np.ndarray:
    """Indices ordering ``values`` by decreasing Re, ties within ``TIE_RTOL`` by decreasing Im."""
    order = np.argsort(-values.real, kind="stable")
    v = values[order]
    step = -np.diff(v.real) > TIE_RTOL * np.maximum(np.abs(v[1:]), np.abs(v[:-1]))
    tie_group = np.concatenate([[0], np.cumsum(step)])[: v.size]
    return order[np.lexsort((-v.imag, tie_group))]


def _match(fine: tuple, coarse: tuple, rtol: float, vectors: bool, infinite_tol: float):
    """Candidates (Im s >= 0, decreasing Re s) of ``fine``, distances to ``coarse``, vectors."""
    out = finite_eigenvalues(*fine, vectors=vectors, infinite_tol=infinite_tol)
    values, V = out if vectors else (out, None)
    reference = finite_eigenvalues(*coarse, infinite_tol=infinite_tol)
    keep = np.flatnonzero(values.imag >= -IMAG_TOL * np.abs(values))
    values = values[keep]
    values = np.where(np.abs(values.imag) <= IMAG_TOL * np.abs(values), values.real + 0j, values)
    if reference.size:
        dist = np.min(np.abs(values[:, None] - reference[None, :]), axis=1)
    else:
        dist = np.full(values.shape, np.inf)
    accepted = dist <= rtol * np.abs(values)
    return values, dist, accepted, None if V is None else V[:, keep]


def _modes(values, dist, V, chosen, fine, coarse, rtol, skipped) -> Modes:
    return Modes(values=values[chosen], error_estimate=dist[chosen],
                 vectors=None if V is None else V[:, chosen],
                 sizes=(_dense(fine[0]).shape[0], _dense(coarse[0]).shape[0]), rtol=rtol,
                 skipped=skipped)


def converged_modes(fine: tuple, coarse: tuple, *, rtol: float = 1e-6, vectors: bool = False,
                    infinite_tol: float = INFINITE_TOL) -> Modes:
    """All eigenvalues with Im s >= 0 of ``fine`` that ``coarse`` reproduces within rtol |s|.

    Sorted by decreasing Re s; ``skipped`` counts the rejected ones. Parameters as in
    :func:`least_damped`; the result may be empty.
    """
    rtol = require_positive("rtol", rtol)
    values, dist, accepted, V = _match(fine, coarse, rtol, vectors, infinite_tol)
    chosen = np.flatnonzero(accepted)
    return _modes(values, dist, V, chosen, fine, coarse, rtol, int(np.sum(~accepted)))


def least_damped(fine: tuple, coarse: tuple, *, count: int, rtol: float = 1e-6,
                 vectors: bool = False, infinite_tol: float = INFINITE_TOL) -> Modes:
    """The ``count`` converged eigenvalues of largest Re s with Im s >= 0 (module docstring).

    Parameters
    ----------
    fine, coarse : (L, M) of the same problem at a higher and a lower resolution.
    count : number of modes wanted, >= 1.
    rtol : an eigenvalue s of ``fine`` is accepted when ``coarse`` has one within rtol |s|.
    vectors : also return the eigenvectors of ``fine``.
    infinite_tol : see :func:`finite_eigenvalues`.

    Returns
    -------
    Modes, with ``skipped`` the number of rejected eigenvalues of larger Re s than the last one
    returned.

    Raises
    ------
    ParameterError : bad arguments (see :func:`finite_eigenvalues`).
    ConvergenceError : fewer than ``count`` eigenvalues converged; raise both resolutions (or
        rtol) and try again.
    """
    count = require_int_in_range("count", count, 1)
    rtol = require_positive("rtol", rtol)
    values, dist, accepted, V = _match(fine, coarse, rtol, vectors, infinite_tol)
    chosen = np.flatnonzero(accepted)[:count]
    if chosen.size < count:
        raise ConvergenceError(
            f"only {chosen.size} of count = {count} eigenvalues agree to rtol = {rtol:g} between "
            f"the pencils of size {_dense(fine[0]).shape[0]} and {_dense(coarse[0]).shape[0]} "
            f"({int(np.sum(~accepted))} unconverged ones with Im s >= 0): raise the resolution "
            "or rtol")
    skipped = int(np.sum(~accepted[:chosen[-1]]))
    return _modes(values, dist, V, chosen, fine, coarse, rtol, skipped)
