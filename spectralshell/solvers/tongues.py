"""Ince-Strutt diagrams: the tips (minima) of the fingers of marginal tau over a kappa grid, and
the boundary curves traced through the marginal tau of neighbouring kappa.

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
from ..results.records import Boundary, MarginalTau, Tip
from .marginal import ZERO_CLUSTER, marginal_tau, solve_truncation

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

    The root is accepted as a tip only where the tracked tau is continuous there: no larger than
    ``tau_guess`` and with |d tau/d kappa| <= TIP_SLOPE x the bracket's end slopes (or the
    zero plateau); otherwise the tracked value jumped between branches (a finger narrower than
    the grid step, e.g. the cochlea's k = 1 subharmonic finger near omega = 345 rad/s on a
    10 rad/s grid, where the jump sat at tau = 0.68 above a bottom near 0.15).

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
    at = tracked(kappa)
    plateau = at == 0.0
    steep = 0.0 if plateau or at <= ZERO_CLUSTER else abs(tau_slope(factory, kind, kappa, at, n))
    if not plateau and (at > tau_guess + max(tol, 1e-9)  # a corner at tau = 0 may be steep
                        or steep > TIP_SLOPE * max(abs(g_lo), abs(g_hi))):
        # the tracked tau jumped between branches inside the bracket (a finger narrower than
        # the grid step, one of whose sides the bracket misses): the root is that jump
        raise ConvergenceError(
            f"{kind} finger near kappa in [{lo:.6g}, {hi:.6g}]: the tau nearest {tau_guess:.6g} "
            f"jumps to another branch inside the bracket (at kappa = {kappa:.10g}, tau = "
            f"{at:.6g}, above the sampled minimum or with slope {steep:.3g}): the finger "
            "is narrower than the grid step; refine the grid to locate its tip")
    if plateau:  # a multiple zero, merged by the QZ path: bisect its extent
        left = _bisect(lambda k: tracked(k) == 0.0, lo, kappa)
        right = _bisect(lambda k: tracked(k) != 0.0, kappa, hi)
        kappa, kappa_error = 0.5 * (left + right), max(kappa_error, 0.5 * (right - left))
    res = marginal_tau(factory(kappa), kind, tol=tol, method="dense")  # every tau, not the least
    tau = float(res.tau[np.argmin(np.abs(res.tau - (tracked(kappa) if plateau else at)))])
    # On a plateau the tip's tau is the merged zero; its error covers the converged solver's
    # nearest tau. Elsewhere tau inherits the kappa error through the finger's slope (one-sided
    # at a corner tip).
    spread = abs(tau) if plateau else max(abs(g_lo), abs(g_hi)) * kappa_error
    tau = 0.0 if plateau else tau
    tau_error = max(float(res.error_estimate or 0.0), 8 * np.finfo(float).eps * max(tau, 1.0), spread)
    return Tip(kind=kind, kappa=float(kappa), tau=tau, kappa_error=float(kappa_error),
               tau_error=tau_error)


#: A located tip's |d tau/d kappa| is at most this fraction of its bracket's end slopes
#: (:func:`refine_tip`; Brent's root to 1e-14 in kappa leaves ~1e-12 of them at a smooth minimum).
TIP_SLOPE = 1e-6


#: Halvings of a finger's bracket at most when its tip cannot be tracked across it
#: (:func:`narrowed_tip`): a grid step down to 1/256 of itself.
TIP_HALVINGS = 8


def narrowed_tip(factory: SystemFactory, kind: str, kappa: list[float], tau: list[float], *,
                 tol: float = 1e-10, halvings: int = TIP_HALVINGS) -> Tip:
    """The tip of the finger whose sampled minimum is ``tau[1]`` at ``kappa[1]`` between
    ``kappa[0]`` and ``kappa[2]``: :func:`refine_tip` on that bracket; where the tracked tau jumps
    between branches inside it (a finger narrower than the bracket), tau_min is solved at the
    two half-interval midpoints and the search repeats on the three points around the smallest
    of the five, up to ``halvings`` times."""
    try:
        return refine_tip(factory, kind, kappa[0], kappa[2], tau[1], tol=tol)
    except ConvergenceError:
        if halvings == 0:
            raise
    mid = [0.5 * (kappa[0] + kappa[1]), 0.5 * (kappa[1] + kappa[2])]
    at = [marginal_tau(factory(k), kind, tol=tol).tau_min for k in mid]
    five_k = [kappa[0], mid[0], kappa[1], mid[1], kappa[2]]
    five_t = [tau[0], np.inf if at[0] is None else at[0], tau[1],
              np.inf if at[1] is None else at[1], tau[2]]
    i = 1 + int(np.argmin(five_t[1:4]))  # the ends lie above tau[1]: the minimum is inside
    return narrowed_tip(factory, kind, five_k[i - 1:i + 2], five_t[i - 1:i + 2], tol=tol,
                        halvings=halvings - 1)


def find_tips(factory: SystemFactory, kappas: np.ndarray, rows: list[dict[str, MarginalTau]],
              kinds: tuple[str, ...], *, tol: float = 1e-10) -> tuple[list[Tip], list[str]]:
    """Tips of every finger visible as an interior local minimum of tau_min(kappa) on the grid
    (:func:`narrowed_tip`), and a message for each one that could not be located."""
    tips, failures = [], []
    for kind in kinds:
        tmin = np.array([r[kind].tau_min if r[kind].tau_min is not None else np.inf for r in rows])
        for i in range(1, len(kappas) - 1):
            # a neighbour without tau (none, or none below a tau_max cap) counts as +inf
            if np.isfinite(tmin[i]) and tmin[i] <= tmin[i - 1] and tmin[i] < tmin[i + 1]:
                try:
                    tips.append(narrowed_tip(factory, kind, [float(k) for k in kappas[i - 1:i + 2]],
                                             [float(t) for t in tmin[i - 1:i + 2]], tol=tol))
                except ConvergenceError as exc:
                    failures.append(f"tip near kappa = {kappas[i]:.6g} ({kind}) not located: {exc}")
    return sorted(tips, key=lambda t: t.kappa), failures


# ---------------------------------------------------------------------------------------------
# Boundary curves: continuation in kappa, refined where neighbouring values cannot be linked
# ---------------------------------------------------------------------------------------------

#: Largest tau step between consecutive vertices of a traced boundary, above which the kappa
#: interval is bisected (a fiftieth of the unit tau axis of the thesis's diagrams).
BOUNDARY_DTAU = 0.02
#: Smallest kappa interval bisected, as a fraction of the diagram's kappa range: where a branch
#: is steeper than BOUNDARY_DTAU over it (a fold, a finger tip at tau = 0, a branch leaving
#: through tau_max), the refinement stops there.
BOUNDARY_MIN_DKAPPA = 1e-4
#: Boundaries are traced up to tau_max, or up to this where the diagram has none.
BOUNDARY_TAU_MAX = 1.0
#: Two curve ends at one kappa closer than this in tau are joined: a double root split by
#: rounding (by ~1e-6 at the tip of an undamped finger, where both of its sides meet at tau = 0).
SAME_TAU = 1e-5


def boundary_taus(marginal: MarginalTau, tau_max: float) -> np.ndarray:
    """The distinct marginal tau <= ``tau_max`` of one kind at one kappa, ascending."""
    return np.unique(marginal.tau[np.isfinite(marginal.tau) & (marginal.tau <= tau_max)])


def match_taus(a: np.ndarray, b: np.ndarray) -> list[tuple[int, int]]:
    """Order-preserving pairs (i, j) of the ascending values a and b, as many as the shorter
    has, of least total |a[i] - b[j]| (dynamic programming): which value of one kappa continues
    which value of its neighbour."""
    swap = a.size > b.size
    short, long = (b, a) if swap else (a, b)
    n, m = short.size, long.size
    cost = np.full((n + 1, m + 1), np.inf)
    cost[0, :] = 0.0
    for i in range(1, n + 1):
        for j in range(i, m + 1):
            cost[i, j] = min(cost[i, j - 1], cost[i - 1, j - 1] + abs(short[i - 1] - long[j - 1]))
    pairs, i, j = [], n, m
    while i > 0:
        if j > i and cost[i, j] == cost[i, j - 1]:
            j -= 1
        else:
            pairs.append((i - 1, j - 1))
            i, j = i - 1, j - 1
    pairs.reverse()
    return [(j, i) for i, j in pairs] if swap else pairs


def _linked(a: np.ndarray, b: np.ndarray, dtau: float) -> bool:
    """Whether every value of two neighbouring kappa continues one of the other within dtau."""
    return a.size == b.size and all(abs(a[i] - b[j]) <= dtau for i, j in match_taus(a, b))


def refinement_points(kappas: np.ndarray, taus: list[np.ndarray], *, dtau: float,
                      min_dkappa: float) -> list[float]:
    """Midpoints of the intervals between neighbouring kappa (ascending) wider than
    ``min_dkappa`` whose marginal tau cannot yet be linked: a different number of values (a
    branch turns back at a fold, starts, or leaves through tau_max), or a value moving by more
    than ``dtau`` (a steep branch)."""
    return [0.5 * (kappas[j] + kappas[j + 1]) for j in range(len(kappas) - 1)
            if kappas[j + 1] - kappas[j] > min_dkappa and not _linked(taus[j], taus[j + 1], dtau)]


def _edges(taus: list[np.ndarray]) -> set[tuple[tuple[int, int], tuple[int, int]]]:
    """Segments between vertices (column, index): matched values of neighbouring columns; the
    two values left unmatched next to each other in one column (a fold, where two branches
    merge between the columns); a value left alone beside a matched one, joined to that one's
    partner if it has a free side (two branches leaving one point, as both sides of a tilted
    undamped finger leave its tip at tau = 0); and two curve ends in one column closer than
    SAME_TAU (a double root split by rounding)."""
    edges, alone = set(), []
    for j in range(len(taus) - 1):
        pairs = match_taus(taus[j], taus[j + 1])
        edges |= {((j, a), (j + 1, b)) for a, b in pairs}
        side, col = (0, j) if taus[j].size > taus[j + 1].size else (1, j + 1)
        free = sorted(set(range(taus[col].size)) - {p[side] for p in pairs})
        joined = set()
        for u, v in zip(free[:-1], free[1:]):
            if v == u + 1 and u not in joined:
                edges.add(((col, u), (col, v)))
                joined |= {u, v}
        partner = {p[side]: (col + 1 - 2 * side, p[1 - side]) for p in pairs}
        alone += [(col, u, partner) for u in free if u not in joined]
    degree: dict[tuple[int, int], int] = {}
    for u, v in edges:
        degree[u], degree[v] = degree.get(u, 0) + 1, degree.get(v, 0) + 1
    for col, u, partner in alone:
        near = [partner[i] for i in (u - 1, u + 1) if i in partner and degree.get(partner[i], 0) < 2]
        if near:
            w = min(near, key=lambda w: abs(taus[w[0]][w[1]] - taus[col][u]))
            edges.add(((col, u), w))
            degree[w] = degree.get(w, 0) + 1
            degree[(col, u)] = degree.get((col, u), 0) + 1
    for j, tau in enumerate(taus):
        for u in range(tau.size - 1):
            if (tau[u + 1] - tau[u] < SAME_TAU and degree.get((j, u), 0) < 2
                    and degree.get((j, u + 1), 0) < 2):
                edges.add(((j, u), (j, u + 1)))
                degree[(j, u)] = degree.get((j, u), 0) + 1
                degree[(j, u + 1)] = degree.get((j, u + 1), 0) + 1
    return edges


def link_boundaries(kind: str, kappas: np.ndarray, taus: list[np.ndarray]) -> list[Boundary]:
    """The boundary curves of one kind through the marginal tau ``taus[j]`` (ascending) at the
    ascending ``kappas[j]``: each value joined to the value that continues it at the
    neighbouring kappa (:func:`match_taus`) and, at a fold, to its partner; every vertex is a
    point-solver value. Isolated values (no neighbour on either side) are left out."""
    neighbours: dict[tuple[int, int], list[tuple[int, int]]] = {}
    for u, v in _edges(taus):
        neighbours.setdefault(u, []).append(v)
        neighbours.setdefault(v, []).append(u)
    seen: set[tuple[int, int]] = set()
    curves = []
    # open curves from their ends first, then closed loops from any vertex
    starts = sorted(neighbours, key=lambda v: (len(neighbours[v]) != 1, v))
    for start in starts:
        if start in seen:
            continue
        path, here = [start], start
        seen.add(start)
        while True:
            ahead = [v for v in neighbours[here] if v not in seen]
            if not ahead:
                break
            here = ahead[0]
            seen.add(here)
            path.append(here)
        if len(path) > 2 and start in neighbours[here]:
            path.append(start)  # a closed loop
        if len(path) > 1:
            curves.append(Boundary(kind=kind, kappa=np.array([kappas[j] for j, _ in path]),
                                   tau=np.array([taus[j][i] for j, i in path])))
    return curves
