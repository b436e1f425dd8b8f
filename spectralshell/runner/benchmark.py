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

fibre-release. The same window and sampling from the fibre's least damped mode, but no
stepping: the release from rest is inverted exactly from its Laplace transform
(:func:`spectralshell.solvers.laplace.release`: residues at the natural modes, Talbot contour
for the continuous spectrum), error bound from two contour resolutions.

sphere-parametric and fibre-parametric. tau_min from :func:`spectralshell.runner.floquet.floquet`,
at tau = (1 -+ margin) tau_min the two least stable Floquet exponents
(:func:`spectralshell.runner.floquet.exponents`) and the periodic eigen-shape
(:func:`spectralshell.solvers.marginal_mode.floquet_mode`, bound from the coarser truncation).
The sphere's amplitudes are stepped as above in the time unit 1 / omega (``STEPS_PER_PERIOD``
steps per forcing period, ``PERIODS`` periods) and their growth rates fitted (DMD over whole
periods from ``FIT_FROM_PERIOD``); the fibre has no stepper, and score fits a user's run after
the transient (:func:`_rate_window`).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.ndimage import maximum_filter1d
from scipy.special import lpmv

from .._version import stamp
from ..discretise.sphere_stepping import N_STEP, scene_blocks
from ..errors import ParameterError, SpectralShellError
from ..models.cochlea import TONE_WIDTH
from ..models.fibre import lambda0_squared
from ..models.registry import hill_system
from ..params.benchmarks import (BENCHMARKS, FIBRE_ZETA_RANGE, IB_SPRING_FACTOR,
                                 benchmark_params, benchmark_problem, release_scales)
from ..params.physical import PhysicalSphere, cochlea_forced, fibre_forced
from ..params.registry import make_params
from ..results.benchmark import (ERROR_SUFFIX, BenchmarkScore, PeakScore, QuantityScore,
                                 attrs_json, axis, read_series, reference_columns, write_csv,
                                 write_netcdf)
from ..results.notebook import dataset, json_attr, variable
from ..solvers.marginal import coarser
from ..solvers.laplace import CIRCLE_NODES, TALBOT_NODES, release
from ..solvers.marginal_mode import floquet_mode
from ..solvers.oscillation_fit import fit_damped_oscillation
from ..solvers.rate_fit import fit_rate
from ..solvers.stepper import integrate
from .floquet import exponents, floquet
from .modes import natural_modes
from .response import RESPONSE_POINTS, response

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
LAPLACE = ("exact Laplace inversion of the release from rest (solvers/laplace.py): residues at "
           "the natural modes plus a Talbot contour around the branch cut; bound from 8 fewer "
           "contour nodes and half the circle nodes")
STEPPING = ("IMEX time stepping of the radial Chebyshev system of degree l "
            "(discretise/sphere_stepping.py); bound from 2 dt and n - 8 nodes")
# sphere-parametric (time unit 1 / omega, forcing period 2 pi)
STEPS_PER_PERIOD = 512   # SBDF4: the fitted growth rate to ~1e-10 (2.9e-10 .. 1e-9 at 256)
PERIODS = 120            # the run: 120 forcing periods
FIT_FROM_PERIOD = 40     # the fit (and score) window: period 40 to the end
SHAPE_POINTS = 64        # samples of the periodic eigen-shape over its period
LOCKED = 1e-9            # |Im gamma - 0 or 1/2| of an exponent locked to the forcing
# fibre-parametric (no reference series): score's window for a user's run
TRANSIENT_EFOLDS = 10.0  # starts when the next Floquet solution is e^-10 of the leading one
SCORE_PERIODS = 40       # and lasts 40 forcing periods
# cochlea-tone
TONE_MODES = 512         # cosine modes of the reference (bound from TONE_MODES // 2)
TONE_BOUND_REACH = 10    # the bound of a sample: the largest change within 10 samples of it


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


def _run(system, initial, step: float, every: int, steps: int) -> tuple[np.ndarray, np.ndarray]:
    """(times, (samples, q)): X^Y at the saved times and, unforced, dX^Y/dt (the X^Y row of
    L y, the reduced ODE's right-hand side; collocation systems: M = I); q = 2, or 1 forced."""
    if system.radial != "collocation":
        raise SpectralShellError(f"the reference needs the collocation system, not "
                                 f"{system.radial!r} (n_radial = {system.n_inner})")
    row = system.membrane.start

    def observe(y):
        if system.forcing is not None:
            return np.array([y[row, 0]])
        return np.array([y[row, 0], (system.L[row] @ y)[0]])

    run = integrate(system, initial, scheme=SCHEME, dt=step, t_end=steps * step, every=every,
                    observe=observe)
    return run.times, run.values


def _stepped(shape: dict, kappa: float, nu: float, tau: float, step: float, every: int,
             steps: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
    """The degree of ``shape`` stepped from rest (dimensionless) at the resolution for TOL ->
    (times, values of :func:`_run`, their error bound |fine - step 2h| + |fine - (n - 8) radial
    nodes|, provenance of the resolution)."""
    (fine,) = scene_blocks(shape=shape, twist={}, kappa=kappa, nu=nu, tau=tau, tol=TOL)
    (coarse,) = scene_blocks(shape=shape, twist={}, kappa=kappa, nu=nu, tau=tau,
                             n_radial=fine.system.n_inner - N_STEP)
    times, f = _run(fine.system, fine.initial, step, every, steps)
    _, c_time = _run(fine.system, fine.initial, 2 * step, every // 2, steps // 2)
    _, c_space = _run(coarse.system, coarse.initial, step, every, steps)
    resolution = {"n_radial": fine.system.n_inner, "n_radial_check": coarse.system.n_inner,
                  "exterior_scale": fine.system.exterior_scale,
                  "spatial_error": fine.system.spatial_error}
    return times, f, np.abs(f - c_time) + np.abs(f - c_space), resolution


def _sphere_release(p: dict[str, Any]) -> dict[str, Any]:
    """Dimensionless runs and fits of sphere-release -> physical series, bounds and metadata."""
    phys = PhysicalSphere(rho=p["rho"], mu=p["mu"], radius=p["radius"], sigma=p["sigma"])
    T, zeta, l, k = phys.time_scale, phys.zeta, p["l"], p["k"]
    exact = complex(natural_modes("sphere", m=l, kappa=1.0, nu=zeta, count=1).gamma[0])
    period, t_a, t_b = _release_window(exact)
    step = DT_FACTOR / abs(exact)
    every = 2 * max(1, round(period / SAMPLES_PER_PERIOD / step / 2))
    steps = math.ceil((t_b + period) / (every * step)) * every
    times, f, bound, resolution = _stepped({(l, k): p["epsilon"]}, 1.0, zeta, 0.0, step, every,
                                           steps)
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
                  **resolution, "method": STEPPING}
    return _release_reference(times, series, params, provenance, exact, fit, T, (t_a, t_b))


def _release_window(exact: complex) -> tuple[float, float, float]:
    """(period, t_a, t_b) of a release problem (units of T) from its least damped mode: the fit
    window starts after FIT_START periods of transient and covers the decay by e^-EFOLDS."""
    period = 2 * math.pi / exact.imag
    t_a = FIT_START * period
    return period, t_a, t_a + EFOLDS / -exact.real


def _release_reference(times: np.ndarray, series: dict, params: dict, provenance: dict,
                       exact: complex, fit, T: float, window: tuple[float, float]
                       ) -> dict[str, Any]:
    """The reference of a release problem from its dimensionless run (times, fit, window in
    units of T) and physical series: every series follows the exact mode; score fits over
    SCORE_EFOLDS e-folds from the window's start."""
    t_a, t_b = window
    rate = (exact.real / T, exact.imag / T)
    return {"t": times * T, "series": series, "params": params, "provenance": provenance,
            "exact": dict.fromkeys(series, rate), "fitted": {},
            "score_window": (t_a * T, t_a * T + SCORE_EFOLDS / -rate[0]),
            "attrs": {"exact_growth_rate": rate[0], "exact_frequency": rate[1],
                      "fitted_growth_rate": fit.growth_rate / T,
                      "fitted_frequency": fit.frequency / T, "fit_window": [t_a * T, t_b * T]}}


def _fibre_release(p: dict[str, Any]) -> dict[str, Any]:
    """fibre-release by exact Laplace inversion (:func:`spectralshell.solvers.laplace.release`)
    of the fibre's unforced system at kappa = 1, nu = zeta -> physical series, bounds and
    metadata; sampled SAMPLES_PER_PERIOD times per period over the window of sphere-release."""
    T, zeta = release_scales("fibre-release", p)
    m, R = p["m"], p["radius"]
    modes = natural_modes("fibre", m=m, kappa=1.0, nu=zeta).gamma
    exact = complex(modes[0])
    period, t_a, t_b = _release_window(exact)
    dt = period / SAMPLES_PER_PERIOD
    times = dt * np.arange(math.ceil((t_b + period) / dt) + 1)
    system = hill_system(make_params("fibre", {"m": m, "kappa": 1.0, "nu": zeta}))
    run = release(system.unforced, np.array([p["epsilon"], 0.0]), times, modes)
    fit = fit_rate(times, run.position[:, 0], window=(t_a, t_b))
    series = {"amplitude": (R * run.position[:, 0], R * run.position_error[:, 0]),
              "u_r": (R / T * run.velocity[:, 0], R / T * run.velocity_error[:, 0])}
    params = {**p, "T": T, "zeta": zeta}
    provenance = {**stamp(), "method": LAPLACE, "talbot_nodes": TALBOT_NODES,
                  "circle_nodes": CIRCLE_NODES,
                  "poles": [[g.real, g.imag] for g in map(complex, modes)]}
    return _release_reference(times, series, params, provenance, exact, fit, T, (t_a, t_b))


def tau_min(model: str, kappa: float, nu: float, m: int) -> tuple[float, str]:
    """(tau_min, kind): the smallest marginal forcing amplitude of wavenumber (degree) m of
    ``model`` over both kinds (tip of the lowest tongue;
    :func:`spectralshell.runner.floquet.floquet`)."""
    result = floquet(model, m=m, kappa=kappa, nu=nu)
    tips = [(marginal.tau_min, kind) for kind in ("subharmonic", "harmonic")
            if (marginal := getattr(result, kind)) is not None and marginal.tau_min is not None]
    if not tips:
        raise ParameterError(f"wavenumber {m} of the {model} is invalid at kappa = {kappa:.6g}, "
                             f"nu = {nu:.6g}: it has no resonance tongue")
    return min(tips)


def _parametric_taus(model: str, p: dict[str, Any]
                     ) -> tuple[float, float, int, float, str, dict[str, float]]:
    """(kappa, nu, wavenumber, tau_min, kind, {below, above: tau}) of a parametric problem of
    ``model`` ('sphere': degree l, 'fibre': wavenumber m); ParameterError when
    (1 + margin) tau_min reaches 1/2."""
    physical = {k: p[k] for k in ("rho", "mu", "radius", "sigma", "omega")}
    if model == "sphere":
        kappa_nu, m = PhysicalSphere(**physical).forced(), p["l"]
    else:
        kappa_nu, m = fibre_forced(**physical), p["m"]
    kappa, nu = kappa_nu["kappa"], kappa_nu["nu"]
    tip, kind = tau_min(model, kappa, nu, m)
    if (1 + p["margin"]) * tip >= 0.5:
        raise ParameterError(f"margin = {p['margin']:g} is invalid here: tau_min = {tip:.6g} "
                             f"(wavenumber {m}), so (1 + margin) tau_min must stay below 1/2 "
                             "(K(t) > 0)")
    return kappa, nu, m, tip, kind, {"below": (1 - p["margin"]) * tip,
                                     "above": (1 + p["margin"]) * tip}


def _eigen_shape(system, tau: float, gamma: complex, n_temporal: int) -> tuple[str, np.ndarray]:
    """(kind, p): the radial periodic eigen-shape at SHAPE_POINTS phases over its period
    (4 pi subharmonic, 2 pi harmonic, from forcing phase 0), max |p| = 1."""
    mode = floquet_mode(system, tau, gamma, n_temporal)
    period = 4 * math.pi if mode.kind == "subharmonic" else 2 * math.pi
    shape = mode.evaluate(np.linspace(0.0, period, SHAPE_POINTS, endpoint=False))[:, 0]
    return mode.kind, shape / np.max(np.abs(shape))


def _floquet_case(model: str, system, kappa: float, nu: float, m: int, tau: float,
                  omega: float) -> dict[str, Any]:
    """The least stable Floquet exponent of wavenumber m at tau (physical rate and growth per
    forcing period), the next one (the slowest transient), and the periodic eigen-shape p(t)
    over one period with its error bound |p_N - p_N'| (N' the coarser truncation)."""
    result = exponents(model, m=m, kappa=kappa, nu=nu, tau=tau, count=2)
    gamma = complex(result.gamma[0])
    if min(abs(gamma.imag % 1.0 - lock) for lock in (0.0, 0.5, 1.0)) > LOCKED:
        raise ParameterError(f"margin is invalid here: at tau = {tau:.6g} the least stable "
                             f"Floquet exponent {gamma:.6g} is not locked to the forcing (Im "
                             "gamma not 0 or 1/2: a beating response without a periodic "
                             "eigen-shape); a smaller margin keeps tau_below in the locked "
                             "band just below tau_min, whose width grows with nu")
    kind, shape = _eigen_shape(system, tau, gamma, result.n_temporal)
    _, check = _eigen_shape(system, tau, gamma, coarser(result.n_temporal))
    check *= np.sign(check @ shape)            # the null vector's sign is arbitrary
    period = (4 if kind == "subharmonic" else 2) * math.pi / omega
    return {"tau": tau, "gamma_real": gamma.real, "gamma_imag": gamma.imag,
            "growth_rate": gamma.real * omega, "frequency": (gamma.imag % 1.0) * omega,
            "growth_per_period": math.exp(2 * math.pi * gamma.real),
            "next_growth_rate": float(result.gamma[1].real) * omega,
            "error_estimate": result.error_estimate, "n_temporal": result.n_temporal,
            "kind": kind, "shape_t": list(np.arange(SHAPE_POINTS) * period / SHAPE_POINTS),
            "shape": list(shape), "shape_error": list(np.abs(shape - check))}


def _sphere_parametric(p: dict[str, Any]) -> dict[str, Any]:
    """Floquet exponents, eigen-shapes and stepped runs of sphere-parametric below and above
    tau_min -> physical series, bounds and metadata."""
    omega, R, k = p["omega"], p["radius"], p["k"]
    kappa, nu, l, tip, kind, taus = _parametric_taus("sphere", p)
    system = hill_system(make_params("sphere", {"m": l, "kappa": kappa, "nu": nu}))
    step = 2 * math.pi / STEPS_PER_PERIOD
    every = STEPS_PER_PERIOD // SAMPLES_PER_PERIOD
    steps = PERIODS * STEPS_PER_PERIOD
    window = (FIT_FROM_PERIOD * 2 * math.pi, steps * step)
    series, floquet_cases, exact, fitted, resolution = {}, {}, {}, {}, {}
    for case, tau in taus.items():
        case_data = _floquet_case("sphere", system, kappa, nu, l, tau, omega)
        times, f, bound, resolution[case] = _stepped({(l, k): p["epsilon"]}, kappa, nu, tau,
                                                     step, every, steps)
        fit = fit_rate(times, f[:, 0], period=2 * math.pi, window=window)
        name = f"amplitude_{case}"
        series[name] = (R * f[:, 0], R * bound[:, 0])
        floquet_cases[case] = case_data
        exact[name] = (case_data["growth_rate"], case_data["frequency"])
        fitted[name] = (fit.growth_rate * omega, fit.frequency * omega)
    params = {**p, "kappa": kappa, "nu": nu, "tau_min": tip, "kind": kind,
              "tau_below": taus["below"], "tau_above": taus["above"],
              "sigma_star": IB_SPRING_FACTOR * p["sigma"], "forcing_period": 2 * math.pi / omega}
    provenance = {**stamp(), "scheme": SCHEME, "dt": step / omega, "samples_every": every,
                  "resolution": resolution, "method": STEPPING,
                  "floquet": "Hill's method on the exact fluid (solvers/hill_exponents.py), "
                             "eigen-shape the null vector of the truncated Hill matrix"}
    return {"t": times / omega, "series": series, "params": params, "provenance": provenance,
            "exact": exact, "fitted": fitted,
            "score_window": (window[0] / omega, window[1] / omega),
            "attrs": {"forcing_frequency": omega, "floquet": json_attr(floquet_cases)}}


def _rate_window(rates, omega: float) -> tuple[float, float]:
    """(start, end) in s of score's window for a run without reference series: from where the
    next Floquet solution has decayed by e^-TRANSIENT_EFOLDS against the leading one (in the
    slower of the cases) over SCORE_PERIODS forcing periods; ``rates`` = (leading, next)
    growth rates in 1/s, one pair per case."""
    start = max(TRANSIENT_EFOLDS / (leading - following) for leading, following in rates)
    return start, start + SCORE_PERIODS * 2 * math.pi / omega


def _fibre_parametric(p: dict[str, Any]) -> dict[str, Any]:
    """Floquet exponents and eigen-shapes of fibre-parametric below and above tau_min -> the
    eigen-shapes over one period (s) with their truncation bounds, and metadata; the window
    where score fits a user's run starts when the next Floquet solution has decayed by
    e^-TRANSIENT_EFOLDS against the leading one (the slower of the two cases)."""
    omega = p["omega"]
    kappa, nu, m, tip, kind, taus = _parametric_taus("fibre", p)
    system = hill_system(make_params("fibre", {"m": m, "kappa": kappa, "nu": nu}))
    cases = {case: _floquet_case("fibre", system, kappa, nu, m, tau, omega)
             for case, tau in taus.items()}
    series = {f"shape_{case}": (np.array(c["shape"]), np.array(c["shape_error"]))
              for case, c in cases.items()}
    exact = {f"{prefix}_{case}": (c["growth_rate"], c["frequency"])
             for case, c in cases.items() for prefix in ("shape", "amplitude")}
    params = {**p, "kappa": kappa, "nu": nu, "tau_min": tip, "kind": kind,
              "tau_below": taus["below"], "tau_above": taus["above"],
              "forcing_period": 2 * math.pi / omega}
    provenance = {**stamp(), "method": "Hill's method on the exact fluid "
                  "(solvers/hill_exponents.py); eigen-shape the null vector of the truncated "
                  "Hill matrix, bound from the coarser truncation; no time stepping"}
    return {"t": np.array(cases["below"]["shape_t"]), "series": series, "params": params,
            "provenance": provenance, "exact": exact, "fitted": {},
            "score_window": _rate_window(((c["growth_rate"], c["next_growth_rate"])
                                          for c in cases.values()), omega),
            "attrs": {"forcing_frequency": omega, "floquet": json_attr(cases)}}


def _tone_responses(p: dict[str, Any]):
    """The cochlea's pure-tone responses at TONE_MODES and TONE_MODES // 2 cosine modes (the
    response command at the problem's cgs inputs)."""
    return tuple(response("cochlea", kind="tone", n_spatial=M, **p)
                 for M in (TONE_MODES, TONE_MODES // 2))


def _cochlea_tone(p: dict[str, Any]) -> dict[str, Any]:
    """cochlea-tone: the envelope along the membrane (x in cm) with the bound: the largest
    |envelope(M) - envelope(M / 2)| within TONE_BOUND_REACH samples (the change itself crosses
    zero where the two truncations agree by chance), and the peak position and its error (cm)
    in the attrs."""
    fine, coarse = _tone_responses(p)
    params = {**p, **cochlea_forced(**p), "n_spatial": TONE_MODES, "width": TONE_WIDTH}
    provenance = {**stamp(), "method": "cosine-Galerkin solve at s = i omega "
                  "(runner/response.py), bound from half the modes; no time stepping",
                  "n_spatial": TONE_MODES, "n_spatial_check": TONE_MODES // 2}
    return {"axis": ("x", fine.to_cm(fine.x), "position along the membrane from the base",
                     "cm"),
            "series": {"envelope": (fine.envelope, maximum_filter1d(
                np.abs(fine.envelope - coarse.envelope), 2 * TONE_BOUND_REACH + 1))},
            "params": params, "provenance": provenance, "exact": {}, "fitted": {},
            "attrs": {"peak_x_cm": float(fine.to_cm(fine.peak_x)),
                      "peak_error_cm": float(fine.to_cm(fine.peak_error)),
                      "tone_start_cm": float(fine.to_cm(4 * TONE_WIDTH))}}


#: The reference computation of each registered problem.
COMPUTE = {"sphere-release": _sphere_release, "sphere-parametric": _sphere_parametric,
           "fibre-parametric": _fibre_parametric, "fibre-release": _fibre_release,
           "cochlea-tone": _cochlea_tone}
assert set(COMPUTE) == set(BENCHMARKS)


def benchmark(name: str, **params: Any) -> xr.Dataset:
    """Reference data of benchmark ``name`` at the given physical parameters (cgs; defaults
    from the problem) -> ``xarray.Dataset`` over ``t`` (s; cochlea-tone: over ``x`` in cm,
    the envelope and its bound, the peak position in the attrs): each quantity (attrs: units, the
    exact growth rate (1/s) and angular frequency (rad/s) its late part follows and, where
    fitted, the same fitted from it) and its per-sample error bound ``<quantity>_error``;
    attributes: problem, title, params and provenance (JSON: package and library versions,
    scheme, resolution), the window where score fits (s), the specification and the problem's
    own (the release problems: the exact and fitted decay; the parametric problems: the
    Floquet data; fibre-parametric: the exact rates of the series a user's run gives,
    ``rate_only``)."""
    problem = benchmark_problem(name)
    p = benchmark_params(problem, params)
    ref = COMPUTE[name](p)
    units = {q.name: q for q in problem.quantities}
    dim, coordinate, long_name, unit = ref["axis"] if "axis" in ref else ("t", ref["t"],
                                                                          "time t", "s")
    data = {}
    rate_only = {q.name: dict(zip(("exact_growth_rate", "exact_frequency"), ref["exact"][q.name]))
                 for q in problem.rate_only}
    for q, (values, bound) in ref["series"].items():
        data[q] = variable((dim,), values, units[q].description, units[q].units)
        rates = {**({"exact": ref["exact"][q]} if q in ref["exact"] else {}),
                 **({"fitted": ref["fitted"][q]} if q in ref["fitted"] else {})}
        for which, (rate, frequency) in rates.items():
            data[q][2].update({f"{which}_growth_rate": rate, f"{which}_frequency": frequency})
        data[q + ERROR_SUFFIX] = variable((dim,), bound, f"error bound of {q}", units[q].units)
    attrs = {"title": f"spectralshell benchmark {name}: {problem.title}", "problem": name,
             "params": json_attr(ref["params"]), "provenance": json_attr(ref["provenance"]),
             **({"score_window": list(ref["score_window"])} if "score_window" in ref else {}),
             **ref["attrs"],
             **({"rate_only": json_attr(rate_only)} if rate_only else {}),
             "specification": specification_text(name, **params)}
    return dataset(data, {dim: variable((dim,), coordinate, long_name, unit)}, attrs)


def _release_fields(p: dict[str, Any]) -> dict[str, Any]:
    """The specification's values of sphere-release."""
    phys = PhysicalSphere(rho=p["rho"], mu=p["mu"], radius=p["radius"], sigma=p["sigma"])
    T = phys.time_scale
    exact = complex(natural_modes("sphere", m=p["l"], kappa=1.0, nu=phys.zeta, count=1).gamma[0])
    return {"T": T, "zeta": phys.zeta, "growth_rate": exact.real / T,
            "frequency": exact.imag / T, "growth_rate_nd": exact.real, "frequency_nd": exact.imag,
            "lamb": phys.lamb_frequency(p["l"]), "efolds": EFOLDS,
            "jump_factor": pressure_jump_factor(p)}


def _parametric_fields(model: str, p: dict[str, Any]) -> dict[str, Any]:
    """The specification's values of a parametric problem of ``model`` (tau_min, both
    exponents; the fibre: score's window)."""
    kappa, nu, m, tip, kind, taus = _parametric_taus(model, p)
    omega = p["omega"]
    out = {"kappa": kappa, "nu": nu, "tau_min": tip, "kind": kind,
           "forcing_period": 2 * math.pi / omega, "periods": PERIODS,
           "shape_period": (4 if kind == "subharmonic" else 2) * math.pi / omega,
           "transient_efolds": TRANSIENT_EFOLDS}
    rates = []
    for case, tau in taus.items():
        gamma = exponents(model, m=m, kappa=kappa, nu=nu, tau=tau, count=2).gamma
        out.update({f"tau_{case}": tau, f"rate_{case}": gamma[0].real * omega,
                    f"rate_{case}_nd": gamma[0].real,
                    f"growth_{case}": math.exp(2 * math.pi * gamma[0].real)})
        rates.append((gamma[0].real * omega, gamma[1].real * omega))
    start, end = _rate_window(rates, omega)
    return {**out, "score_start": start, "score_end": end}


def _fibre_release_fields(p: dict[str, Any]) -> dict[str, Any]:
    """The specification's values of fibre-release."""
    T, zeta = release_scales("fibre-release", p)
    exact = complex(natural_modes("fibre", m=p["m"], kappa=1.0, nu=zeta, count=1).gamma[0])
    return {"T": T, "zeta": zeta, "growth_rate": exact.real / T, "frequency": exact.imag / T,
            "growth_rate_nd": exact.real, "frequency_nd": exact.imag, "efolds": EFOLDS,
            "rayleigh": math.sqrt(lambda0_squared(p["m"], 1.0)) / T,
            "zeta_lo": FIBRE_ZETA_RANGE[0], "zeta_hi": FIBRE_ZETA_RANGE[1]}


def _tone_fields(p: dict[str, Any]) -> dict[str, Any]:
    """The specification's values of cochlea-tone (the dimensionless parameters, the peak)."""
    fine, _ = _tone_responses(p)
    wkb = ("none (needs mu > 0 and lambda_c > 0)" if fine.wkb_peak_x is None
           else f"{fine.to_cm(fine.wkb_peak_x):.4g} cm")
    return {**cochlea_forced(**p), "width": TONE_WIDTH,
            "width_cm": TONE_WIDTH * p["length"] / math.pi, "hertz": p["omega"] / (2 * math.pi),
            "points": RESPONSE_POINTS, "peak_cm": fine.to_cm(fine.peak_x),
            "peak_error_cm": fine.to_cm(fine.peak_error),
            "peak_share": 100 * fine.peak_x / math.pi, "wkb": wkb,
            "omega_lo": BENCHMARKS["cochlea-tone"].omega_range[0],
            "omega_hi": BENCHMARKS["cochlea-tone"].omega_range[1]}


FIELDS = {"sphere-release": _release_fields, "fibre-release": _fibre_release_fields,
          "sphere-parametric": lambda p: _parametric_fields("sphere", p),
          "fibre-parametric": lambda p: _parametric_fields("fibre", p),
          "cochlea-tone": _tone_fields}


def specification_text(name: str, **params: Any) -> str:
    """The one-page specification of problem ``name`` at the given (or default) parameters."""
    problem = benchmark_problem(name)
    p = benchmark_params(problem, params)
    return problem.specification.format(
        **p, **FIELDS[name](p), amplitude=p.get("epsilon", 0.0) * p.get("radius", 0.0),
        sigma_star=IB_SPRING_FACTOR * p["sigma"], reference=problem.reference)


def score_window(ds) -> tuple[float, float]:
    """(t_a, t_b) in s where score fits a user's series (and the reference alike): the release
    problems from the start of the reference's fit window over SCORE_EFOLDS e-folds of the
    exact mode (longer windows let the algebraic tail bias the fit); sphere-parametric from period
    FIT_FROM_PERIOD to the end; fibre-parametric after the transient (:func:`_rate_window`)."""
    return tuple(float(v) for v in ds.attrs["score_window"])


def _fit(t: np.ndarray, x: np.ndarray, window: tuple[float, float], guess: complex,
         forcing: float | None):
    """(rate, frequency, error) of x in the window, or (None, None, None) if it cannot be fitted."""
    inside = (t >= window[0]) & (t <= window[1])
    try:
        return fit_damped_oscillation(t[inside], x[inside], guess=guess, forcing=forcing)
    except SpectralShellError:
        return None, None, None


def _score_quantity(ds, name: str, t_user: np.ndarray, x_user: np.ndarray) -> QuantityScore:
    """Errors of one user series against the reference (interpolated by a cubic spline onto
    the reference times inside the user's range) and its fitted rate and frequency (a damped
    cosine, or forced a Floquet solution, started from the exact values)."""
    t_ref = ds["t"].values
    inside = (t_ref >= t_user[0]) & (t_ref <= t_user[-1])
    if inside.sum() < 2 or t_user.size < 4:
        raise ParameterError(f"user data column {name} is invalid: its times "
                             f"{t_user[0]:g}..{t_user[-1]:g} s cover fewer than 2 reference "
                             "times (or it has fewer than 4 samples)")
    ref = ds[name].values[inside]
    diff = CubicSpline(t_user, x_user)(t_ref[inside]) - ref
    attrs = ds[name].attrs
    guess = complex(attrs["exact_growth_rate"], attrs["exact_frequency"])
    forcing = ds.attrs.get("forcing_frequency")
    window = score_window(ds)
    rate, frequency, error = _fit(t_user, x_user, window, guess, forcing)
    ref_fit = _fit(t_ref, ds[name].values, window, guess, forcing)
    return QuantityScore(name=name, units=attrs.get("units", ""),
                         exact_growth_rate=float(guess.real), exact_frequency=float(guess.imag),
                         reference_growth_rate=ref_fit[0], reference_frequency=ref_fit[1],
                         relative_l2=float(np.linalg.norm(diff) / np.linalg.norm(ref)),
                         max_error=float(np.max(np.abs(diff))),
                         reference_error=float(np.max(ds[name + ERROR_SUFFIX].values[inside])),
                         growth_rate=rate, frequency=frequency, fit_error=error,
                         samples=int(inside.sum()))


def _score_rate(ds, name: str, t_user: np.ndarray, x_user: np.ndarray,
                exact: dict[str, float]) -> QuantityScore:
    """The growth rate and frequency of a user series the reference has no samples of
    (fibre-parametric), fitted in the score window, against the exact ones; ParameterError when
    the run does not cover the window."""
    window = score_window(ds)
    if t_user[0] > window[0] or t_user[-1] < window[1]:
        raise ParameterError(f"user data column {name} is invalid: its times "
                             f"{t_user[0]:g}..{t_user[-1]:g} s must cover the fit window "
                             f"{window[0]:.6g}..{window[1]:.6g} s (after the transient)")
    guess = complex(exact["exact_growth_rate"], exact["exact_frequency"])
    rate, frequency, error = _fit(t_user, x_user, window, guess, ds.attrs["forcing_frequency"])
    inside = (t_user >= window[0]) & (t_user <= window[1])
    return QuantityScore(name=name, units="", exact_growth_rate=float(guess.real),
                         exact_frequency=float(guess.imag), relative_l2=None, max_error=None,
                         reference_error=None, growth_rate=rate, frequency=frequency,
                         fit_error=error, reference_growth_rate=None, reference_frequency=None,
                         samples=int(inside.sum()))


def _user_peak(spline: CubicSpline, low: float, high: float) -> float:
    """Where ``spline`` is largest on [low, high] (among its stationary points there and the
    ends)."""
    roots = spline.derivative().roots(extrapolate=False)
    candidates = np.concatenate([[low, high], roots[(roots >= low) & (roots <= high)]])
    return float(candidates[int(np.argmax(spline(candidates)))])


def _score_envelope(ds, path, x_user: np.ndarray, columns: dict) -> PeakScore:
    """cochlea-tone: the user's envelope (column 'envelope', x in cm) divided by its largest
    sample (as the reference is), interpolated by a cubic spline onto the reference x inside its range, against the
    reference; its peak past the load (x >= tone_start_cm) against the exact one."""
    if {c for c in columns if not c.endswith(ERROR_SUFFIX)} != {"envelope"}:
        raise ParameterError(f"user data {str(path)!r} columns {', '.join(columns)} are invalid: "
                             "expected x (cm) and envelope")
    x_ref = ds["x"].values
    inside = (x_ref >= x_user[0]) & (x_ref <= x_user[-1])
    start = ds.attrs["tone_start_cm"]
    if x_user.size < 4 or inside.sum() < 2 or x_user[-1] <= start:
        raise ParameterError(f"user data column x is invalid: {x_user[0]:g}..{x_user[-1]:g} cm "
                             f"must reach past {start:.4g} cm (the load) and cover at least 2 "
                             "reference points with 4 samples")
    spline = CubicSpline(x_user, columns["envelope"])
    scale = float(np.max(columns["envelope"]))
    if not scale > 0:
        raise ParameterError(f"user data column envelope is invalid: its maximum {scale:g} "
                             "must be positive")
    ref = ds["envelope"].values[inside]
    diff = spline(x_ref[inside]) / scale - ref
    peak = _user_peak(spline, max(start, x_user[0]), x_user[-1])
    return PeakScore(problem=ds.attrs["problem"], params=attrs_json(ds, "params"), scale=scale,
                     relative_l2=float(np.linalg.norm(diff) / np.linalg.norm(ref)),
                     max_error=float(np.max(np.abs(diff))),
                     reference_error=float(np.max(ds["envelope" + ERROR_SUFFIX].values[inside])),
                     peak_x=peak, exact_peak_x=float(ds.attrs["peak_x_cm"]),
                     exact_peak_error=float(ds.attrs["peak_error_cm"]),
                     samples=int(inside.sum()))


def score(name: str, path: str | Path, *, reference: xr.Dataset | None = None,
          **params: Any) -> tuple[BenchmarkScore | PeakScore, xr.Dataset, tuple]:
    """Score the user's CSV ``path`` (format: :mod:`spectralshell.results.benchmark`) against
    the reference of ``name`` at ``params`` (or the given ``reference`` Dataset) ->
    (score, reference Dataset, (axis values of the user, {column: values})); cochlea-tone
    (over x): a :class:`~spectralshell.results.benchmark.PeakScore`."""
    ds = reference if reference is not None else benchmark(name, **params)
    t_user, columns = read_series(path, axis(ds))
    if axis(ds) == "x":
        return (_score_envelope(ds, path, t_user, columns), ds,
                (t_user, {"envelope": columns["envelope"]}))
    rate_only = attrs_json(ds, "rate_only") if "rate_only" in ds.attrs else {}
    known = reference_columns(ds) + list(rate_only)
    unknown = [c for c in columns if c not in known and not c.endswith(ERROR_SUFFIX)]
    if unknown:
        raise ParameterError(f"user data column {unknown[0]!r} is unknown: expected "
                             f"{', '.join(known)}")
    scored = [c for c in known if c in columns]
    if not scored:
        raise ParameterError(f"user data {str(path)!r} has no quantity column: expected one of "
                             f"{', '.join(known)}")
    result = BenchmarkScore(problem=name, params=attrs_json(ds, "params"),
                            exact_growth_rate=ds.attrs.get("exact_growth_rate"),
                            exact_frequency=ds.attrs.get("exact_frequency"),
                            fit_window=score_window(ds),
                            quantities=tuple(
                                _score_rate(ds, c, t_user, columns[c], rate_only[c])
                                if c in rate_only else _score_quantity(ds, c, t_user, columns[c])
                                for c in scored))
    return result, ds, (t_user, {c: columns[c] for c in scored})


def listing() -> list[dict[str, str]]:
    """[{name, title}] of the registered problems."""
    return [{"name": p.name, "title": p.title} for p in BENCHMARKS.values()]

