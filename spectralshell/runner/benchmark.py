"""Reference data of the benchmark problems (:mod:`spectralshell.params.benchmarks`), and the
score of a user's run against them.

sphere-release. In the time unit T = sqrt(rho R^3 / sigma) (kappa = 1, nu = zeta) the degree l
of the linearised problem is one ODE system of :mod:`spectralshell.discretise.sphere_stepping`
(radial collocation, reduced; resolution chosen for ``TOL``), stepped by SBDF4 at
h = ``DT_FACTOR`` / |s| (s the least damped natural mode) from the membrane shape at rest.
Saved ``SAMPLES_PER_PERIOD`` times per period 2 pi / Im s: the membrane coefficient X^Y and its
velocity dX^Y/dt (the X^Y row of L y: the semi-discrete equations themselves, not a finite
difference). The run covers ``FIT_START`` periods of transient, then the mode's decay by
e^-``EFOLDS`` (the fit window), then one more period. Error bound per sample: |fine - step 2h| +
|fine - (n - 8) radial nodes|. The fitted decay rate and frequency (DMD,
:func:`~spectralshell.solvers.rate_fit.fit_rate`, on the fit window) are stored next to the
exact ones of the dispersion relation (:func:`spectralshell.runner.modes.natural_modes`).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.special import lpmv

from .._version import stamp
from ..discretise.sphere_stepping import N_STEP, scene_blocks
from ..errors import ParameterError, SpectralShellError
from ..params.benchmarks import (BENCHMARKS, IB_SPRING_FACTOR, benchmark_params,
                                 benchmark_problem)
from ..params.physical import PhysicalSphere
from ..results.benchmark import (ERROR_SUFFIX, BenchmarkScore, QuantityScore, attrs_json,
                                 read_series, reference_columns, write_csv, write_netcdf)
from ..results.notebook import dataset, json_attr, variable
from ..solvers.oscillation_fit import fit_damped_oscillation
from ..solvers.rate_fit import fit_rate
from ..solvers.stepper import integrate
from .modes import natural_modes

if TYPE_CHECKING:
    import xarray as xr

SCHEME = "SBDF4"
DT_FACTOR = 0.004        # h |s|: rate and frequency of the run to ~1e-10 (SBDF4)
TOL = 1e-11              # radial resolution's target relative error of the mode
SAMPLES_PER_PERIOD = 32
FIT_START = 4.0          # periods of transient (continuous spectrum) before the fit window
EFOLDS = 12.0            # the fit window: the mode's decay by e^-EFOLDS
SCORE_EFOLDS = 3.0       # score's fit of a user's series (and of the reference, alike)
POINTS = {"pole": (0.0, 0.0), "equator": (math.pi / 2, 0.0)}   # (theta, phi)


def real_harmonic(l: int, k: int, theta: float, phi: float) -> float:
    """Yr_{l,k}(theta, phi): the real orthonormal harmonic (Condon-Shortley phase) of
    :mod:`spectralshell.discretise.shtns_adapter`."""
    a = abs(k)
    norm = math.sqrt((2 * l + 1) / (4 * math.pi) * math.factorial(l - a) / math.factorial(l + a))
    value = norm * float(lpmv(a, l, math.cos(theta)))
    if k == 0:
        return value
    return math.sqrt(2.0) * value * (math.cos(a * phi) if k > 0 else math.sin(a * phi))


def pressure_jump_factor(p: dict[str, Any]) -> float:
    """(l - 1)(l + 2) sigma / R^2 in dyn/cm^3: the jump p_in - p_out - 2 sigma / R per cm of
    membrane amplitude in the linearised problem (thesis (6.17) in cgs units; the viscous normal
    stress does not jump)."""
    return (p["l"] - 1) * (p["l"] + 2) * p["sigma"] / p["radius"] ** 2


def _at_points(name: str, modal: tuple[np.ndarray, np.ndarray], l: int, k: int) -> dict:
    """{name_pole, name_equator: (values, bounds)} of a modal series (values, bounds) times
    Yr_{l,k} at the POINTS where it does not vanish."""
    out = {}
    for where, (theta, phi) in POINTS.items():
        y = real_harmonic(l, k, theta, phi)
        if abs(y) > 1e-12:
            out[f"{name}_{where}"] = (y * modal[0], abs(y) * modal[1])
    return out


def _run(system, initial, step: float, every: int, steps: int) -> np.ndarray:
    """(times, (samples, 2)): X^Y and dX^Y/dt of the run at the saved times; dX^Y/dt is the
    X^Y row of L y, the reduced ODE's right-hand side (collocation systems: M = I)."""
    if system.radial != "collocation":
        raise SpectralShellError(f"the reference needs the collocation system, not "
                                 f"{system.radial!r} (n_radial = {system.n_inner})")
    row = system.membrane.start

    def observe(y):
        return np.array([y[row, 0], (system.L[row] @ y)[0]])

    run = integrate(system, initial, scheme=SCHEME, dt=step, t_end=steps * step, every=every,
                    observe=observe)
    return run.times, run.values


def _sphere_release(p: dict[str, Any]) -> dict[str, Any]:
    """Dimensionless runs and fits of sphere-release -> physical series, bounds and metadata."""
    phys = PhysicalSphere(rho=p["rho"], mu=p["mu"], radius=p["radius"], sigma=p["sigma"])
    T, zeta, l, k = phys.time_scale, phys.zeta, p["l"], p["k"]
    exact = complex(natural_modes("sphere", m=l, kappa=1.0, nu=zeta, count=1).gamma[0])
    shape = {(l, k): p["epsilon"]}
    (fine,) = scene_blocks(shape=shape, twist={}, kappa=1.0, nu=zeta, tau=0.0, tol=TOL)
    (coarse,) = scene_blocks(shape=shape, twist={}, kappa=1.0, nu=zeta, tau=0.0,
                             n_radial=fine.system.n_inner - N_STEP)
    period = 2 * math.pi / exact.imag
    t_a = FIT_START * period
    t_b = t_a + EFOLDS / -exact.real
    step = DT_FACTOR / abs(exact)
    every = 2 * max(1, round(period / SAMPLES_PER_PERIOD / step / 2))
    steps = math.ceil((t_b + period) / (every * step)) * every
    times, f = _run(fine.system, fine.initial, step, every, steps)
    _, c_time = _run(fine.system, fine.initial, 2 * step, every // 2, steps // 2)
    _, c_space = _run(coarse.system, coarse.initial, step, every, steps)
    bound = np.abs(f - c_time) + np.abs(f - c_space)
    fit = fit_rate(times, f[:, 0], window=(t_a, t_b))
    R = p["radius"]
    jump = pressure_jump_factor(p)
    pressure = (jump * R * f[:, 0], jump * R * bound[:, 0])
    series = {"amplitude": (R * f[:, 0], R * bound[:, 0]),
              **_at_points("u_r", (R / T * f[:, 1], R / T * bound[:, 1]), l, k),
              "pressure_jump": pressure, **_at_points("pressure_jump", pressure, l, k)}
    params = {**p, "T": T, "zeta": zeta, "sigma_star": IB_SPRING_FACTOR * p["sigma"],
              "lamb_frequency": phys.lamb_frequency(l)}
    provenance = {**stamp(), "scheme": SCHEME, "dt": step * T, "samples_every": every,
                  "n_radial": fine.system.n_inner, "n_radial_check": coarse.system.n_inner,
                  "exterior_scale": fine.system.exterior_scale,
                  "spatial_error": fine.system.spatial_error,
                  "method": "IMEX time stepping of the radial Chebyshev system of degree l "
                            "(discretise/sphere_stepping.py); bound from 2 dt and n - 8 nodes"}
    return {"t": times * T, "series": series, "params": params, "provenance": provenance,
            "exact": (exact.real / T, exact.imag / T), "fitted": (fit.growth_rate / T,
                                                                  fit.frequency / T),
            "fit_window": (t_a * T, t_b * T)}


#: The reference computation of each registered problem.
COMPUTE = {"sphere-release": _sphere_release}
assert set(COMPUTE) == set(BENCHMARKS)


def benchmark(name: str, **params: Any) -> xr.Dataset:
    """Reference data of benchmark ``name`` at the given physical parameters (cgs; defaults
    from the problem) -> ``xarray.Dataset`` over ``t`` (s): each quantity and its per-sample
    error bound ``<quantity>_error`` (units in attrs); attributes: problem, title, params and
    provenance (JSON: package and library versions, scheme, resolution), exact and fitted
    late-time growth rate (1/s) and angular frequency (rad/s), fit window (s), specification."""
    problem = benchmark_problem(name)
    p = benchmark_params(problem, params)
    ref = COMPUTE[name](p)
    units = {q.name: q for q in problem.quantities}
    data = {}
    for q, (values, bound) in ref["series"].items():
        data[q] = variable(("t",), values, units[q].description, units[q].units)
        data[q + ERROR_SUFFIX] = variable(("t",), bound, f"error bound of {q}", units[q].units)
    attrs = {"title": f"spectralshell benchmark {name}: {problem.title}", "problem": name,
             "params": json_attr(ref["params"]), "provenance": json_attr(ref["provenance"]),
             "exact_growth_rate": ref["exact"][0], "exact_frequency": ref["exact"][1],
             "fitted_growth_rate": ref["fitted"][0], "fitted_frequency": ref["fitted"][1],
             "fit_window": list(ref["fit_window"]),
             "specification": specification_text(name, **params)}
    return dataset(data, {"t": variable(("t",), ref["t"], "time t", "s")}, attrs)


def specification_text(name: str, **params: Any) -> str:
    """The one-page specification of problem ``name`` at the given (or default) parameters."""
    problem = benchmark_problem(name)
    p = benchmark_params(problem, params)
    phys = PhysicalSphere(rho=p["rho"], mu=p["mu"], radius=p["radius"], sigma=p["sigma"])
    T = phys.time_scale
    exact = complex(natural_modes("sphere", m=p["l"], kappa=1.0, nu=phys.zeta, count=1).gamma[0])
    return problem.specification.format(
        **p, amplitude=p["epsilon"] * p["radius"], T=T, zeta=phys.zeta,
        growth_rate=exact.real / T, frequency=exact.imag / T, growth_rate_nd=exact.real,
        frequency_nd=exact.imag, lamb=phys.lamb_frequency(p["l"]), efolds=EFOLDS,
        sigma_star=IB_SPRING_FACTOR * p["sigma"], jump_factor=pressure_jump_factor(p),
        reference=problem.reference)


def score_window(ds) -> tuple[float, float]:
    """(t_a, t_b) in s where score fits a user's series: from the start of the reference's fit
    window over SCORE_EFOLDS e-folds of the exact mode (longer windows let the algebraic tail
    bias the fit)."""
    t_a = float(ds.attrs["fit_window"][0])
    return t_a, t_a + SCORE_EFOLDS / -float(ds.attrs["exact_growth_rate"])


def _fit(t: np.ndarray, x: np.ndarray, window: tuple[float, float], guess: complex):
    """(rate, frequency, error) of x in the window, or (None, None, None) if it cannot be fitted."""
    inside = (t >= window[0]) & (t <= window[1])
    try:
        return fit_damped_oscillation(t[inside], x[inside], guess=guess)
    except SpectralShellError:
        return None, None, None


def _score_quantity(ds, name: str, t_user: np.ndarray, x_user: np.ndarray,
                    guess: complex) -> QuantityScore:
    """Errors of one user series against the reference (interpolated by a cubic spline onto
    the reference times inside the user's range) and its fitted rate and frequency."""
    t_ref = ds["t"].values
    inside = (t_ref >= t_user[0]) & (t_ref <= t_user[-1])
    if inside.sum() < 2 or t_user.size < 4:
        raise ParameterError(f"user data column {name} is invalid: its times "
                             f"{t_user[0]:g}..{t_user[-1]:g} s cover fewer than 2 reference "
                             "times (or it has fewer than 4 samples)")
    ref = ds[name].values[inside]
    diff = CubicSpline(t_user, x_user)(t_ref[inside]) - ref
    t_a, t_b = score_window(ds)
    rate, frequency, error = _fit(t_user, x_user, (t_a, t_b), guess)
    ref_fit = _fit(t_ref, ds[name].values, (t_a, t_b), guess)
    return QuantityScore(name=name, units=ds[name].attrs.get("units", ""),
                         reference_growth_rate=ref_fit[0], reference_frequency=ref_fit[1],
                         relative_l2=float(np.linalg.norm(diff) / np.linalg.norm(ref)),
                         max_error=float(np.max(np.abs(diff))),
                         reference_error=float(np.max(ds[name + ERROR_SUFFIX].values[inside])),
                         growth_rate=rate, frequency=frequency, fit_error=error,
                         samples=int(inside.sum()))


def score(name: str, path: str | Path, *, reference: xr.Dataset | None = None,
          **params: Any) -> tuple[BenchmarkScore, xr.Dataset, tuple]:
    """Score the user's CSV ``path`` (format: :mod:`spectralshell.results.benchmark`) against
    the reference of ``name`` at ``params`` (or the given ``reference`` Dataset) ->
    (score, reference Dataset, (t_user, {column: values})) ."""
    ds = reference if reference is not None else benchmark(name, **params)
    t_user, columns = read_series(path)
    known = reference_columns(ds)
    unknown = [c for c in columns if c not in known and not c.endswith(ERROR_SUFFIX)]
    if unknown:
        raise ParameterError(f"user data column {unknown[0]!r} is unknown: expected "
                             f"{', '.join(known)}")
    scored = [c for c in known if c in columns]
    if not scored:
        raise ParameterError(f"user data {str(path)!r} has no quantity column: expected one of "
                             f"{', '.join(known)}")
    guess = complex(ds.attrs["exact_growth_rate"], ds.attrs["exact_frequency"])
    result = BenchmarkScore(problem=name, params=attrs_json(ds, "params"),
                            exact_growth_rate=float(guess.real), exact_frequency=float(guess.imag),
                            fit_window=score_window(ds),
                            quantities=tuple(_score_quantity(ds, c, t_user, columns[c], guess)
                                             for c in scored))
    return result, ds, (t_user, {c: columns[c] for c in scored})


def listing() -> list[dict[str, str]]:
    """[{name, title}] of the registered problems."""
    return [{"name": p.name, "title": p.title} for p in BENCHMARKS.values()]

