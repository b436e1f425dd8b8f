"""The Python API facade: the public entry points, each forwarding to the stage that owns it.

Conventions (see README "Conventions"): K(t) = kappa (1 + 2 tau sin t), forcing period 2 pi,
harmonic gamma = 0, subharmonic gamma = i/2. The computations live in :mod:`spectralshell.runner`
(floquet, tongues, tau maps, exponents, stability and scenes in ``runner.floquet``; natural modes
in ``runner.modes``; the cochlea's response in ``runner.response``; Lindstedt-Poincare
coefficients in ``runner.lp``); this module holds no numerics.
"""

from __future__ import annotations

import importlib
from pathlib import Path
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Any

from .errors import ParameterError
from .params.registry import models, models_with, parameters_doc
from .runner.floquet import exponents, floquet, run_scene, stability, tau_map, tongues

if TYPE_CHECKING:  # lazy at run time: xarray costs ~0.35 s to import
    import xarray as xr

    from .results.stepped import SteppedRun
    from .results.trajectory import Trajectory

__all__ = ["floquet", "tongues", "tau_map", "exponents", "stability", "run_scene",
           "natural_modes", "response", "lp_coefficient", "lp_summary", "sweep", "sweep_summary",
           "open_sweep", "simulate", "benchmark"]


def _list_model_parameters(*functions: Callable[..., Any]) -> None:
    """Append the models' parameters, with meaning, units and defaults, to the docstrings of
    the entry points that take them as ``**params`` (the models registered at import)."""
    text = "\n\n    " + parameters_doc().replace("\n", "\n    ")
    for function in functions:
        function.__doc__ = (function.__doc__ or "").rstrip() + text


_list_model_parameters(floquet, tongues, tau_map, exponents, stability)

#: Entry points whose modules a Floquet solve does not need (natural modes bring the continued
#: eigensolvers, lp the nonlinear orbits): imported on first use (PEP 562), which keeps the
#: command line's start short; those taking ``**params`` get the parameter list then.
_LAZY = {"natural_modes": ".runner.modes", "response": ".runner.response",
         "lp_coefficient": ".runner.lp", "lp_summary": ".runner.lp"}


def __getattr__(name: str) -> Any:
    if name not in _LAZY:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    function = getattr(importlib.import_module(_LAZY[name], __package__), name)
    if name in ("natural_modes", "response"):
        _list_model_parameters(function)
    globals()[name] = function  # documented once; later lookups find it directly
    return function


def sweep(scene: str | Path | Mapping, *, executor: str = "processes", workers: int | None = None,
          scheduler: str | None = None, out: str | Path | None = None,
          progress: bool = False, max_seconds: float | None = None) -> xr.Dataset:
    """Parameter sweep of a scene with a [grid] -> labelled ``xarray.Dataset``.

    Parameters
    ----------
    scene : path, TOML string or dict: model, ask = ["tau_min"], [params], [grid] (value lists,
        {start, stop, num} or {start, stop, num, spacing = "log"}; 'm' integers; 'kind'),
        optional [tau_min] (tol, n_temporal, tau_max = 0.5, continuation) and [sweep] (chunk).
    executor : 'serial', 'processes' (all cores, or ``workers``) or 'dask' (``scheduler`` =
        'local' for a LocalCluster, or 'tcp://HOST:PORT').
    out : ``*.zarr`` written chunk by chunk (a rerun resumes, a different scene is refused) or
        ``*.nc`` written at the end; None keeps the result in memory.
    max_seconds : raise the limit on the estimated work of a sweep of a model with spatial
        modes (the cochlea; default 600 s or $SPECTRALSHELL_MAX_SECONDS): its points are priced
        before any work and the sweep refused above it
        (:func:`spectralshell.runner.sweep.priced_sweep`).

    Notes
    -----
    Variables tau_min (NaN where has_tau is false: no instability), has_tau, error_estimate,
    n_temporal, complete_to, computed over the grid axes (units in attrs); for models with
    spatial modes (cochlea) also n_spatial and spatial_converged (False: the refinement in
    n_spatial stopped at its limit; the values are those at the limit); provenance in attrs. Every executor gives
    the same numbers. See :mod:`spectralshell.runner`.

    ``complete_to`` says how far each point's answer is proved: a point with no tau found
    whose emptiness the zero count could not prove is kept, marked
    (:func:`spectralshell.results.maps.uncertified`), never as "none", and an
    :class:`~spectralshell.errors.UncertifiedWarning` counts such points.
    """
    from .runner.sweep import sweep as run  # lazy: xarray costs ~0.35 s to import

    return run(scene, executor=executor, workers=workers, scheduler=scheduler, out=out,
               progress=progress, max_seconds=max_seconds)


def sweep_summary(scene: str | Path | Mapping, **kwargs: Any) -> dict[str, Any]:
    """Run :func:`sweep` and return ``{"points", "computed", "skipped", "damaged", "outdated",
    "uncertified", "out", "seconds"}`` (damaged: points recomputed because their chunk of the
    store was damaged; outdated: because their chunks were written before ``complete_to``
    existed, or under an earlier stopping rule of the refinement in M; uncertified: points with
    no tau found and none proved)."""
    from .runner import sweep_summary as run

    return run(scene, **kwargs)


def open_sweep(path: str | Path) -> xr.Dataset:
    """Load a stored sweep (.zarr or .nc) as an ``xarray.Dataset``; a Zarr store is verified
    chunk by chunk first (:class:`~spectralshell.errors.StoreDamaged` if any chunk is missing,
    unreadable or altered, or the store was written before ``complete_to`` existed)."""
    from .runner import open_sweep as load

    return load(path)


def simulate(target: str | Path | Mapping, *, progress: bool = False,
             **keywords: Any) -> Trajectory | SteppedRun:
    """Time-step a model -> its trajectory and the fitted growth rates.

    ``target`` is a model that can be time-stepped (the sphere, the fibre, the cochlea: those
    registered with a :class:`~spectralshell.params.registry.TimeStepping`) given with its
    ``keywords``, or a scene of one (TOML path or string, or mapping; keys in
    :mod:`spectralshell.params.simulation`: a fibre or cochlea scene holds exactly the keywords
    in its tables, and gives the run of those keywords)::

        ss.simulate("sphere", m=2, kappa=0.06, nu=0.002, tau=0.25, t_end=200)
        ss.simulate("fibre", m=3, kappa=0.02, nu=2e-4, tau=0.3)
        ss.simulate("cochlea", kappa=0.5, nu=1e-3, alpha=1, n_spatial=4, tau=0.42)

    Sphere (keywords: those of a scene's [params], [initial] and [simulate], with ``m`` for an
    initial (m, 0) shape): the linearised membrane in unsteady Stokes flow inside and outside
    the unit sphere, one semi-discrete system per degree of the initial shape (radial
    Chebyshev, reduced to an ODE; :mod:`spectralshell.discretise.sphere_stepping`), stepped
    with an IMEX scheme of :mod:`spectralshell.solvers.imex`; nu = 0 steps the Mathieu
    equation per degree. Returns a :class:`Trajectory`: the mode coefficients against time and,
    per excited mode, the fitted growth rate and frequency with an error estimate
    (:mod:`spectralshell.runner.simulate`).

    Fibre (m, kappa, nu, forcing, tau; :mod:`spectralshell.runner.fibre_stepping`) and cochlea
    (kappa, nu, alpha, n_spatial M, tau; :mod:`spectralshell.runner.cochlea_stepping`): the
    model's second, independent discretisation (radial, resp. vertical, Chebyshev collocation
    of the fluid; :mod:`spectralshell.discretise.fibre_radial`,
    :mod:`spectralshell.discretise.cochlea_vertical`), stepped with K(t) for ``t_end`` (default
    sixty forcing periods, at least ten). Returns a
    :class:`~spectralshell.results.stepped.SteppedRun`: the series against time and the
    growth rate and frequency fitted to them with an error estimate, which approximate
    Re gamma and |Im gamma| of the leading Floquet exponent of ``exponents`` (to 1e-6 in the
    tests, above and below tau_min). Start: fibre X = amplitude (1, -1/m), the fluid at rest;
    cochlea: the sum of the real parts of its oscillatory natural modes times ``amplitude``.
    Run keywords of both: t_end, scheme, dt, amplitude, the resolution (fibre n_inner,
    n_outer; cochlea n_vertical, vertical_scale) and max_seconds, which raises the limit on
    the estimated run time (600 s; priced before the work starts). |tau| > 1/2 (negative
    stiffness during the cycle) is computed and flagged in ``warnings``.

    Raises
    ------
    ParameterError : a model that cannot be time-stepped, an unknown or missing keyword, a
        value out of range, a run above a size limit.
    ConvergenceError : the spatial resolution cannot reach the run's tolerance (sphere), no
        oscillatory mode is resolved (fibre, cochlea), or the state blew up.
    """
    # lazy: keeps `import spectralshell` light
    from .runner.simulate import simulate as run, simulate_model

    if isinstance(target, str) and target in models():
        return simulate_model(target, progress=progress, **keywords)
    if keywords:
        name = sorted(keywords)[0]
        raise ParameterError(f"{name} is invalid with a scene: keywords need a model name "
                             f"first ({', '.join(models_with('time_stepping'))}); a scene "
                             "holds its own values")
    return run(target, progress=progress)


def benchmark(name: str, **params: Any) -> xr.Dataset:
    """Reference data of a benchmark problem for IB / FSI codes -> ``xarray.Dataset``.

    ``name``: a registered problem (``spectralshell benchmark list``; e.g. 'sphere-release');
    ``params``: its physical inputs in cgs units (rho, mu, radius, sigma, the initial shape
    l, k, epsilon; sphere-parametric adds omega (rad/s) and margin; defaults from the problem).
    The Dataset holds the time series over ``t`` (s), each with its per-sample error bound
    ``<quantity>_error`` and, in attrs, its units and the exact late-time growth rate (1/s) and
    angular frequency (rad/s) it follows; attributes: the parameters and provenance (package
    and library versions, scheme, resolution) as JSON, the one-page specification and the
    problem's own data (sphere-release: the exact and fitted decay; sphere-parametric: the
    Floquet exponents, growth per period and eigen-shapes as JSON).
    :mod:`spectralshell.runner.benchmark` computes it.

    Raises
    ------
    ParameterError : an unknown problem or parameter, or a value out of range.
    """
    from .runner.benchmark import benchmark as run  # lazy: brings scipy and the solvers

    return run(name, **params)
