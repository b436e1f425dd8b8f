"""Floquet computations of a model: marginal tau (with refinement in the spatial modes),
Ince-Strutt diagrams, tau maps, exponents, degree stability and planned scenes."""

from __future__ import annotations

import dataclasses
import functools
import itertools
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .._validate import require_int_in_range, require_positive, require_real
from ..discretise.fourier import expand_kind
from ..errors import ConvergenceError, ParameterError
from ..models.base import HillSystem
from ..models.registry import hill_system
from ..params.grid import parse_int_range, parse_range
from ..params.limits import RESULT_BYTES, SECONDS, check_grid, check_points
from ..params.sweep_grid import physical_names, sweep_spec
from ..params.physical import physical_inputs
from ..params.sphere import is_nonuniform, nonuniform_params
from ..params.stiffness import amplitude_warnings, threshold_warnings
from ..params.registry import (check_model, get_model, int_bounds, make_params, param_fields,
                               physical_values, require_capability)
from ..params.scene import Plan, plan
from ..results.spatial import SpatialFloquetResult
from ..results.floquet import (ExponentsResult, FloquetResult, StabilityResult, TonguesResult,
                              certification_warnings, provenance, resolution_warnings)
from ..solvers.cost import CostEstimate, spatial_cost
from ..solvers.exponents import distance, floquet_exponents
from ..solvers.marginal import N_MAX
from ..solvers.spatial_refinement import TOL_SPATIAL, spatial_error
from .solve import solve_kinds, spatial_point, spatial_system
from .progress import progress_bar
from ..solvers.tongues import (BOUNDARY_DTAU, BOUNDARY_MIN_DKAPPA, BOUNDARY_TAU_MAX, boundary_taus,
                               find_tips, link_boundaries, refinement_points)

if TYPE_CHECKING:
    import xarray as xr


def solver_options(tol: float, n_temporal: int | None, tau_max: float | None = None) -> dict[str, Any]:
    tol = require_positive("tol", tol)
    if n_temporal is not None:
        n_temporal = require_int_in_range("n_temporal", n_temporal, 1, N_MAX)
    options = {"tol": tol, "n_temporal": n_temporal}
    if tau_max is not None:
        options["tau_max"] = require_positive("tau_max", tau_max)
    return options


#: floquet's answers: an empty one (no tau <= tau_max) of a viscous model is proved by the zero
#: count at both truncations, or refused (marginal_tau's ``certify_empty``; issue 23, section 2).
CERTIFIED = {"certify_empty": True}
#: The maps' answers (tongues' rows; sweeps say it in SolverOptions.marginal_kwargs): the same
#: proof, but a point it cannot prove is kept, marked by complete_to = 0, and counted.
MARKED = {"certify_empty": "mark"}


def _system(model: str, params: Mapping[str, Any]) -> tuple[Any, HillSystem]:
    p = make_params(model, dict(params))
    return p, hill_system(p)


def floquet(model: str, *, kind: str = "both", tol: float = 1e-10, n_temporal: int | None = None,
            tau_max: float | None = None, tol_spatial: float | None = None,
            max_seconds: float | None = None, progress: bool = False,
            **params: Any) -> FloquetResult:
    """Marginal forcing amplitudes tau (Floquet boundaries) of a model.

    Parameters
    ----------
    model : a name from ``spectralshell.params.registry.models()`` ('mathieu', 'sphere', ...).
    kind : 'both', 'harmonic' (gamma = 0) or 'subharmonic' (gamma = i/2); only those are computed.
    tol : absolute tolerance on tau_min; the truncation grows until it is met. Where rounding,
        not the truncation, keeps the error estimate above tol (tau = 0 as a double eigenvalue
        at an undamped finger tip) the result's ``warnings`` say so.
    n_temporal : fix the truncation N instead (the error estimate compares with a smaller N).
    tau_max : compute only the marginal tau <= tau_max (e.g. 0.5, the physical range); the
        truncation then grows only as far as those need, and tau_min is None when there is none.
    tol_spatial : models with spatial modes (a parameter ``n_spatial``, e.g. 'cochlea') only:
        with ``n_spatial=None`` the number of spatial modes is raised from 16 (16, 24, 32, 48,
        ...) until every tau_min is within ``tol_spatial`` (absolute; default 1e-3) of its
        values at the two M before, M / 2 among them, see
        :func:`_floquet_spatial`. The sphere with a non-uniform kappa: the tolerance of
        tau_min in the degree truncation l_max (default 1e-6).
    max_seconds : models with spatial modes, and the non-uniform sphere, only: raise the
        limit on the estimated cost (default :data:`spectralshell.params.limits.SECONDS`, 600 s,
        or $SPECTRALSHELL_MAX_SECONDS). The truncations N and M a solve needs are priced from
        the parameters before it starts (:mod:`spectralshell.solvers.cost`); a solve whose least
        work is estimated above the limit is refused with what it needs. The non-uniform
        sphere prices each degree truncation's sector solves before solving it
        (:class:`spectralshell.runner.nonuniform.Price`).
    progress : models with spatial modes, and the non-uniform sphere, only: a progress bar
        over the spatial truncations M on stderr, its label stating the estimate (the sphere:
        over the sector solves of each l_max).
    **params : the model's parameters, e.g. ``kappa``, ``nu`` for 'mathieu'; for 'cochlea' also
        the cgs inputs rho, mu, sigma, length, lambda_c, omega (Table 5.1 defaults for the
        missing ones; omega required), converted by :func:`params.physical.cochlea_params`.
        For 'sphere', ``kappa`` given as text, an expression in theta and phi (e.g.
        ``"0.02*(1 + 0.3*cos(theta)**2)"``), is a non-uniform stiffness: the degrees couple,
        ``m`` and ``component`` are refused, ``l_max`` ('auto', the default, or an integer
        4..64) is the degree truncation, and the result is a
        :class:`~spectralshell.results.nonuniform.NonUniformFloquetResult`
        (:mod:`spectralshell.runner.nonuniform`).

    Notes
    -----
    Solves the Hill system (thesis (2.6) with reality conditions (2.7)/(2.8)) of the model.

    Raises
    ------
    ParameterError : a parameter, kind or option out of range; an estimated cost above the
        limit.
    ConvergenceError : tau_min did not converge to ``tol`` (or to ``tol_spatial`` in n_spatial).
    """
    model = check_model(model)
    kinds = expand_kind(kind)
    options = solver_options(tol, n_temporal, tau_max)
    if is_nonuniform(model, params):
        return _floquet_nonuniform(kind, options, params, tol_spatial, max_seconds, progress)
    params, physical = physical_values(model, dict(params))
    if get_model(model).spatial:
        return _floquet_spatial(model, kind, options, params, physical, tol_spatial,
                                max_seconds, progress)
    for name, value in (("tol_spatial", tol_spatial), ("max_seconds", max_seconds)):
        if value is not None:
            raise ParameterError(f"{name} = {value!r} is invalid for model {model!r}: it has no "
                                 "spatial modes")
    p, system = _system(model, params)
    res = solve_kinds(system, kinds, {**options, **CERTIFIED})
    warnings = threshold_warnings({k: [m.tau_min] for k, m in res.items()})
    if n_temporal is None:
        warnings += resolution_warnings(res, options["tol"])
    warnings += certification_warnings(res, options.get("tau_max"))
    return FloquetResult(model=model, params=dataclasses.asdict(p), harmonic=res.get("harmonic"),
                         subharmonic=res.get("subharmonic"),
                         provenance=provenance({"kind": kind, **options}), warnings=tuple(warnings))


def _floquet_nonuniform(kind: str, options: dict[str, Any], params: dict[str, Any],
                        tol_spatial: float | None, max_seconds: float | None, progress: bool):
    """The sphere with stiffness kappa(theta, phi) given as an expression
    (:func:`spectralshell.runner.nonuniform.floquet_nonuniform`)."""
    from .nonuniform import floquet_nonuniform

    p = nonuniform_params(params)
    return floquet_nonuniform(p, kind=kind, tol_spatial=tol_spatial, options=options,
                              progress=progress, max_seconds=max_seconds)


def priced_spatial(model: str, factory, kinds: tuple[str, ...], options: dict[str, Any],
                   n_spatial: int | None, max_seconds: float | None) -> CostEstimate:
    """The cost estimate of a solve with spatial modes, refused (ParameterError) when its least
    work is above the limit on estimated seconds -- unless the caller fixed both truncations
    (n_spatial and n_temporal): then nothing is refined and the size is the caller's choice
    (the dense price overstates the Arnoldi path there: N = 20, M = 300 priced 17 min, ran in
    1.6 s)."""
    estimate = spatial_cost(factory, kinds, n_spatial=n_spatial,
                            n_temporal=options["n_temporal"])
    if n_spatial is not None and options["n_temporal"] is not None:
        return estimate
    SECONDS.check(f"{model} solve needing {estimate.describe()}", estimate.seconds, max_seconds,
                  "fix the truncations with n_spatial=M and n_temporal=N")
    return estimate


def _counted(factory, bar):
    """``factory`` that moves ``bar`` by one at each M it builds."""
    def build(n_spatial: int) -> HillSystem:
        bar.set_postfix_str(f"M = {n_spatial}")
        bar.update(1)
        return factory(n_spatial)
    return build


def _floquet_spatial(model: str, kind: str, options: dict[str, Any], params: dict[str, Any],
                     physical: dict[str, float] | None, tol_spatial: float | None,
                     max_seconds: float | None = None,
                     progress: bool = False) -> SpatialFloquetResult:
    """Marginal tau of a model with spatial modes, with an error estimate in their number M.

    * ``spatial_mode`` given (a single decoupled mode): one solve, exact in space.
    * ``n_spatial = M`` given: solves at M and at M // 2; the spatial change
      |tau_min(M) - tau_min(M // 2)| (the thesis's epsilon_M of 5.3, Fig 5.6) enters the error
      estimate.
    * ``n_spatial = None``: M = 16, 24, 32, 48, 64, ... until every asked kind's tau_min at an M
      (L) differs by at most ``tol_spatial`` from its values at the two M before it (L / 2 and
      3L / 4 or 2L / 3; a kind without tau_min at all three counts as converged once L / 2
      reaches the kind's resonance); ConvergenceError past
      M = SPATIAL_LIMIT (:func:`spectralshell.solvers.spatial_refinement.refine_spatial`).

    Before any solve (but the single mode's) the cost is estimated and checked against the
    limit ``max_seconds`` (:func:`priced_spatial`); ``progress`` shows a bar over the M solved.

    With ``tau_max`` the change is that of tau_min capped at tau_max (a missing tau_min counts
    as tau_max). Each kind's ``error_estimate`` becomes max(temporal estimate, spatial change); a
    missing change (tau_min at one M only without tau_max, or M = 1) makes it tau_min itself, as
    for the temporal one.
    """
    kinds = expand_kind(kind)
    first = make_params(model, params)
    n_given = first.n_spatial
    if tol_spatial is not None and (n_given is not None or first.spatial_mode is not None):
        raise ParameterError(f"tol_spatial = {tol_spatial!r} is invalid with a fixed n_spatial or "
                             "spatial_mode: it sets when the automatic refinement in n_spatial stops")
    tol_spatial = require_positive("tol_spatial", TOL_SPATIAL if tol_spatial is None else tol_spatial)
    factory = functools.partial(spatial_system, model, params)
    if first.spatial_mode is not None:
        p, fine = first, solve_kinds(hill_system(first), kinds, {**options, **CERTIFIED})
        m_fine, m_coarse, change = 1, None, {k: 0.0 for k in kinds}
    else:
        estimate = priced_spatial(model, factory, kinds, options, n_given, max_seconds)
        with progress_bar(estimate.levels, f"{model} ({estimate.describe()})", "M", progress,
                          leave=False) as bar:
            found = spatial_point(_counted(factory, bar), kinds, {**options, **CERTIFIED},
                                  n_given, tol_spatial)
        p = first if n_given is not None else make_params(
            model, {**params, "n_spatial": found.n_spatial})
        fine, change = found.taus, found.change
        m_fine, m_coarse = found.n_spatial, found.n_spatial_previous
    res = {k: spatial_error(fine[k], change[k]) for k in kinds}
    warnings = threshold_warnings({k: [m.tau_min] for k, m in res.items()})
    auto = n_given is None and first.spatial_mode is None
    opts = {"kind": kind, **options, "tol_spatial": tol_spatial if auto else None}
    result = SpatialFloquetResult(model=model, params=dataclasses.asdict(p),
                                  harmonic=res.get("harmonic"), subharmonic=res.get("subharmonic"),
                                  provenance=provenance(opts), warnings=tuple(warnings),
                                  n_spatial=m_fine, n_spatial_previous=m_coarse,
                                  spatial_change=change, physical=physical)
    notes = resolution_warnings(res, options["tol"], result.error_reason)
    return dataclasses.replace(result, warnings=result.warnings + tuple(notes))


PARALLEL_MIN_POINTS = 400  # below this a process pool costs more than it saves
CHUNKS_PER_WORKER = 128
MIN_CHUNK = 64


def _map(factory, points: list, kinds: tuple[str, ...], workers: int | None, progress: bool,
         desc: str, options: dict[str, Any]) -> list:
    """Marginal tau at every point through the sweep runner: serial for ``workers=1`` or small
    grids, otherwise a process pool (all cores when ``workers`` is None)."""
    serial = workers == 1 or (workers is None and len(points) < PARALLEL_MIN_POINTS)
    # CHUNKS_PER_WORKER tasks per worker, of at least MIN_CHUNK points: the progress bar moves
    # often (a 200 x 200 Fig 6.13 map: every ~780 points, under one beat-rate row; with 32 per
    # worker its first, dearest chunks took ~1.5 min), and the dispatch cost (~0.5 ms per task,
    # validation/bench_sweep.py) stays ~1 % of a chunk's compute even for the cheapest points
    # (Mathieu, ~0.5 ms each); each point is solved alone, so the numbers do not depend on it
    from .sweep import map_points  # lazy: the sweep's modules import xarray

    per_worker = -(-len(points) // (CHUNKS_PER_WORKER * (workers or os.cpu_count() or 1)))
    chunk = max(MIN_CHUNK, per_worker)
    return map_points(factory, points, kinds, executor="serial" if serial else "processes",
                      workers=None if serial else workers, chunk=chunk, progress=progress,
                      desc=desc, **options)


def family_system(model: str, params: Mapping[str, Any], name: str, value: float) -> HillSystem:
    """The Hill system of ``model`` at ``params`` with ``name`` = ``value``: one member of a
    one-parameter family (``name`` a model parameter, or a cgs input such as the cochlea's
    omega, converted as :func:`floquet` converts it); picklable through functools.partial."""
    values, _ = physical_values(model, {**params, name: value})
    return _system(model, values)[1]


def ince_strutt(factory, grid: np.ndarray, kinds: tuple[str, ...], options: dict[str, Any], *,
                tips: bool = True, boundaries: bool = True, workers: int | None = None,
                progress: bool = False, desc: str = "tongues") -> tuple[list, list, list, tuple]:
    """The Ince-Strutt diagram of the family ``factory`` over ``grid``: (rows: the marginal tau
    of each kind at each grid value, the finger tips (:func:`~spectralshell.solvers.tongues.
    find_tips`), the tips that could not be located (messages), the traced boundaries
    (:func:`trace_boundaries`)); ``tips``/``boundaries`` False skip those. The one engine of
    :func:`tongues` (kappa) and of the figures drawn against another parameter (the cochlea's
    omega and wavenumber k)."""
    rows = _map(factory, list(grid), kinds, workers, progress, desc, options)
    found, failures = (find_tips(factory, grid, rows, kinds, tol=options["tol"]) if tips
                       else ([], []))
    traced = trace_boundaries(factory, grid, rows, found, kinds, workers=workers,
                              progress=progress, options=options) if boundaries else ()
    return rows, found, failures, traced


def _grid(name: str, spec: Any, max_points: int | None) -> np.ndarray:
    """A non-empty 1-D grid from 'start:stop:num', {start, stop, num} or array-like values, its
    size checked against the points limit before it is made (a range) or converted (values)."""
    if isinstance(spec, (str, Mapping)):
        return parse_range(name, spec, max_points)
    values = np.atleast_1d(np.asarray(spec, dtype=object))
    check_points(name, values.size, max_points)
    if not values.size:
        raise ParameterError(f"{name} = [] is invalid: must be a non-empty grid")
    return np.array([require_real(name, v) for v in values])


def tongues(model: str, *, kappa: str | Mapping[str, Any] | Sequence[float] | np.ndarray,
            kind: str = "both", tol: float = 1e-10, n_temporal: int | None = None,
            tau_max: float | None = None, tips: bool = True,
            workers: int | None = None, progress: bool = False, max_points: int | None = None,
            boundaries: bool = True, **params: Any) -> TonguesResult:
    """Ince-Strutt diagram: marginal tau of each kind over a kappa grid, and the finger tips.

    Parameters
    ----------
    kappa : the grid (array-like, or 'start:stop:num').
    tips : locate the minimum (kappa, tau) of every finger that shows as a local minimum of
        tau_min on the grid (to ~1e-12 in kappa; see ``solvers.tongues.refine_tip``).
    workers : processes (None: all cores for large grids; 1: serial). progress : show a bar.
    tau_max : only the marginal tau <= tau_max are computed (as in :func:`floquet`). An empty
        row of a viscous model is proved by the zero count; one it cannot prove is kept
        (``complete_to`` 0), listed in the result's ``uncertified`` and warned of: not raised,
        so that the rest of the diagram stays (the CLI exits 1).
    boundaries : trace each boundary as a curve (``TonguesResult.boundaries``) through the
        grid, the finger tips and kappa added by bisection wherever a branch is steep (tau moves
        by more than 0.02 between neighbouring kappa), turns back or ends, down to 1e-4 of the
        kappa range; up to tau_max (1 where there is none).
    max_points : raise the limit on the grid's points (default
        :data:`spectralshell.params.limits.POINTS`, 1e6, or $SPECTRALSHELL_MAX_POINTS); a grid
        above it, or whose results exceed the memory limit, is refused before any work.
    Other parameters as in :func:`floquet`; ``params`` must not contain ``kappa``.
    """
    model = check_model(model)
    kinds = expand_kind(kind)
    options = solver_options(tol, n_temporal, tau_max)
    grid = _grid("kappa", kappa, max_points)
    check_grid("kappa", (grid.size,), RESULT_BYTES, max_points)
    for k in (grid.min(), grid.max()):
        make_params(model, {**params, "kappa": k})
    factory = functools.partial(family_system, model, dict(params), "kappa")
    rows, found, failures, traced = ince_strutt(
        factory, grid, kinds, options if tau_max is None else {**options, **MARKED}, tips=tips,
        boundaries=boundaries, workers=workers, progress=progress)
    warnings = threshold_warnings({k: [r[k].tau_min for r in rows] for k in kinds}) + failures
    unproved = tuple((float(k), kind) for k, r in zip(grid, rows) for kind in kinds
                     if tau_max is not None and r[kind].unproved_empty(tau_max))
    p = dataclasses.asdict(make_params(model, {**params, "kappa": float(grid[0])}))
    p.pop("kappa")
    result = TonguesResult(model=model, params=p, kappa=grid, kinds=kinds, rows=tuple(rows),
                         tips=tuple(found), boundaries=traced, warnings=tuple(warnings),
                         uncertified=unproved,
                         provenance=provenance({"kind": kind, "tips": tips,
                                                "boundaries": boundaries, **options}))
    return dataclasses.replace(result, warnings=result.warnings + tuple(
        [result.uncertified_note()] if unproved else []))


#: The boundary solves (every=True) stop at N = 2 x the grid's largest N plus this.
BOUNDARY_N_MARGIN = 8
#: Rounds of bisection at most when tracing boundaries (each halves the unresolved intervals:
#: from a grid step of 1/300 of the range down to BOUNDARY_MIN_DKAPPA takes 5).
BOUNDARY_ROUNDS = 12


def trace_boundaries(factory, grid: np.ndarray, rows: list, tips: list, kinds: tuple[str, ...],
                     *, workers: int | None, progress: bool, options: dict[str, Any]) -> tuple:
    """The boundary curves of each kind of an Ince-Strutt diagram over ``grid`` (any
    one-parameter family ``factory``; ``rows``: the grid's marginal tau, ``tips``: its finger
    tips, ``options``: the solver's) (:func:`~spectralshell.solvers.tongues.link_boundaries`)
    through the grid's marginal tau, the finger tips' kappa and the kappa added by bisection
    where neighbouring values cannot be linked (:func:`~spectralshell.solvers.tongues.
    refinement_points`), traced up to tau_max (BOUNDARY_TAU_MAX where there is none).

    A curve follows every tau up to that cap, not only tau_min: each added kappa, and each grid
    point whose list is not complete up to the cap (``complete_to``), is solved with
    ``every=True`` (:func:`~spectralshell.solvers.marginal.marginal_tau`), which raises N until
    every tau below the cap has converged, up to twice the grid's largest N. A point where that does not converge keeps its grid
    row (its curve may end there); an added kappa where it does not is left out, its interval
    unrefined."""
    cap = options.get("tau_max") if options.get("tau_max") is not None else BOUNDARY_TAU_MAX
    wanted = {**options, "tau_max": cap}
    if options.get("n_temporal") is None:  # up to twice the grid's largest N (a bound on the
        # cost where the larger tau never settle, e.g. the cochlea at M = 64: N = 400, ~100 s)
        deepest = max((row[kind].n_temporal for row in rows for kind in kinds), default=0)
        wanted.update(every=True, n_max=min(N_MAX, 2 * deepest + BOUNDARY_N_MARGIN))
    min_dkappa = BOUNDARY_MIN_DKAPPA * float(grid.max() - grid.min())
    solved, failed = dict(zip(grid.tolist(), rows)), set()
    short = [k for k, row in solved.items()
             if any(row[kind].complete_to < cap for kind in kinds)]
    # a tip within rounding of a grid point is that point (one vertex where the sides meet)
    extra = sorted({float(t.kappa) for t in tips
                    if np.min(np.abs(grid - t.kappa)) > 1e-9 * min_dkappa})
    for _ in range(BOUNDARY_ROUNDS + 1):
        todo = short + extra
        if todo:
            solved.update(_solve_some(factory, todo, kinds, workers, progress, wanted, failed))
        short = []
        kappas = np.array(sorted(solved))
        taus = {kind: [boundary_taus(solved[k][kind], cap) for k in kappas] for kind in kinds}
        extra = sorted({k for kind in kinds for k in refinement_points(
            kappas, taus[kind], dtau=BOUNDARY_DTAU, min_dkappa=min_dkappa)} - failed)
        if not extra:
            break
    return tuple(b for kind in kinds for b in link_boundaries(kind, kappas, taus[kind]))


def _solve_some(factory, points: list, kinds: tuple[str, ...], workers: int | None,
                progress: bool, options: dict[str, Any], failed: set) -> dict:
    """kappa -> marginal tau of each kind for the ``points`` that converge (all at once through
    the sweep runner, else one at a time); the others are added to ``failed``."""
    try:
        return dict(zip(points, _map(factory, points, kinds, workers, progress,
                                     "tongue boundaries", options)))
    except ConvergenceError:  # one at a time: keep the points that converge
        out = {}
        for k in points:
            try:
                out[k] = solve_kinds(factory(k), kinds, options)
            except ConvergenceError:
                failed.add(k)
        return out


def _map_axis(model: str, label: str, axis: object, physical: bool,
              max_points: int | None, nonuniform: bool = False) -> tuple[str, Any]:
    """(name, grid spec) of the map axis ``label`` = (name, grid): the name one of the model's
    real parameters, or with physical input one of the model's cgs quantities in a sweep, or
    for the sphere with a non-uniform kappa nu or l_max (``nonuniform``)."""
    cgs = physical_names(model)
    names = ("nu", "l_max") if nonuniform else tuple(cgs) if physical else tuple(
        f.name for f in param_fields(model) if f.type in (float, "float"))
    if not (isinstance(axis, (tuple, list)) and len(axis) == 2):
        raise ParameterError(f"{label} = {axis!r} is invalid: must be a pair (name, grid) with "
                             f"name one of {', '.join(names)}")
    if not isinstance(axis[0], str) or axis[0] not in names:
        hint = f" (cgs axes {', '.join(cgs)} need physical=)" if cgs and not physical else ""
        raise ParameterError(f"{label} axis name = {axis[0]!r} is invalid: must be one of "
                             f"{', '.join(names)}{hint}")
    grid = axis[1]
    if axis[0] == "l_max":  # integers: the sweep reads them
        return "l_max", grid if isinstance(grid, str) else list(np.atleast_1d(grid).tolist())
    if not isinstance(grid, (str, Mapping)):  # values: plain floats for the scene
        grid = _grid(axis[0], grid, max_points).tolist()
    return str(axis[0]), grid


def tau_map(model: str, *, x: tuple[str, Any], y: tuple[str, Any],
            m: int | str | Sequence[int] | None = None, kind: str = "both",
            tau_max: float = 0.5, tol: float = 1e-8, physical: Mapping[str, float] | None = None,
            workers: int | None = None, progress: bool = False, max_points: int | None = None,
            max_seconds: float | None = None, **params: Any) -> xr.Dataset:
    """Marginal tau_min <= tau_max on an x-y grid, for each degree ``m`` and kind: a sweep
    (:func:`spectralshell.runner.sweep.run_sweep`) run in memory.

    Parameters
    ----------
    x, y : (parameter name, grid), the grid as array-like, 'start:stop:num' or {start, stop,
        num[, spacing = 'log']}. Names are real model parameters (e.g. 'kappa', 'nu') or, with
        ``physical``, the model's cgs quantities (sphere: 'sigma' (dyn/cm), 'omega' (rad/s),
        'bpm' (beats/min), 'radius', 'mu', 'rho'; see :mod:`spectralshell.params.sweep_grid`).
        The sphere with ``kappa`` an expression in theta, phi (a non-uniform stiffness, fixed):
        'nu' and 'l_max' (integers, the degree truncation: a map of the convergence in l), and
        the Dataset also holds l_max and the critical mode's largest (l, k) share.
    m : degrees, e.g. '2:6' (models with a degree m; None for the others).
    tau_max : only instabilities below it count (1/2: stiffness > 0).
    physical : fixed cgs values (e.g. rho, mu, radius), converted with the axes' values as the
        sweep converts them (sphere: (6.4)-(6.5), :class:`~spectralshell.params.physical.PhysicalSphere`).
    tol : absolute tolerance on each tau_min (1e-8 is ample for a picture).
    workers : processes (None: all cores for large grids; 1: serial). progress : a bar.
    max_points : raise the limit on x * y * degrees * kinds points.
    max_seconds : a model with spatial modes (the cochlea): raise the limit on the estimated
        work of the map, priced before any work (:func:`spectralshell.runner.sweep.priced_sweep`).

    Returns
    -------
    xarray.Dataset : the sweep's (:func:`spectralshell.sweep`): tau_min, has_tau,
        error_estimate, n_temporal, complete_to over (x, y, m, kind), units and provenance in
        attrs. A point where no tau was found but the zero count could not prove that none
        exists is kept, marked (:func:`spectralshell.results.maps.uncertified`), and counted
        by an :class:`~spectralshell.errors.UncertifiedWarning`.
        :func:`spectralshell.results.maps.minimum_map` reduces it to the smallest tau over m and
        kind with the m/kind attaining it (thesis Fig 6.13 labels 'm H/S'), and
        :func:`spectralshell.plots.tau_map.save` draws it.

    Notes
    -----
    Every point solves only the marginal tau <= tau_max, each continuing from its neighbour
    along y (:mod:`spectralshell.runner.solve`): values agree with independent ``floquet``
    solves within ``tol``.
    """
    from .sweep import flagged, run_sweep  # lazy: xarray costs ~0.35 s to import

    model = check_model(model)
    kinds = expand_kind(kind)
    require_positive("tol", tol)
    require_positive("tau_max", tau_max)
    cgs = physical_inputs(physical, physical_names(model)) if physical is not None else {}
    nonuniform = is_nonuniform(model, params)
    if nonuniform and (m is not None or physical is not None):
        name, value = ("m", m) if m is not None else ("physical", physical)
        raise ParameterError(f"{name} = {value!r} is invalid with a non-uniform kappa: its "
                             "degrees couple (the map's axes are nu and l_max)")
    (xname, xgrid), (yname, ygrid) = (_map_axis(model, label, axis, physical is not None,
                                                max_points, nonuniform)
                                      for label, axis in (("x", x), ("y", y)))
    grid: dict[str, Any] = {xname: xgrid, yname: ygrid}
    if m is not None:
        grid["m"] = m if isinstance(m, str) else (list(m) if isinstance(m, (list, tuple))
                                                  else [m])
    grid["kind"] = list(kinds)
    scene = {"model": model, "ask": ["tau_min"], "params": {**params, **cgs}, "grid": grid,
             "tau_min": {"tol": float(tol), "tau_max": float(tau_max)}}
    spec = sweep_spec(scene, max_points=max_points)
    serial = workers == 1 or (workers is None and spec.size < PARALLEL_MIN_POINTS)
    return flagged(run_sweep(spec, executor="serial" if serial else "processes",
                             workers=None if serial else workers, progress=progress,
                             max_seconds=max_seconds))


def exponents(model: str, *, tau: float, tol: float = 1e-10, n_temporal: int | None = None,
              count: int | None = None, max_seconds: float | None = None,
              **params: Any) -> ExponentsResult:
    """Floquet characteristic exponents gamma at forcing amplitude ``tau``.

    Re gamma is the growth rate per unit time; Im gamma is folded into (-1/2, 1/2]; the list
    is sorted by decreasing Re gamma, and ``count`` keeps that many (the least damped).

    Notes
    -----
    A model with a matrix-polynomial D(s) (Mathieu, the inviscid reductions, the inviscid
    cochlea): every exponent of Hill's companion-form eigenproblem
    (:mod:`spectralshell.solvers.exponents`), verified against the monodromy matrix of
    ``scipy.integrate.solve_ivp`` in the tests. A viscous model (non-polynomial D(s)): the
    natural modes (tau = 0) continued in tau as roots of the truncated Hill determinant, their
    number in a region of the strip proved by the argument principle (``complete_in``)
    (:mod:`spectralshell.solvers.hill_exponents`). The sphere with ``kappa`` an expression in
    theta, phi (a non-uniform stiffness; ``l_max`` 'auto' or an integer 4..64, as in
    :func:`floquet`): the exponents of every decoupled sector of the coupled degrees, each
    continued from the sector's natural modes
    (:func:`spectralshell.runner.nonuniform.exponents_nonuniform`); ``params`` states the l_max
    used. Each of its degree truncations is priced as :func:`floquet`'s and refused above the
    limit on estimated seconds (default :data:`spectralshell.params.limits.SECONDS`, 600 s, or
    $SPECTRALSHELL_MAX_SECONDS), which ``max_seconds`` raises (that sphere only).
    """
    model = check_model(model)
    tau = require_real("tau", tau)
    if count is not None:
        count = require_int_in_range("count", count, 1)
    options = solver_options(tol, n_temporal)
    if is_nonuniform(model, params):
        from .nonuniform import exponents_nonuniform

        p = nonuniform_params(params)
        result, l_max = exponents_nonuniform(p, tau=tau, options=options,
                                             max_seconds=max_seconds)
        p = dataclasses.replace(p, l_max=l_max)
    else:
        if max_seconds is not None:
            raise ParameterError(f"max_seconds = {max_seconds!r} is invalid for the exponents of "
                                 f"model {model!r}: only the sphere with a non-uniform kappa "
                                 "is priced")
        p, result = _exponents(model, tau, options, params)
    if count is not None and count < result.gamma.size:
        bounds = result.complete_in  # still proved: lo < Re gamma <= hi, lo the first dropped
        if bounds is not None:
            bounds = (float(result.gamma[count].real), bounds[1])
        result = dataclasses.replace(result, gamma=result.gamma[:count], complete_in=bounds)
    coarser, warnings = _spatial_check(model, p, tau, options, params, result.gamma, tol)
    return ExponentsResult.build(model=model, params=dataclasses.asdict(p), tau=tau,
                                 exponents=result, options=options, coarser=coarser,
                                 warnings=warnings)


def _spatial_check(model: str, p: Any, tau: float, options: dict[str, Any],
                   params: dict[str, Any], gamma: np.ndarray, tol: float):
    """((M // 2, spatial change), warnings) of exponents ``gamma`` solved at ``n_spatial`` = M
    (:class:`~spectralshell.results.floquet.ExponentsResult`): the exponents at M // 2, and
    the largest distance (mod i) from one of ``gamma`` to the nearest of them -- as floquet's
    epsilon_M (thesis 5.3) for tau_min. (None, ()) for a model without spatial modes or a
    single decoupled mode; at M = 1 (None, a warning that the spatial error is not estimated)."""
    n_spatial = getattr(p, "n_spatial", None)
    if n_spatial is None or getattr(p, "spatial_mode", None) is not None:
        return None, ()
    if n_spatial < 2:
        return None, (f"n_spatial = {n_spatial}: the error estimate covers the temporal "
                      "truncation only (no coarser spatial truncation to compare with)",)
    _, coarse = _exponents(model, tau, options, {**params, "n_spatial": n_spatial // 2})
    change = distance(gamma, coarse.gamma)
    if not np.isfinite(change):
        raise ConvergenceError(f"no Floquet exponent found at n_spatial = {n_spatial // 2} to "
                               f"compare with those at n_spatial = {n_spatial}")
    warnings = () if change <= tol else (
        f"the exponents listed moved by up to {change:.2g} between n_spatial = "
        f"{n_spatial // 2} and {n_spatial} (the error estimate includes it): raise n_spatial "
        "for spatially converged exponents, or list fewer with count",)
    return (n_spatial // 2, change), warnings


def _exponents(model: str, tau: float, options: dict[str, Any], params: dict[str, Any]):
    """(the model's parameters, its Floquet exponents at ``tau``) of a model given by
    parameters (:func:`exponents`)."""
    from ..solvers.hill_exponents import hill_exponents  # lazy: only the viscous models' path
    from .modes import natural_modes

    p, system = _system(model, params)
    if system.polynomial is not None:
        result = floquet_exponents(system, tau, **options)
    else:
        require_capability(model, "Floquet exponents of a non-polynomial D(s) (continued from "
                           "the natural modes)", "modal_system", "mode_family")
        if not np.count_nonzero(system.forcing):
            raise ParameterError(f"parameters {dataclasses.asdict(p)} are invalid for Floquet "
                                 f"exponents of model {model!r}: nothing oscillates there")
        try:
            seeds = natural_modes(model, **dataclasses.asdict(p)).gamma
        except ParameterError as exc:
            raise ParameterError(f"{exc} (the Floquet exponents of model {model!r} are continued "
                                 "from its natural modes)") from None
        result = hill_exponents(system, tau, seeds, **options)
    return p, result


def stability(model: str, *, tau: float, m: int | str | Sequence[int], kind: str = "both",
              tol: float = 1e-10, n_temporal: int | None = None,
              **params: Any) -> StabilityResult:
    """Is each degree m unstable at forcing amplitude ``tau``, and with which kind?

    ``m``: degrees (an integer, 'start:stop' or a list). A real parameter in ``params`` may
    also be a grid ('start:stop:num' or a list of values, e.g. the cylinder's ``k``): then each
    (m, value) pair is decided, m outermost; a pair the model does not define (e.g. the
    cylinder's m = 0 at k < 1) is listed with ``defined`` False and the model's ``reason``
    instead of stopping the rest.

    Notes
    -----
    Every marginal tau of a kind is a Floquet multiplier crossing +1 (harmonic) or -1
    (subharmonic); for one oscillatory degree of freedom, successive crossings of the same kind
    alternately enter and leave the instability finger (thesis 2.2, Fig 2.2), so a kind is unstable
    at ``tau`` when an odd number of its marginal amplitudes lie below ``tau``. Where both kinds are
    unstable, ``kind`` names the one with the lower threshold. The rule is checked against the Floquet
    exponents in the tests.

    A verdict is given only where it is proved (issue 23): each kind's list of marginal tau is
    certified complete below ``tau`` (:func:`_complete_below`), an empty one by the zero count,
    and for a model with coupled components (block size > 1) at most one tau of each kind lies
    below ``tau``. Where the solve fails, a single point raises ConvergenceError; of several
    points, the point is kept with ``proved`` False and the ``reason`` (never as "stable"), as
    is a point the parity rule does not decide; the result's ``warnings`` count them and the
    CLI exits 1.
    """
    model = check_model(model)
    tau = require_real("tau", tau)
    degrees = parse_int_range("m", m, int_bounds(model, "m"))
    options = solver_options(tol, n_temporal)
    swept = {name: _grid(name, params.pop(name), None) for name in _grid_params(model, params)}
    points = [dict(zip(("m", *swept), values))
              for values in itertools.product(degrees, *swept.values())]
    modes, solved = [], None
    for point in points:  # only the marginal tau below the asked tau are needed
        at = _point_params(point)
        entry: dict[str, Any] = {**at, "unstable": False, "kind": None}
        try:
            if tau > 0:
                res = floquet(model, kind=kind, tau_max=tau, **options, **params, **at)
                solved = res.params
                lists, undecided = _complete_below(model, res, expand_kind(kind), tau, options)
            else:  # marginal tau are >= 0: none lies below tau <= 0, nothing to solve
                lists, undecided = None, None
                solved = dataclasses.asdict(make_params(model, {**params, **at}))
        except ParameterError as exc:
            if len(points) == 1:
                raise
            modes.append({**entry, "defined": False, "reason": str(exc),
                          **{f"tau_{k}": [] for k in expand_kind(kind)}})
            continue
        except ConvergenceError as exc:  # the verdict cannot be proved: marked, never "stable"
            if len(points) == 1:
                raise
            if solved is None:  # the parameters, as floquet converts them
                values = physical_values(model, {**params, **at})[0]
                solved = dataclasses.asdict(make_params(model, values))
            modes.append({**entry, "proved": False, "reason": str(exc).splitlines()[0],
                          **{f"tau_{k}": [] for k in expand_kind(kind)}})
            continue
        thresholds = {}
        for k in expand_kind(kind):
            below = [] if lists is None else [float(t) for t in lists[k].tau if t < tau]
            entry[f"tau_{k}"] = below
            if len(below) % 2 == 1:
                thresholds[k] = below[0]
        if undecided is not None:
            entry.update(proved=False, reason=undecided)
        elif thresholds:
            entry["unstable"], entry["kind"] = True, min(thresholds, key=thresholds.get)
        modes.append(entry)
    if solved is None:  # every pair refused: say why for the first
        raise ParameterError(modes[0]["reason"])
    p = {k: v for k, v in solved.items() if k != "m" and k not in swept}
    result = StabilityResult(model=model, tau=tau, params=p, modes=tuple(modes),
                             swept=tuple(swept), warnings=tuple(amplitude_warnings(tau)),
                             provenance=provenance({"kind": kind, **options}))
    note = result.unproved_note()
    return dataclasses.replace(result, warnings=result.warnings + ((note,) if note else ()))


def _complete_below(model: str, res: FloquetResult, kinds: tuple[str, ...], tau: float,
                    options: dict[str, Any]) -> tuple[dict[str, Any], str | None]:
    """(each kind's marginal tau, proved complete below ``tau``; why the parity rule of
    :func:`stability` does not decide the point, or None where it does).

    ``res`` was solved with tau_max = ``tau``; a kind whose list is proved complete only below
    some complete_to < tau is solved again with ``every=True`` (N raised until every
    tau <= tau has converged and the list is certified up to tau; an empty one by the zero
    count). The parity rule holds for one oscillatory degree of freedom (block size 1: the
    Mathieu equation, the inviscid reductions); with coupled components, two crossings of one
    kind may be two modes entering instability (the fibre at m = 3, kappa = 0.3, nu = 0.001,
    tau = 0.9: two subharmonic tau below, 0.541 and 0.714, and an exponent with
    Re gamma = 1.12), so there only 0 (stable) or 1 (unstable) crossing decides.

    Raises
    ------
    ConvergenceError : that solve does not converge, or N is fixed (n_temporal), so that the
        list stays unproved up to tau; the message says up to where it is proved.
    """
    lists = {k: getattr(res, k) for k in kinds}
    short = tuple(k for k in kinds if lists[k].complete_to < tau)
    if short and options["n_temporal"] is not None:
        k = short[0]
        raise ConvergenceError(
            f"{k}: the marginal tau below tau={tau:g} are proved complete only up to "
            f"{lists[k].complete_to:.4g} at the fixed n_temporal={options['n_temporal']}, so "
            "the stability verdict is not proved; leave n_temporal= unset, or give a smaller tau")
    system = functools.cache(lambda: _system(model, res.params)[1])
    if short:
        lists.update(solve_kinds(system(), short, {**options, "tau_max": tau, "every": True,
                                                   **CERTIFIED}))
    crossings = {k: int(np.count_nonzero(lists[k].tau < tau)) for k in kinds}
    many = [k for k in kinds if crossings[k] >= 2]
    if many and system().block_size > 1:
        return lists, (f"{crossings[many[0]]} {many[0]} marginal tau lie below tau={tau:g}: the "
                       "parity rule decides one degree of freedom only, not "
                       f"{system().block_size} coupled components; the Floquet exponents at "
                       "this tau (exponents) decide it")
    return lists, None


def _point_params(point: Mapping[str, Any]) -> dict[str, Any]:
    """A stability point's model parameters: m as int, the swept reals as float."""
    return {k: (int(v) if k == "m" else float(v)) for k, v in point.items()}


def _grid_params(model: str, params: Mapping[str, Any]) -> list[str]:
    """The real parameters of ``model`` given as a grid in ``params`` (a 'start:stop:num' text or
    a list, tuple or array of values), in the model's parameter order."""
    return [f.name for f in param_fields(model) if f.name in params and f.type in (float, "float")
            and (isinstance(params[f.name], (list, tuple, np.ndarray))
                 or (isinstance(params[f.name], str) and ":" in params[f.name]))]


def run_scene(scene: str | Path | Mapping | Plan, *, progress: bool = False,
              workers: int | None = None) -> dict[str, Any]:
    """Plan a scene, then compute only what it asks; returns {task name: result}."""
    the_plan = scene if isinstance(scene, Plan) else plan(scene)
    out: dict[str, Any] = {}
    for task in the_plan.tasks:
        opts = dict(task.options)
        kind = "both" if len(task.kinds) == 2 else (task.kinds[0] if task.kinds else None)
        if task.name == "floquet":
            out["floquet"] = floquet(the_plan.model, kind=kind, **opts, **the_plan.params)
        elif task.name == "tongues":
            params = {k: v for k, v in the_plan.params.items() if k != "kappa"}
            out["tongues"] = tongues(the_plan.model, kind=kind, progress=progress,
                                     workers=workers, **opts, **params)
        elif task.name == "exponents":
            out["exponents"] = exponents(the_plan.model, **opts, **the_plan.params)
    return out


