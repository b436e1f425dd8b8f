"""Least-squares fit of one damped oscillation exp(gamma t)(a cos w t + b sin w t) to samples,
plus a polynomial trend of degree ``TREND`` (the slowly varying, non-oscillating part: the
algebraic tail of the unbounded fluid's continuous spectrum, a drift of a user's code).

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


def _residual(theta: np.ndarray, t: np.ndarray, x: np.ndarray) -> np.ndarray:
    """x minus its best fit by exp(gamma t) (a cos w t + b sin w t) at (gamma, w) = theta."""
    gamma, w = theta
    envelope = np.exp(gamma * t)
    s = t / t[-1]
    basis = np.column_stack([envelope * np.cos(w * t), envelope * np.sin(w * t),
                             *(s**j for j in range(TREND + 1))])
    coef, *_ = np.linalg.lstsq(basis, x, rcond=None)
    return basis @ coef - x


def fit_damped_oscillation(times, values, *, guess: complex) -> tuple[float, float, float]:
    """(growth rate gamma, angular frequency w, standard error of both) of the samples.

    ``guess`` = gamma0 + i w0 starts the search (e.g. the exact mode). ParameterError for fewer
    than MIN_SAMPLES finite samples; ConvergenceError if the search fails."""
    t = np.asarray(times, dtype=float)
    x = np.asarray(values, dtype=float)
    if t.shape != x.shape or t.ndim != 1 or t.size < MIN_SAMPLES:
        raise ParameterError(f"fit samples of shape {t.shape} are invalid: need >= {MIN_SAMPLES}")
    t = t - t[0]
    scale = float(np.max(np.abs(x))) or 1.0
    start = np.array([guess.real, abs(guess.imag)])
    sol = least_squares(_residual, start, args=(t, x / scale), method="lm", xtol=1e-15,
                        ftol=1e-15, gtol=1e-15)
    if not sol.success:
        raise ConvergenceError(f"damped-oscillation fit failed: {sol.message}")
    dof = max(1, t.size - 5 - TREND)
    variance = float(sol.fun @ sol.fun) / dof
    try:
        cov = np.linalg.inv(sol.jac.T @ sol.jac) * variance
        error = float(np.sqrt(max(cov[0, 0], cov[1, 1], 0.0)))
    except np.linalg.LinAlgError:
        error = float("inf")
    return float(sol.x[0]), float(abs(sol.x[1])), error
