"""Growth rate and frequency of the dominant component of a sampled signal (model-agnostic).

A linear system's response is a sum of exponentials c_i exp(gamma_i t) (unforced) or of Floquet
solutions exp(gamma_i t) p_i(t) with p_i of period T (periodically forced). Both are fitted by
dynamic mode decomposition (an ESPRIT / matrix-pencil variant):

* unforced, samples x_j at spacing h: snapshots y_k = (x_k, ..., x_{k+S-1}) (a Hankel embedding of
  depth S); y_{k+1} = A y_k holds exactly for a sum of r <= S exponentials, and the eigenvalues of
  A restricted to the leading r singular directions of [y_0 .. y_{K-2}] are mu_i = exp(gamma_i h);
* forced, P = T/h samples per period: snapshots are whole periods y_k = (x_{kP}, ..., x_{kP+P-1});
  then y_{k+1} = A y_k with eigenvalues the Floquet multipliers mu_i = exp(gamma_i T).

The rank r counts the singular values above ``rank_tol`` times the largest. The dominant
component is the one with the largest amplitude anywhere in the fit window. Growth rate =
log|mu|/h (or /T); frequency = |arg mu|/h (unforced) or, forced, the dominant angular frequency
|Im gamma + n| of exp(gamma t) p(t), n the largest Fourier harmonic of p (1/2 for a
period-doubling response, 0 or 1 for a harmonic one). The error estimate is the largest change of
growth rate or frequency when the fit is repeated on the first and on the last 70 % of the window,
following there the component closest to the one found on the whole window.
"""

from __future__ import annotations

import numpy as np

from .._validate import require_positive, require_real
from ..errors import ConvergenceError, ParameterError
from ..results.records import RateFit
from .stepper import one_blas_thread

SUB_WINDOW = 0.7
DEPTH = 40


def _dmd(Y: np.ndarray, rank_tol: float) -> tuple[np.ndarray, np.ndarray, int]:
    """Eigenvalues mu_i and modes (columns) of the snapshot map Y[:, k+1] = A Y[:, k]."""
    H0, H1 = Y[:, :-1], Y[:, 1:]
    U, s, Vh = np.linalg.svd(H0, full_matrices=False)
    if s.size == 0 or s[0] == 0.0:
        raise ConvergenceError("the signal is zero in the fit window: nothing to fit")
    r = int(np.sum(s > rank_tol * s[0]))
    U, s, Vh = U[:, :r], s[:r], Vh[:r]
    A = U.conj().T @ H1 @ Vh.conj().T / s
    mu, W = np.linalg.eig(A)
    modes = U @ W
    # amplitudes of each component at the first snapshot
    amp, *_ = np.linalg.lstsq(modes, Y[:, 0].astype(complex), rcond=None)
    return mu, modes * amp, r


def _dominant(mu: np.ndarray, modes: np.ndarray, snapshots: int) -> int:
    size = np.linalg.norm(modes, axis=0) * np.maximum(1.0, np.abs(mu) ** (snapshots - 1))
    # one of each conjugate pair: prefer Im mu >= 0 among (near) ties
    size = size * (1 + 1e-9 * (mu.imag >= 0))
    return int(np.argmax(size))


def _fit(x: np.ndarray, h: float, period_samples: int | None, rank_tol: float,
         target: complex | None = None):
    if period_samples is None:
        depth = min(DEPTH, x.size // 3)
        if depth < 4:
            raise ParameterError(f"signal length {x.size} is invalid: must be >= 12 samples")
        Y = np.lib.stride_tricks.sliding_window_view(x, depth).T
        step = h
    else:
        K = x.size // period_samples
        if K < 4:
            raise ParameterError(f"fit window of {K} periods is invalid: must hold >= 4 periods")
        Y = x[:K * period_samples].reshape(K, period_samples).T
        step = h * period_samples
    mu, modes, r = _dmd(Y, rank_tol)
    if target is None:
        i = _dominant(mu, modes, Y.shape[1])
    else:     # follow the component found on the whole window
        i = int(np.argmin(np.abs(mu - target) + 1e-9 * (mu.imag < 0)))
    m = complex(mu[i])
    if m == 0:
        raise ConvergenceError("the dominant component decays to zero within one step")
    gamma = np.log(m) / step
    if period_samples is None:
        frequency = abs(gamma.imag)
    else:
        phases = np.arange(period_samples) * h
        p = modes[:, i] * np.exp(-gamma * phases)
        harmonics = np.fft.fft(p)
        n = np.fft.fftfreq(period_samples, d=1.0 / period_samples)
        frequency = abs(gamma.imag + n[np.argmax(np.abs(harmonics))])
    return float(gamma.real), float(frequency), m, r


def fit_rate(times, values, *, period: float | None = None, skip: float = 0.2,
             window: tuple[float, float] | None = None, rank_tol: float = 1e-12) -> RateFit:
    """Fit the dominant growth rate and frequency of ``values`` sampled at uniform ``times``.

    Parameters
    ----------
    times, values : uniform samples (real).
    period : forcing period T (the spacing must divide it), or None for an unforced signal.
    skip : fraction of the run left out at the start (initial transient), in [0, 0.9].
    window : (t_a, t_b), the fitted interval instead (e.g. to leave out a late algebraic tail
        that is not an exponential); with ``period``, t_a is moved to the next whole period.
    rank_tol : relative singular-value threshold of the fitted rank.

    Raises
    ------
    ParameterError : non-uniform times, too short a window, a period not a multiple of the spacing.
    ConvergenceError : a zero signal.

    Runs with one BLAS thread (the matrices are small).
    """
    with one_blas_thread():
        return _fit_rate(times, values, period=period, skip=skip, window=window,
                         rank_tol=rank_tol)


def _fit_rate(times, values, *, period, skip, window, rank_tol) -> RateFit:
    t = np.asarray(times, dtype=float)
    x = np.asarray(values, dtype=float)
    if t.ndim != 1 or t.shape != x.shape or t.size < 12:
        raise ParameterError(f"times/values shapes {t.shape}, {x.shape} are invalid: must be equal "
                             "1-d arrays of >= 12 samples")
    h = (t[-1] - t[0]) / (t.size - 1)
    if not np.allclose(np.diff(t), h, rtol=1e-8, atol=0):
        raise ParameterError("times are invalid: must be uniformly spaced")
    if not 0.0 <= skip <= 0.9:
        raise ParameterError(f"skip = {skip!r} is invalid: must be in [0, 0.9]")
    rank_tol = require_positive("rank_tol", rank_tol)
    P = None
    if period is not None:
        period = require_positive("period", period)
        P = int(round(period / h))
        if abs(P * h - period) > 1e-9 * period:
            raise ParameterError(f"period = {period!r} is invalid: must be a multiple of the sample "
                                 f"spacing {h!r}")
    start, stop = int(np.ceil(skip * (t.size - 1))), t.size
    if window is not None:
        t_a, t_b = (require_real("window start", window[0]), require_real("window end", window[1]))
        if not t[0] <= t_a < t_b:
            raise ParameterError(f"window = {window!r} is invalid: must satisfy t0 <= t_a < t_b")
        start = int(np.ceil((t_a - t[0]) / h - 1e-9))
        stop = min(t.size, int(np.floor((t_b - t[0]) / h + 1e-9)) + 1)
    if P is not None:       # start at a whole period after t0 (phases relative to the forcing)
        start = int(np.ceil(start / P)) * P
    x, t = x[start:stop], t[start:stop]
    if x.size < 12:
        raise ParameterError(f"fit window of {x.size} samples is invalid: must hold >= 12")
    best = _fit(x, h, P, rank_tol)
    n = x.size
    cut = int(SUB_WINDOW * n)
    if P is not None:
        cut = (cut // P) * P
    others = []
    for part in (x[:cut], x[n - cut:] if P is None else x[(n - cut) // P * P:]):
        try:
            others.append(_fit(part, h, P, rank_tol, target=best[2]))
        except ParameterError:
            continue
    if not others:
        raise ParameterError("fit window too short for an error estimate: run longer")
    error = max(max(abs(o[0] - best[0]), abs(o[1] - best[1])) for o in others)
    return RateFit(growth_rate=best[0], frequency=best[1], multiplier=best[2],
                   error_estimate=float(error), window=(float(t[0]), float(t[-1])), rank=best[3])
