"""Marginal forcing amplitudes tau of a Hill pencil A v = tau B v, and their convergence in N.

Structured fast path
--------------------
A is block diagonal, so T = A^{-1} B costs O(N b^3) and its eigenvalues are mu = 1/tau. When B
couples only Fourier indices of opposite parity (``HillMatrices.bipartite``: no self-coupling),
T = [[0, X], [Y, 0]] in an even/odd ordering and mu^2 are the eigenvalues of the half-size product W = X Y. Real tau
correspond to real positive mu^2 (tau and -tau, a time shift by pi, always come together).

* harmonic: the real form is bipartite, so W is real and a real tau is an exactly real
  eigenvalue of W (LAPACK returns zero imaginary part for it): classification is exact.
* subharmonic: the real form has an n = 0 self-coupling and is not bipartite; the two-sided form
  is. Its W is complex with real-or-conjugate-pair spectrum (the reality condition (2.8) makes
  W = Z conj(Z)), and mu^2 counts as real when |Im mu^2| <= 1e-9 |mu^2|.

Infinite tau (mu = 0: B is singular, and the harmonic Im u_0 slot is a zero row) are removed as
mu^2 <= 64 eps ||W_bal||_F, W_bal the diagonally balanced W that the eigen-solver works on: such
eigenvalues are indistinguishable from zero. Spurious, truncation-made eigenvalues are removed by
requiring each reported tau to reappear at the previous truncation.

If a diagonal block of A is singular or ill conditioned, in itself (1-norm condition > 1e8) or
against the coupling (||A_k^{-1}|| ||B_k|| > 1e8: some tau ~< 1e-8, e.g. undamped Mathieu at
sqrt(kappa) = k/2, where tau = 0 is an eigenvalue), squaring would lose the small tau and the
solver falls back to QZ on the real form (``method = "qz"``), which handles singular A and B. A singular A makes tau = 0
an exact eigenvalue, often defective (two fingers leave the axis together), which rounding
spreads by ~eps^(1/2); such a cluster within ZERO_CLUSTER = 1e-6 of 0 is reported as one tau = 0
whose uncertainty is its largest magnitude (:func:`qz_taus`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from ..discretise.hill import HillMatrices, assemble
from ..errors import ConvergenceError
from ..models.base import HillSystem

COND_LIMIT = 1e8
ZERO_CLUSTER = 1e-6
REAL_RTOL = 1e-9
N_MAX = 400


@dataclass(frozen=True, kw_only=True, eq=False)
class MarginalTau:
    """Marginal amplitudes of one Floquet kind.

    Attributes
    ----------
    kind : 'harmonic' or 'subharmonic'.
    tau : ascending real tau >= 0 at the final truncation that reappear at the previous one to
        within max(tol, error_estimate) * max(1, tau).
    tau_min : smallest such tau (None if there is none).
    n_temporal : final truncation N.
    n_previous : the truncation it was compared with.
    error_estimate : max(|tau_min(N) - tau_min(previous N)|, spread of a reported tau = 0,
        8 eps max(1, tau_min)) (None if there is no tau_min).
    method : 'structured' or 'qz' (the fallback), at the final truncation.
    """

    kind: str
    tau: np.ndarray
    tau_min: float | None
    n_temporal: int
    n_previous: int
    error_estimate: float | None
    method: str


def _tau_from_squares(lam: np.ndarray, floor: float, exact_real: bool) -> np.ndarray:
    """tau = 1/sqrt(mu^2) for the real eigenvalues mu^2 of W above ``floor``."""
    if exact_real:
        real = lam.imag == 0.0
    else:
        real = np.abs(lam.imag) <= REAL_RTOL * np.abs(lam)
    keep = real & (lam.real > floor)
    return np.sort(1.0 / np.sqrt(lam.real[keep]))


def _half_product(hill: HillMatrices) -> np.ndarray | None:
    """W = X Y of a bipartite pencil, from the blocks C-_k = A_k^{-1} B_{k,k-1} and
    C+_k = A_k^{-1} B_{k,k+1}: on even block positions p,
    W_{p,p} = C-_p C+_{p-1} + C+_p C-_{p+1}, W_{p,p+2} = C+_p C+_{p+1}, W_{p,p-2} = C-_p C-_{p-1}.
    Returns None when a block of A is singular or ill conditioned (module notes)."""
    K, s, _ = hill.diag.shape
    try:
        inv = np.linalg.inv(hill.diag)
    except np.linalg.LinAlgError:
        return None
    inv_norm = np.abs(inv).sum(axis=1).max(axis=-1)
    cond = np.abs(hill.diag).sum(axis=1).max(axis=-1) * inv_norm
    coupling = np.abs(hill.lower).sum(axis=1).max(axis=-1).max() + \
        np.abs(hill.upper).sum(axis=1).max(axis=-1).max()
    if not np.all(np.isfinite(cond)) or max(cond.max(), inv_norm.max() * coupling) > COND_LIMIT:
        return None
    zero = np.zeros((1, s, s), dtype=inv.dtype)
    cm = np.concatenate([zero, inv[1:] @ hill.lower, zero])    # cm[k] = C-_k, k = 0..K (0 at ends)
    cp = np.concatenate([zero, inv[:-1] @ hill.upper, zero])   # cp[k + 1] = C+_k, k = -1..K-1
    p = np.arange(0, K, 2)
    m = len(p)
    W = np.zeros((m, s, m, s), dtype=np.result_type(inv, hill.lower))
    i = np.arange(m)
    W[i, :, i, :] = cm[p] @ cp[p] + cp[p + 1] @ cm[p + 1]
    W[i[:-1], :, i[1:], :] = cp[p[:-1] + 1] @ cp[p[:-1] + 2]
    W[i[1:], :, i[:-1], :] = cm[p[1:]] @ cm[p[1:] - 1]
    return W.reshape(m * s, m * s)


def structured_taus(hill: HillMatrices) -> np.ndarray | None:
    """Real tau >= 0 of a bipartite pencil via the half-size product W (None if A is ill
    conditioned; see the module notes)."""
    if not hill.bipartite:
        raise ValueError("structured_taus needs a bipartite pencil (no self-coupling in B)")
    W = _half_product(hill)
    if W is None:
        return None
    balanced = sla.matrix_balance(W, permute=False, separate=False)[0]
    floor = 64 * np.finfo(float).eps * np.linalg.norm(balanced)
    return _tau_from_squares(sla.eigvals(balanced, overwrite_a=True, check_finite=False),
                             floor, exact_real=hill.is_real)


def _finite_eigenvalues(hill: HillMatrices) -> np.ndarray:
    """Finite eigenvalues of the pencil by dense QZ; infinite ones (beta = 0) are dropped."""
    alpha, beta = sla.eigvals(hill.A.toarray(), hill.B.toarray(), homogeneous_eigvals=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        tau = alpha / beta
    return tau[np.isfinite(tau)]


def _real_part_of_real(tau: np.ndarray, exact: bool) -> np.ndarray:
    real = tau.imag == 0.0 if exact else np.abs(tau.imag) <= REAL_RTOL * np.maximum(np.abs(tau), 1.0)
    return np.sort(tau.real[real])


def dense_taus(hill: HillMatrices) -> np.ndarray:
    """Real tau (either sign) of the pencil by dense QZ (``scipy.linalg.eigvals(A, B)``): the
    reference path."""
    return _real_part_of_real(_finite_eigenvalues(hill), hill.is_real)


def qz_taus(hill: HillMatrices) -> tuple[np.ndarray, float]:
    """Real tau >= 0 by QZ; a defective zero eigenvalue is reported as one exact 0.

    Returns (tau, spread): eigenvalues within ZERO_CLUSTER of 0 that are not a simple +-tau pair
    (symmetric to 1 %, as the tau -> -tau symmetry makes every simple one) are the rounding
    spread of a multiple zero and are merged into tau = 0 with ``spread`` their largest magnitude.
    """
    tau = _finite_eigenvalues(hill)
    near = np.abs(tau) <= ZERO_CLUSTER
    cluster = tau[near]
    simple_pair = (len(cluster) == 2 and np.all(cluster.imag == 0)
                   and abs(cluster.real.sum()) <= 1e-2 * np.abs(cluster.real).max())
    if simple_pair or not near.any():
        near[:] = False
    positive = _real_part_of_real(tau[~near], hill.is_real)
    positive = positive[positive >= 0]
    if not near.any():
        return positive, 0.0
    return np.concatenate([[0.0], positive]), float(np.max(np.abs(cluster)))


def preferred_form(kind: str) -> str:
    """The bipartite form of each kind: real for harmonic, two-sided for subharmonic."""
    return "real" if kind == "harmonic" else "two-sided"


def solve_truncation(system: HillSystem, kind: str, n_temporal: int) -> tuple[np.ndarray, str, float]:
    """All real tau >= 0 of one truncation: (ascending tau, method, uncertainty of a reported 0)."""
    if not np.any(system.forcing):
        return np.empty(0), "structured", 0.0  # no forcing: no finite marginal amplitude
    taus = structured_taus(assemble(system, kind, n_temporal, preferred_form(kind)))
    if taus is not None:
        return taus, "structured", 0.0
    taus, spread = qz_taus(assemble(system, kind, n_temporal, "real"))
    return taus, "qz", spread


def _start(system: HillSystem) -> int:
    return int(np.ceil(system.n_resonant)) + 8


def _next(n: int) -> int:
    return n + max(6, n // 2)


def _previous(n: int) -> int:
    return max(1, n - max(2, n // 4))


def _matched(tau: np.ndarray, previous: np.ndarray, tol: float) -> np.ndarray:
    if not tau.size or not previous.size:
        return tau[:0]
    dist = np.min(np.abs(tau[:, None] - previous[None, :]), axis=1)
    return tau[dist <= tol * np.maximum(1.0, tau)]


def _result(kind, tau, prev, n, n_prev, tol, method, spread) -> MarginalTau:
    if tau.size and prev.size:
        err = max(abs(float(tau[0] - prev[0])), spread, 8 * np.finfo(float).eps * max(1.0, tau[0]))
    elif tau.size:
        err = float(tau[0])  # nothing to compare with: the whole value is uncertain
    else:
        err = None
    kept = _matched(tau, prev, max(tol, err or 0.0))
    if tau.size and (not kept.size or kept[0] != tau[0]):
        kept = np.concatenate([tau[:1], kept[kept > tau[0]]])
    return MarginalTau(kind=kind, tau=kept, tau_min=float(tau[0]) if tau.size else None,
                       n_temporal=n, n_previous=n_prev, error_estimate=err, method=method)


def _capped(tau: np.ndarray, tau_max: float) -> np.ndarray:
    return tau[tau <= tau_max]


def marginal_tau(system: HillSystem, kind: str, *, tol: float = 1e-10,
                 n_temporal: int | None = None, n_max: int = N_MAX,
                 tau_max: float = np.inf) -> MarginalTau:
    """Marginal amplitudes tau of one Floquet kind, converged in the truncation N.

    Parameters
    ----------
    system : the model's physics (D(s), G).
    kind : 'harmonic' (gamma = 0) or 'subharmonic' (gamma = i/2).
    tol : with ``n_temporal=None``, N is raised (N -> N + max(6, N // 2), starting above the
        model's resonant index) until tau_min changes by less than ``tol`` (absolute).
    n_temporal : fixed truncation N instead; the error estimate then compares with a smaller N.
    tau_max : only tau <= tau_max are wanted (e.g. 1/2, where the stiffness stays positive, or
        the amplitude a stability question asks about): larger ones are dropped at every
        truncation before the convergence test, so the truncation is raised only as far as the
        wanted values need. ``tau_min`` is None when no tau <= tau_max exists at two successive
        truncations.

    Raises
    ------
    ConvergenceError : tau_min has not converged to ``tol`` by N = ``n_max``.
    """
    if n_temporal is not None:
        n_prev = _previous(n_temporal)
        tau, method, spread = solve_truncation(system, kind, n_temporal)
        prev = _capped(solve_truncation(system, kind, n_prev)[0], tau_max)
        return _result(kind, _capped(tau, tau_max), prev, n_temporal, n_prev, tol, method, spread)
    n_prev = min(_start(system), _previous(n_max))
    prev = _capped(solve_truncation(system, kind, n_prev)[0], tau_max)
    while True:
        n = min(_next(n_prev), n_max)
        tau, method, spread = solve_truncation(system, kind, n)
        tau = _capped(tau, tau_max)
        both_empty = not tau.size and not prev.size
        if both_empty or (tau.size and prev.size and abs(tau[0] - prev[0]) < tol):
            return _result(kind, tau, prev, n, n_prev, tol, method, spread)
        if n >= n_max:
            change = abs(tau[0] - prev[0]) if tau.size and prev.size else float("nan")
            raise ConvergenceError(
                f"{kind} tau_min did not converge to tol={tol:g} by n_temporal={n} "
                f"(last change {change:.3g}); relax --tol or raise the truncation limit")
        prev, n_prev = tau, n
