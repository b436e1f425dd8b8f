"""Run a simulation scene: build the per-degree systems, step them, fit rates -> Trajectory.

Time grid. The step is dt = ``DT_FACTOR`` / max(1, |s|), s the fastest degree's leading natural
mode (its inviscid frequency lambda0 when nu = 0), unless the scene gives dt. With forcing
(tau != 0) the step is then reduced so that one period 2 pi is a whole number of steps, a multiple
of ``SAMPLES_PER_PERIOD``, and the run ends at the first step >= t_end. Samples are saved
``SAMPLES_PER_PERIOD`` times per forcing period, or per period 2 pi / |s| of the leading mode when
unforced.

Fits and their error. Each excited mode's coefficient is fitted by
:func:`spectralshell.solvers.rate_fit.fit_rate` on the window [t_a, t_b]: t_a leaves out the
initial transient (two periods of the leading mode, or of the forcing, and at most 20 % of the
run); for a decaying mode t_b is where it has decayed by e^-25, beyond which the run holds the
algebraic long-time tail of the unbounded fluid (the discretised continuous spectrum) rather than
the mode. The error estimate adds (1) the fit's own (sub-window) spread, (2) the change of the
fit when the whole run is repeated at step 2 dt (time discretisation; conservative, the error at
dt being smaller by 2^p) and (3) the radial discretisation error of the degree's leading mode
times |gamma|.

A uniform kappa steps one system per degree (its orders k as columns) and fits every mode of the
shape; a kappa(theta, phi) steps the coupled system of :mod:`spectralshell.discretise.sphere_coupled`
and fits every mode reaching ``EXCITED`` times the largest amplitude.
"""

from __future__ import annotations

import dataclasses
import importlib
import time
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from .._validate import require_positive, require_real
from .._version import stamp
from ..discretise.sphere_stepping import scene_blocks, shape_coefficients
from ..errors import ParameterError, SpectralShellError
from ..params.limits import SECONDS
from ..params.registry import get_model, param_names, stepping_keywords
from ..params.simulation import (STEPPED_T_END, Expression, SimulationScene, SteppedScene,
                                 simulation_scene, sphere_scene)
from ..params.stiffness import amplitude_warnings
from ..results.records import RateFit
from ..results.stepped import SteppedRun
from ..results.trajectory import ModeFit, Trajectory
from ..solvers.cost import DENSE_SECONDS
from ..solvers.imex import scheme as get_scheme
from ..solvers.rate_fit import fit_rate
from ..solvers.stepper import MAX_STEPS, Run, integrate
from .progress import progress_bar

DT_FACTOR = 0.02
SAMPLES_PER_PERIOD = 32
TRANSIENT_PERIODS = 2.0
DECAY_WINDOW = 25.0      # e-folds of a decaying mode kept in the fit window
EXCITED = 1e-3           # coupled runs: modes above this fraction of the largest are fitted
MIN_PERIODS = 10         # the fibre's and the cochlea's fits need this many forcing periods
#: Seconds per step per n^2 of a dense system of n unknowns (the implicit solve and the explicit
#: product). Measured, SBDF3 with its 2 dt check run, on a 2-core machine under a load of ~6:
#: the cochlea at t_end = 40 pi, M = 4 (n = 388) and M = 8 (n = 776), took 8.6 s and 31 s in
#: all, against estimates (these steps and DENSE_SECONDS per eigenproblem) of 4.9 s and 22 s;
#: the price is an order of magnitude, enough to refuse a run of hours before it starts.
STEP_SECONDS = 3e-9


def time_grid(*, dt: float | None, rate: float, tau: float, t_end: float) -> tuple[float, int, int, float]:
    """(step, save every, steps, end time) of a run (see the module docstring); steps is a
    multiple of 2 every. ParameterError when t_end / step exceeds the stepper's MAX_STEPS."""
    step = dt if dt is not None else DT_FACTOR / max(1.0, rate)
    if t_end / step > MAX_STEPS:
        source = "simulate.dt" if dt is not None else "the fastest mode's step DT_FACTOR / |s|"
        raise ParameterError(f"simulate.t_end = {t_end:g} is invalid with dt = {step:.3g} "
                             f"({source}): {t_end / step:.3g} steps, above the limit of {MAX_STEPS:,}; shorten "
                             "t_end or give a larger dt")
    if tau != 0.0:
        per_period = int(np.ceil(2 * np.pi / step - 1e-9))
        samples = min(SAMPLES_PER_PERIOD, per_period)
        per_period = int(np.ceil(per_period / samples)) * samples
        step = 2 * np.pi / per_period
        every = per_period // samples
    else:
        every = max(1, int(round(2 * np.pi / max(rate, 1e-12) / SAMPLES_PER_PERIOD / step)))
    steps = int(np.ceil(t_end / step - 1e-9))
    every = min(every, max(1, steps // 24))
    steps = int(np.ceil(steps / (2 * every))) * 2 * every     # even: the check run takes 2 dt
    return step, every, steps, steps * step


def fit_window(t_end: float, leading: complex, forced: bool) -> tuple[float, float]:
    period = 2 * np.pi if forced else 2 * np.pi / max(abs(leading), 1e-12)
    t_a = min(TRANSIENT_PERIODS * period, 0.2 * t_end)
    t_b = t_end
    if not forced and leading.real < 0:
        t_b = min(t_end, t_a + DECAY_WINDOW / -leading.real)
    return t_a, t_b


def _fit_mode(mode: tuple[int, int], fine: tuple, coarse: tuple, leading: complex,
              spatial_error: float, forced: bool, warnings: list[str]) -> list[ModeFit]:
    """The fit of one mode's coefficient (fine and coarse (times, values)), with its error."""
    t_a, t_b = fit_window(fine[0][-1], leading, forced)
    period = 2 * np.pi if forced else None
    try:
        f = fit_rate(*fine, period=period, window=(t_a, t_b))
        c = fit_rate(*coarse, period=period, window=(t_a, t_b))
    except SpectralShellError as exc:
        warnings.append(f"mode {mode}: no rate fitted ({exc})")
        return []
    time_error = max(abs(f.growth_rate - c.growth_rate), abs(f.frequency - c.frequency))
    space_error = spatial_error * abs(complex(f.growth_rate, f.frequency))
    return [Trajectory.fit_of(mode[0], mode[1], f, time_error + space_error)]


def stepped_runs(systems: list, initials: list, scheme: str, step: float, steps: int, every: int,
          progress: bool) -> tuple[list[Run], list[Run]]:
    """Every system stepped at dt and, for the error estimate, at 2 dt (same saved times when
    ``every`` is even, every other one otherwise)."""
    coarse_every = every // 2 if every % 2 == 0 else every
    total = len(systems) * (steps + steps // 2)
    with progress_bar(total, "simulate", "step", progress) as bar:
        fine = [integrate(s, y0, scheme=scheme, dt=step, t_end=steps * step, every=every,
                          observe=s.displacement, progress=bar.update)
                for s, y0 in zip(systems, initials)]
        coarse = [integrate(s, y0, scheme=scheme, dt=2 * step, t_end=steps * step,
                            every=coarse_every, observe=s.displacement, progress=bar.update)
                  for s, y0 in zip(systems, initials)]
    return fine, coarse


def _provenance(scheme, step, steps, every, degrees, method, started) -> dict:
    return {**stamp(), "scheme": scheme, "dt": step, "steps": steps, "samples_every": every,
            "degrees": degrees, "method": method, "seconds": time.perf_counter() - started}


def _degrees(systems) -> list[dict]:
    return [{"m": s.m, "component": s.component, "n_radial": s.n_inner,
             "exterior_scale": s.exterior_scale, "spatial_error": s.spatial_error}
            for s in systems]


def _decoupled(sc: SimulationScene, shape: dict, scheme: str, warnings: list[str],
               progress: bool, started: float) -> Trajectory:
    blocks = scene_blocks(shape=shape, twist=sc.twist, kappa=sc.kappa, nu=sc.nu, tau=sc.tau,
                          n_radial=sc.n_radial, tol=sc.tol)
    rate = max(abs(b.system.leading) for b in blocks)
    step, every, steps, t_end = time_grid(dt=sc.dt, rate=rate, tau=sc.tau, t_end=sc.t_end)
    fine, coarse = stepped_runs([b.system for b in blocks], [b.initial for b in blocks], scheme, step,
                         steps, every, progress)
    times = fine[0].times
    columns: dict[str, list] = {"radial": [], "tangential": [], "toroidal": []}
    modes, toroidal_modes, fits = [], [], []
    for b, f, c in zip(blocks, fine, coarse):
        for j, mk in enumerate(b.modes):
            if b.system.component == "poloidal":
                modes.append(mk)
                columns["radial"].append(f.values[:, 0, j])
                columns["tangential"].append(f.values[:, 1, j] if b.system.nu > 0
                                             else np.zeros(times.size))
            else:
                toroidal_modes.append(mk)
                columns["toroidal"].append(f.values[:, 0, j])
            fits += _fit_mode(mk, (times, f.values[:, 0, j]), (c.times, c.values[:, 0, j]),
                              b.system.leading, b.system.spatial_error, sc.tau != 0.0, warnings)
    arrays = {k: np.column_stack(v) if v else np.zeros((times.size, 0))
              for k, v in columns.items()}
    prov = _provenance(scheme, step, steps, every, _degrees(b.system for b in blocks),
                       "IMEX time stepping of the radial Chebyshev system per degree "
                       "(discretise/sphere_stepping.py)", started)
    return Trajectory(model="sphere", params={**sc.params(), "t_end": t_end, "scheme": scheme,
                                              "dt": step},
                      times=times, modes=tuple(modes), toroidal_modes=tuple(toroidal_modes),
                      fits=tuple(fits), provenance=prov, warnings=tuple(warnings), **arrays)


def _coupled(sc: SimulationScene, shape: dict, scheme: str, warnings: list[str], progress: bool,
             started: float) -> Trajectory:
    from ..discretise.sphere_coupled import coupled_system

    if sc.twist:
        raise ParameterError("initial.twist is not supported with a non-uniform kappa")
    system = coupled_system(kappa=sc.kappa.function, shape=shape, nu=sc.nu, tau=sc.tau,
                            l_max=sc.l_max, max_degree=sc.l_max if sc.l_max_given else None,
                            n_radial=sc.n_radial, tol=sc.tol)
    warnings += system.warnings
    rate = max(abs(g.system.leading) for g in system.groups)
    step, every, steps, t_end = time_grid(dt=sc.dt, rate=rate, tau=sc.tau, t_end=sc.t_end)
    (fine,), (coarse,) = stepped_runs([system], [system.initial_state(shape)], scheme, step, steps,
                               every, progress)
    n = len(system.modes)
    radial, tangential, toroidal = fine.values[:, :n], fine.values[:, n:2 * n], fine.values[:, 2 * n:]
    by_degree = {g.m: g.system for g in system.groups if g.component == "poloidal"}
    scale = np.max(np.abs(radial))
    fits = []
    for j, mk in enumerate(system.modes):   # modes carrying at least 1e-3 of the largest amplitude
        if np.max(np.abs(radial[:, j])) >= EXCITED * scale:
            deg = by_degree[mk[0]]
            fits += _fit_mode(mk, (fine.times, radial[:, j]), (coarse.times, coarse.values[:, j]),
                              deg.leading, deg.spatial_error, sc.tau != 0.0, warnings)
    prov = _provenance(scheme, step, steps, every, _degrees(g.system for g in system.groups),
                       "IMEX time stepping, degrees coupled by kappa(theta, phi) through products "
                       "on an SHTns grid (discretise/sphere_coupled.py)", started)
    prov["kappa_mean"] = system.kappa_mean
    return Trajectory(model="sphere", params={**sc.params(), "t_end": t_end, "scheme": scheme,
                                              "dt": step},
                      times=fine.times, modes=system.modes, radial=radial, tangential=tangential,
                      toroidal_modes=system.toroidal_modes, toroidal=toroidal, fits=tuple(fits),
                      provenance=prov, warnings=tuple(warnings))


def simulate_model(model: str, *, progress: bool = False,
                   **keywords: Any) -> Trajectory | SteppedRun:
    """``ss.simulate(model, **keywords)``: the model's stepper (its registered
    :class:`~spectralshell.params.registry.TimeStepping`), after the keywords are checked
    against the ones it declares.

    Raises
    ------
    ParameterError : the model cannot be time-stepped, an unknown or missing keyword.
    """
    known = stepping_keywords(model)
    unknown = sorted(set(keywords) - set(known))
    if unknown:
        raise ParameterError(f"{unknown[0]} is not a keyword of simulate for model {model!r}: "
                             f"expected {', '.join(known)}")
    stepping = get_model(model).time_stepping
    missing = [k for k in stepping.required if keywords.get(k) is None]
    if missing:
        raise ParameterError(f"{missing[0]}= is missing: simulate of model {model!r} needs "
                             f"{', '.join(k + '=' for k in stepping.required)}")
    module, _, function = stepping.runner.partition(":")
    run = getattr(importlib.import_module(module), function)
    return run(progress=progress, **{k: v for k, v in keywords.items() if v is not None})


def simulate_sphere(*, progress: bool = False, **keywords: Any) -> Trajectory:
    """``ss.simulate("sphere", **keywords)``: the scene of the keywords
    (:func:`spectralshell.params.simulation.sphere_scene`) simulated."""
    return simulate(sphere_scene(keywords), progress=progress)


def stepped_settings(tau: Any, t_end: Any, dt: Any, amplitude: Any, scheme: Any
                     ) -> tuple[float, float, float | None, float, str, list[str]]:
    """(tau, t_end, dt, amplitude, scheme name, warnings) of a run of the fibre or the cochlea,
    validated: t_end >= MIN_PERIODS forcing periods (the fit's window) and its steps within the
    stepper's limit at the largest step the run may take (dt, or DT_FACTOR), amplitude nonzero
    (a linear system started at 0 stays there), |tau| > 1/2 flagged."""
    tau = require_real("tau", tau)
    t_end = require_real("t_end", t_end)
    least = MIN_PERIODS * 2 * np.pi
    if not t_end >= least:
        raise ParameterError(f"t_end = {t_end!r} is invalid: must be >= {least:.6g} "
                             f"({MIN_PERIODS} forcing periods 2 pi; default {STEPPED_T_END:.6g})")
    dt = None if dt is None else require_positive("dt", dt)
    time_grid(dt=dt, rate=1.0, tau=tau, t_end=t_end)    # the fewest steps the run may take
    amplitude = require_real("amplitude", amplitude)
    if amplitude == 0.0:
        raise ParameterError("amplitude = 0 is invalid: must be nonzero (the linear system "
                             "started at rest stays there)")
    if not isinstance(scheme, str):
        raise ParameterError(f"scheme = {scheme!r} is invalid: must be a scheme name")
    return tau, t_end, dt, amplitude, get_scheme(scheme.upper()).name, amplitude_warnings(tau)


def price_stepping(what: str, size: int, *, eigenproblems: int = 0, steps: int = 0,
                   max_seconds: float | None = None) -> float:
    """Refuse a run of a dense system of ``size`` unknowns above the limit on estimated
    seconds (:data:`spectralshell.params.limits.SECONDS`): ``eigenproblems`` dense
    eigenproblems (DENSE_SECONDS n^3 each) and ``steps`` steps (STEP_SECONDS n^2 each, the
    2 dt check run's half as many included by the caller). Returns the estimate."""
    seconds = DENSE_SECONDS * eigenproblems * size ** 3 + STEP_SECONDS * steps * size ** 2
    work = f"{eigenproblems} dense eigenproblems" if eigenproblems else f"{steps:,} steps"
    SECONDS.check(f"{what} ({work} of {size} unknowns)", seconds, max_seconds,
                  "lower the resolution, or t_end, or give a larger dt")
    return seconds


def stepped_fit(fine: Run, coarse: Run, columns: range | list[int], window: tuple[float, float],
                forced: bool, relative_space_error: float) -> tuple[int, RateFit]:
    """(the column, its fit) of the fastest-growing of ``columns`` of the run at dt, with the
    error estimate: the fit's own, plus its change in the 2 dt run, plus
    ``relative_space_error`` times |gamma|."""
    period = 2 * np.pi if forced else None
    fits = [[fit_rate(run.times, run.values[:, j], period=period, window=window)
             for j in columns] for run in (fine, coarse)]
    best = int(np.argmax([fit.growth_rate for fit in fits[0]]))
    f, c = fits[0][best], fits[1][best]
    time_error = max(abs(f.growth_rate - c.growth_rate), abs(f.frequency - c.frequency))
    space_error = relative_space_error * abs(complex(f.growth_rate, f.frequency))
    return list(columns)[best], dataclasses.replace(
        f, error_estimate=float(f.error_estimate + time_error + space_error))


def leading_exponent(run: SteppedRun) -> complex:
    """The leading Floquet exponent gamma (largest Re gamma) of ``ss.exponents`` at the model
    parameters and tau of a stepped run: what its fitted growth rate approximates (the
    reference slope of its figure). It costs a fraction of the run: 0.4 s for the fibre
    (m = 3), 0.5 s and 5.7 s for the cochlea at M = 4 and 16 (one core).

    Raises
    ------
    ConvergenceError : the exponents cannot be computed to their tolerance.
    """
    from .floquet import exponents

    params = {k: v for k, v in run.params.items() if k in param_names(run.model)}
    return complex(exponents(run.model, tau=run.params["tau"], count=1, **params).gamma[0])


def stepped_result(model: str, params: dict[str, Any], fine: Run, series: tuple[str, ...],
                   column: int, fit: RateFit, *, scheme: str, every: int, method: str,
                   resolution: dict[str, Any], warnings: list[str], started: float) -> SteppedRun:
    """The :class:`SteppedRun` of a stepped fibre or cochlea (``params``: the model's and the
    run's settings; ``resolution``: the discretisation and its error, for the provenance)."""
    prov = {**stamp(), "scheme": scheme, "dt": fine.dt, "steps": fine.steps,
            "samples_every": every, "method": method, **resolution,
            "seconds": time.perf_counter() - started}
    return SteppedRun(model=model, params={**params, "t_end": float(fine.times[-1]),
                                           "scheme": scheme, "dt": fine.dt},
                      times=fine.times, series=series, values=np.asarray(fine.values),
                      fitted=series[column], fit=fit, provenance=prov, warnings=tuple(warnings))


def simulate(scene: str | Path | Mapping | SimulationScene | SteppedScene, *,
             progress: bool = False) -> Trajectory | SteppedRun:
    """Simulate a scene (see :mod:`spectralshell.params.simulation`): the sphere's ->
    :class:`Trajectory`; another model's -> its stepper's result (the fibre's and the
    cochlea's :class:`SteppedRun`), exactly ``ss.simulate(model, **keywords)`` of the
    scene's keywords."""
    started = time.perf_counter()
    sc = scene if isinstance(scene, (SimulationScene, SteppedScene)) else simulation_scene(scene)
    if isinstance(sc, SteppedScene):
        return simulate_model(sc.model, progress=progress, **sc.keywords)
    scheme = get_scheme(sc.scheme).name
    warnings = list(sc.warnings)
    shape = sc.shape
    if isinstance(shape, Expression):
        shape, more = shape_coefficients(shape.function, sc.l_max)
        warnings += more
    run = _coupled if isinstance(sc.kappa, Expression) else _decoupled
    return run(sc, dict(shape), scheme, warnings, progress, started)


SNAPSHOTS = 4


def shape_snapshots(traj: Trajectory, count: int = SNAPSHOTS):
    """(theta, phi, [X^Y on the grid], times) at ``count`` evenly spaced saved times, for the
    membrane-shape figure (synthesis on an SHTns grid)."""
    from ..discretise.shtns_adapter import Grid

    l_max = max([m for m, _ in traj.modes] + [2])
    grid = Grid(l_max, n_theta=max(32, 2 * l_max), n_phi=max(64, 4 * l_max))
    picks = np.unique(np.linspace(0, traj.times.size - 1, count).round().astype(int))
    fields = [grid.synthesise({mk: traj.radial[i, j] for j, mk in enumerate(traj.modes)})
              for i in picks]
    return grid.theta, grid.phi, fields, traj.times[picks]
