"""Time stepping of the box cochlea, M cosine modes: the growth rate of a pumped basilar membrane.

The cochlea's second, independent discretisation (:mod:`spectralshell.discretise.cochlea_vertical`:
per cosine mode, vertical Chebyshev collocation of unsteady Stokes flow, the modes coupled by the
stiffness profile e^{-alpha x}) is stepped with K(t) = kappa e^{-alpha x} (1 + 2 tau sin t) and
the dominant growth rate of the modal coordinates (below) is fitted. It checks
the Floquet exponents of the Hill system (``ss.exponents("cochlea", ...)``), which use the
closed-form transfer functions Z_k(s) instead; the two share only the coupling matrix C.

Start. The state starts as the sum of the real parts of every resolved oscillatory natural mode
of the stepping pencil itself (each scaled to a largest membrane amplitude 1): a consistent state
of the DAE, fluid included, that excites each Floquet family, whereas an impulsive start (fluid at
rest) also excites the discretised continuum near s = -nu k^2, which decays more slowly than the
modes.

Fit. The rate fit (:func:`spectralshell.solvers.rate_fit.fit_rate`) keeps the component of
largest amplitude anywhere in its window, which for decaying components is the one largest at
the start, not the least damped (at M = 6 below tau_min the leading family -0.01066 carries
1/13 of the amplitude of the next, -0.01173, in h(0, t) = sum_k h_k). So the run observes the modal
coordinates q_j(t) = Re(u_j^T M v(t)), u_j the left eigenvector of natural mode j of the pencil
(u_j^T M v_i = 0 for i != j at tau = 0): each q_j is dominated by the Floquet family continued
from mode j, every q_j is fitted and the largest growth rate is the result (with its frequency).

Window. The start excites the most damped modes as much as the least damped ones, and their many
Floquet components exceed what the fit resolves (M = 8 below tau_min: a bias of 1.2e-5 with the
window of ``simulate``, which starts after two periods); so the window starts when the most
damped oscillatory mode has decayed by e^-TRANSIENT_EFOLDS (at MAX_SKIP of the run at the
latest) and ends as in ``simulate``.

Time grid, the window's end and the 2 dt check run are those of ``simulate``
(:func:`.simulate.time_grid`: a whole number of steps per forcing period, DT_FACTOR / |s| at
most, s the fastest oscillatory natural mode, as the sphere's fastest degree: the M modes are
the cochlea's degrees). Stepping at the least damped mode's |s| alone left the harmonic tongues
of kappa = 2 and 2.5 (alpha = 0.5, nu = 1e-3, M = 4: modes up to |s| = 1.5 and 1.8) off by
1.6e-6 and 1.8e-6, the third-order time error (2.0e-7 at dt / 2); now 4.8e-7 and 3.6e-7. The
error estimate adds the fit's own sub-window spread, the change of the fit at step 2 dt and the
vertical error, the largest relative change of an oscillatory eigenvalue of the pencil between
n_vertical and N_CHECK nodes fewer, times |gamma|. Measured against the exponents at
kappa = 0.5, nu = 1e-3, alpha = 1, tau = tau_min -+ 0.02: 1.7e-9 and 5.8e-8 (M = 4), 2.7e-9
and 9.6e-8 (M = 6), 1.1e-7 and 1.3e-7 (M = 8), with stated errors 2e-8 .. 8e-7
(tests/test_cochlea_stepping.py), and at seven other parameter sets (kappa 0.3 .. 4, nu 1e-3,
3e-3, alpha 0 .. 1.5, harmonic and subharmonic tongues; tests/test_simulate_models.py):
2.1e-8 .. 1.1e-7 on the subharmonic tongues, 6.5e-8 .. 4.8e-7 on the harmonic ones, with stated
errors 1.7e-7 .. 3.4e-6.

Public as ``ss.simulate("cochlea", ...)`` (:func:`simulate_cochlea`): the run's series (the
modal coordinates and the membrane's cosine coefficients) with the fit.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from typing import Any
from dataclasses import dataclass

import numpy as np

from .._validate import require_int_in_range, require_real
from ..discretise.cochlea_vertical import (N_VERTICAL_MIN, CochleaStepping,
                                           cochlea_vertical_operators, stepping_system)
from ..discretise.sphere_radial import N_RADIAL_MAX
from ..discretise.sphere_stepping import OSCILLATORY, oscillatory_leader
from ..errors import ConvergenceError, ParameterError
from ..models.cochlea import natural_frequencies
from ..params.cochlea import CochleaParams
from ..params.simulation import STEPPED_T_END
from ..results.records import RateFit
from ..results.stepped import SteppedRun
from ..solvers.eigen import finite_eigenvalues
from .simulate import (fit_window, price_stepping, stepped_fit, stepped_result, stepped_runs,
                       stepped_settings, time_grid)

N_VERTICAL = 48         # default vertical resolution (natural modes to 7e-9 at M = 4, 6, nu = 1e-3)
VERTICAL_SCALE = 1.0    # L of the map y = L (1/xi - 1): the decay length of the first mode
N_CHECK = 8             # the vertical error compares with this many nodes fewer
PERIODS = 60.0          # default run length in forcing periods
FLOOR = 0.1             # oscillatory modes have |s| > FLOOR w_1 (w_1 the lowest inviscid frequency)
TRANSIENT_EFOLDS = 10.0  # the fit starts when the most damped mode has decayed by e^-10 ...
MAX_SKIP = 0.4          # ... or at this fraction of the run, whichever is first


def _oscillatory(values: np.ndarray, floor: float) -> np.ndarray:
    """Indices of the eigenvalues with Im s > OSCILLATORY |s| and |s| > floor (the nearly real
    discretised continuum near s = 0 left out, as :func:`.sphere_stepping.oscillatory_leader`)."""
    return np.flatnonzero((values.imag > OSCILLATORY * np.abs(values)) & (np.abs(values) > floor))


def cochlea_rate(*, kappa: float, nu: float, alpha: float, n_spatial: int, tau: float,
                 periods: float = PERIODS, scheme: str = "SBDF3", dt: float | None = None,
                 n_vertical: int = N_VERTICAL, vertical_scale: float = VERTICAL_SCALE) -> RateFit:
    """Growth rate (and frequency) of the time-stepped cochlea of M cosine modes (module docstring).

    Parameters
    ----------
    kappa, nu, alpha, n_spatial : as ``ss.exponents("cochlea", ...)``; nu > 0 (the vertical
        stepper has viscous fluid) and a fixed number M of cosine modes.
    tau : pumping amplitude of K(t) = kappa e^{-alpha x} (1 + 2 tau sin t).
    periods : run length in forcing periods 2 pi (>= 10).
    scheme, dt : IMEX scheme and step (None: the simulate default).
    n_vertical : vertical unknowns per field and mode (>= 6 + N_CHECK).
    vertical_scale : L of the vertical map y = L (1/xi - 1).

    Returns
    -------
    RateFit of the modal coordinate q_j that grows fastest: growth_rate approximates Re gamma
    of the leading Floquet exponent, frequency its locked frequency (1/2 subharmonic, 0 or 1
    harmonic when forced).

    Raises
    ------
    ParameterError : a parameter out of range (nu = 0 and n_spatial = None included).
    ConvergenceError : no oscillatory mode resolved.
    """
    if not require_real("periods", periods) >= 10:
        raise ParameterError(f"periods = {periods!r} is invalid: must be >= 10")
    return simulate_cochlea(kappa=kappa, nu=nu, alpha=alpha, n_spatial=n_spatial, tau=tau,
                            t_end=periods * 2 * math.pi, scheme=scheme, dt=dt,
                            n_vertical=n_vertical, vertical_scale=vertical_scale).fit


def simulate_cochlea(*, kappa: float, nu: float, alpha: float, n_spatial: int | None = None,
                     tau: float = 0.0, t_end: float = STEPPED_T_END, scheme: str = "SBDF3",
                     dt: float | None = None, amplitude: float = 1.0,
                     n_vertical: int = N_VERTICAL, vertical_scale: float = VERTICAL_SCALE,
                     max_seconds: float | None = None, progress: bool = False) -> SteppedRun:
    """Time-step the cochlea of M cosine modes and fit the fastest-growing modal coordinate ->
    :class:`SteppedRun` (``ss.simulate("cochlea", ...)``; module docstring).

    Parameters
    ----------
    kappa, nu, alpha, n_spatial : as ``ss.exponents("cochlea", ...)``; nu > 0 and a fixed
        number M of cosine modes (required).
    tau : pumping amplitude of K(t) = kappa e^{-alpha x} (1 + 2 tau sin t); |tau| > 1/2 is
        flagged.
    t_end : end time, >= 20 pi (ten forcing periods; default sixty).
    scheme, dt : IMEX scheme and step (None: :func:`.simulate.time_grid`'s).
    amplitude : the start (the sum of the real parts of the oscillatory natural modes of the
        stepped pencil, each of largest membrane amplitude 1) times ``amplitude`` (nonzero).
    n_vertical : vertical unknowns per field and mode (>= 6 + N_CHECK).
    vertical_scale : L of the vertical map y = L (1/xi - 1).
    max_seconds : raise the limit on the estimated run time (default 600 s or
        $SPECTRALSHELL_MAX_SECONDS), priced before the eigenproblems and before the steps.

    Returns
    -------
    SteppedRun with series q1, ..., (the modal coordinates) and h1, ..., hM (the membrane's
    cosine coefficients); the fit is that of the modal coordinate growing fastest: growth_rate
    approximates Re gamma of the leading Floquet exponent, frequency its |Im gamma|.

    Raises
    ------
    ParameterError : a parameter out of range (nu = 0 and n_spatial = None included), a run
        priced above the limit.
    ConvergenceError : no oscillatory mode resolved.
    """
    started = time.perf_counter()
    p = CochleaParams(kappa=kappa, nu=nu, alpha=alpha, n_spatial=n_spatial)
    if p.nu == 0.0:
        raise ParameterError("nu = 0 is invalid: must be > 0 for the cochlea's vertical time "
                             "stepper (the inviscid cochlea is a matrix Mathieu equation)")
    if p.n_spatial is None:
        raise ParameterError("n_spatial = None is invalid: the time stepper needs a fixed number "
                             "of cosine modes M >= 1")
    tau, t_end, dt, amplitude, scheme, warnings = stepped_settings(tau, t_end, dt, amplitude,
                                                                   scheme)
    n_vertical = require_int_in_range("n_vertical", n_vertical, N_VERTICAL_MIN + N_CHECK,
                                      N_RADIAL_MAX)
    size = p.n_spatial * (2 * n_vertical + 1)
    price_stepping("cochlea run", size, eigenproblems=4, max_seconds=max_seconds)
    floor = FLOOR * float(natural_frequencies(p.kappa, p.alpha, np.arange(1, p.n_spatial + 1))[0])
    fine_ops, coarse_ops = (
        cochlea_vertical_operators(n_spatial=p.n_spatial, nu=p.nu, alpha=p.alpha,
                                   n_vertical=n_vertical - k, vertical_scale=vertical_scale)
        for k in (0, N_CHECK))
    values, vectors = finite_eigenvalues(*fine_ops.pencil(p.kappa), vectors=True)
    coarse_values = finite_eigenvalues(*coarse_ops.pencil(p.kappa))
    leading = oscillatory_leader(values, floor)
    if leading is None:
        raise ConvergenceError(f"no resolved oscillatory mode at zeta = nu/sqrt(kappa) = "
                               f"{p.nu / math.sqrt(p.kappa):.3g}: raise n_vertical")
    osc = _oscillatory(values, floor)
    vertical = max(np.min(np.abs(coarse_values - values[i])) / abs(values[i]) for i in osc)
    shapes = vectors[:, osc] / _peaks(vectors[fine_ops.blocks["membrane"]][:, osc])
    left_values, left_vectors = finite_eigenvalues(*(A.T for A in fine_ops.pencil(p.kappa)),
                                                   vectors=True)
    left = left_vectors[:, [int(np.argmin(np.abs(left_values - values[i]))) for i in osc]]
    rows = left.T @ fine_ops.M                          # u_j^T M: q_j(v) = Re(rows_j v)
    rows /= np.abs(np.diag(rows @ shapes))[:, None]     # q_j = 1 on mode j's shape
    system = _Modal.of(stepping_system(fine_ops, kappa=p.kappa, tau=tau), rows,
                       fine_ops.blocks["membrane"])
    fastest_mode = float(np.max(np.abs(values[osc])))   # the step resolves every mode
    step, every, steps, t_end = time_grid(dt=dt, rate=fastest_mode, tau=tau, t_end=t_end)
    price_stepping("cochlea run", size, steps=steps + steps // 2, max_seconds=max_seconds)
    (fine,), (coarse,) = stepped_runs([system], [amplitude * shapes.real.sum(axis=1)], scheme,
                                      step, steps, every, progress)
    forced = tau != 0.0
    t_a, t_b = fit_window(t_end, leading, forced)
    fastest = float(np.max(-values[osc].real))
    window = (max(t_a, min(TRANSIENT_EFOLDS / fastest, MAX_SKIP * t_end)), t_b)
    column, fit = stepped_fit(fine, coarse, range(osc.size), window, forced, vertical)
    params: dict[str, Any] = {"kappa": p.kappa, "nu": p.nu, "alpha": p.alpha,
                              "n_spatial": p.n_spatial, "tau": tau, "amplitude": amplitude}
    resolution = {"n_vertical": n_vertical, "vertical_scale": vertical_scale,
                  "spatial_error": vertical,
                  "natural_modes": [[g.real, g.imag] for g in values[osc]]}
    series = (*(f"q{j + 1}" for j in range(osc.size)),
              *(f"h{k}" for k in range(1, p.n_spatial + 1)))
    return stepped_result("cochlea", params, fine, series, column, fit, scheme=scheme,
                          every=every, method="IMEX time stepping of the vertical Chebyshev "
                          "system per cosine mode (discretise/cochlea_vertical.py), the fit on "
                          "the modal coordinates q_j", resolution=resolution, warnings=warnings,
                          started=started)


def _peaks(membrane: np.ndarray) -> np.ndarray:
    """The entry of largest modulus of each column."""
    return membrane[np.argmax(np.abs(membrane), axis=0), np.arange(membrane.shape[1])]


@dataclass(frozen=True, kw_only=True, eq=False)
class _Modal:
    """The system M dv/dt = L v + f(t) N v of a :class:`.cochlea_vertical.CochleaStepping`
    observed through its modal coordinates: ``displacement`` (what
    :func:`.simulate.stepped_runs` records) returns Re(rows v), then the membrane's cosine
    coefficients v[membrane]."""

    M: np.ndarray
    L: np.ndarray
    N: np.ndarray | None
    forcing: Callable[[float], float] | None
    rows: np.ndarray
    membrane: slice

    @classmethod
    def of(cls, system: CochleaStepping, rows: np.ndarray, membrane: slice) -> _Modal:
        return cls(M=system.M, L=system.L, N=system.N, forcing=system.forcing, rows=rows,
                   membrane=membrane)

    def displacement(self, v: np.ndarray) -> np.ndarray:
        return np.concatenate([(self.rows @ v).real, v[self.membrane]])
