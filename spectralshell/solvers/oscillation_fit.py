"""Least-squares fit of one damped oscillation exp(gamma t)(a cos w t + b sin w t) to samples,
plus a polynomial trend of degree ``TREND`` (the slowly varying, non-oscillating part: the
algebraic tail of the unbounded fluid's continuous spectrum, a drift of a user's code).

With a forcing frequency W (a parametrically forced system) the oscillation is a Floquet
solution exp(gamma t) p(t), p periodic: the fit takes exp(gamma t)(a_j cos (w + j W) t +
b_j sin (w + j W) t) for j = 0 .. ``HARMONICS`` (w = W/2 for a period-doubling response,
0 for a harmonic one).

For data that are not uniformly sampled or carry noise (a user's simulation), where the
Hankel/DMD fit of :mod:`.rate_fit` needs uniform, nearly noise-free samples. The amplitudes
(a, b and the trend) enter linearly and are eliminated (variable projection); (gamma, w) are
found by scipy's Levenberg-Marquardt least squares from a starting guess, and their standard
errors from the Jacobian at the optimum (residual variance times the diagonal of (J^T J)^-1).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import least_squares

from ..errors import ConvergenceError, ParameterError

MIN_SAMPLES = 8
TREND = 3        # degree of the polynomial fitted along (a slowly varying, non-oscillating part)
HARMONICS = 6    # forced: the harmonics w + j W, j = 0 .. HARMONICS, of the periodic part


def _residual(theta: np.ndarray, t: np.ndarray, x: np.ndarray, shifts: np.ndarray) -> np.ndarray:
    """x minus its best fit by exp(gamma t) sum_j (a_j cos (w + shift_j) t + b_j sin ...) plus
    the trend, at (gamma, w) = theta."""
    gamma, w = theta
    envelope = np.exp(gamma * t)
    phase = np.outer(t, w + shifts)
    s = t / t[-1]
    basis = np.column_stack([envelope[:, None] * np.cos(phase), envelope[:, None] * np.sin(phase),
                             *(s**j for j in range(TREND + 1))])
    coef, *_ = np.linalg.lstsq(basis, x, rcond=None)
    return basis @ coef - x


def fit_damped_oscillation(times, values, *, guess: complex,
                           forcing: float | None = None) -> tuple[float, float, float]:
    """(growth rate gamma, angular frequency w, standard error of both) of the samples.

    ``guess`` = gamma0 + i w0 starts the search (e.g. the exact mode or Floquet exponent);
    ``forcing``: the forcing's angular frequency W of a parametrically forced system (the fit
    then includes the harmonics w + j W of the module docstring). ParameterError for fewer
    than MIN_SAMPLES finite samples; ConvergenceError if the search fails."""
    t = np.asarray(times, dtype=float)
    x = np.asarray(values, dtype=float)
    if t.shape != x.shape or t.ndim != 1 or t.size < MIN_SAMPLES:
        raise ParameterError(f"fit samples of shape {t.shape} are invalid: need >= {MIN_SAMPLES}")
    t = t - t[0]
    scale = float(np.max(np.abs(x))) or 1.0
    start = np.array([guess.real, abs(guess.imag)])
    shifts = np.zeros(1) if forcing is None else forcing * np.arange(HARMONICS + 1)
    sol = least_squares(_residual, start, args=(t, x / scale, shifts), method="lm", xtol=1e-15,
                        ftol=1e-15, gtol=1e-15)
    if not sol.success:
        raise ConvergenceError(f"damped-oscillation fit failed: {sol.message}")
    dof = max(1, t.size - 3 - 2 * shifts.size - TREND)
    variance = float(sol.fun @ sol.fun) / dof
    try:
        cov = np.linalg.inv(sol.jac.T @ sol.jac) * variance
        error = float(np.sqrt(max(cov[0, 0], cov[1, 1], 0.0)))
    except np.linalg.LinAlgError:
        error = float("inf")
    return float(sol.x[0]), float(abs(sol.x[1])), error
