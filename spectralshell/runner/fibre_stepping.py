"""Time stepping of the fibre, one wavenumber m: the growth rate of a pumped membrane.

The fibre's second, independent discretisation (:mod:`spectralshell.discretise.fibre_radial`:
radial Chebyshev collocation of unsteady Stokes flow inside and outside the circle) is stepped
with K(t) = kappa (1 + 2 tau sin t) from the membrane displaced as (X^r, X^theta) = (1, -1/m)
(the inviscid mode's slaved shape) and the fluid at rest, and the dominant growth rate of X^r is
fitted. It checks the Floquet exponents of the Hill system (``ss.exponents("fibre", ...)``),
which use the Bessel-function load D(s) instead; the two share no physics code.

Time grid, fit window and the 2 dt check run are those of ``simulate``
(:func:`.simulate.time_grid`: a whole number of steps per forcing period, DT_FACTOR / lambda0 at
most, lambda0 the inviscid frequency). The error estimate adds the fit's own sub-window spread,
the change of the fit at step 2 dt and the radial error, the relative change of the least damped
oscillatory eigenvalue of the pencil between (n_inner, n_outer) and 8 nodes fewer each, times
|gamma|. Measured against the exponents: 2e-10 at m = 3, kappa = 0.02, nu = 2e-4, tau = tau_min
+- 0.02 (tests/test_fibre_stepping.py).

Public as ``ss.simulate("fibre", ...)`` (:func:`simulate_fibre`): the run's X^r and X^theta
with the fit.
"""

from __future__ import annotations

import math
import time
from typing import Any

from .._validate import require_int_in_range, require_real
from ..discretise.fibre_radial import fibre_radial_operators, stepping_system
from ..discretise.sphere_radial import N_RADIAL_MAX, exterior_scale_hint
from ..discretise.sphere_stepping import CONTINUUM_FLOOR, oscillatory_leader
from ..errors import ConvergenceError, ParameterError
from ..models.fibre import lambda0_squared
from ..params.fibre import FibreParams
from ..params.simulation import STEPPED_T_END
from ..results.records import RateFit
from ..results.stepped import SteppedRun
from ..solvers.eigen import finite_eigenvalues
from ..solvers.stepper import Run
from .simulate import (fit_window, price_stepping, stepped_fit, stepped_result, stepped_runs,
                       stepped_settings, time_grid)

N_INNER, N_OUTER = 48, 64       # default radial resolution (both modes to ~1e-9 at zeta = 1e-3)
N_CHECK = 8                     # the radial error compares with this many nodes fewer
PERIODS = 60.0                  # default run length in forcing periods


def fibre_rate(*, m: int, kappa: float, nu: float, tau: float, forcing: str = "both",
               periods: float = PERIODS, scheme: str = "SBDF3", dt: float | None = None,
               n_inner: int = N_INNER, n_outer: int = N_OUTER) -> RateFit:
    """Growth rate (and frequency) of the time-stepped fibre, wavenumber m (module docstring).

    Parameters
    ----------
    m, kappa, nu, forcing : as ``ss.floquet("fibre", ...)``; nu > 0 (the radial stepper has
        viscous fluid; nu = 0 is the Mathieu equation).
    tau : pumping amplitude of K(t) = kappa (1 + 2 tau sin t).
    periods : run length in forcing periods 2 pi (>= 10).
    scheme, dt : IMEX scheme and step (None: the simulate default).
    n_inner, n_outer : radial unknowns per field inside and outside (>= 4 + 8, 6 + 8).

    Returns
    -------
    RateFit of X^r: growth_rate approximates Re gamma of the leading Floquet exponent, frequency
    its locked frequency (1/2 subharmonic, 0 or 1 harmonic when forced).

    Raises
    ------
    ParameterError : a parameter out of range (nu = 0 included).
    ConvergenceError : no oscillatory mode resolved (modes near the branch cut, large zeta).
    """
    if not require_real("periods", periods) >= 10:
        raise ParameterError(f"periods = {periods!r} is invalid: must be >= 10")
    return simulate_fibre(m=m, kappa=kappa, nu=nu, tau=tau, forcing=forcing,
                          t_end=periods * 2 * math.pi, scheme=scheme, dt=dt, n_inner=n_inner,
                          n_outer=n_outer).fit


def simulate_fibre(*, m: int, kappa: float, nu: float, forcing: str = "both", tau: float = 0.0,
                   t_end: float = STEPPED_T_END, scheme: str = "SBDF3", dt: float | None = None,
                   amplitude: float = 1.0, n_inner: int = N_INNER, n_outer: int = N_OUTER,
                   max_seconds: float | None = None, progress: bool = False) -> SteppedRun:
    """Time-step the fibre, wavenumber m, and fit the growth rate of X^r -> :class:`SteppedRun`
    (``ss.simulate("fibre", ...)``; module docstring).

    Parameters
    ----------
    m, kappa, nu, forcing : as ``ss.floquet("fibre", ...)``; nu > 0.
    tau : pumping amplitude of K(t) = kappa (1 + 2 tau sin t); |tau| > 1/2 is flagged.
    t_end : end time, >= 20 pi (ten forcing periods; default sixty).
    scheme, dt : IMEX scheme and step (None: :func:`.simulate.time_grid`'s).
    amplitude : the start X = amplitude (1, -1/m), the fluid at rest (nonzero).
    n_inner, n_outer : radial unknowns per field inside and outside (>= 12, 14).
    max_seconds : raise the limit on the estimated run time (default 600 s or
        $SPECTRALSHELL_MAX_SECONDS), priced before the eigenproblems and before the steps.

    Returns
    -------
    SteppedRun with series X^r, X^theta; the fit is that of X^r: growth_rate approximates
    Re gamma of the leading Floquet exponent, frequency its |Im gamma|.

    Raises
    ------
    ParameterError : a parameter out of range (nu = 0 included), a run priced above the limit.
    ConvergenceError : no oscillatory mode resolved (modes near the branch cut, large zeta).
    """
    started = time.perf_counter()
    p = FibreParams(m=m, kappa=kappa, nu=nu, forcing=forcing)
    if p.nu == 0.0:
        raise ParameterError("nu = 0 is invalid: must be > 0 for the fibre's radial time stepper "
                             "(the inviscid fibre is the Mathieu equation)")
    tau, t_end, dt, amplitude, scheme, warnings = stepped_settings(tau, t_end, dt, amplitude,
                                                                   scheme)
    n_inner = require_int_in_range("n_inner", n_inner, 4 + N_CHECK, N_RADIAL_MAX)
    n_outer = require_int_in_range("n_outer", n_outer, 6 + N_CHECK, N_RADIAL_MAX)
    size = 2 * (n_inner + n_outer) + 2
    price_stepping("fibre run", size, eigenproblems=2, max_seconds=max_seconds)
    lam = math.sqrt(lambda0_squared(p.m, p.kappa))
    scale = exterior_scale_hint(nu=p.nu, s_scale=lam)
    fine_ops, coarse_ops = (
        fibre_radial_operators(m=p.m, nu=p.nu, n_inner=n_inner - k, n_outer=n_outer - k,
                               exterior_scale=scale) for k in (0, N_CHECK))
    leaders = [oscillatory_leader(finite_eigenvalues(*ops.pencil(p.kappa)), CONTINUUM_FLOOR * lam)
               for ops in (fine_ops, coarse_ops)]
    if None in leaders:
        raise ConvergenceError(f"no resolved oscillatory mode at zeta = nu/sqrt(kappa) = "
                               f"{p.nu / math.sqrt(p.kappa):.3g}: the real exterior map does not "
                               "resolve modes near the branch cut")
    leading = leaders[0]
    system = stepping_system(fine_ops, kappa=p.kappa, tau=tau, pumping=p.forcing)
    step, every, steps, t_end = time_grid(dt=dt, rate=abs(leading), tau=system.tau, t_end=t_end)
    price_stepping("fibre run", size, steps=steps + steps // 2, max_seconds=max_seconds)
    y0 = system.initial_state([amplitude, -amplitude / p.m])
    (fine,), (coarse,) = stepped_runs([system], [y0], scheme, step, steps, every, progress)
    forced = system.tau != 0.0
    space_error = abs(leaders[0] - leaders[1]) / abs(leading)
    column, fit = stepped_fit(fine, coarse, [0], fit_window(t_end, leading, forced), forced,
                              space_error)
    params: dict[str, Any] = {"m": p.m, "kappa": p.kappa, "nu": p.nu, "forcing": p.forcing,
                              "tau": tau, "amplitude": amplitude}
    resolution = {"n_inner": n_inner, "n_outer": n_outer, "exterior_scale": scale,
                  "spatial_error": space_error, "leading_mode": [leading.real, leading.imag]}
    return stepped_result("fibre", params, fine, ("X^r", "X^theta"), column, fit, scheme=scheme,
                          every=every, method="IMEX time stepping of the radial Chebyshev "
                          "system (discretise/fibre_radial.py)", resolution=resolution,
                          warnings=warnings, started=started)
