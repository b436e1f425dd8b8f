"""Roots of a dispersion relation f(x) = 0: the natural modes of a :class:`ModalSystem`.

Method. Newton's method in double precision from the model's seeds, best first,
x <- x - f/f' with the step capped at |x|/2 (a trust region against jumps far from the seed). A
seed succeeds when the step falls below ``tol`` |x|, or stalls at the rounding floor (a step that
no longer shrinks, below 1e-9 |x|). Each root is put in the form with Im gamma >= 0 (the
``conjugate`` of a root with Im gamma < 0), compared with the roots found so far (a duplicate
within 1e-8 |x| is dropped; when gamma is real to within its error, the representative is the
one with Im x >= 0) and classified by the model's sheet margin (Re beta for the sphere):

* principal sheet: margin > e_x, a genuine mode (decaying, bounded fields);
* on the cut: |margin| <= e_x, the sheet is not resolved at this precision; the mode is, to
  working accuracy, a real exponential decay on the branch cut (counted as a mode);
* otherwise an unphysical-sheet root (a resonance), which is skipped.

Here e_x = max(|last Newton step|, 64 eps |x|) bounds the error of the root: the last step bounds
the error of the iterate it started from, and 64 eps |x| is the accuracy floor of the residual
(its kernels are accurate to about 1e-14). Drawing seeds stops once the model's n_modes modes are
found; the least damped ``count`` of them (largest Re gamma) are returned. Because ``n_modes`` is
the whole natural-mode spectrum of the model (one of each conjugate pair), finding all of them is
what makes "least damped" a statement about every mode, not only about those near a seed.

With ``precision`` digits each root is polished by Newton's method in mpmath at
``precision + 10`` digits from the double root, until the step is below 10^-(precision+5) |x|;
the error estimate then becomes max(step, 10^-precision |x|) mapped to gamma, and the difference
between the double and the polished root is reported as ``double_error``.

Error estimates are absolute in gamma: |gamma(x + e_x) - gamma(x)| (maximised over the real and
imaginary directions of the perturbation).
"""

from __future__ import annotations

import cmath
import math
from dataclasses import dataclass

import mpmath
import numpy as np

from .._validate import require_int_in_range
from ..errors import ConvergenceError, ParameterError
from ..models.base import ModalSystem
from ..results.records import ModeRoots

_EPS = 2.220446049250313e-16
FLOOR = 64 * _EPS
DUPLICATE_RTOL = 1e-8
STALL_RTOL = 1e-9
PRECISION_MAX = 1000


@dataclass(frozen=True)
class _Root:
    x: complex
    step: float


def _newton(system: ModalSystem, x: complex, tol: float, max_iter: int) -> tuple[_Root | None, int]:
    """Newton's method in double from x; (root, evaluations) or (None, evaluations)."""
    previous = math.inf
    for k in range(1, max_iter + 1):
        try:
            f, fp = system.residual(x)
        except (ZeroDivisionError, OverflowError, ParameterError):
            return None, k
        if fp == 0 or not (cmath.isfinite(f) and cmath.isfinite(fp)):
            return None, k
        step = f / fp
        size, scale = abs(step), abs(x)
        if size > 0.5 * scale:
            step *= 0.5 * scale / size
            size = 0.5 * scale
        x = x - step
        if x == 0 or not cmath.isfinite(x):
            return None, k
        if size <= tol * abs(x) or (size >= previous and size <= STALL_RTOL * abs(x)):
            return _Root(x, max(size, FLOOR * abs(x))), k
        previous = size
    return None, max_iter


def _gamma_error(system: ModalSystem, x, err) -> float:
    g = system.to_gamma(x)
    return float(max(abs(system.to_gamma(x + err) - g), abs(system.to_gamma(x + 1j * err) - g)))


def polish_root(residual_mp, x: complex, *, precision: int, max_iter: int = 40):
    """Root of f near x by Newton's method in mpmath at precision + 10 digits, from residual_mp:
    x -> (f, f') at the current ``mpmath.mp.dps`` (any pair whose ratio is the Newton step).

    Each step is capped at |x|/2; the iteration stops when the step is below 10^-(precision+5) |x|.
    Returns (x_mp, error bound): max(last step, 10^-precision |x|), an mpmath number.

    Raises
    ------
    ConvergenceError : no convergence in ``max_iter`` steps.
    """
    with mpmath.workdps(precision + 10):
        xm = mpmath.mpc(x)
        target = mpmath.mpf(10) ** (-(precision + 5))
        for _ in range(max_iter):
            f, fp = residual_mp(xm)
            if fp == 0:
                break
            step = f / fp
            if abs(step) > abs(xm) / 2:
                step *= (abs(xm) / 2) / abs(step)
            xm -= step
            if abs(step) <= target * abs(xm):
                return xm, max(abs(step), mpmath.mpf(10) ** (-precision) * abs(xm))
    raise ConvergenceError(
        f"the {precision}-digit polish of the root x = {x!r} did not converge in {max_iter} "
        "Newton steps: lower `precision`, or report the parameters (the double-precision root may "
        "sit next to a nearly double root)")


def find_modes(system: ModalSystem, *, count: int | None = None, precision: int | None = None,
               tol: float = 1e-13, max_iter: int = 40, max_seeds: int = 40) -> ModeRoots:
    """The ``count`` least damped natural modes of a :class:`ModalSystem` (see the module docstring).

    Parameters
    ----------
    count : number of modes returned, >= 1 (default, and when it exceeds system.n_modes: all of
        them; the caller compares with ``len(gamma)`` to flag the shortfall).
    precision : None (double precision) or digits (>= 16) of an mpmath polish.
    tol : relative step size at which Newton's method stops in double precision.
    max_iter : Newton steps per seed; max_seeds : seeds drawn at most.

    Raises
    ------
    ParameterError : count or precision out of range.
    ConvergenceError : fewer than system.n_modes distinct modes found from the seeds, or a polish
        that does not converge.
    """
    count = system.n_modes if count is None else require_int_in_range("count", count, 1)
    if precision is not None:
        precision = require_int_in_range("precision", precision, 16, PRECISION_MAX)
    found: list[_Root] = []
    evaluations = tried = 0
    for seed in system.seeds():
        if tried == max_seeds:
            break
        tried += 1
        root, n = _newton(system, complex(seed), tol, max_iter)
        evaluations += n
        if root is None:
            continue
        x = root.x
        imag, err = system.to_gamma(x).imag, _gamma_error(system, x, root.step)
        if imag < -err or (abs(imag) <= err and x.imag < 0):
            x = complex(system.conjugate(x))  # Im gamma >= 0; for a real gamma, Im x >= 0
        if any(abs(x - r.x) <= DUPLICATE_RTOL * abs(x) for r in found):
            continue
        if system.sheet_margin(x) < -root.step:
            continue  # a root on the unphysical sheet (a resonance), not a mode
        found.append(_Root(x, root.step))
        if len(found) == system.n_modes:
            break
    if len(found) < system.n_modes:
        raise ConvergenceError(
            f"found {len(found)} of the {system.n_modes} natural modes of {system.name!r} from "
            f"{tried} seeds ({evaluations} residual evaluations): the seeds failed for these "
            "parameters; report them (a continuation in the parameters from a nearby point where "
            "the solver succeeds is the workaround)")
    found.sort(key=lambda r: -system.to_gamma(r.x).real)
    found = found[:count]
    xs = [r.x for r in found]
    errs = [r.step for r in found]
    digits = double_error = None
    if precision is not None:
        polished = [polish_root(system.residual_mp, x, precision=precision, max_iter=max_iter)
                    for x in xs]
        with mpmath.workdps(precision + 10):
            gammas_mp = [system.to_gamma(xm) for xm, _ in polished]
            digits = tuple((mpmath.nstr(g.real, precision), mpmath.nstr(g.imag, precision))
                           for g in gammas_mp)
            double_error = np.array([float(abs(system.to_gamma(mpmath.mpc(x)) - g))
                                     for x, g in zip(xs, gammas_mp)])
            margins = [system.sheet_margin(xm) for xm, _ in polished]
            err_x = [e for _, e in polished]
            gerr = np.array([_gamma_error(system, xm, e) for (xm, _), e in zip(polished, err_x)])
            principal = np.array([bool(mg > e) for mg, e in zip(margins, err_x)])
            cut = np.array([bool(abs(mg) <= e) for mg, e in zip(margins, err_x)])
            xs = [complex(xm) for xm, _ in polished]
            gamma = np.array([complex(g) for g in gammas_mp])
    else:
        gamma = np.array([complex(system.to_gamma(x)) for x in xs])
        gerr = np.array([_gamma_error(system, x, e) for x, e in zip(xs, errs)])
        margins = [system.sheet_margin(x) for x in xs]
        principal = np.array([bool(mg > e) for mg, e in zip(margins, errs)])
        cut = np.array([bool(abs(mg) <= e) for mg, e in zip(margins, errs)])
    return ModeRoots(x=np.array(xs, dtype=complex), gamma=gamma, error_estimate=gerr,
                     principal_sheet=principal, on_cut=cut, precision=precision,
                     gamma_digits=digits, double_error=double_error, evaluations=evaluations,
                     seeds_tried=tried)
