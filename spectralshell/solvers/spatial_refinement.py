"""Convergence of tau_min in the number M of spatial modes (models with a spatial truncation).

A model whose Hill blocks carry M spatial modes (the cochlea's cosine modes, thesis 5.3) is solved
at M = 16, 24, 32, 48, 64, 96, ... (the ladder of :func:`finer_spatial`: powers of two and 3/2 of
them) until, over a *window* of three successive M of the ladder, L / 2 < L' < L, every asked kind's
tau_min at L differs by at most ``tol_spatial`` (absolute) from its value at L / 2 and at L'. The
pair (L / 2, L) is the thesis's spatial error epsilon_M = |tau_2M - tau_M| of 5.3 (Fig 5.6), used
here as a stopping rule; the middle M L' guards it against two truncations too coarse to resolve the
resonant wave that agree by chance. On the seeded 100-point Fig 5.18 sample of
validation/bench_sweep.py the pair alone (on M = 16, 32, 64, ...) passed at M = 64 for two points
whose tau_min moved on by 56 and 27 times the reported change: the human cochlea at 2826 Hz,
sigma = 2.72e8 g cm^-2 s^-2 (tau_min at M = 32, 48, 64: 0.029229, 0.047184, 0.029293; 0.032849 from
M = 128 on) and at 17.2 kHz, sigma = 1.06e9 (0.038589, 0.037211, 0.039216; 0.022488 from M = 192
on). The window ends them at M = 192 and 256 on the converged values; the sample as a whole costs
the same (239 s against 232 s CPU, side by side), since the ladder's finer steps end most points at
a smaller M than doubling. Refinements of the plain rule:

* Cap. With a finite tau_max the compared quantity is tau_min capped at tau_max (what a sweep
  stores: tau_max where there is none), so a tau_min just below tau_max at one M and none at the
  other differ by tau_max - tau_min. Near tau_max = 1/2, tau_min often leaves and re-enters the
  interval from one M to the next; uncapped, such points would refine to the limit. Without
  tau_max, a kind with a tau_min at only some M of the window has not converged.
* Reach. A kind with no tau_min <= tau_max at any M of the window has converged only if its coarsest
  M already reaches the kind's resonance (:func:`reaches_resonance`): some natural frequency of the
  truncation, pumped to at most sqrt(1 + 2 tau_max) times itself, attains the kind's lowest response
  frequency (1/2 subharmonic, 1 harmonic). Without it a truncation too short to carry the resonant
  waves finds no tau at M = 16 and 32 and stops there: e.g. the cochlea of Table 5.1 at f = 20 kHz,
  sigma = 1e8 g cm^-2 s^-2 (kappa = 5.7e-3) has a subharmonic tau_min = 0.049 from M = 128 on, and
  none at M <= 64.

The window that passed is reported by its coarsest and finest M (L / 2, L) with the change of
each kind, the larger of its two changes, and ``spatial_error`` folds the change into the
temporal error estimate: max(temporal estimate, change), or tau_min itself when there is no
change to compare (as the temporal estimate does with nothing to compare).

Work reuse. Each M is solved once: a window shares two of its M with the next.
Nothing is shared between different M (the blocks of M modes are a leading corner of those of
2M, but the eigenproblem does not split), and the temporal loop of each M restarts at its own
first truncation: its smaller truncations cost a few per cent of the largest.

Hopeless last step. When the next window would be the last (its finest M = ``limit``), every
change already passes, and only the reach test fails -- a kind found nothing in the window and
its middle M, the next window's coarsest, does not reach the kind's resonance either -- that
window fails the reach test too, so the refinement stops at once, unconverged, with the values
at the finest M: the solves at ``limit``, the costliest, would decide nothing and change no
value beyond tol_spatial (only a tau appearing at ``limit`` within tol_spatial of the other
values could have passed there).
Where a value still moves, the last step is taken.

Hint of the coarser M. At each M every kind's solver ``hint`` (where the shift-invert
cover of its big truncations starts, :func:`~spectralshell.solvers.marginal.marginal_tau`) is
its tau_min at the M before it, where it has one (:func:`coarser_hints`); only speed depends on
it.

Continuation. A caller that solves neighbouring points (a sweep line) may pass ``start`` = a
neighbour's coarsest M halved instead of SPATIAL_START: the solves below it are skipped, and
the need can still fall by half per point. The result equals the independent solve's whenever
that one passes at a window at or above the first from ``start``; otherwise it is the value at
a larger M, which passed the same test.

Minimum over kinds (:func:`refine_minimum`). A map of the smallest marginal tau over both kinds
(thesis Fig 5.18) needs only the kind attaining it resolved; the other kind needs only the
certainty that it has no tau below it. So at each M the kinds are solved in turn, the one that
attained the minimum at the previous M first, each later one with tau_max lowered to the
smallest tau_min found so far at this M (its *cap*). Where the other kind's tau lie above the
minimum this costs a few truncations instead of a full temporal convergence: e.g. the human
cochlea (Table 5.1) at f = 50 Hz, sigma = 2e9 g cm^-2 s^-2, where the subharmonic kind has only
high-order resonances crowding towards tau = 1/2 (temporal truncations to N = 300 at M = 16, 32,
64) while the harmonic tau_min = 0.483 converges at N = 60: 45 s jointly against 944 s for the
two kinds refined on their own (one thread; validation of the minimum against dense QZ and the
per-kind refinement in tests/test_spatial_refinement_minimum.py). The tests of the plain rule
apply per kind with the smallest of the kind's caps in the window in place of tau_max (a tau_min
above the cap counts as the cap), and the minimum itself must change by at most ``tol_spatial``. The
reach test keeps the margin tau_max: a capped kind that found nothing below its cap in the window
needs what the plain rule asks to certify nothing below tau_max, a stronger statement. (Its own cap
as the margin would ask for more -- the harmonic kind under a subharmonic minimum of 0.079 of the
human cochlea at f = 6 kHz, sigma = 1e7 is not reached at M = 256 with margin 0.079 -- and flag
points that the per-kind refinement certifies.)

Proof of empty answers. With ``certify_empty`` among the options (and no ``n_temporal``), each
M is solved without it, and only the window that ends the refinement has its empty answers
proved (:func:`~spectralshell.solvers.marginal.certify_empty_answer`): those of the finest M,
which are returned (the same proof and the same answer as certifying every M), and those of
the two coarser M, on which the window's changes and reach test rest (a coarse truncation that
missed a real tau below the cap would otherwise pass with change 0, and put 0 into the error
estimate). The counts at the other M decided nothing that is returned (on a crowded Fig 5.18
cell, human 63.6 Hz, sigma = 1.85e9, the counts at M = 16, which fail after their 500 nodes,
and at M = 32 were 9.5 s of its 42 s; issue 25). Where a coarser M's empty answer of a passing
window cannot be proved, that kind's change is unknown (None: the error estimate is tau_min
itself) and the window has not converged: the refinement goes on while the finest M's answers
are proved (the next window's middle M), and stops there otherwise, unconverged, with the
finest M's unproved answer marked (its next window could not pass either). With
``certify_empty=True`` an empty answer of the finest M that cannot be proved raises; with
``strict`` an unconverged end raises as at the limit.
Cost of the coarser M's proof, measured with the pair rule (seeded Fig 5.18 sample cells, each alone
as validation/bench_sweep.py solves it, one BLAS thread, CPU time, 2 cores under a load of 5-8): the
crowded cell (human, 63.6 Hz, sigma = 1.85e9, pair M = 32, 64; its subharmonic empty below the
harmonic 0.4944, where the disk bound fails and the count walks) 58.6 and 64.4 s before, 66.1 and
68.6 s after (alternately), of which the count at M = 32 is 7.6 s (the one at M = 64 17.4 s);
the M = 16 counts stay dropped. Where the disk bound proves the empty kind it is a few per cent:
human 8353 Hz, sigma = 5.7e8 (M = 128, 256) 0.13 s of 3.2 s; gerbil 35.5 kHz, sigma = 1.54e8
(M = 256, 512) 0.71 s of 13.9 s.

A kind with no tau below its cap at one M is solved at the next M with
``expect_empty`` (:func:`~spectralshell.solvers.marginal.marginal_tau`): its truncations are
tried first by the zero count (its disk bound first), which replaces the Krylov solve where it
proves them empty and makes their later proof free (``empty_proved``); where it fails, the
proof of that answer at its cap fails at once (``count_failed``: the same count, not walked
twice). The values are the same.

Threads. Every solve and proof here runs on one BLAS thread (marginal_tau and
certify_empty_answer limit themselves for blocks larger than 2 x 2:
:func:`~spectralshell.solvers.marginal.on_block_threads`; the reach test here): their work is
LAPACK and BLAS calls on M x M blocks (M <= 1024), where OpenBLAS's threads only cost.
Measured on the 2826 Hz point of tests/test_spatial_refinement_window.py (refine_minimum, M to
192, 2 cores, nothing else running): 11.6 s wall (22.7 s CPU) on OpenBLAS's two threads,
1.43 s on one.

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

from .._threads import one_blas_thread
from ..errors import ConvergenceError, ParameterError
from ..models.base import HillSystem
from ..results.records import MarginalTau
from .marginal import certify_empty_answer, marginal_tau

SPATIAL_START = 16    # first M of the refinement
SPATIAL_LIMIT = 512   # the refinement stops (not converged) at this M
#: Limit of :func:`refine_minimum`: only the minimum's kind (and a capped solve of the other)
#: is pushed there. Fig 5.18's default 6 x 6 grids: M = 1024 settles the human cochlea at
#: 20 kHz, sigma = 8.3e7 and the gerbil at 50 kHz, sigma = 1.5e8 (~90 s each, one thread).
MINIMUM_LIMIT = 2 * SPATIAL_LIMIT
TOL_SPATIAL = 1e-3    # default absolute tolerance of tau_min in M
#: The stopping rule of the module notes, by name. A sweep chunk's completion record carries it
#: (runner/integrity.py), so that chunks of a store written under another rule (before it, the
#: pair (M / 2, M) alone: two coarse M that agree by chance passed) are recomputed on a rerun,
#: not mixed with this rule's values.
SPATIAL_RULE = "window of three M: L/2, middle, L"
#: Lowest response frequency (units of the forcing frequency) of each Floquet kind: the
#: principal subharmonic resonance at 1/2, the first harmonic one at 1.
RESONANCE = {"harmonic": 1.0, "subharmonic": 0.5}


@dataclass(frozen=True, kw_only=True, eq=False)
class SpatialTau:
    """Per-kind marginal tau at the finest M of the last compared window.

    taus : kind -> MarginalTau at ``n_spatial`` (temporal error estimate only; see
        :func:`spatial_error`).
    n_spatial, n_spatial_previous : the finest and coarsest M of the window compared last,
        L and L / 2 on the ladder (None: M = 1 alone).
    change : kind -> the larger :func:`spatial_change` between the window's finest M and
        each of its two coarser M (tau_min capped at tau_max, or at
        the smaller of the kind's two caps with :func:`refine_minimum`); None where it is
        unknown, e.g. the kind's empty answer at a coarser M is not proved (module notes,
        "Proof of empty answers").
    converged : every change is <= tol_spatial (False only with ``strict=False``: the
        refinement reached ``limit``, or a hopeless last step, or a window whose coarser M's
        empty answer is not proved, first; the values are those at ``n_spatial``).
    caps : kind -> the tau_max its ``taus`` entry was solved with at ``n_spatial``: tau_max
        (:func:`refine_spatial`), or below it for a kind that did not attain the minimum
        (:func:`refine_minimum`; its tau_min None then means no tau <= its cap).
    """

    taus: dict[str, MarginalTau]
    n_spatial: int
    n_spatial_previous: int | None
    change: dict[str, float | None]
    converged: bool
    caps: dict[str, float] = dataclasses.field(default_factory=dict)


def finer_spatial(m: int) -> int:
    """The M after ``m`` (>= 1) on the refinement's ladder 1, 2, 3, 4, 6, 8, 12, 16, 24, ...:
    the powers of two and 3/2 of them, so that every M >= 4 on it has M / 2 two steps below."""
    k = m.bit_length() - 1
    return 3 << (k - 1) if k >= 1 and m < 3 << (k - 1) else 1 << (k + 1)


def spatial_ladder(start: int, limit: int) -> tuple[int, ...]:
    """The M a refinement from ``start`` may solve, up to ``limit``: start,
    finer_spatial(start), ..."""
    out = [start]
    while out[-1] < limit:
        out.append(finer_spatial(out[-1]))
    return tuple(m for m in out if m <= limit)


def spatial_change(fine: MarginalTau, coarse: MarginalTau,
                   tau_max: float = math.inf) -> float | None:
    """|tau_min(fine) - tau_min(coarse)| of tau_min capped at tau_max (a missing one counts as
    tau_max); 0 when neither has a tau_min; None when only one has and tau_max is infinite."""
    return _capped_change(fine.tau_min, coarse.tau_min, tau_max)


def _capped_change(fine: float | None, coarse: float | None, cap: float) -> float | None:
    if fine is None and coarse is None:
        return 0.0
    if (fine is None or coarse is None) and not math.isfinite(cap):
        return None
    capped = [cap if t is None else min(t, cap) for t in (fine, coarse)]
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
    with one_blas_thread():  # an M x M matrix (module notes, "Threads")
        return bool(np.linalg.eigvalsh(0.5 * (d + d.conj().T))[-1] > 0.0)


def solve_at(factory: Callable[[int], HillSystem], n_spatial: int, kinds: Iterable[str],
             options: dict[str, Any]) -> dict[str, MarginalTau]:
    """marginal_tau of each kind with ``n_spatial`` modes (``options``: tol, n_temporal,
    tau_max of :func:`~spectralshell.solvers.marginal.marginal_tau`)."""
    return _solve(factory(n_spatial), tuple(kinds), options, joint=False)[0]


def solve_fixed(factory: Callable[[int], HillSystem], n_spatial: int, kinds: Iterable[str],
                options: dict[str, Any]) -> SpatialTau:
    """tau_min of each kind at the caller's M = ``n_spatial``, with the change from M // 2 (none
    for M = 1) as its spatial error: the thesis's epsilon_M of 5.3 (Fig 5.6); unknown (None)
    where the kind's empty answer at M // 2 is not proved (``certify_empty`` with a fixed
    ``n_temporal`` marks it, complete_to below tau_max). Nothing is refined, so ``converged``
    is True."""
    kinds = tuple(kinds)
    fine = solve_at(factory, n_spatial, kinds, options)
    coarse = solve_at(factory, n_spatial // 2, kinds, options) if n_spatial > 1 else None
    cap = options.get("tau_max") or math.inf
    doubt = [] if coarse is None else _unproved(coarse, dict.fromkeys(kinds, cap))
    change = {k: None if coarse is None or k in doubt else spatial_change(fine[k], coarse[k], cap)
              for k in kinds}
    return SpatialTau(taus=fine, n_spatial=n_spatial, n_spatial_previous=n_spatial // 2 or None,
                      change=change, converged=True, caps={k: cap for k in kinds})


def minimum(taus: dict[str, MarginalTau]) -> float | None:
    """The smallest tau_min over the kinds of ``taus`` (None if no kind has one)."""
    found = [m.tau_min for m in taus.values() if m.tau_min is not None]
    return min(found) if found else None


def _solve(system: HillSystem, kinds: tuple[str, ...], options: dict[str, Any], joint: bool,
           hints: dict[str, float | None] | None = None,
           empty: Iterable[str] = ()) -> tuple[dict[str, MarginalTau], dict[str, float]]:
    """(marginal_tau of each kind, the tau_max each was solved with), the kinds in the given
    order; ``joint``: each kind's tau_max is lowered to the smallest tau_min found before it.
    ``hints``: kind -> marginal_tau's ``hint`` in place of options' (dropped above the cap).
    ``empty``: the kinds solved with ``expect_empty`` (none below their cap at the coarser M)."""
    cap = options.get("tau_max") or math.inf
    taus, caps = {}, {}
    for k in kinds:
        caps[k] = cap
        own = {} if hints is None else {"hint": _below(hints.get(k), cap)}
        if k in empty:
            own["expect_empty"] = True
        taus[k] = marginal_tau(system, k, **{**options, "tau_max": cap, **own})
        if joint and taus[k].tau_min is not None:
            cap = min(cap, taus[k].tau_min)
    return taus, caps


def coarser_hints(coarse: dict[str, MarginalTau], hints: dict[str, float | None] | None,
                  default: float | None) -> dict[str, float | None]:
    """The solver's hint of each kind at the next M: its tau_min at the coarser M, which the
    refinement expects to move by about ``tol_spatial``, else the caller's (``hints``, or
    ``default``: a neighbour's tau_min)."""
    own = {} if hints is None else hints
    return {k: m.tau_min if m.tau_min is not None else own.get(k, default)
            for k, m in coarse.items()}


def _below(hint: float | None, cap: float) -> float | None:
    return hint if hint is not None and hint <= cap else None


def _leader_first(kinds: tuple[str, ...], taus: dict[str, MarginalTau]) -> tuple[str, ...]:
    """``kinds`` with the one attaining :func:`minimum` of ``taus`` first (unchanged if none)."""
    low = minimum(taus)
    lead = next((k for k in kinds if taus[k].tau_min == low), None) if low is not None else None
    return kinds if lead is None else (lead, *(k for k in kinds if k != lead))


def _none_below(m: MarginalTau, cap: float) -> bool:
    return m.tau_min is None or m.tau_min > cap


def refine_spatial(factory: Callable[[int], HillSystem], kinds: Iterable[str], *,
                   options: dict[str, Any], tol_spatial: float = TOL_SPATIAL,
                   start: int = SPATIAL_START, limit: int = SPATIAL_LIMIT,
                   strict: bool = True) -> SpatialTau:
    """tau_min of each kind, converged in M = start, finer_spatial(start), ... to
    ``tol_spatial`` over a window of three successive M (module notes).

    Parameters
    ----------
    factory : M -> the model's HillSystem with M spatial modes.
    kinds : 'harmonic' and/or 'subharmonic'.
    options : marginal_tau options (tol, n_temporal, tau_max; tau_max also sets the margin of
        :func:`reaches_resonance`).
    start : the first M (a neighbour's M for continuation, see the module notes); its
        window of three M must fit below ``limit`` (start <= limit // 2 suffices for start > 1).
    limit : the largest M tried (the last window's finest M is the last of :func:`spatial_ladder`).
    strict : raise when ``limit`` is reached unconverged (or the last step is hopeless, or
        an empty answer of the last window cannot be proved, see the module notes); with False
        return the values at the last M with ``converged = False`` (a map records and flags
        such points).

    Raises
    ------
    ParameterError : start < 1, or its first window exceeds ``limit``.
    ConvergenceError : (strict) not converged by M = limit; or marginal_tau's own, in N.
    """
    return _refine(factory, tuple(kinds), options, tol_spatial, start, limit, strict, joint=False)


def refine_minimum(factory: Callable[[int], HillSystem], kinds: Iterable[str], *,
                   options: dict[str, Any], tol_spatial: float = TOL_SPATIAL,
                   start: int = SPATIAL_START, limit: int = MINIMUM_LIMIT,
                   strict: bool = True,
                   hints: dict[str, float | None] | None = None) -> SpatialTau:
    """The smallest tau_min over ``kinds``, converged in M as :func:`refine_spatial` does, each
    kind but the minimum's resolved only up to it (module notes, "Minimum over kinds").

    Parameters and errors as :func:`refine_spatial` (``limit`` by default MINIMUM_LIMIT);
    ``kinds`` in the order tried at ``start``
    (put first the kind expected to attain the minimum, e.g. a neighbour's). The result's
    ``caps`` say up to where each kind was resolved; :func:`minimum` of its ``taus`` is the
    converged value, and each kind's ``change`` is that of tau_min capped at its cap.
    ``hints``: kind -> a tau expected near its tau_min (e.g. a neighbour's), marginal_tau's
    ``hint`` for that kind at every M (not passed where it exceeds the kind's cap); only speed
    depends on it.
    """
    return _refine(factory, tuple(kinds), options, tol_spatial, start, limit, strict, joint=True,
                   hints=hints)


@dataclass(frozen=True, eq=False)
class _Level:
    """One M of a refinement: its system, each kind's tau and the cap it was solved with, and
    whether its empty answers are proved (or marked)."""

    m: int
    system: HillSystem
    taus: dict[str, MarginalTau]
    caps: dict[str, float]
    proved: bool = False


def _refine(factory: Callable[[int], HillSystem], kinds: tuple[str, ...], options: dict[str, Any],
            tol_spatial: float, start: int, limit: int, strict: bool, joint: bool,
            hints: dict[str, float | None] | None = None) -> SpatialTau:
    if not (isinstance(start, int) and start >= 1 and finer_spatial(finer_spatial(start)) <= limit):
        raise ParameterError(f"start = {start!r} is invalid: must be an integer >= 1 with a window "
                             f"of three M up to limit = {limit} (at most {limit // 2})")
    tau_max = options.get("tau_max") or math.inf
    certify = options.get("certify_empty", False) if options.get("n_temporal") is None else False
    if certify:  # proved for the finest M alone, the one kept (module notes)
        options = {**options, "certify_empty": False}

    def solve(m: int, below: _Level | None) -> _Level:
        system = factory(m)
        if below is None:
            taus, caps = _solve(system, kinds, options, joint, hints)
            return _Level(m, system, taus, caps)
        order = _leader_first(kinds, below.taus) if joint else kinds
        taus, caps = _solve(system, order, options, joint,
                            coarser_hints(below.taus, hints, options.get("hint")),
                            [k for k, t in below.taus.items() if t.tau_min is None])
        return _Level(m, system, {k: taus[k] for k in kinds}, {k: caps[k] for k in kinds})

    window = [solve(start, None)]
    window.append(solve(finer_spatial(start), window[0]))
    while True:
        window = [*window[-2:], solve(finer_spatial(window[-1].m), window[-1])]
        coarse, fine = window[0], window[-1]
        caps = {k: min(level.caps[k] for level in window) for k in kinds}
        change = {k: _worst(_capped_change(fine.taus[k].tau_min, level.taus[k].tau_min, caps[k])
                            for level in window[:-1]) for k in kinds}
        short = [k for k in kinds if all(_none_below(level.taus[k], caps[k]) for level in window)
                 and not reaches_resonance(coarse.system, k, tau_max)]
        settled = all(c is not None and c <= tol_spatial for c in change.values())
        if joint:
            low = _worst(_capped_change(minimum(fine.taus), minimum(level.taus), tau_max)
                         for level in window[:-1])
            settled = settled and low is not None and low <= tol_spatial
        converged = settled and not short
        last = finer_spatial(fine.m) > limit  # no later window fits below limit
        # the next window, the last, could not pass: its coarsest M (this middle one) does not
        # reach either
        hopeless = settled and not converged and not last \
            and finer_spatial(finer_spatial(fine.m)) > limit \
            and any(not reaches_resonance(window[1].system, k, tau_max) for k in short)
        doubt: list[str] = []
        if certify and (converged or hopeless or last):
            window = [level if level.proved else
                      dataclasses.replace(level, proved=True, taus=_proved(
                          level.system, level.taus, level.caps,
                          certify if level is fine else "mark"))
                      for level in window]
            coarse, fine = window[0], window[-1]
            doubt = sorted({k for level in window[:-1] for k in _unproved(level.taus, level.caps)})
            change.update(dict.fromkeys(doubt, None))
            if doubt and converged:
                converged = False
                if not last and not _unproved(fine.taus, fine.caps):
                    continue
            break
        if converged or hopeless or last:
            break
    if not converged and strict:
        why = f"; n_spatial={coarse.m} does not reach the {' and '.join(short)} resonance" \
            if short else ""
        if doubt:
            at = ", ".join(str(level.m) for level in window[:-1]
                           if _unproved(level.taus, level.caps))
            why += (f"; the empty {' and '.join(doubt)} answer at n_spatial={at} is not "
                    "proved by the zero count")
        raise ConvergenceError(
            f"tau_min did not converge to tol_spatial={tol_spatial:g} by n_spatial={fine.m} "
            f"(last changes {list(change.values())}{why}); relax tol_spatial or give n_spatial")
    return SpatialTau(taus=fine.taus, n_spatial=fine.m, n_spatial_previous=coarse.m,
                      change=change, converged=converged, caps=fine.caps)


def _worst(changes: Iterable[float | None]) -> float | None:
    """The largest of ``changes``, None if any is None."""
    out = 0.0
    for c in changes:
        if c is None:
            return None
        out = max(out, c)
    return out


def _proved(system: HillSystem, taus: dict[str, MarginalTau], caps: dict[str, float],
            certify: bool | str) -> dict[str, MarginalTau]:
    """``taus`` (solved at ``caps``) with each empty answer proved or marked
    (:func:`~spectralshell.solvers.marginal.certify_empty_answer`)."""
    return {k: certify_empty_answer(system, k, m, caps[k], certify) for k, m in taus.items()}


def _unproved(taus: dict[str, MarginalTau], caps: dict[str, float]) -> list[str]:
    """The kinds whose empty answer :func:`_proved` marked: complete_to below their cap."""
    return [k for k, m in taus.items() if m.unproved_empty(caps[k])]
