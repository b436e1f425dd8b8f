"""The Python API facade: validate, plan, dispatch to the solvers, return result objects.

Conventions (see README "Conventions"): K(t) = kappa (1 + 2 tau sin t), forcing period 2 pi,
harmonic gamma = 0, subharmonic gamma = i/2.
"""

from __future__ import annotations

import dataclasses
import functools
import os
import sys
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import mpmath
import numpy as np

from ._validate import require_int_in_range, require_nonnegative, require_positive, require_real
from .discretise.fourier import expand_kind
from .errors import ConvergenceError, ParameterError
from .models.base import HillSystem
from .models.registry import hill_system, modal_system
from .models.nonlinear_coefficients import lp_coefficient as lp_coefficient_float
from .models.nonlinear_coefficients import lp_coefficient_exact
from .models.fibre import lambda0_squared as fibre_lambda0_squared
from .models.sphere import lambda0_squared
from .models import sphere_nonlinear
from .models.sphere_nonlinear import lambda0_over_sqrt_kappa
from .params.grid import parse_int_range, parse_range
from .params.limits import RESULT_BYTES, SECONDS, check_grid, check_points
from .params.physical import (PHYSICAL_UNITS, SPHERE_INPUTS, PhysicalSphere, physical_inputs,
                              sphere_forced_params)
from .params.physical import convert_physical
from .params.stiffness import amplitude_warnings, threshold_warnings
from .params.registry import PARAMS, check_model, int_bounds, make_params, param_names
from .params.scene import Plan, plan
from .results.maps import TauMapResult
from .results.modes import NaturalModesResult
from .results.spatial import SpatialFloquetResult
from .results.floquet import (ExponentsResult, FloquetResult, StabilityResult, TonguesResult,
                              certification_warnings, provenance, resolution_warnings)
from .solvers.cost import CostEstimate, spatial_cost
from .solvers.exponents import floquet_exponents
from .solvers.marginal import N_MAX, marginal_tau
from .solvers.spatial_refinement import (TOL_SPATIAL, refine_spatial, solve_at,
                                           spatial_change, spatial_error)
from .solvers.modes import find_modes
from .solvers.nonlinear_orbit import frequency_slope
from .runner import map_points
from .solvers.tongues import find_tips


def _solver_options(tol: float, n_temporal: int | None, tau_max: float | None = None) -> dict[str, Any]:
    tol = require_positive("tol", tol)
    if n_temporal is not None:
        n_temporal = require_int_in_range("n_temporal", n_temporal, 1, N_MAX)
    options = {"tol": tol, "n_temporal": n_temporal}
    if tau_max is not None:
        options["tau_max"] = require_positive("tau_max", tau_max)
    return options


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
    model : a name from ``spectralshell.params.registry.PARAMS`` ('mathieu', 'sphere', ...).
    kind : 'both', 'harmonic' (gamma = 0) or 'subharmonic' (gamma = i/2); only those are computed.
    tol : absolute tolerance on tau_min; the truncation grows until it is met. Where rounding,
        not the truncation, keeps the error estimate above tol (tau = 0 as a double eigenvalue
        at an undamped finger tip) the result's ``warnings`` say so.
    n_temporal : fix the truncation N instead (the error estimate compares with a smaller N).
    tau_max : compute only the marginal tau <= tau_max (e.g. 0.5, the physical range); the
        truncation then grows only as far as those need, and tau_min is None when there is none.
    tol_spatial : models with spatial modes (a parameter ``n_spatial``, e.g. 'cochlea') only:
        with ``n_spatial=None`` the number of spatial modes is doubled from 16 until every
        tau_min changes by at most ``tol_spatial`` (absolute; default 1e-3), see
        :func:`_floquet_spatial`.
    max_seconds : models with spatial modes only: raise the limit on the estimated cost
        (default :data:`spectralshell.params.limits.SECONDS`, 600 s, or
        $SPECTRALSHELL_MAX_SECONDS). The truncations N and M a solve needs are priced from the
        parameters before it starts (:mod:`spectralshell.solvers.cost`); a solve whose least
        work is estimated above the limit is refused with what it needs.
    progress : models with spatial modes only: a progress bar over the spatial truncations
        M on stderr, its label stating the estimate.
    **params : the model's parameters, e.g. ``kappa``, ``nu`` for 'mathieu'; for 'cochlea' also
        the cgs inputs rho, mu, sigma, length, lambda_c, omega (Table 5.1 defaults for the
        missing ones; omega required), converted by :func:`params.physical.cochlea_params`.

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
    options = _solver_options(tol, n_temporal, tau_max)
    params, physical = convert_physical(model, dict(params))
    if "n_spatial" in param_names(model):
        return _floquet_spatial(model, kind, options, params, physical, tol_spatial,
                                max_seconds, progress)
    for name, value in (("tol_spatial", tol_spatial), ("max_seconds", max_seconds)):
        if value is not None:
            raise ParameterError(f"{name} = {value!r} is invalid for model {model!r}: it has no "
                                 "spatial modes")
    p, system = _system(model, params)
    res = {k: marginal_tau(system, k, **options) for k in kinds}
    warnings = threshold_warnings({k: [m.tau_min] for k, m in res.items()})
    if n_temporal is None:
        warnings += resolution_warnings(res, options["tol"])
    warnings += certification_warnings(res)
    return FloquetResult(model=model, params=dataclasses.asdict(p), harmonic=res.get("harmonic"),
                         subharmonic=res.get("subharmonic"),
                         provenance=provenance({"kind": kind, **options}), warnings=tuple(warnings))


def _spatial_factory(model: str, params: dict[str, Any], n_spatial: int) -> HillSystem:
    return hill_system(make_params(model, {**params, "n_spatial": n_spatial}))


def _priced(model: str, factory, kinds: tuple[str, ...], options: dict[str, Any],
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
                  "fix the truncations with n_spatial= / --n-spatial M and n_temporal= / "
                  "--n-temporal N")
    return estimate


def _counted(factory, bar):
    """``factory`` that moves ``bar`` by one at each M it builds."""
    def build(n_spatial: int) -> HillSystem:
        bar.set_postfix_str(f"M = {n_spatial}")
        bar.update(1)
        return factory(n_spatial)
    return build


def _solve_spatial(model: str, params: dict[str, Any], first, factory, kinds: tuple[str, ...],
                   options: dict[str, Any], tol_spatial: float) -> tuple:
    """(params, tau of each kind, spatial change, M, coarser M) at the given n_spatial of
    ``first`` (M and M // 2) or refined in M (see :func:`_floquet_spatial`)."""
    n_given = first.n_spatial
    if n_given is None:
        found = refine_spatial(factory, kinds, options=options, tol_spatial=tol_spatial)
        p = make_params(model, {**params, "n_spatial": found.n_spatial})
        return p, found.taus, found.change, found.n_spatial, found.n_spatial_previous
    fine = solve_at(factory, n_given, kinds, options)
    m_coarse = n_given // 2 or None
    coarse = None if m_coarse is None else solve_at(factory, m_coarse, kinds, options)
    cap = options.get("tau_max") or float("inf")
    change = {k: None if coarse is None else spatial_change(fine[k], coarse[k], cap)
              for k in kinds}
    return first, fine, change, n_given, m_coarse


def _floquet_spatial(model: str, kind: str, options: dict[str, Any], params: dict[str, Any],
                     physical: dict[str, float] | None, tol_spatial: float | None,
                     max_seconds: float | None = None,
                     progress: bool = False) -> SpatialFloquetResult:
    """Marginal tau of a model with spatial modes, with an error estimate in their number M.

    * ``spatial_mode`` given (a single decoupled mode): one solve, exact in space.
    * ``n_spatial = M`` given: solves at M and at M // 2; the spatial change
      |tau_min(M) - tau_min(M // 2)| (the thesis's epsilon_M of 5.3, Fig 5.6) enters the error
      estimate.
    * ``n_spatial = None``: M = 16, 32, 64, ... until every asked kind's tau_min changes by at
      most ``tol_spatial`` between successive M (a kind without tau_min at both counts as
      converged once the coarser M reaches the kind's resonance); ConvergenceError past
      M = SPATIAL_LIMIT (:func:`spectralshell.solvers.spatial_refinement.refine_spatial`).

    Before any solve (but the single mode's) the cost is estimated and checked against the
    limit ``max_seconds`` (:func:`_priced`); ``progress`` shows a bar over the M solved.

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
    factory = functools.partial(_spatial_factory, model, params)
    if first.spatial_mode is not None:
        p, fine = first, {k: marginal_tau(hill_system(first), k, **options) for k in kinds}
        m_fine, m_coarse, change = 1, None, {k: 0.0 for k in kinds}
    else:
        from tqdm import tqdm  # lazy: keeps `import spectralshell` light

        estimate = _priced(model, factory, kinds, options, n_given, max_seconds)
        with tqdm(total=estimate.levels, desc=f"{model} ({estimate.describe()})", unit="M",
                  disable=not progress, file=sys.stderr, leave=False) as bar:
            p, fine, change, m_fine, m_coarse = _solve_spatial(
                model, params, first, _counted(factory, bar), kinds, options, tol_spatial)
    res = {k: spatial_error(fine[k], change[k]) for k in kinds}
    warnings = threshold_warnings({k: [m.tau_min] for k, m in res.items()})
    auto = n_given is None and first.spatial_mode is None
    opts = {"kind": kind, **options, "tol_spatial": tol_spatial if auto else None}
    return SpatialFloquetResult(model=model, params=dataclasses.asdict(p),
                                harmonic=res.get("harmonic"), subharmonic=res.get("subharmonic"),
                                provenance=provenance(opts), warnings=tuple(warnings),
                                n_spatial=m_fine, n_spatial_previous=m_coarse,
                                spatial_change=change, physical=physical)


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
    per_worker = -(-len(points) // (CHUNKS_PER_WORKER * (workers or os.cpu_count() or 1)))
    chunk = max(MIN_CHUNK, per_worker)
    return map_points(factory, points, kinds, executor="serial" if serial else "processes",
                      workers=None if serial else workers, chunk=chunk, progress=progress,
                      desc=desc, **options)


def _factory(model: str, params: dict[str, Any], kappa: float) -> HillSystem:
    return _system(model, {**params, "kappa": kappa})[1]


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


def tongues(model: str, *, kappa, kind: str = "both", tol: float = 1e-10,
            n_temporal: int | None = None, tau_max: float | None = None, tips: bool = True,
            workers: int | None = None, progress: bool = False, max_points: int | None = None,
            **params: Any) -> TonguesResult:
    """Ince-Strutt diagram: marginal tau of each kind over a kappa grid, and the finger tips.

    Parameters
    ----------
    kappa : the grid (array-like, or 'start:stop:num').
    tips : locate the minimum (kappa, tau) of every finger that shows as a local minimum of
        tau_min on the grid (to ~1e-12 in kappa; see ``solvers.tongues.refine_tip``).
    workers : processes (None: all cores for large grids; 1: serial). progress : show a bar.
    tau_max : only the marginal tau <= tau_max are computed (as in :func:`floquet`).
    max_points : raise the limit on the grid's points (default
        :data:`spectralshell.params.limits.POINTS`, 1e6, or $SPECTRALSHELL_MAX_POINTS); a grid
        above it, or whose results exceed the memory limit, is refused before any work.
    Other parameters as in :func:`floquet`; ``params`` must not contain ``kappa``.
    """
    model = check_model(model)
    kinds = expand_kind(kind)
    options = _solver_options(tol, n_temporal, tau_max)
    grid = _grid("kappa", kappa, max_points)
    check_grid("kappa", (grid.size,), RESULT_BYTES, max_points)
    for k in (grid.min(), grid.max()):
        make_params(model, {**params, "kappa": k})
    factory = functools.partial(_factory, model, dict(params))
    rows = _map(factory, list(grid), kinds, workers, progress, "tongues", options)
    found, failures = find_tips(factory, grid, rows, kinds, tol=options["tol"]) if tips else ([], [])
    warnings = threshold_warnings({k: [r[k].tau_min for r in rows] for k in kinds}) + failures
    p = dataclasses.asdict(make_params(model, {**params, "kappa": float(grid[0])}))
    p.pop("kappa")
    return TonguesResult(model=model, params=p, kappa=grid, kinds=kinds, rows=tuple(rows),
                         tips=tuple(found), warnings=tuple(warnings),
                         provenance=provenance({"kind": kind, "tips": tips, **options}))


def _point_params(params: dict[str, Any], physical: dict[str, float] | None,
                  names: tuple[str, str], point: tuple[float, float, int]) -> dict[str, Any]:
    """Model parameters of one map point (x, y, m), converted from cgs when ``physical`` is given."""
    x, y, degree = point
    values = {**params, names[0]: float(x), names[1]: float(y), "m": int(degree)}
    return values if physical is None else sphere_forced_params({**physical, **values})


def _map_system(model: str, params: dict[str, Any], physical: dict[str, float] | None,
                names: tuple[str, str], point: tuple[float, float, int]) -> HillSystem:
    return _system(model, _point_params(params, physical, names, point))[1]


def _map_axis(model: str, label: str, axis: object, physical: bool,
              max_points: int | None) -> tuple[str, np.ndarray]:
    """(name, grid) of the map axis ``label`` = (name, grid spec): the name one of the model's
    real parameters, or with physical input one of PHYSICAL_UNITS; the grid by :func:`_grid`."""
    names = tuple(PHYSICAL_UNITS) if physical else tuple(
        f.name for f in dataclasses.fields(PARAMS[model]) if f.type in (float, "float"))
    if not (isinstance(axis, (tuple, list)) and len(axis) == 2):
        raise ParameterError(f"{label} = {axis!r} is invalid: must be a pair (name, grid) with "
                             f"name one of {', '.join(names)}")
    if not isinstance(axis[0], str) or axis[0] not in names:
        hint = "" if physical else f" (cgs axes {', '.join(PHYSICAL_UNITS)} need physical=)"
        raise ParameterError(f"{label} axis name = {axis[0]!r} is invalid: must be one of "
                             f"{', '.join(names)}{hint}")
    name = str(axis[0])
    return name, _grid(name, axis[1], max_points)


def tau_map(model: str, *, x: tuple[str, Any], y: tuple[str, Any], m, kind: str = "both",
            tau_max: float = 0.5, tol: float = 1e-8, physical: Mapping[str, float] | None = None,
            workers: int | None = None, progress: bool = False, max_points: int | None = None,
            **params: Any) -> TauMapResult:
    """Map of the smallest marginal tau <= tau_max over degrees ``m`` and kinds on an x-y grid.

    Parameters
    ----------
    x, y : (parameter name, grid), the grid as array-like or 'start:stop:num'. Names are model
        parameters (e.g. 'kappa', 'nu') or, with ``physical``, the cgs quantities 'sigma'
        (dyn/cm), 'omega' (rad/s), 'bpm' (beats/min), 'radius', 'mu', 'rho'.
    m : degrees, e.g. '2:6'. tau_max : only instabilities below it count (1/2: stiffness > 0).
    physical : fixed cgs values (e.g. rho, mu, radius) for the conversion (6.4)-(6.5) of
        :class:`spectralshell.params.physical.PhysicalSphere`.
    tol : absolute tolerance on each tau_min (1e-8 is ample for a picture).
    max_points : raise the limit on x * y * degrees points (as in :func:`tongues`).

    Notes
    -----
    Every point solves only the marginal tau <= tau_max (``marginal_tau(tau_max=...)``), in
    parallel over all cores with a progress bar; the value is the minimum over m and kind, and
    ``degree``/``kind`` record which one attains it (thesis Fig 6.13 labels 'm H/S').
    """
    model = check_model(model)
    kinds = expand_kind(kind)
    options = _solver_options(tol, None, tau_max)
    degrees = parse_int_range("m", m, int_bounds(model, "m"), max_points)
    phys = None if physical is None else physical_inputs(physical, PHYSICAL_UNITS)
    (names, grids) = zip(*(_map_axis(model, label, axis, phys is not None, max_points)
                           for label, axis in (("x", x), ("y", y))))
    check_grid(f"tau map {names[0]} x {names[1]} x m", (grids[0].size, grids[1].size,
                                                        len(degrees)), RESULT_BYTES, max_points)
    factory = functools.partial(_map_system, model, dict(params), phys, names)
    for gx in (grids[0][0], grids[0][-1]):  # validate the grid's corners before the sweep
        for gy in (grids[1][0], grids[1][-1]):
            make_params(model, _point_params(dict(params), phys, names, (gx, gy, degrees[0])))
    points = [(gx, gy, d) for gy in grids[1] for gx in grids[0] for d in degrees]
    rows = _map(factory, points, kinds, workers, progress, "tau map", options)
    shape = (grids[1].size, grids[0].size, len(degrees))
    best = np.full(shape[:2], float(tau_max))
    has = np.zeros(shape[:2], dtype=bool)
    degree = np.zeros(shape[:2], dtype=int)
    which = np.full(shape[:2], "", dtype="<U1")
    err = np.zeros(shape[:2])
    for idx, row in zip(np.ndindex(*shape), rows):
        for k in kinds:
            t = row[k].tau_min
            if t is not None and t <= best[idx[:2]] and (not has[idx[:2]] or t < best[idx[:2]]):
                best[idx[:2]], has[idx[:2]] = t, True
                degree[idx[:2]], which[idx[:2]] = degrees[idx[2]], k[0].upper()
                err[idx[:2]] = row[k].error_estimate or 0.0
    units = {n: PHYSICAL_UNITS.get(n, "dimensionless") for n in names}
    p = dict(params) if phys is None else {**params, **phys}
    return TauMapResult(model=model, params=p, x_name=names[0], y_name=names[1], units=units,
                        x=grids[0], y=grids[1], degrees=tuple(degrees), tau_max=float(tau_max),
                        tau_min=best, has_tau=has, degree=degree, kind=which, error_estimate=err,
                        provenance=provenance({"kind": kind, **options}))


def natural_modes(model: str, *, count: int | None = None, precision: int | None = None,
                  zeta: float | None = None, physical: Mapping[str, float] | None = None,
                  **params: Any) -> NaturalModesResult:
    """Least-damped natural modes gamma (tau = 0: X ~ exp(gamma t)) of a model, one per
    conjugate pair (Im gamma >= 0), least damped first, each with an error estimate.

    Parameters
    ----------
    count : number of modes (default: every mode the dispersion relation has; a larger count
        returns them all, with a warning).
    precision : digits (e.g. 30) of an mpmath polish of every root (reference values).
    zeta : shorthand for kappa = 1, nu = zeta (the modes depend on zeta = nu/sqrt(kappa) only).
    physical : cgs values {rho, mu, radius, sigma} instead of kappa, nu: the modes are then
        returned in s^-1 (gamma / T, T = sqrt(rho R^3/sigma); ``params['units']``).
    **params : the model's parameters (sphere: m, kappa, nu, component; fibre: m, kappa, nu).

    Notes
    -----
    Roots of det D(gamma) = 0 (thesis (7.14); fibre: derivations/fibre_modes.py), solved in
    beta = sqrt(gamma/nu) by Newton's method from asymptotic seeds
    (:mod:`spectralshell.models.sphere_modes`, :func:`spectralshell.models.fibre.modal_system`,
    :func:`solvers.modes.find_modes`). Both models have two modes with Im gamma >= 0 (sphere:
    poloidal; its toroidal component has one). nu = 0 has the closed form gamma = i lambda0
    ((7.4), Lamb/Rayleigh; fibre: lambda0^2 = kappa m (m^2-1)/2) and no other mode.
    """
    model = check_model(model)
    if model == "cochlea":
        return _cochlea_natural_modes(count=count, precision=precision, zeta=zeta,
                                      physical=physical, params=params)
    if model not in ("sphere", "fibre"):
        raise ParameterError(f"model = {model!r} is invalid for natural modes: must be 'sphere', "
                             "'fibre' or 'cochlea'")
    if model == "fibre" and physical is not None:
        raise ParameterError("physical = given for model 'fibre' is invalid: give kappa and nu "
                             "(params.physical.fibre_forced converts cgs values) or zeta")
    scale = 1.0
    if zeta is not None or physical is not None:
        if {"kappa", "nu"} & set(params) or (zeta is not None and physical is not None):
            raise ParameterError("zeta/physical = given with kappa or nu is invalid: give one of "
                                 "(kappa, nu), zeta, or physical (rho, mu, radius, sigma)")
        if physical is not None:
            phys = PhysicalSphere(**physical_inputs(physical, SPHERE_INPUTS, SPHERE_INPUTS))
            zeta, scale = phys.zeta, 1.0 / phys.time_scale
        params = {**params, "kappa": 1.0, "nu": require_nonnegative("zeta", zeta)}
    p = make_params(model, dict(params))
    options = {"count": count, "precision": precision}
    if p.nu == 0.0:
        result = _inviscid_modes(model, p, count, precision, options)
    else:
        roots = find_modes(modal_system(p), count=count, precision=precision)
        result = NaturalModesResult.build(model=model, params=_unforced(p), roots=roots,
                                          options=options)
    if physical is None:
        return result
    digits = None if result.gamma_digits is None else tuple(
        tuple(mpmath.nstr(mpmath.mpf(d) * scale, len(d)) for d in pair) for pair in result.gamma_digits)
    return dataclasses.replace(result, gamma=result.gamma * scale,
                               error_estimate=result.error_estimate * scale, gamma_digits=digits,
                               params={**result.params, **physical, "units": "s^-1"})


def _unforced(p) -> dict[str, Any]:
    """Parameters of an unforced (tau = 0) computation: without the fibre's ``forcing`` (which
    jumps are pumped), which has no effect on natural modes."""
    return {k: v for k, v in dataclasses.asdict(p).items() if k != "forcing"}


MODES_START = 1e-10  # continuation of the cochlea's modes starts at zeta = MODES_START * zeta


def _cochlea_natural_modes(*, count, precision, zeta, physical, params) -> NaturalModesResult:
    """Natural modes of the cochlea: eigenvalues of the nonlinear matrix function
    T(s) = diag(Z_k(s; zeta)) + C (D(gamma)/kappa, s = gamma/sqrt(kappa), thesis (5.14)).

    Method (model-agnostic solver :mod:`spectralshell.solvers.nonlinear_eigen`): the inviscid
    modes s = i w_j (w_j^2 the eigenvalues of diag(sqrt(k/2)) C diag(sqrt(k/2))) are continued in
    zeta from MODES_START * zeta to zeta with step control (Newton on det T in trace form; the
    branches advance together, so a branch is compared with its neighbours at the same zeta; a
    conjugate pair that meets on the real axis in (-zeta, 0) is followed on as its two real roots).
    Roots are reported with Im s >= 0 (conjugate pairs), least damped first; the sheet margin
    min_k Re sqrt(s/zeta + k^2) classifies them. Near the cut s < -zeta (large zeta) the least
    damped modes become nearly real decays just above the cut, thesis Fig 5.7 right: at
    zeta = 1e-2, alpha = 1.56, M = 20 the three slowest have Im s = 2.5e-8, 1.6e-7, 7.5e-7; from
    zeta ~ 0.013 they pass the branch point -zeta one by one and become real decays on (-zeta, 0)
    (their mirror images leave through the branch point onto the other sheet).
    Completeness: the winding number of det T around the upper half of the physical sheet (a box
    of half-width 2 max|s| + 1 whose bottom edge runs along the upper edge of the cut, see
    :func:`spectralshell.models.cochlea.upper_half_contour`) must equal the number of modes found
    in it; otherwise the result warns.
    ``precision`` (digits >= 16): every root is polished by Newton's method on det T in mpmath
    at precision + 10 digits (:func:`spectralshell.solvers.modes.polish_root`,
    :func:`spectralshell.models.cochlea.natural_mode_residual_mp`), error = max(last step,
    10^-precision |s|), for the parameters as given in double precision (physical input is
    converted in double precision).
    Units: with ``zeta`` 1/sqrt(kappa) (kappa = 1); with ``kappa``, ``nu`` the forcing period
    (gamma = sqrt(kappa) s); with ``physical`` (cgs: rho, mu, sigma, length, lambda_c, Table 5.1
    defaults for the missing ones) s^-1, gamma = s / T with T = sqrt(rho L/(pi sigma)).
    """
    from .models.cochlea import natural_frequencies, natural_mode_family, sheet_margin
    from .params.physical import TABLE_5_1, cochlea_forced, cochlea_time_scale
    from .solvers.modes import PRECISION_MAX
    from .solvers.nonlinear_eigen import SINGULAR_RTOL, continue_roots, newton, singular_ratio

    if precision is not None:
        precision = require_int_in_range("precision", precision, 16, PRECISION_MAX)
    params = dict(params)
    scale, extras = 1.0, {}
    if zeta is not None or physical is not None:
        if {"kappa", "nu"} & set(params) or (zeta is not None and physical is not None):
            raise ParameterError("zeta/physical = given with kappa or nu is invalid: give one of "
                                 "(kappa, nu), zeta, or physical (rho, mu, sigma, length, lambda_c)")
        if physical is not None:
            phys = {**{k: TABLE_5_1[k] for k in ("rho", "mu", "sigma", "length", "lambda_c")},
                    **physical_inputs(physical, ("rho", "mu", "sigma", "length", "lambda_c"))}
            dimless = cochlea_forced(**phys, omega=1.0)
            zeta = dimless["nu"] / np.sqrt(dimless["kappa"])
            scale = 1.0 / cochlea_time_scale(rho=phys["rho"], sigma=phys["sigma"], length=phys["length"])
            if "alpha" in params:
                raise ParameterError("alpha = given with physical input is invalid: lambda_c sets it")
            params["alpha"] = dimless["alpha"]
            extras = {**phys, "zeta": float(zeta), "units": "s^-1"}
        params = {**params, "kappa": 1.0, "nu": require_nonnegative("zeta", zeta)}
    p = make_params("cochlea", params)
    if p.n_spatial is None or p.spatial_mode is not None:
        raise ParameterError(f"n_spatial = {p.n_spatial!r} is invalid for natural modes: give the "
                             "number of cosine modes M (e.g. 20, as in thesis Fig 5.7)")
    M = p.n_spatial
    count = None if count is None else require_int_in_range("count", count, 1, M)
    zeta = p.nu / np.sqrt(p.kappa)
    unit, scale = scale, scale * np.sqrt(p.kappa)  # s^-1 per forcing-period unit; gamma = scale s
    start = 1j * natural_frequencies(1.0, p.alpha, np.arange(1, M + 1))
    warnings: list[str] = []
    if zeta == 0.0:
        roots, steps = start, 4 * np.finfo(float).eps * np.abs(start)
    else:
        family = natural_mode_family(alpha=p.alpha, n_spatial=M)
        roots, steps, ok = continue_roots(family, MODES_START * zeta, zeta, start,
                                          conjugate_symmetric=True)
        T, dT = family(zeta)
        lost = 0
        for i in np.flatnonzero(~ok):  # a lost branch (near-collision): deflated Newton at zeta
            known = np.concatenate([roots[ok], roots[ok].conj()])  # roots pair up: T(conj s) = conj T(s)
            out = newton(T, dT, roots[i], known=known)
            near = np.min(np.abs(known - out[0]), initial=np.inf) if out is not None else 0.0
            if out is None or near <= 1e-5 * abs(out[0]) or singular_ratio(T, out[0]) > SINGULAR_RTOL:
                lost += 1
                continue
            roots[i], steps[i] = out
            ok[i] = True
        if lost:
            warnings.append(f"{lost} of the {roots.size} mode branches could not be followed to "
                            f"zeta = {zeta:g} and no further root was found near their last position")
        roots, steps = roots[ok], steps[ok]
        roots = np.where(roots.imag < 0, roots.conj(), roots)
        keep = [i for i in range(roots.size)
                if not np.any(np.abs(roots[:i] - roots[i]) <= 1e-8 * abs(roots[i]))]
        if len(keep) < roots.size:
            warnings.append(f"{roots.size - len(keep)} branch(es) merged with a conjugate branch")
        roots, steps = roots[keep], steps[keep]
        warnings += _cochlea_completeness(T, dT, roots, steps, zeta, M)
    order = np.argsort(-roots.real)[:count]
    roots, steps = roots[order], np.maximum(steps[order], 64 * np.finfo(float).eps * np.abs(roots[order]))
    digits, double_error = None, None
    if precision is not None:
        roots, steps, digits, double_error = _cochlea_polish(roots, precision, p, M, unit)
    gamma, err = roots * scale, steps * scale
    margin = np.array([np.inf if zeta == 0.0 else sheet_margin(r, zeta, M) for r in roots])
    margin_err = steps / max(zeta, 1e-300) / np.maximum(margin, 1e-300)  # d(Re sqrt) ~ ds/(zeta sqrt)
    on_cut = margin <= margin_err
    if on_cut.any():
        warnings.append(f"{int(on_cut.sum())} mode(s) lie on the branch cut to within their error")
    options = {"count": count, "precision": precision, "method": "continuation in zeta, Newton on "
               "det T (trace form)", "zeta": float(zeta)}
    if double_error is not None:
        options["double_error"] = [float(e) for e in double_error]
    return NaturalModesResult(model="cochlea", params={**dataclasses.asdict(p), **extras},
                              gamma=gamma, error_estimate=err, principal_sheet=~on_cut,
                              on_cut=on_cut, precision=precision, provenance=provenance(options),
                              gamma_digits=digits, warnings=tuple(warnings))


def _cochlea_completeness(T, dT, roots: np.ndarray, steps: np.ndarray, zeta: float,
                          M: int) -> list[str]:
    """Warnings unless the winding number of det T around the upper half of the physical sheet
    (:func:`spectralshell.models.cochlea.upper_half_contour`, half-width 2 max|s| + 1, dip
    zeta/4 deep, capped by the half-width) equals the number of modes found inside it: each mode
    with Im s > 0, plus, in the dip under (-zeta, 0), the mirror image of each complex mode there
    (a real mode counts once)."""
    from .models.cochlea import upper_half_contour
    from .solvers.nonlinear_eigen import count_by_winding

    radius = 2.0 * float(np.abs(roots).max(initial=0.0)) + 1.0
    depth = min(zeta, radius) / 4.0
    real = np.abs(roots.imag) <= steps
    mirrored = (~real) & (roots.real > -zeta) & (roots.real < 0) & (roots.imag < depth)
    expected = int(roots.size + mirrored.sum())
    try:
        counted = count_by_winding(T, upper_half_contour(zeta=zeta, n_spatial=M, radius=radius,
                                                         depth=depth), dT=dT)
    except ConvergenceError as exc:
        return [f"completeness not checked: {exc}"]
    if counted == expected:
        return []
    return [f"the winding number of det T counts {counted} modes with Im s >= 0 and |s| < "
            f"{radius:.3g} on the physical sheet where {expected} were found: "
            + ("some were missed" if counted > expected else "some found roots are spurious")]


def _cochlea_polish(roots: np.ndarray, precision: int, p, M: int, unit: float):
    """(roots, errors, gamma digits, |double - polished| in gamma): every root s of det T
    polished to ``precision`` digits (:func:`spectralshell.solvers.modes.polish_root`); gamma =
    unit sqrt(kappa) s, with sqrt(kappa) and zeta = nu/sqrt(kappa) in mpmath."""
    from .models.cochlea import natural_mode_residual_mp
    from .solvers.modes import polish_root

    with mpmath.workdps(precision + 10):
        zeta = mpmath.mpf(p.nu) / mpmath.sqrt(mpmath.mpf(p.kappa))
        residual = functools.partial(natural_mode_residual_mp, zeta=zeta, alpha=p.alpha, n_spatial=M)
        polished = [polish_root(residual, complex(r), precision=precision) for r in roots]
        factor = mpmath.mpf(unit) * mpmath.sqrt(mpmath.mpf(p.kappa))
        digits = tuple((mpmath.nstr(s.real * factor, precision), mpmath.nstr(s.imag * factor, precision))
                       for s, _ in polished)
        double_error = np.array([float(abs(s - r) * factor) for (s, _), r in zip(polished, roots)])
        return (np.array([complex(s) for s, _ in polished]),
                np.array([float(e) for _, e in polished]), digits, double_error)


#: model -> (lambda0^2(m, kappa), its source): the inviscid natural frequency of each model.
_INVISCID = {"sphere": (lambda0_squared, "closed form (7.4)"),
             "fibre": (fibre_lambda0_squared, "closed form lambda0^2 = kappa m (m^2 - 1)/2 "
                       "(derivations/fibre_linear_result.md, 4a)")}


FEWER_INVISCID = ("count = {} asks for more modes than nu = 0 has: its one mode is returned (the "
                  "viscous branches vanish with the viscosity)")


def _inviscid_modes(model, p, count, precision, options) -> NaturalModesResult:
    """nu = 0: the exact modes gamma = +-i lambda0 (sphere (7.4), fibre kappa m (m^2-1)/2); the
    viscous branches (the sphere's toroidal mode, the fast Stokes-layer modes) are absent."""
    if getattr(p, "component", None) == "toroidal":
        raise ParameterError("nu = 0 is invalid for toroidal modes: without viscosity the "
                             "toroidal component carries no mode")
    warnings = ()
    if count is not None and require_int_in_range("count", count, 1) > 1:
        warnings = (FEWER_INVISCID.format(count),)
    squared, method = _INVISCID[model]
    lam = np.sqrt(squared(p.m, p.kappa))
    digits = None
    if precision is not None:
        with mpmath.workdps(require_int_in_range("precision", precision, 16, 1000)):
            exact = mpmath.sqrt(squared(p.m, mpmath.mpf(p.kappa)))
            digits = (("0", mpmath.nstr(exact, precision)),)
    return NaturalModesResult(model=model, params=_unforced(p), gamma=np.array([1j * lam]),
                              error_estimate=np.array([4 * np.finfo(float).eps * lam]),
                              principal_sheet=np.array([True]), on_cut=np.array([False]),
                              precision=precision, gamma_digits=digits, warnings=warnings,
                              provenance=provenance({**options, "method": method}))


RESPONSE_MODES = 128    # default number of cosine modes of a response
RESPONSE_POINTS = 2001  # grid on [0, pi]
RESPONSE_TIMES = 256    # time samples per period of the parametric solution
GAMMA_OF_KIND = {"harmonic": 1.0, "subharmonic": 0.5}  # dominant response frequency


def _peak(x: np.ndarray, env: np.ndarray, start: float) -> float:
    """Location of the maximum of env over x >= start, refined by a parabola through 3 points."""
    i = int(np.flatnonzero(x >= start)[0] + np.argmax(env[x >= start]))
    if 0 < i < x.size - 1:
        a, b, c = env[i - 1], env[i], env[i + 1]
        denom = a - 2 * b + c
        if denom < 0:
            return float(x[i] + 0.5 * (a - c) / denom * (x[1] - x[0]))
    return float(x[i])


def _response_at(p, n_spatial: int, kind: str, options: dict[str, Any]):
    """(envelope, profile, peak, tau, response frequency) of the cochlea with n_spatial modes."""
    from .models.cochlea import TONE_WIDTH, tone_response
    from .solvers.marginal_mode import marginal_mode

    x = np.linspace(0.0, np.pi, RESPONSE_POINTS)
    basis = np.cos(np.outer(x, np.arange(1, n_spatial + 1)))
    if kind == "tone":
        h = basis @ tone_response(kappa=p.kappa, nu=p.nu, alpha=p.alpha, n_spatial=n_spatial)
        env = np.abs(h)
        profile = (h * np.exp(-1j * np.angle(h[np.argmax(env)]))).real  # t_peak: phase of the peak
        tau, freq, start = None, 1.0, 4 * TONE_WIDTH
    else:
        q = make_params("cochlea", {**dataclasses.asdict(p), "n_spatial": n_spatial})
        system = hill_system(q)
        m = marginal_tau(system, kind, **options)
        if m.tau_min is None:
            raise ParameterError(f"kind = {kind!r} has no marginal tau here (tau_max = "
                                 f"{options.get('tau_max')}): no parametric response to show")
        mode = marginal_mode(system, kind, m.tau_min, m.n_temporal)
        period = 2 * np.pi if kind == "harmonic" else 4 * np.pi
        field = mode.evaluate(np.linspace(0.0, period, RESPONSE_TIMES, endpoint=False)) @ basis.T
        env = np.abs(field).max(axis=0)
        profile = field[np.argmax(np.abs(field).max(axis=1))]
        tau, freq, start = m.tau_min, GAMMA_OF_KIND[kind], 0.0
    scale = env.max()
    return x, env / scale, profile / scale, _peak(x, env, start), tau, freq


def response(model: str, *, kind: str = "tone", tol: float = 1e-10, n_temporal: int | None = None,
             tau_max: float | None = None, max_seconds: float | None = None,
             **params: Any) -> "ResponseResult":
    """Basilar-membrane displacement envelope for a pure tone (thesis 5.5, Figs 5.8-5.10).

    Parameters
    ----------
    model : 'cochlea'.
    kind : 'tone' (passive response, tau = 0, to a pressure load at the base oscillating at the
        forcing frequency: the externally forced tone of LeVeque, Peskin & Lax), or 'harmonic' /
        'subharmonic' (the Floquet solution at tau_min of that kind, as in thesis 5.5: response
        at the forcing frequency, or half of it).
    tol, n_temporal, tau_max : options of the marginal tau (parametric kinds).
    max_seconds : raises the limit on the estimated cost of the parametric kinds' solves (at M
        and M // 2; refused above it before anything runs, as for :func:`floquet`).
    **params : as for :func:`floquet` ('cochlea' parameters or cgs inputs with omega);
        n_spatial defaults to RESPONSE_MODES; the peak's error estimate compares with n_spatial // 2.

    Notes
    -----
    The envelope is the largest |h(x, t)| over a period (for the tone, |complex amplitude|); the
    thesis draws the Hilbert-transform envelope of one snapshot instead. The peak is searched for
    x >= 4 * TONE_WIDTH for the tone (the load region itself is excluded).
    """
    from .results.response import ResponseResult

    model = check_model(model)
    if model != "cochlea":
        raise ParameterError(f"model = {model!r} is invalid for response: must be 'cochlea'")
    if kind not in ("tone", "harmonic", "subharmonic"):
        raise ParameterError(f"kind = {kind!r} is invalid: must be one of 'tone', 'harmonic', "
                             "'subharmonic'")
    options = _solver_options(tol, n_temporal, tau_max)
    params, physical = convert_physical(model, dict(params))
    p = make_params(model, params)
    if p.spatial_mode is not None:
        raise ParameterError(f"spatial_mode = {p.spatial_mode} is invalid for response: the "
                             "envelope needs n_spatial cosine modes")
    M = p.n_spatial or RESPONSE_MODES
    if kind != "tone":  # the parametric kinds solve marginal_tau at M and M // 2: priced first
        _priced(model, functools.partial(_spatial_factory, model, dataclasses.asdict(p)), (kind,),
                options, M, max_seconds)
    elif max_seconds is not None:
        raise ParameterError(f"max_seconds = {max_seconds!r} is invalid for kind = 'tone': it "
                             "solves no marginal tau")
    x, env, profile, peak, tau, freq = _response_at(p, M, kind, options)
    coarse = _response_at(p, max(M // 2, 1), kind, options)[3]
    from .models.cochlea import wkb_peak

    wkb = wkb_peak(kappa=p.kappa, nu=p.nu, alpha=p.alpha, frequency=freq) if p.nu > 0 and p.alpha > 0 \
        else float("nan")
    warnings = [] if np.isfinite(wkb) else ["the WKB peak needs nu > 0 and alpha > 0: reported as NaN"]
    if np.isfinite(wkb) and not 0 < wkb < np.pi:
        warnings.append(f"the WKB peak x = {wkb:.3g} lies outside the membrane [0, pi]")
    return ResponseResult(model=model, params={**dataclasses.asdict(p), "n_spatial": M}, kind=kind,
                          response_frequency=freq, x=x, envelope=env, profile=profile,
                          peak_x=peak, peak_error=abs(peak - coarse) + (x[1] - x[0]) / 10,
                          wkb_peak_x=wkb if np.isfinite(wkb) else None, tau=tau,
                          length=None if physical is None else physical["length"],
                          physical=physical, provenance=provenance({"kind": kind, **options}),
                          warnings=tuple(warnings))


def exponents(model: str, *, tau: float, tol: float = 1e-10, n_temporal: int | None = None,
              **params: Any) -> ExponentsResult:
    """Floquet characteristic exponents gamma at forcing amplitude ``tau``.

    Re gamma is the growth rate per unit time; Im gamma is folded into (-1/2, 1/2]. Verified
    against the monodromy matrix of ``scipy.integrate.solve_ivp`` in the tests.
    """
    model = check_model(model)
    tau = require_real("tau", tau)
    options = _solver_options(tol, n_temporal)
    p, system = _system(model, params)
    if system.polynomial is None:  # Hill's companion form needs a matrix polynomial D(s)
        if getattr(p, "nu", 0.0):
            raise ParameterError(f"nu = {p.nu!r} is invalid for Floquet exponents of model {model!r}: "
                                 "must be 0 (the viscous load is not polynomial in s); use "
                                 "floquet/stability for the marginal tau of the viscous model")
        raise ParameterError(f"component = {getattr(p, 'component', None)!r} is invalid for Floquet "
                             "exponents at nu = 0: must be 'poloidal' (the inviscid toroidal component "
                             "has no dynamics)")
    result = floquet_exponents(system, tau, **options)
    return ExponentsResult.build(model=model, params=dataclasses.asdict(p), tau=tau,
                                 exponents=result, options=options)


def stability(model: str, *, tau: float, m, kind: str = "both", tol: float = 1e-10,
              n_temporal: int | None = None, **params: Any) -> StabilityResult:
    """Is each degree m unstable at forcing amplitude ``tau``, and with which kind?

    Notes
    -----
    Every marginal tau of a kind is a Floquet multiplier crossing +1 (harmonic) or -1
    (subharmonic); for one oscillatory degree of freedom, successive crossings of the same kind
    alternately enter and leave the instability finger (thesis 2.2, Fig 2.2), so a kind is unstable
    at ``tau`` when an odd number of its marginal amplitudes lie below ``tau``. Where both kinds are
    unstable, ``kind`` names the one with the lower threshold. The rule is checked against the Floquet
    exponents in the tests.
    """
    model = check_model(model)
    tau = require_real("tau", tau)
    degrees = parse_int_range("m", m, int_bounds(model, "m"))
    options = _solver_options(tol, n_temporal)
    modes = []
    for degree in degrees:  # only the marginal tau below the asked tau are needed
        if tau > 0:
            res = floquet(model, kind=kind, m=degree, tau_max=tau, **options, **params)
            solved = res.params
        else:  # marginal tau are >= 0: none lies below tau <= 0, nothing to solve
            res, solved = None, dataclasses.asdict(make_params(model, {**params, "m": degree}))
        entry: dict[str, Any] = {"m": degree, "unstable": False, "kind": None}
        thresholds = {}
        for k in expand_kind(kind):
            below = [] if res is None else [float(t) for t in getattr(res, k).tau if t < tau]
            entry[f"tau_{k}"] = below
            if len(below) % 2 == 1:
                thresholds[k] = below[0]
        if thresholds:
            entry["unstable"], entry["kind"] = True, min(thresholds, key=thresholds.get)
        modes.append(entry)
    p = {k: v for k, v in solved.items() if k != "m"}
    return StabilityResult(model=model, tau=tau, params=p, modes=tuple(modes),
                           warnings=tuple(amplitude_warnings(tau)),
                           provenance=provenance({"kind": kind, **options}))


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


def sweep(scene: str | Path | Mapping, *, executor: str = "processes", workers: int | None = None,
          scheduler: str | None = None, out: str | Path | None = None, progress: bool = False):
    """Parameter sweep of a scene with a [grid] -> labelled ``xarray.Dataset``.

    Parameters
    ----------
    scene : path, TOML string or dict: model, ask = ["tau_min"], [params], [grid] (value lists,
        {start, stop, num} or {start, stop, num, spacing = "log"}; 'm' integers; 'kind'),
        optional [tau_min] (tol, n_temporal, tau_max = 0.5, continuation) and [sweep] (chunk).
    executor : 'serial', 'processes' (all cores, or ``workers``) or 'dask' (``scheduler`` =
        'local' for a LocalCluster, or 'tcp://HOST:PORT').
    out : '*.zarr' written chunk by chunk (a rerun resumes, a different scene is refused) or
        '*.nc' written at the end; None keeps the result in memory.

    Notes
    -----
    Variables tau_min (= tau_max where has_tau is false: NaN-free), has_tau, error_estimate,
    n_temporal, computed over the grid axes (units in attrs); for models with spatial modes
    (cochlea) also n_spatial and spatial_converged (False: the refinement in n_spatial stopped
    at its limit; the values are those at the limit); provenance in attrs. Every executor gives
    the same numbers. See :mod:`spectralshell.runner`.
    """
    from .runner import sweep as run  # lazy: xarray costs ~0.35 s to import

    return run(scene, executor=executor, workers=workers, scheduler=scheduler, out=out,
               progress=progress)


def sweep_summary(scene: str | Path | Mapping, **kwargs: Any) -> dict[str, Any]:
    """Run :func:`sweep` and return ``{"points", "computed", "skipped", "damaged", "out",
    "seconds"}`` (damaged: points recomputed because their chunk of the store was damaged)."""
    from .runner import sweep_summary as run

    return run(scene, **kwargs)


def open_sweep(path: str | Path):
    """Load a stored sweep (.zarr or .nc) as an ``xarray.Dataset``; a Zarr store is verified
    chunk by chunk first (:class:`~spectralshell.errors.StoreDamaged` if any chunk is missing,
    unreadable or altered)."""
    from .runner import open_sweep as load

    return load(path)


def simulate(scene: str | Path | Mapping, *, progress: bool = False):
    """Time-step a sphere scene (TOML path or string, or mapping) -> :class:`Trajectory`.

    The linearised membrane in unsteady Stokes flow inside and outside the unit sphere, one
    semi-discrete system per degree of the initial shape (radial Chebyshev, reduced to an ODE;
    :mod:`spectralshell.discretise.sphere_stepping`), stepped with an IMEX scheme of
    :mod:`spectralshell.solvers.imex`; nu = 0 steps the Mathieu equation per degree. Returns the
    mode coefficients against time and, per excited mode, the fitted growth rate and frequency
    with an error estimate (:mod:`spectralshell.runner.simulate`). Scene keys:
    :mod:`spectralshell.params.simulation`.

    Raises
    ------
    ParameterError : a scene value out of range.
    ConvergenceError : the radial resolution cannot reach the scene's tol, or the state blew up.
    """
    from .runner.simulate import simulate as run  # lazy: keeps `import spectralshell` light

    return run(scene, progress=progress)


def lp_coefficient(m: int, k: int = 0, *, volume: str = "reference") -> float:
    """Nonlinear frequency coefficient c_{m,k}: lambda = lambda0 (1 + c eps^2 + O(eps^4)) for the
    inviscid sphere started from 1 + eps Y_{m,k} (thesis 7.3; radial-only membrane displacement).

    Exact values generated by ``derivations/lindstedt_sphere.py`` (Lindstedt-Poincare with Gaunt
    coefficients; degrees 0 and 1 carried); the thesis's printed c_2, c_3, c_4 do not survive
    (see :mod:`spectralshell.models.nonlinear_coefficients`). ``volume``: 'reference' (enclosed
    volume of the unit sphere) or 'literal' (the shape exactly 1 + eps Y; c shifts by -3/(8 pi)).
    """
    return lp_coefficient_float(m, k, volume=volume)


def lp_summary(m: int, k: int = 0, *, volume: str = "reference", check: bool = False) -> dict[str, Any]:
    """The JSON of ``spectralshell lp``: coefficient (float and exact), lambda0/sqrt(kappa), and
    with ``check`` the slope fitted to direct periodic-orbit solves (no expansion in eps)."""
    num, den = lp_coefficient_exact(m, k, volume=volume)
    out: dict[str, Any] = {"m": int(m), "k": int(k), "coefficient": lp_coefficient(m, k, volume=volume),
                           "coefficient_exact": f"{num}/({den}*pi)",
                           "lambda0_over_sqrt_kappa": lambda0_over_sqrt_kappa(int(m)),
                           "volume": volume}
    if check:
        fit = frequency_slope(sphere_nonlinear, int(m), int(k))
        out["check"] = {"slope": fit.c, "uncertainty": fit.uncertainty,
                        "method": "Fourier x spherical-harmonic periodic orbit, Newton, "
                                  "fit of lambda/lambda0 - 1 against eps^2"}
    return out
