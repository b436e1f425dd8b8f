"""Convergence of tau_min in the number M of spatial modes (models with a spatial truncation).

A model whose Hill blocks carry M spatial modes (the cochlea's cosine modes, thesis 5.3) is
solved at M = start, 2 start, 4 start, ... until every asked kind's tau_min changes by at most
``tol_spatial`` (absolute) between two successive M: the thesis's spatial error epsilon_M of
5.3 (Fig 5.6), used here as a stopping rule. Two refinements of the plain rule:

* Cap. With a finite tau_max the compared quantity is tau_min capped at tau_max (what a sweep
  stores: tau_max where there is none), so a tau_min just below tau_max at one M and none at the
  other differ by tau_max - tau_min. Near tau_max = 1/2, tau_min often leaves and re-enters the
  window from one M to the next; uncapped, such points would refine to the limit. Without
  tau_max, a kind with a tau_min at only one of the two M has not converged.
* Reach. A kind with no tau_min <= tau_max at both M has converged only if the coarser M already
  reaches the kind's resonance (:func:`reaches_resonance`): some natural frequency of the
  truncation, pumped to at most sqrt(1 + 2 tau_max) times itself, attains the kind's lowest
  response frequency (1/2 subharmonic, 1 harmonic). Without it a truncation too short to carry
  the resonant waves finds no tau at M = 16 and 32 and stops there: e.g. the cochlea of Table
  5.1 at f = 20 kHz, sigma = 1e8 g cm^-2 s^-2 (kappa = 5.7e-3) has a subharmonic
  tau_min = 0.049 from M = 128 on, and none at M <= 64.

The pair (M / 2, M) that passed is reported with the change of each kind, and
``spatial_error`` folds the change into the temporal error estimate: max(temporal estimate,
change), or tau_min itself when there is no change to compare (as the temporal estimate does
with nothing to compare).

Work reuse. Each M is solved once: the finer solve of one step is the coarser of the next.
Nothing is shared between different M (the blocks of M modes are a leading corner of those of
2M, but the eigenproblem does not split), and the temporal loop of each M restarts at its own
first truncation: its smaller truncations cost a few per cent of the largest.

Continuation. A caller that solves neighbouring points (a sweep line) may pass ``start`` = a
neighbour's coarser M halved (one step below the neighbour's pair) instead of SPATIAL_START: the
solves below it are skipped, and the need can still fall one step per point. The result equals
the independent solve's whenever that one passes at a pair at or above ``(start, 2 start)``;
otherwise it is the value at a larger M, which passed the same test.

The model is seen only through ``factory(M) -> HillSystem``: this module never knows which
model it solves.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ConvergenceError, ParameterError
from ..models.base import HillSystem
from .marginal import MarginalTau, marginal_tau

SPATIAL_START = 16    # first M of the refinement
SPATIAL_LIMIT = 512   # the refinement stops (not converged) at this M
TOL_SPATIAL = 1e-3    # default absolute tolerance of tau_min in M
#: Lowest response frequency (units of the forcing frequency) of each Floquet kind: the
#: principal subharmonic resonance at 1/2, the first harmonic one at 1.
RESONANCE = {"harmonic": 1.0, "subharmonic": 0.5}


@dataclass(frozen=True, kw_only=True, eq=False)
class SpatialTau:
    """Per-kind marginal tau at the finer M of the last compared pair.

    taus : kind -> MarginalTau at ``n_spatial`` (temporal error estimate only; see
        :func:`spatial_error`).
    n_spatial, n_spatial_previous : the pair (M, M / 2) compared last.
    change : kind -> :func:`spatial_change` of the pair (tau_min capped at tau_max).
    converged : every change is <= tol_spatial (False only with ``strict=False``: the
        refinement reached ``limit`` first, and the values are those at ``limit``).
    """

    taus: dict[str, MarginalTau]
    n_spatial: int
    n_spatial_previous: int
    change: dict[str, float | None]
    converged: bool


def spatial_change(fine: MarginalTau, coarse: MarginalTau,
                   tau_max: float = math.inf) -> float | None:
    """|tau_min(fine) - tau_min(coarse)| of tau_min capped at tau_max (a missing one counts as
    tau_max); 0 when neither has a tau_min; None when only one has and tau_max is infinite."""
    if fine.tau_min is None and coarse.tau_min is None:
        return 0.0
    if (fine.tau_min is None or coarse.tau_min is None) and not math.isfinite(tau_max):
        return None
    capped = [tau_max if m.tau_min is None else m.tau_min for m in (fine, coarse)]
    return abs(capped[0] - capped[1])


def spatial_error(m: MarginalTau, change: float | None) -> MarginalTau:
    """``m`` with error_estimate = max(temporal estimate, spatial change), or tau_min when the
    change is unknown (None); unchanged when there is no tau_min."""
    if m.tau_min is None:
        return m
    err = m.tau_min if change is None else max(m.error_estimate, change)
    return dataclasses.replace(m, error_estimate=float(err))


def reaches_resonance(system: HillSystem, kind: str, tau_max: float = math.inf) -> bool:
    """Whether some natural frequency w_j of the truncation satisfies
    w_j sqrt(1 + 2 tau_max) > RESONANCE[kind], i.e. the pumped stiffness (at most 1 + 2 tau_max
    times its mean) can bring a mode to the kind's lowest response frequency.

    Notes
    -----
    Counted without computing the w_j: with w = RESONANCE[kind] / sqrt(1 + 2 tau_max), the
    Hermitian part of D(i w) has a positive eigenvalue. For D(i w) = K - w^2 M with K, M
    symmetric positive definite (the inviscid cochlea: kappa C - w^2 diag(2/k)), Sylvester's law
    of inertia makes the number of positive eigenvalues the number of natural frequencies above
    w; viscosity adds a positive added mass (Re D(i w) = K - w^2 M - w (viscous terms)), which
    lowers the frequencies, and the count follows. tau_max = inf gives w = 0 and D(0), positive
    definite: always True.
    """
    w = RESONANCE[kind] / math.sqrt(1.0 + 2.0 * tau_max)
    d = system.unforced(np.array([1j * w]))[0]
    return bool(np.linalg.eigvalsh(0.5 * (d + d.conj().T))[-1] > 0.0)


def solve_at(factory: Callable[[int], HillSystem], n_spatial: int, kinds: Iterable[str],
             options: dict[str, Any]) -> dict[str, MarginalTau]:
    """marginal_tau of each kind with ``n_spatial`` modes (``options``: tol, n_temporal,
    tau_max of :func:`~spectralshell.solvers.marginal.marginal_tau`)."""
    return _solve(factory(n_spatial), kinds, options)


def _solve(system: HillSystem, kinds: Iterable[str], options: dict[str, Any]) -> dict[str, MarginalTau]:
    return {k: marginal_tau(system, k, **options) for k in kinds}


def refine_spatial(factory: Callable[[int], HillSystem], kinds: Iterable[str], *,
                   options: dict[str, Any], tol_spatial: float = TOL_SPATIAL,
                   start: int = SPATIAL_START, limit: int = SPATIAL_LIMIT,
                   strict: bool = True) -> SpatialTau:
    """tau_min of each kind, converged in M = start, 2 start, ... to ``tol_spatial``.

    Parameters
    ----------
    factory : M -> the model's HillSystem with M spatial modes.
    kinds : 'harmonic' and/or 'subharmonic'.
    options : marginal_tau options (tol, n_temporal, tau_max; tau_max also sets the margin of
        :func:`reaches_resonance`).
    start : the first M (a neighbour's M for continuation, see the module notes); < limit.
    limit : the largest M tried.
    strict : raise when ``limit`` is reached unconverged; with False return the values at
        ``limit`` with ``converged = False`` (a map records and flags such points).

    Raises
    ------
    ParameterError : start < 1 or start >= limit.
    ConvergenceError : (strict) not converged by M = limit; or marginal_tau's own, in N.
    """
    kinds = tuple(kinds)
    if not 1 <= start < limit:
        raise ParameterError(f"start = {start!r} is invalid: must be an integer in [1, {limit})")
    tau_max = options.get("tau_max") or math.inf
    m_coarse = start
    system = factory(m_coarse)
    coarse = _solve(system, kinds, options)
    while True:
        m_fine = 2 * m_coarse
        fine_system = factory(m_fine)
        fine = _solve(fine_system, kinds, options)
        change = {k: spatial_change(fine[k], coarse[k], tau_max) for k in kinds}
        short = [k for k in kinds if fine[k].tau_min is None and coarse[k].tau_min is None
                 and not reaches_resonance(system, k, tau_max)]
        converged = not short and all(c is not None and c <= tol_spatial for c in change.values())
        if converged or m_fine >= limit:
            break
        m_coarse, coarse, system = m_fine, fine, fine_system
    if not converged and strict:
        why = f"; n_spatial={m_coarse} does not reach the {' and '.join(short)} resonance" \
            if short else ""
        raise ConvergenceError(
            f"tau_min did not converge to tol_spatial={tol_spatial:g} by n_spatial={m_fine} "
            f"(last changes {list(change.values())}{why}); relax tol_spatial or give n_spatial")
    return SpatialTau(taus=fine, n_spatial=m_fine, n_spatial_previous=m_coarse, change=change,
                      converged=converged)
