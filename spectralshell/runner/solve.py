"""Solving a point: the one place where the marginal tau of a model are solved at given
parameters -- independently (:func:`solve_kinds`, :func:`spatial_point`: ``floquet``,
``tongues``, ``response``) or point by point along the lines of a sweep, continued from a
neighbour (:func:`solve_chunk`: ``sweep``, ``tau_map``, the map figures). Who owns what:

* the truncation schedule in N: :class:`~spectralshell.solvers.marginal.TruncationSchedule`,
  read here for continuation, never restated;
* the refinement in M (models with spatial modes):
  :mod:`spectralshell.solvers.spatial_refinement`, started here from a neighbour's M;
* tol, n_temporal, tau_max: one options mapping (``marginal_tau``'s keywords; a sweep's
  :class:`~spectralshell.params.sweep_grid.SolverOptions` gives them by ``marginal_kwargs``);
* continuation hints (a neighbour's truncation pair, M and tau_min): here, per line.

Continuation along the line axis
--------------------------------
``marginal_tau`` solves the truncations x_0 < x_1 < ... (x_0 just above the model's resonant
index, x_{i+1} = x_i + max(6, x_i // 2): ``solvers.marginal.TruncationSchedule``) until tau_min changes by less than ``tol`` between two
successive ones, and reports the pair (n_previous, n_temporal). Neighbouring points of a line
need about the same pair, so when the neighbour stopped at (x_k, x_{k+1}) with k >= 3, a point
runs the same loop but starts one step lower, at x_{k-1}: it skips x_0 .. x_{k-2}, and, starting
below the neighbour, follows the need down as well as up. It accepts the first pair that passes
the solver's test with a tau <= tau_max at both truncations; if none has up to one step beyond
the neighbour's pair, or there is no tau there, it falls back to the full ``marginal_tau``.

The result is bitwise the independent solve's whenever that converges at the same pair (the
same truncations through the same code); it differs -- by less than ``tol``, the accepted
value passing the same test at a larger N -- only where the independent solve would have stopped
below x_{k-1}. What continuation saves is solver calls (k - 1 per point) rather than
floating-point work, since the skipped truncations are the small ones: see the measurements in
``validation/bench_sweep.py``. The sequence is the solver's own schedule, read from
``TruncationSchedule``, and the acceptance test is the solver's own ``converged_pair``.

Besides the truncation pair, each point passes its neighbour's tau_min to the solver as ``hint``
(``marginal_tau`` / ``truncation_taus``): where a truncation is big enough for the shift-invert
cover (finite tau_max), its first shift sits just below that value. Only speed depends on it; the
values agree with independent solves within their error estimates (tests/test_cochlea_sweep.py).

Spatial modes (the cochlea)
---------------------------
Where the scene leaves the number M of spatial modes open, each point and kind is refined in M
by :func:`~spectralshell.solvers.spatial_refinement.refine_spatial` (each kind on its own, so a
kind is never pushed to a larger M by the other; the values equal ``api.floquet(model, kind=k,
tol_spatial=...)`` at the point), with ``strict=False``: a point that reaches M = 512
unconverged is kept, with its values at M = 512, and flagged ``spatial_converged = False``.
With continuation, a point starts its refinement below its neighbour's last window (at the
neighbour's coarsest M halved, at least 16) instead of at 16. Inside the refinement each M runs
the full temporal loop (no truncation continuation: the M-refinement changes the block size),
with the neighbour's tau_min as the solver's hint. Measured on a sigma line of the Table 5.1
cochlea (1000 Hz, sigma 1e8 .. 2e8, 6 points, both kinds): 175 s without continuation, 56 s with
it, the same values (``validation/bench_sweep.py``).

With the scene option ``over_kinds = "minimum"`` (a minimum-tau map) the kinds are refined
jointly by :func:`~spectralshell.solvers.spatial_refinement.refine_minimum`
(:func:`solve_spatial_minimum`: only the smallest tau_min over the kinds is converged, the other
kind resolved only below it, up to M = 1024), starting with the neighbour's minimising kind.
Such a map plans each point's basis first (:func:`spatial_basis`): where at most
natural_modes.CROWDING natural frequencies of 128 cosine modes lie below the forcing frequency
(low tones), its blocks are the M / 4 lowest natural modes of M cosine modes
(:mod:`spectralshell.discretise.natural_modes`, M from 32), elsewhere the M cosine modes; the
refinement, its window rule, certificates and error estimates are the same in either, and
n_spatial is M. On the seeded 100-point Fig 5.18 sample this took 87 s of CPU against 229 s
in cosine modes throughout, every point within its error estimates of the cosine values.
"""

from __future__ import annotations

import bisect
import dataclasses
import functools
import math
import time
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ConvergenceError, ParameterError, SpectralShellError
from ..models.base import HillSystem
from ..discretise.natural_modes import (CROWDING, PROBE_MODES, RATIO,
                                        START as NATURAL_START, natural_basis_pays,
                                        natural_mode_system)
from ..models.registry import hill_system
from ..params.registry import make_params
from ..params.sphere import nonuniform_params
from ..params.sweep_grid import SolverOptions, SweepSpec
from ..results.records import MarginalTau
from ..solvers.marginal import (Truncation, TruncationSchedule, certified_bound,
                                converged_pair, marginal_tau, truncation_taus)
from ..solvers.spatial_refinement import (MINIMUM_LIMIT, SPATIAL_LIMIT, SPATIAL_RULE,
                                          SPATIAL_START, SpatialTau, refine_minimum,
                                          refine_spatial, solve_fixed, spatial_error)
from .engine import PartialFailure
from .layout import Chunk, block_index, block_shape, chunk_points

#: What the records of a minimum-tau map add to SPATIAL_RULE: its blocks' basis, planned per point
#: (:func:`spatial_basis`). Stores written before it are recomputed once (runner/integrity.py).
NATURAL_RULE = (f"natural basis (M/{RATIO} natural modes of M cosine modes, from M = "
                f"{NATURAL_START}) where at most {CROWDING} natural frequencies of {PROBE_MODES} "
                "cosine modes lie below the forcing frequency")


def spatial_rule(spec: SweepSpec) -> str:
    """The stopping rule of a sweep's refinement in M as its chunk records name it:
    SPATIAL_RULE, and for a minimum-tau map (``over_kinds = "minimum"``) its basis too."""
    return f"{SPATIAL_RULE}; {NATURAL_RULE}" if spec.options.over_kinds == "minimum" \
        else SPATIAL_RULE


#: The solver method of a sweep's points: a sweep stores tau_min only, so the truncations of
#: 2 x 2 block models need only their smallest real tau, certified by the argument principle
#: (:mod:`spectralshell.solvers.contour`); other models solve as 'auto'.
SWEEP_METHOD = "smallest"
#: Result variables of the ask 'tau_min' and their dtypes.
VARIABLES = {"tau_min": np.float64, "has_tau": np.bool_, "error_estimate": np.float64,
             "n_temporal": np.int32, "complete_to": np.float64}
#: Further variables of models with spatial modes (SweepSpec.spatial).
SPATIAL_VARIABLES = {"n_spatial": np.int32, "spatial_converged": np.bool_}
#: Further variables of the sphere with a non-uniform kappa (SweepSpec.nonuniform): the degree
#: truncation of the values and the critical mode's largest (l, k) share (0, 0, 0 where there
#: is no tau_min).
NONUNIFORM_VARIABLES = {"l_max": np.int32, "critical_l": np.int32, "critical_k": np.int32,
                        "critical_share": np.float64}


class SweepError(SpectralShellError, RuntimeError):
    """A sweep could not finish (a point's solve raised, or a worker died); finished chunks are
    kept in the store."""


@dataclass(frozen=True)
class KindSolution:
    """tau_min of one kind at one point: ``has_tau`` False means no marginal tau <= tau_max
    was found, and then tau_min is NaN and error_estimate 0.

    complete_to : no real tau below it was missed (at most tau_max: :func:`solve_chunk` caps
        it): tau_min is the smallest real tau, and an empty answer is proved only up to it (0:
        the zero count could not prove it, an uncertified point; see
        :func:`spectralshell.results.maps.uncertified`).
    n_previous, n_temporal : the truncation pair of the convergence test.
    continued : accepted from the neighbour's truncation pair.
    """

    has_tau: bool
    tau_min: float
    error_estimate: float
    n_temporal: int
    n_previous: int
    continued: bool = False
    complete_to: float = math.inf
    n_spatial: int = 0
    n_spatial_previous: int = 0
    spatial_converged: bool = True
    l_max: int = 0
    critical_l: int = 0
    critical_k: int = 0
    critical_share: float = 0.0


def variables(spec: SweepSpec) -> dict[str, type]:
    """Result variables of a sweep and their dtypes (VARIABLES, plus SPATIAL_VARIABLES for a
    model with spatial modes, NONUNIFORM_VARIABLES for a non-uniform sphere, but l_max where
    it is an axis)."""
    if spec.nonuniform:
        return {**VARIABLES, **{name: dtype for name, dtype in NONUNIFORM_VARIABLES.items()
                                if name not in spec.dims}}
    return {**VARIABLES, **SPATIAL_VARIABLES} if spec.spatial else dict(VARIABLES)


def from_marginal(m: MarginalTau) -> KindSolution:
    """KindSolution of a full ``marginal_tau`` result."""
    if m.tau_min is None:
        return KindSolution(has_tau=False, tau_min=math.nan, error_estimate=0.0,
                            n_temporal=m.n_temporal, n_previous=m.n_previous,
                            complete_to=float(m.complete_to))
    return KindSolution(has_tau=True, tau_min=float(m.tau_min),
                        error_estimate=float(m.error_estimate), n_temporal=m.n_temporal,
                        n_previous=m.n_previous, complete_to=float(m.complete_to))


def solve_kinds(system: HillSystem, kinds: Iterable[str], options: Mapping[str, Any],
                hints: Mapping[str, float | None] | None = None) -> dict[str, MarginalTau]:
    """The marginal tau of each kind at one point, solved independently: ``marginal_tau`` with
    ``options`` (tol, n_temporal, tau_max), its truncations N those of
    :class:`~spectralshell.solvers.marginal.TruncationSchedule`; ``hints``: kind -> a
    neighbour's tau_min, the solver's ``hint`` (only speed depends on it). ``floquet``,
    ``tongues`` (through :func:`solve_points`) and the sweep's fallback all solve here."""
    hints = hints or {}
    return {k: marginal_tau(system, k, **options, hint=hints.get(k)) for k in kinds}


def spatial_point(factory: Callable[[int], HillSystem], kinds: tuple[str, ...],
                  options: Mapping[str, Any], n_spatial: int | None,
                  tol_spatial: float) -> SpatialTau:
    """The marginal tau of each kind of a model with spatial modes at one point (``factory``:
    M -> its Hill system): at the caller's M = ``n_spatial`` and M // 2
    (:func:`~spectralshell.solvers.spatial_refinement.solve_fixed`), or, with None, refined in
    M until tau_min changes by at most ``tol_spatial``, raising past the limit
    (:func:`~spectralshell.solvers.spatial_refinement.refine_spatial`). The sweep refines with
    its neighbours' hints instead (:func:`solve_spatial`)."""
    if n_spatial is None:
        return refine_spatial(factory, kinds, options=dict(options), tol_spatial=tol_spatial)
    return solve_fixed(factory, n_spatial, kinds, dict(options))


def solve_full(system: HillSystem, kind: str, options: SolverOptions,
               tau_hint: float | None = None) -> KindSolution:
    """Independent solve of one kind (:func:`solve_kinds`; ``tau_hint``, a neighbour's
    tau_min, is the solver's ``hint``: only speed depends on it)."""
    found = solve_kinds(system, (kind,), {**options.marginal_kwargs(), "method": SWEEP_METHOD},
                        {kind: tau_hint})[kind]
    return from_marginal(found)


def continuation_start(system: HillSystem, hint: tuple[int, int] | None) -> int | None:
    """Index in this point's sequence where continuation from the neighbour's pair ``hint``
    starts (one step below it), or None when that would skip fewer than two truncations."""
    if hint is None:
        return None
    seq = TruncationSchedule.of(system).sequence()
    k = bisect.bisect_right(seq, hint[0]) - 1  # largest x_k <= hint[0]
    return k - 1 if k >= 3 else None


def _truncation(system: HillSystem, kind: str, n: int, tau_max: float,
                hint: float | None) -> tuple[Truncation, np.ndarray]:
    found = truncation_taus(system, kind, n, tau_max=tau_max, hint=hint, method=SWEEP_METHOD)
    return found, found.tau[found.tau <= tau_max]


def _first(tau: np.ndarray, otherwise: float | None) -> float | None:
    return float(tau[0]) if tau.size else otherwise


def solve_continued(system: HillSystem, kind: str, options: SolverOptions, start: int,
                    tau_hint: float | None = None) -> KindSolution | None:
    """The solver's loop from index ``start`` (one below the neighbour's pair) of this point's
    truncation sequence; None -- leave it to the full solve -- when no pair with a tau <= tau_max
    passes the solver's test (:func:`~spectralshell.solvers.marginal.converged_pair`) up to one
    step beyond the neighbour's pair, or none has a tau at all. The first truncation's ``hint``
    is ``tau_hint`` (the neighbour's tau_min), each later one's the previous truncation's
    tau_min."""
    seq = TruncationSchedule.of(system).sequence()
    previous, prev = _truncation(system, kind, seq[start], options.tau_max, tau_hint)
    for i in range(start + 1, min(start + 4, len(seq))):
        found, tau = _truncation(system, kind, seq[i], options.tau_max, _first(prev, tau_hint))
        if tau.size and prev.size and converged_pair(found, previous, options.tol,
                                                     options.tau_max):
            change = abs(float(tau[0] - prev[0]))
            error = max(change, found.spread, 8 * np.finfo(float).eps * max(1.0, float(tau[0])))
            return KindSolution(has_tau=True, tau_min=float(tau[0]), error_estimate=error,
                                n_temporal=seq[i], n_previous=seq[i - 1], continued=True,
                                complete_to=certified_bound(found, previous))
        if not tau.size and not prev.size:
            return None
        previous, prev = found, tau
    return None


def solve_kind(system: HillSystem, kind: str, options: SolverOptions,
               hint: tuple[int, int] | None = None,
               tau_hint: float | None = None) -> KindSolution:
    """One kind at one point: continued from the neighbour's pair ``hint`` where that saves
    solver calls and converges, else the full solve; ``tau_hint`` (the neighbour's tau_min) is
    passed to the solver as its ``hint``."""
    start = continuation_start(system, hint)
    if start is not None and options.continuation and options.n_temporal is None:
        found = solve_continued(system, kind, options, start, tau_hint)
        if found is not None:
            return found
    return solve_full(system, kind, options, tau_hint)


def spatial_system(model: str, params: dict, n_spatial: int) -> HillSystem:
    """The model's HillSystem at ``params`` with ``n_spatial`` spatial modes (M)."""
    return hill_system(make_params(model, {**params, "n_spatial": n_spatial}))


def natural_system(model: str, params: dict, n_spatial: int) -> HillSystem:
    """The model's HillSystem at ``params`` with ``n_spatial`` cosine modes M projected onto
    their M / RATIO lowest natural modes (:mod:`spectralshell.discretise.natural_modes`)."""
    return natural_mode_system(spatial_system(model, params, n_spatial), n_spatial // RATIO)


def spatial_basis(model: str, params: dict) -> tuple[Callable[[int], HillSystem], int]:
    """(M -> HillSystem, its first M) of a point's minimum-tau refinement, planned before it
    runs: the natural basis (:func:`natural_system`, from M = natural_modes.START) where
    :func:`~spectralshell.discretise.natural_modes.natural_basis_pays` for the point's probe
    truncation, the cosine modes (:func:`spatial_system`, from SPATIAL_START) elsewhere."""
    if natural_basis_pays(spatial_system(model, params, PROBE_MODES)):
        return functools.partial(natural_system, model, params), NATURAL_START
    return functools.partial(spatial_system, model, params), SPATIAL_START


def spatial_start(hint: int | None, first: int = SPATIAL_START) -> int:
    """First M of a point's refinement: below the neighbour's last window (``hint``: its
    coarsest M, halved), at least ``first`` (the basis's own start); ``first`` without a
    neighbour."""
    return first if hint is None else max(first, hint // 2)


def solve_spatial(spec: SweepSpec, params: dict, kind: str, hint: int | None = None,
                  tau_hint: float | None = None) -> KindSolution:
    """One kind at one point, refined in M from :func:`spatial_start` (see the module notes);
    ``tau_hint`` (the neighbour's tau_min) is the solver's ``hint`` at every M."""
    start = spatial_start(hint)
    found = refine_spatial(functools.partial(spatial_system, spec.model, params), (kind,),
                           options={**spec.options.marginal_kwargs(), "hint": tau_hint},
                           tol_spatial=spec.options.tol_spatial, start=start,
                           limit=SPATIAL_LIMIT, strict=False)
    return _spatial_solutions(found, (kind,), start > SPATIAL_START)[kind]


def solve_spatial_minimum(spec: SweepSpec, params: dict, hint: int | None, leader: str | None,
                          tau_hints: dict[str, float | None]) -> dict[str, KindSolution]:
    """Every kind at one point, M refined for the smallest tau_min over the kinds
    (:func:`~spectralshell.solvers.spatial_refinement.refine_minimum`, up to M = MINIMUM_LIMIT):
    the kind attaining it in full, each other kind only below it -- where it has nothing there,
    has_tau is False (tau_min NaN), as where there is none <= tau_max. ``leader``: the
    neighbour's minimising kind, tried first; ``hint``: the neighbour's coarser M; ``tau_hints``: its tau_min per kind
    (the solver's hint). The blocks are those of :func:`spatial_basis` (natural modes where
    they pay); n_spatial is M, the cosine modes behind them, in either basis."""
    factory, first = spatial_basis(spec.model, params)
    start = spatial_start(hint, first)
    kinds = spec.kinds if leader is None else (leader, *(k for k in spec.kinds if k != leader))
    found = refine_minimum(factory, kinds, options=spec.options.marginal_kwargs(),
                           tol_spatial=spec.options.tol_spatial, start=start,
                           limit=MINIMUM_LIMIT, strict=False, hints=tau_hints)
    return _spatial_solutions(found, spec.kinds, start > first)


def _spatial_solutions(found, kinds: tuple[str, ...], continued: bool) -> dict[str, KindSolution]:
    """KindSolution of each kind of a refinement in M (``continued``: started above its
    basis's first M); a kind without a tau below its cap (tau_max, or the minimum for a capped
    kind) gets has_tau False."""
    out = {}
    for k in kinds:
        sol = from_marginal(spatial_error(found.taus[k], found.change[k]))
        out[k] = dataclasses.replace(sol, continued=continued,
                                     n_spatial=found.n_spatial,
                                     n_spatial_previous=found.n_spatial_previous,
                                     spatial_converged=found.converged)
    return out


def _minimising(solutions: dict[str, KindSolution]) -> str | None:
    """The kind with the smallest tau_min among those that have one."""
    found = [k for k, sol in solutions.items() if sol.has_tau]
    return min(found, key=lambda k: solutions[k].tau_min) if found else None


def solve_nonuniform(spec: SweepSpec, params: dict) -> dict[str, KindSolution]:
    """Every kind of the sweep at one point of a non-uniform sphere: its ``floquet``
    (:func:`~spectralshell.runner.nonuniform.floquet_nonuniform` with the sweep's kinds and
    options), with the degree truncation and the critical mode's largest (l, k) share."""
    from .nonuniform import floquet_nonuniform

    kind = "both" if len(spec.kinds) == 2 else spec.kinds[0]
    res = floquet_nonuniform(nonuniform_params(params), kind=kind,
                             tol_spatial=spec.options.tol_spatial,
                             options=spec.options.marginal_kwargs())
    out = {}
    for k in spec.kinds:
        sol = dataclasses.replace(from_marginal(getattr(res, k)), l_max=res.l_max)
        if k in res.content:
            lead = res.content[k][0]
            sol = dataclasses.replace(sol, critical_l=lead["l"], critical_k=lead["k"],
                                      critical_share=lead["share"])
        out[k] = sol
    return out


def _fixed_modes(params: dict) -> int:
    """M of a point with the spatial truncation given (1 for a single spatial_mode)."""
    return int(params.get("n_spatial") or 1)


@dataclass(frozen=True, eq=False)
class ChunkResult:
    """Solved block of one chunk: arrays of ``block_shape`` per variable, compute time (s) in
    the worker, and how many kind solves were accepted from continuation / fell back.
    ``point_seconds`` (block shape): the time of each kind solve (not stored: it varies between
    runs; for cost maps)."""

    index: int
    arrays: dict[str, np.ndarray]
    seconds: float
    continued: int
    fallbacks: int
    point_seconds: np.ndarray | None = None


def _describe(values: dict, kind: str, params: dict) -> str:
    where = ", ".join(f"{k} = {v!r}" for k, v in {**values, "kind": kind}.items())
    given = ", ".join(f"{k} = {v!r}" for k, v in params.items())
    return f"point {where} (parameters: {given})"


def _point_error(exc: Exception, values: dict, kind: str, params: dict) -> Exception:
    """The error of a failed point, naming the point and its parameters (one line)."""
    first_line = str(exc).splitlines()[0] if str(exc) else ""
    text = f"{_describe(values, kind, params)} failed: {first_line}"
    if isinstance(exc, ConvergenceError):
        return ConvergenceError(text)
    if isinstance(exc, ParameterError):
        return ParameterError(text)
    return SweepError(f"{text} ({type(exc).__name__})")


def solve_chunk(spec: SweepSpec, chunk: Chunk) -> ChunkResult:
    """Solve every point and kind of a chunk in line order, each point continuing from the
    previous one (when ``spec.options.continuation``): in the truncation N, or, where M is
    refined per point, in M.

    Raises
    ------
    ConvergenceError, ParameterError, SweepError : a point failed; the message names it.
    """
    t0 = time.perf_counter()
    shape = block_shape(spec, chunk)
    names = variables(spec)
    arrays = {name: np.zeros(shape, dtype=dtype) for name, dtype in names.items()}
    stored = tuple(name for name in names if name != "complete_to")  # complete_to: capped
    point_seconds = np.zeros(shape)
    hints: dict[str, tuple[int, int] | None] = {k: None for k in spec.kinds}
    spatial_hints: dict[str, int | None] = {k: None for k in spec.kinds}
    tau_hints: dict[str, float | None] = {k: None for k in spec.kinds}  # the solver's hint
    leader: str | None = None  # over_kinds = 'minimum': the neighbour's minimising kind
    continued = fallbacks = 0
    continuing = spec.options.continuation and spec.options.n_temporal is None
    joint_wanted = (spec.refines_spatial and spec.options.over_kinds == "minimum"
                    and len(spec.kinds) > 1)
    for j, values in chunk_points(spec, chunk):
        params = spec.params_at(values)
        kind = spec.kinds[0]
        try:
            system = None if spec.refines_spatial or spec.nonuniform else hill_system(
                make_params(spec.model, params))
            joint = None
            if spec.nonuniform:
                started = time.perf_counter()
                joint = solve_nonuniform(spec, params)
                joint_seconds = time.perf_counter() - started
            elif joint_wanted:
                started = time.perf_counter()
                go_on = spec.options.continuation
                joint = solve_spatial_minimum(spec, params,
                                              spatial_hints[spec.kinds[0]] if go_on else None,
                                              leader if go_on else None,
                                              tau_hints if go_on else {})
                joint_seconds = time.perf_counter() - started
                leader = _minimising(joint)
            for q, kind in enumerate(spec.kinds):
                started = time.perf_counter()
                if joint is not None:
                    sol = joint[kind]
                    spatial_hints[kind] = sol.n_spatial_previous
                elif system is None:
                    hint = spatial_hints[kind] if spec.options.continuation else None
                    sol = solve_spatial(spec, params, kind, hint, tau_hints[kind])
                    spatial_hints[kind] = sol.n_spatial_previous
                else:
                    hint = hints[kind] if continuing else None
                    sol = solve_kind(system, kind, spec.options, hint, tau_hints[kind])
                    hints[kind] = (sol.n_previous, sol.n_temporal) if sol.has_tau else None
                    # a fallback: continuation was tried (it had a start) and not accepted
                    fallbacks += (not sol.continued
                                  and continuation_start(system, hint) is not None)
                    if spec.spatial:
                        sol = dataclasses.replace(sol, n_spatial=_fixed_modes(params))
                if spec.options.continuation:
                    tau_hints[kind] = sol.tau_min if sol.has_tau else None
                continued += sol.continued
                at = block_index(spec, j, q)
                for name in stored:
                    arrays[name][at] = getattr(sol, name)
                arrays["complete_to"][at] = min(sol.complete_to, spec.options.tau_max)
                # the joint solve's time is booked on the first kind (a cell sums its kinds)
                point_seconds[at] = (time.perf_counter() - started if joint is None else
                                     joint_seconds if q == 0 else 0.0)
        except Exception as exc:  # noqa: BLE001 - re-raised naming the point
            raise _point_error(exc, values, kind, params) from exc
    return ChunkResult(index=chunk.index, arrays=arrays, seconds=time.perf_counter() - t0,
                       continued=int(continued), fallbacks=int(fallbacks),
                       point_seconds=point_seconds)


def solve_chunks(spec: SweepSpec, batch: tuple[Chunk, ...]) -> list[ChunkResult]:
    """Solve the chunks of one task in order (:func:`solve_chunk` each).

    Raises
    ------
    PartialFailure : a chunk failed; it carries the chunks solved before it (kept in the store)
        and the chunk's error, as :func:`solve_chunk` raised it.
    """
    done: list[ChunkResult] = []
    for chunk in batch:
        try:
            done.append(solve_chunk(spec, chunk))
        except Exception as exc:  # noqa: BLE001 - delivered with the finished chunks
            raise PartialFailure(done, exc) from None
    return done


def solve_points(factory, points: list, kinds: tuple[str, ...],
                 options: dict) -> list[dict[str, MarginalTau]]:
    """Full ``marginal_tau`` of each kind at each point (``factory(point)`` -> HillSystem): the
    task of :func:`spectralshell.runner.map_points`."""
    return [solve_kinds(system, kinds, options) for system in map(factory, points)]
