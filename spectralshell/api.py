"""The Python API facade: validate, plan, dispatch to the solvers, return result objects.

Conventions (see README "Conventions"): K(t) = kappa (1 + 2 tau sin t), forcing period 2 pi,
harmonic gamma = 0, subharmonic gamma = i/2.
"""

from __future__ import annotations

import dataclasses
import functools
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import mpmath
import numpy as np

from ._validate import require_int_in_range, require_nonnegative, require_positive, require_real
from .discretise.fourier import expand_kind
from .errors import ParameterError
from .models.base import HillSystem
from .models.registry import hill_system, modal_system
from .models.nonlinear_coefficients import lp_coefficient as lp_coefficient_float
from .models.nonlinear_coefficients import lp_coefficient_exact
from .models.sphere import lambda0_squared
from .models.sphere_nonlinear import lambda0_over_sqrt_kappa
from .params.grid import parse_int_range, parse_range
from .params.physical import PHYSICAL_UNITS, PhysicalSphere, sphere_forced_params
from .params.registry import check_model, make_params
from .params.scene import Plan, plan
from .results.maps import TauMapResult
from .results.modes import NaturalModesResult
from .results.floquet import (ExponentsResult, FloquetResult, StabilityResult, TonguesResult,
                              provenance, tau_warnings)
from .solvers.exponents import floquet_exponents
from .solvers.marginal import N_MAX, marginal_tau
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
            tau_max: float | None = None, **params: Any) -> FloquetResult:
    """Marginal forcing amplitudes tau (Floquet boundaries) of a model.

    Parameters
    ----------
    model : a name from ``spectralshell.params.registry.PARAMS`` ('mathieu', 'sphere', ...).
    kind : 'both', 'harmonic' (gamma = 0) or 'subharmonic' (gamma = i/2); only those are computed.
    tol : absolute tolerance on tau_min; the truncation grows until it is met.
    n_temporal : fix the truncation N instead (the error estimate compares with a smaller N).
    tau_max : compute only the marginal tau <= tau_max (e.g. 0.5, the physical range); the
        truncation then grows only as far as those need, and tau_min is None when there is none.
    **params : the model's parameters, e.g. ``kappa``, ``nu`` for 'mathieu'.

    Notes
    -----
    Solves the Hill system (thesis (2.6) with reality conditions (2.7)/(2.8)) of the model.

    Raises
    ------
    ParameterError : a parameter, kind or option out of range.
    ConvergenceError : tau_min did not converge to ``tol``.
    """
    model = check_model(model)
    kinds = expand_kind(kind)
    options = _solver_options(tol, n_temporal, tau_max)
    p, system = _system(model, params)
    res = {k: marginal_tau(system, k, **options) for k in kinds}
    warnings = tau_warnings(t for m in res.values() for t in m.tau)
    return FloquetResult(model=model, params=dataclasses.asdict(p), harmonic=res.get("harmonic"),
                         subharmonic=res.get("subharmonic"),
                         provenance=provenance({"kind": kind, **options}), warnings=tuple(warnings))


PARALLEL_MIN_POINTS = 400  # below this a process pool costs more than it saves


def _map(factory, points: list, kinds: tuple[str, ...], workers: int | None, progress: bool,
         desc: str, options: dict[str, Any]) -> list:
    """Marginal tau at every point through the sweep runner: serial for ``workers=1`` or small
    grids, otherwise a process pool (all cores when ``workers`` is None)."""
    serial = workers == 1 or (workers is None and len(points) < PARALLEL_MIN_POINTS)
    chunk = max(1, -(-len(points) // (4 * (workers or os.cpu_count() or 1))))
    return map_points(factory, points, kinds, executor="serial" if serial else "processes",
                      workers=None if serial else workers, chunk=chunk, progress=progress,
                      desc=desc, **options)


def _factory(model: str, params: dict[str, Any], kappa: float) -> HillSystem:
    return _system(model, {**params, "kappa": kappa})[1]


def tongues(model: str, *, kappa, kind: str = "both", tol: float = 1e-10,
            n_temporal: int | None = None, tau_max: float | None = None, tips: bool = True,
            workers: int | None = None, progress: bool = False, **params: Any) -> TonguesResult:
    """Ince-Strutt diagram: marginal tau of each kind over a kappa grid, and the finger tips.

    Parameters
    ----------
    kappa : the grid (array-like, or 'start:stop:num').
    tips : locate the minimum (kappa, tau) of every finger that shows as a local minimum of
        tau_min on the grid (to ~1e-12 in kappa; see ``solvers.tongues.refine_tip``).
    workers : processes (None: all cores for large grids; 1: serial). progress : show a bar.
    tau_max : only the marginal tau <= tau_max are computed (as in :func:`floquet`).
    Other parameters as in :func:`floquet`; ``params`` must not contain ``kappa``.
    """
    model = check_model(model)
    kinds = expand_kind(kind)
    options = _solver_options(tol, n_temporal, tau_max)
    grid = parse_range("kappa", kappa) if isinstance(kappa, str) else \
        np.array([require_real("kappa", k) for k in np.atleast_1d(kappa)])
    if not grid.size:
        raise ParameterError("kappa = [] is invalid: must be a non-empty grid")
    for k in (grid.min(), grid.max()):
        make_params(model, {**params, "kappa": k})
    factory = functools.partial(_factory, model, dict(params))
    rows = _map(factory, list(grid), kinds, workers, progress, "tongues", options)
    found, failures = find_tips(factory, grid, rows, kinds, tol=options["tol"]) if tips else ([], [])
    warnings = tau_warnings(t for r in rows for m in r.values() for t in m.tau) + failures
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


def tau_map(model: str, *, x: tuple[str, Any], y: tuple[str, Any], m, kind: str = "both",
            tau_max: float = 0.5, tol: float = 1e-8, physical: Mapping[str, float] | None = None,
            workers: int | None = None, progress: bool = False, **params: Any) -> TauMapResult:
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

    Notes
    -----
    Every point solves only the marginal tau <= tau_max (``marginal_tau(tau_max=...)``), in
    parallel over all cores with a progress bar; the value is the minimum over m and kind, and
    ``degree``/``kind`` record which one attains it (thesis Fig 6.13 labels 'm H/S').
    """
    model = check_model(model)
    kinds = expand_kind(kind)
    options = _solver_options(tol, None, tau_max)
    degrees = parse_int_range("m", m)
    names = (str(x[0]), str(y[0]))
    grids = [parse_range(n, g) if isinstance(g, str) else
             np.array([require_real(n, v) for v in np.atleast_1d(g)]) for n, g in (x, y)]
    if any(not g.size for g in grids):
        raise ParameterError("x/y grid = [] is invalid: must be a non-empty grid")
    phys = None if physical is None else {k: float(v) for k, v in physical.items()}
    for name in names:
        if name in PHYSICAL_UNITS and phys is None:
            raise ParameterError(f"axis {name} = physical quantity is invalid without physical=")
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
    count : number of modes (default: every mode the dispersion relation has).
    precision : digits (e.g. 30) of an mpmath polish of every root (reference values).
    zeta : shorthand for kappa = 1, nu = zeta (the modes depend on zeta = nu/sqrt(kappa) only).
    physical : cgs values {rho, mu, radius, sigma} instead of kappa, nu: the modes are then
        returned in s^-1 (gamma / T, T = sqrt(rho R^3/sigma); ``params['units']``).
    **params : the model's parameters (sphere: m, kappa, nu, component).

    Notes
    -----
    Roots of det D(gamma) = 0 (thesis (7.14)), solved in beta = sqrt(gamma/nu) by Newton's method
    from asymptotic seeds (:mod:`spectralshell.models.sphere_modes`, :func:`solvers.modes.find_modes`).
    nu = 0 has the closed form gamma = i lambda0 ((7.4), Lamb/Rayleigh) and no toroidal mode.
    """
    model = check_model(model)
    if model != "sphere":
        raise ParameterError(f"model = {model!r} is invalid for natural modes: must be 'sphere'")
    scale = 1.0
    if zeta is not None or physical is not None:
        if {"kappa", "nu"} & set(params) or (zeta is not None and physical is not None):
            raise ParameterError("zeta/physical = given with kappa or nu is invalid: give one of "
                                 "(kappa, nu), zeta, or physical (rho, mu, radius, sigma)")
        if physical is not None:
            phys = PhysicalSphere(**{k: float(v) for k, v in physical.items()})
            zeta, scale = phys.zeta, 1.0 / phys.time_scale
        params = {**params, "kappa": 1.0, "nu": require_nonnegative("zeta", zeta)}
    p = make_params(model, dict(params))
    options = {"count": count, "precision": precision}
    if p.nu == 0.0:
        result = _inviscid_modes(p, count, precision, options)
    else:
        roots = find_modes(modal_system(p), count=count, precision=precision)
        result = NaturalModesResult.build(model=model, params=dataclasses.asdict(p), roots=roots,
                                          options=options)
    if physical is None:
        return result
    digits = None if result.gamma_digits is None else tuple(
        tuple(mpmath.nstr(mpmath.mpf(d) * scale, len(d)) for d in pair) for pair in result.gamma_digits)
    return dataclasses.replace(result, gamma=result.gamma * scale,
                               error_estimate=result.error_estimate * scale, gamma_digits=digits,
                               params={**result.params, **physical, "units": "s^-1"})


def _inviscid_modes(p, count, precision, options) -> NaturalModesResult:
    """nu = 0: the exact modes gamma = +-i lambda0 ((7.4)); the toroidal part has none."""
    if p.component == "toroidal":
        raise ParameterError("nu = 0 is invalid for toroidal modes: without viscosity the "
                             "toroidal component carries no mode")
    if count is not None:
        require_int_in_range("count", count, 1, 1)
    lam = np.sqrt(lambda0_squared(p.m, p.kappa))
    digits = None
    if precision is not None:
        with mpmath.workdps(require_int_in_range("precision", precision, 16, 1000)):
            exact = mpmath.sqrt(mpmath.mpf(p.kappa) * p.m * (p.m + 1) * (p.m - 1) * (p.m + 2)
                                / (2 * p.m + 1))
            digits = (("0", mpmath.nstr(exact, precision)),)
    return NaturalModesResult(model="sphere", params=dataclasses.asdict(p), gamma=np.array([1j * lam]),
                              error_estimate=np.array([4 * np.finfo(float).eps * lam]),
                              principal_sheet=np.array([True]), on_cut=np.array([False]),
                              precision=precision, gamma_digits=digits,
                              provenance=provenance({**options, "method": "closed form (7.4)"}))


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
    degrees = parse_int_range("m", m)
    options = _solver_options(tol, n_temporal)
    modes = []
    for degree in degrees:  # only the marginal tau below the asked tau are needed
        res = floquet(model, kind=kind, m=degree, tau_max=abs(tau) or None, **options, **params)
        entry: dict[str, Any] = {"m": degree, "unstable": False, "kind": None}
        thresholds = {}
        for k in expand_kind(kind):
            below = [float(t) for t in getattr(res, k).tau if t < tau]
            entry[f"tau_{k}"] = below
            if len(below) % 2 == 1:
                thresholds[k] = below[0]
        if thresholds:
            entry["unstable"], entry["kind"] = True, min(thresholds, key=thresholds.get)
        modes.append(entry)
    p = {k: v for k, v in res.params.items() if k != "m"}
    return StabilityResult(model=model, tau=tau, params=p, modes=tuple(modes),
                           warnings=tuple(tau_warnings([abs(tau)])),
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
    n_temporal, computed over the grid axes (units in attrs); provenance in attrs. Every
    executor gives the same numbers. See :mod:`spectralshell.runner`.
    """
    from .runner import sweep as run  # lazy: xarray costs ~0.35 s to import

    return run(scene, executor=executor, workers=workers, scheduler=scheduler, out=out,
               progress=progress)


def sweep_summary(scene: str | Path | Mapping, **kwargs: Any) -> dict[str, Any]:
    """Run :func:`sweep` and return ``{"points", "computed", "skipped", "out", "seconds"}``."""
    from .runner import sweep_summary as run

    return run(scene, **kwargs)


def open_sweep(path: str | Path):
    """Load a stored sweep (.zarr or .nc) as an ``xarray.Dataset``."""
    from .runner import open_sweep as load

    return load(path)


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
        fit = frequency_slope(int(m), int(k))
        out["check"] = {"slope": fit.c, "uncertainty": fit.uncertainty,
                        "method": "Fourier x spherical-harmonic periodic orbit, Newton, "
                                  "fit of lambda/lambda0 - 1 against eps^2"}
    return out
