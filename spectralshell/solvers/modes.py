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

Count-driven search. A system with a ``region`` (a rectangle of the x plane closed under
conjugation) has as many modes as the argument principle counts there
(:func:`~spectralshell.solvers.nonlinear_eigen.count_by_winding` of f on its edge, with the
``near_zeros`` refinement, each sampled turn checked against f'/f from the model's residual:
``residuals``, one batch per refinement level, where given): deflated Newton's method (each root found and its conjugate divided
out) runs from the seeds, then, while a rectangle holds fewer roots than it counts, from a grid
of starts in it and recursively in its four parts, whose counts must add up to it. A root whose
imaginary part is below its error is tested by Newton's method along the real axis (a real root,
or a complex pair). Roots met between the cut and the rectangle (sheet margin >= -error) are
listed too, flagged ``uncounted`` (a warning names them): the others are exactly the counted
ones. The count does not reach across the cut: there the determinant has poles as well as zeros
(the cylinder's, at large m, along the imaginary beta axis), so a winding number across it
counts zeros minus poles. The model's ``noise`` (the residual's own rounding carried to the
root) floors each error estimate.

Error estimates are absolute in gamma: |gamma(x + e_x) - gamma(x)| (maximised over the real and
imaginary directions of the perturbation).
"""

from __future__ import annotations

import cmath
import math
from collections.abc import Iterable
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


def _newton(system: ModalSystem, x: complex, tol: float, max_iter: int, *,
            known: Iterable[complex] = (), real: bool = False) -> tuple[_Root | None, int]:
    """Newton's method in double from x; (root, evaluations) or (None, evaluations).

    The step is capped at |x - system.branch|/2. ``known`` roots r are divided out (the step is
    that of f/prod(x - r)); ``real``: only the real part of each step is taken (along the real
    axis, where f is real for a real problem: tells a real root from a complex pair whose
    imaginary part is below the error)."""
    known = list(known)
    previous = math.inf
    for k in range(1, max_iter + 1):
        try:
            f, fp = system.residual(x)
        except (ZeroDivisionError, OverflowError, ParameterError):
            return None, k
        g = fp - f * sum(1.0 / (x - r) for r in known)
        if g == 0 or not (cmath.isfinite(f) and cmath.isfinite(g)):
            return None, k
        step = f / g
        if real:
            step = complex(step.real, 0.0)
        size, cap = abs(step), 0.5 * abs(x - system.branch)
        if size > cap:
            step *= cap / size
            size = cap
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


def _seeded_roots(system: ModalSystem, tol: float, max_iter: int,
                  max_seeds: int) -> tuple[list[_Root], int, int]:
    """system.n_modes distinct modes (Im gamma >= 0, physical sheet or cut) by Newton's method
    from the seeds; (roots, evaluations, seeds tried).

    Raises
    ------
    ConvergenceError : fewer than system.n_modes found.
    """
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
        found.append(_with_noise(system, _Root(x, root.step)))
        if len(found) == system.n_modes:
            break
    if len(found) < system.n_modes:
        raise ConvergenceError(
            f"found {len(found)} of the {system.n_modes} natural modes of {system.name!r} from "
            f"{tried} seeds ({evaluations} residual evaluations): the seeds failed for these "
            "parameters; report them (a continuation in the parameters from a nearby point where "
            "the solver succeeds is the workaround)")
    return found, evaluations, tried


class _ScalarDeterminant:
    """The 1 x 1 matrix function [f(x)] of a :class:`ModalSystem` with ``region``, in the form
    :func:`~spectralshell.solvers.nonlinear_eigen.count_by_winding` takes (a StructuredMatrix,
    so that the count's turns are guarded by f'/f: batched phases from ``determinant``, f and
    f'/f from ``residuals`` in one batch, or ``residual`` point by point)."""

    def __init__(self, system: ModalSystem) -> None:
        self.system = system

    def __call__(self, x: complex) -> np.ndarray:
        return np.array([[self.system.determinant(np.array([x], dtype=complex))[0]]])

    def phases(self, x: np.ndarray) -> np.ndarray:
        return _unit(self.system.determinant(np.asarray(x, dtype=complex)))

    def log_derivatives(self, x: np.ndarray) -> np.ndarray:
        return self.phases_and_log_derivatives(x)[1]

    def phases_and_log_derivatives(self, x: np.ndarray) -> np.ndarray:
        x = np.asarray(x, dtype=complex)
        if self.system.residuals is not None:
            f, fp = (np.asarray(a, dtype=complex) for a in self.system.residuals(x))
        else:
            pairs = [self.system.residual(complex(z)) for z in x]
            f = np.array([p[0] for p in pairs], dtype=complex)
            fp = np.array([p[1] for p in pairs], dtype=complex)
        return np.stack([_unit(f), fp / np.where(f != 0, f, 1.0)])


def _unit(f: np.ndarray) -> np.ndarray:
    """f/|f| (0 where f = 0)."""
    f = np.asarray(f, dtype=complex)
    size = np.abs(f)
    return np.where(size > 0, f / np.where(size > 0, size, 1.0), 0.0)


def _with_noise(system: ModalSystem, root: _Root) -> _Root:
    """The root with its error estimate raised to the model's noise bound at it."""
    if system.noise is None:
        return root
    return _Root(root.x, max(root.step, float(system.noise(root.x))))


#: Sub-rectangles of the count-driven search: deepest level, and Newton starts per side of the
#: grid tried in each rectangle before it is cut into four (off-centre, so that the real axis, on
#: which real roots lie, is never an edge).
_MAX_DEPTH = 8
_GRID = 3
_CUTS = (0.45, 0.55, 0.4)


def _counted_roots(system: ModalSystem, tol: float, max_iter: int,
                   max_seeds: int) -> tuple[list[_Root], int, int]:
    """Every root in ``system.region``, conjugates included: the argument principle counts them
    (:func:`~spectralshell.solvers.nonlinear_eigen.count_by_winding` of f on the rectangle's
    edge), deflated Newton's method finds them, first from the seeds, then, while a rectangle
    holds fewer roots found than counted, from a grid of starts in it and in its four parts
    (recursively). Returns (roots, roots on the cut, evaluations, seeds tried): the second are
    the roots met on the way between the cut (sheet margin >= -error) and the box's left edge,
    one of each conjugate pair, listed (``uncounted``) but not counted.

    Raises
    ------
    ConvergenceError : a rectangle holds more roots found than counted, or fewer at the deepest
        level.
    """
    from .nonlinear_eigen import count_by_winding  # one winding counter for every solver

    T = _ScalarDeterminant(system)
    lo, hi, top = system.region
    whole = (lo, hi, -top, top)
    roots: list[_Root] = []
    cut: list[_Root] = []  # roots met left of the box, on the cut to within its width
    tally = {"evaluations": 0, "tried": 0}

    def count(box: tuple[float, float, float, float]) -> int:
        a, b, c, d = box
        return count_by_winding(T, [complex(a, c), complex(b, c), complex(b, d), complex(a, d)],
                                dT=T, near_zeros=True)

    def inside(x: complex, box: tuple[float, float, float, float]) -> bool:
        return box[0] < x.real < box[1] and box[2] < x.imag < box[3]

    def attempt(start: complex) -> None:
        root, n = _newton(system, start, tol, max_iter, known=[r.x for r in roots])
        tally["evaluations"] += n
        if root is None:
            return
        if not inside(root.x, whole):
            if -root.step <= system.sheet_margin(root.x) and root.x.real <= lo and \
                    abs(root.x.imag) < top:  # between the cut and the box: on the cut
                x = root.x if root.x.imag >= 0 else complex(system.conjugate(root.x))
                if not any(abs(x - r.x) <= DUPLICATE_RTOL * abs(x) for r in cut):
                    cut.append(_with_noise(system, _Root(x, root.step)))
            return
        root = _with_noise(system, root)
        if abs(root.x.imag) <= root.step:  # real to within its error: a real root
            real, n = _newton(system, complex(root.x.real, 0.0), tol, max_iter,
                              known=[r.x for r in roots], real=True)
            tally["evaluations"] += n
            if real is not None and abs(real.x - root.x) <= 2 * root.step:
                root = _with_noise(system, real)
            else:  # (a pair closer than its error would count one more than is found: refused)
                root = _Root(complex(root.x.real, 0.0), root.step + abs(root.x.imag))
        if any(abs(root.x - r.x) <= max(DUPLICATE_RTOL * abs(root.x), r.step + root.step)
               for r in roots):
            return
        if root.x.imag == 0:  # a real root is its own conjugate
            roots.append(root)
        else:
            roots.extend([root, _Root(complex(system.conjugate(root.x)), root.step)])

    total = count(whole)
    for seed in system.seeds():  # with nothing counted, the seeds may still meet the cut's
        if (total and len(roots) >= total) or tally["tried"] == max_seeds:
            break
        tally["tried"] += 1
        attempt(complex(seed))

    def search(box: tuple[float, float, float, float], n: int, depth: int) -> None:
        def held() -> int:
            return sum(inside(r.x, box) for r in roots)

        if held() < n:
            a, b, c, d = box
            for i in range(_GRID):
                for j in range(_GRID):
                    attempt(complex(a + (b - a) * (i + 0.5) / _GRID,
                                    c + (d - c) * (j + 0.4) / _GRID))
                    if held() >= n:
                        break
                if held() >= n:
                    break
        if held() > n:
            raise ConvergenceError(
                f"{held()} roots of {system.name!r} found in the rectangle Re x in [{box[0]:.6g}, "
                f"{box[1]:.6g}], Im x in [{box[2]:.6g}, {box[3]:.6g}], where the argument "
                f"principle counts {n}: report the parameters")
        if held() == n:
            return
        if depth == _MAX_DEPTH:
            raise ConvergenceError(
                f"found {len(roots)} of the {total} roots of {system.name!r} counted in its "
                f"region: a rectangle Re x in [{box[0]:.6g}, {box[1]:.6g}], Im x in "
                f"[{box[2]:.6g}, {box[3]:.6g}] holds {n - held()} more that Newton's method did "
                "not reach; report the parameters")
        for cut in _CUTS:  # cut into four; another cut where a root sits on an inner edge
            re, im = a + cut * (b - a), c + (1 - cut) * (d - c)
            parts = [(a, re, c, im), (re, b, c, im), (a, re, im, d), (re, b, im, d)]
            try:
                counts = [count(part) for part in parts]
            except ConvergenceError:
                continue
            if sum(counts) != n:
                raise ConvergenceError(
                    f"the argument-principle counts of {system.name!r} disagree: {n} roots in "
                    f"Re x in [{a:.6g}, {b:.6g}], Im x in [{c:.6g}, {d:.6g}], {sum(counts)} in "
                    "its four parts; report the parameters")
            break
        else:
            raise ConvergenceError(f"no cut of the rectangle Re x in [{a:.6g}, {b:.6g}], Im x in "
                                   f"[{c:.6g}, {d:.6g}] avoids the roots of {system.name!r}")
        for part, k in zip(parts, counts):
            if k:
                search(part, k, depth + 1)

    if len(roots) != total:
        search(whole, total, 0)
    return roots, cut, tally["evaluations"], tally["tried"]


def find_modes(system: ModalSystem, *, count: int | None = None, precision: int | None = None,
               tol: float = 1e-13, max_iter: int = 40, max_seeds: int = 40) -> ModeRoots:
    """The ``count`` least damped natural modes of a :class:`ModalSystem` (see the module docstring).

    Parameters
    ----------
    count : number of modes returned, >= 1 (default, and when it exceeds the number of modes:
        all of them; the caller compares with ``len(gamma)`` to flag the shortfall).
    precision : None (double precision) or digits (>= 16) of an mpmath polish.
    tol : relative step size at which Newton's method stops in double precision.
    max_iter : Newton steps per seed; max_seeds : seeds drawn at most.

    Notes
    -----
    With ``system.region`` the number of modes is the argument-principle count of the roots in
    that rectangle (:func:`_counted_roots`), one of each conjugate pair returned; otherwise it is
    ``system.n_modes``, found from the seeds.

    Raises
    ------
    ParameterError : count or precision out of range.
    ConvergenceError : fewer modes found than there are (system.n_modes, or the count), or a
        polish that does not converge.
    """
    if count is not None:
        count = require_int_in_range("count", count, 1)
    if precision is not None:
        precision = require_int_in_range("precision", precision, 16, PRECISION_MAX)
    if system.region is not None:
        every, cut, evaluations, tried = _counted_roots(system, tol, max_iter, max_seeds)
        found = [r for r in every if r.x.imag >= 0] + cut
        outside = {id(r) for r in cut}
    else:
        found, evaluations, tried = _seeded_roots(system, tol, max_iter, max_seeds)
        outside = None
    if count is None:
        count = len(found)
    found.sort(key=lambda r: -system.to_gamma(r.x).real)
    found = found[:count]
    xs = [r.x for r in found]
    errs = [r.step for r in found]
    uncounted = None if outside is None else np.array([id(r) in outside for r in found], bool)
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
                     seeds_tried=tried, uncounted=uncounted)
