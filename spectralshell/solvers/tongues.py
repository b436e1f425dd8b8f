"""Ince-Strutt diagrams: the tips (minima) of the fingers of marginal tau over a kappa grid.

The grid itself is solved by the sweep runner (:func:`spectralshell.runner.map_points`). The
solver sees only a picklable ``factory(kappa) -> HillSystem``; it never knows the model. "kappa"
names the diagram's horizontal parameter: any real parameter of a one-parameter family of
systems serves (e.g. the cochlea's spatial wavenumber k in thesis Fig 5.11).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import scipy.linalg as sla

from ..discretise.hill import assemble
from ..errors import ConvergenceError
from ..models.base import HillSystem
from ..results.records import MarginalTau, Tip
from .marginal import marginal_tau, solve_truncation

SystemFactory = Callable[[float], HillSystem]


def tau_slope(factory: SystemFactory, kind: str, kappa: float, tau: float, n_temporal: int) -> float:
    """d tau / d kappa of the real eigenvalue ``tau`` of the real-form pencil at ``kappa``.

    Notes
    -----
    First-order perturbation of A v = tau B v with left eigenvector w:
    tau' = w^H (A' - tau B') v / (w^H B v); A', B' by the fourth-order central difference with
    step h = 1e-3 max(kappa, 1e-3) (exact up to rounding when the blocks are polynomials of degree
    <= 4 in kappa, as for every model here).
    """
    hill = assemble(factory(kappa), kind, n_temporal, "real")
    A, B = hill.A.toarray(), hill.B.toarray()
    values, left, right = sla.eig(A, B, left=True, right=True)
    i = int(np.nanargmin(np.abs(values - tau)))
    v, w = right[:, i], left[:, i]
    h = 1e-3 * max(kappa, 1e-3)
    weights = {-2: 1 / 12, -1: -2 / 3, 1: 2 / 3, 2: -1 / 12}
    dA = np.zeros_like(A)
    dB = np.zeros_like(B)
    for j, c in weights.items():
        hj = assemble(factory(kappa + j * h), kind, n_temporal, "real")
        dA += c / h * hj.A.toarray()
        dB += c / h * hj.B.toarray()
    return float((w.conj() @ (dA - tau * dB) @ v / (w.conj() @ B @ v)).real)


def _bisect(predicate, a: float, b: float, steps: int = 60) -> float:
    """Boundary between a (predicate false) and b (predicate true)."""
    for _ in range(steps):
        mid = 0.5 * (a + b)
        if mid in (a, b):
            break
        a, b = (a, mid) if predicate(mid) else (mid, b)
    return 0.5 * (a + b)


def refine_tip(factory: SystemFactory, kind: str, lo: float, hi: float, tau_guess: float,
               *, tol: float = 1e-10) -> Tip:
    """Locate the minimum over kappa in [lo, hi] of the finger whose tau is near ``tau_guess``.

    Notes
    -----
    The tip is the root of d tau/d kappa (:func:`tau_slope`) on the bracket, found by Brent's
    root finder (``scipy.optimize.brentq``, xtol 1e-14): superlinear where the minimum is smooth
    (damped fingers), bisection where the finger touches tau = 0 with a corner or cusp (undamped
    fingers, where tau' changes sign without vanishing). A grid of kappa is never refined.
    Where that root is a defective tau = 0 (reported as an exact 0 over a tiny kappa interval by the
    QZ path), the interval is bisected and its half-width is the kappa error.
    The tracked eigenvalue is the real tau nearest to ``tau_guess`` at the truncation that
    converges tau_min at the bracket's centre (plus 4, for margin).

    Raises
    ------
    ConvergenceError : the finger cannot be tracked across the bracket.
    """
    n = marginal_tau(factory(0.5 * (lo + hi)), kind, tol=tol).n_temporal + 4

    def tracked(kappa: float) -> float:
        taus = solve_truncation(factory(kappa), kind, n)[0]
        if not taus.size:
            raise ConvergenceError(f"no {kind} marginal tau at kappa = {kappa:.17g}")
        return float(taus[np.argmin(np.abs(taus - tau_guess))])

    def slope(kappa: float) -> float:
        tau = tracked(kappa)
        return 0.0 if tau == 0.0 else tau_slope(factory, kind, kappa, tau, n)

    g_lo, g_hi = slope(lo), slope(hi)
    if not (g_lo <= 0.0 <= g_hi):
        raise ConvergenceError(f"{kind} finger near kappa in [{lo:.6g}, {hi:.6g}] has no minimum "
                               f"inside the bracket (slopes {g_lo:.3g}, {g_hi:.3g}): tau_min is not "
                               "smooth there (it jumps to another branch, e.g. where the finger's "
                               "real tau turn complex), so the sampled minimum is not a finger tip")
    xtol, rtol = 1e-14, 4 * np.finfo(float).eps
    from scipy.optimize import brentq  # lazy: ~0.2 s to import, only where tips are refined

    kappa = lo if g_lo == 0.0 else hi if g_hi == 0.0 else brentq(slope, lo, hi, xtol=xtol, rtol=rtol)
    kappa_error = 2 * (xtol + rtol * abs(kappa))
    plateau = tracked(kappa) == 0.0
    if plateau:  # a multiple zero, merged by the QZ path: bisect its extent
        left = _bisect(lambda k: tracked(k) == 0.0, lo, kappa)
        right = _bisect(lambda k: tracked(k) != 0.0, kappa, hi)
        kappa, kappa_error = 0.5 * (left + right), max(kappa_error, 0.5 * (right - left))
    res = marginal_tau(factory(kappa), kind, tol=tol, method="dense")  # every tau, not the least
    tau = float(res.tau[np.argmin(np.abs(res.tau - tracked(kappa)))])
    # On a plateau the tip's tau is the merged zero; its error covers the converged solver's
    # nearest tau. Elsewhere tau inherits the kappa error through the finger's slope (one-sided
    # at a corner tip).
    spread = abs(tau) if plateau else max(abs(g_lo), abs(g_hi)) * kappa_error
    tau = 0.0 if plateau else tau
    tau_error = max(float(res.error_estimate or 0.0), 8 * np.finfo(float).eps * max(tau, 1.0), spread)
    return Tip(kind=kind, kappa=float(kappa), tau=tau, kappa_error=float(kappa_error),
               tau_error=tau_error)


def find_tips(factory: SystemFactory, kappas: np.ndarray, rows: list[dict[str, MarginalTau]],
              kinds: tuple[str, ...], *, tol: float = 1e-10) -> tuple[list[Tip], list[str]]:
    """Tips of every finger visible as an interior local minimum of tau_min(kappa) on the grid,
    and a message for each one that could not be located."""
    tips, failures = [], []
    for kind in kinds:
        tmin = np.array([r[kind].tau_min if r[kind].tau_min is not None else np.inf for r in rows])
        for i in range(1, len(kappas) - 1):
            # a neighbour without tau (none, or none below a tau_max cap) counts as +inf
            if np.isfinite(tmin[i]) and tmin[i] <= tmin[i - 1] and tmin[i] < tmin[i + 1]:
                try:
                    tips.append(refine_tip(factory, kind, float(kappas[i - 1]),
                                           float(kappas[i + 1]), float(tmin[i]), tol=tol))
                except ConvergenceError as exc:
                    failures.append(f"tip near kappa = {kappas[i]:.6g} ({kind}) not located: {exc}")
    return sorted(tips, key=lambda t: t.kappa), failures
