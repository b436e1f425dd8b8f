"""Natural modes of a :class:`~spectralshell.models.base.ModeFamily`: its known zeta -> 0 modes
continued in zeta, lost branches recovered by deflation, completeness by a winding number.

Model-agnostic: the solver sees T(s; zeta), the starting modes, a sheet margin, a contour and an
mpmath residual; never the physics (the cochlea supplies its own in
:func:`spectralshell.models.cochlea.mode_family`).

Method (:mod:`spectralshell.solvers.nonlinear_eigen`): the starting modes are continued in zeta
from MODES_START * zeta to zeta with step control (Newton on det T in trace form; the branches
advance together, so a branch is compared with its neighbours at the same zeta; a conjugate pair
that meets on the real axis is followed on as its two real roots). A branch lost on the way (a
near-collision) is searched for at zeta by deflated Newton from its last position. Roots are
reported with Im s >= 0 (T(conj s) = conj T(s): they pair up), least damped first; the sheet
margin classifies them (on the branch cut within their error, or on the physical sheet).

Completeness: the winding number of det T around the family's contour (the upper half of the
physical sheet, half-width 2 max|s| + 1, dipping zeta/4 below the axis where T is analytic) must
equal the number of modes found in it: each mode with Im s > 0, plus, in the dip, the mirror
image of each complex mode there (a real mode counts once); otherwise the result warns.

``precision`` (digits >= 16): every root is polished by Newton's method on det T in mpmath at
precision + 10 digits (:func:`spectralshell.solvers.modes.polish_root`), error = max(last step,
10^-precision |s|), for the parameters as given in double precision.
"""

from __future__ import annotations

import mpmath
import numpy as np

from .._validate import require_int_in_range
from ..errors import ConvergenceError
from ..models.base import ModeFamily
from ..results.records import ContinuedModes
from .modes import PRECISION_MAX, polish_root
from .nonlinear_eigen import (SINGULAR_RTOL, continue_roots, count_by_winding, newton,
                              singular_ratio)

#: Continuation starts at MODES_START * zeta.
MODES_START = 1e-10
METHOD = "continuation in zeta, Newton on det T (trace form)"


def continued_modes(family: ModeFamily, *, count: int | None = None,
                    precision: int | None = None, unit: float = 1.0) -> ContinuedModes:
    """The ``count`` least damped natural modes of ``family`` (all by default), see the module
    notes; gamma in ``unit`` (e.g. 1 / time scale in s) times the family's gamma_scale."""
    if precision is not None:
        precision = require_int_in_range("precision", precision, 16, PRECISION_MAX)
    start = np.asarray(family.start, dtype=complex)
    count = None if count is None else require_int_in_range("count", count, 1, start.size)
    zeta = family.zeta
    warnings: list[str] = []
    if zeta == 0.0:
        roots, steps = start, 4 * np.finfo(float).eps * np.abs(start)
    else:
        roots, steps, warnings = _continued(family, start)
    order = np.argsort(-roots.real)[:count]
    roots = roots[order]
    steps = np.maximum(steps[order], 64 * np.finfo(float).eps * np.abs(roots))
    digits, double_error = None, None
    scale = unit * family.gamma_scale
    if precision is not None:
        roots, steps, digits, double_error = _polish(family, roots, precision, unit)
    margin = np.array([np.inf if zeta == 0.0 else family.sheet_margin(r, zeta) for r in roots])
    margin_err = np.array([0.0 if zeta == 0.0 else margin_error(family, r, e, m)
                           for r, e, m in zip(roots, steps, margin)])
    on_cut = margin <= margin_err
    if on_cut.any():
        warnings.append(f"{int(on_cut.sum())} mode(s) lie on the branch cut to within their error")
    return ContinuedModes(gamma=roots * scale, error=steps * scale, on_cut=on_cut, digits=digits,
                          double_error=double_error, warnings=tuple(warnings))


def margin_error(family: ModeFamily, root: complex, error: float, margin: float) -> float:
    """How far the sheet margin can move while the root moves by its ``error``: the largest
    change of the margin over root + error e^{i theta}, theta = 0, pi/2, pi, 3 pi/2, times
    sqrt 2 (first order: a real-valued function's change over a disk is |grad| error, and the
    largest of four orthogonal directions is at least |grad| error / sqrt 2).

    Model-agnostic; for the cochlea's margin min_k Re beta_k, beta_k = sqrt(s/zeta + k^2), it
    is ~ error / (2 zeta |beta_k|) (d beta/ds = 1/(2 zeta beta)). Scaling by Re beta instead,
    as before, made it huge near the cut (Re beta -> 0 while |beta| stays large) and flagged
    modes there as on the cut although an argument-principle count puts them on the sheet."""
    zeta = family.zeta
    moved = [family.sheet_margin(root + error * d, zeta) for d in (1, 1j, -1, -1j)]
    return float(np.sqrt(2.0) * max(abs(m - margin) for m in moved))


def _continued(family: ModeFamily, start: np.ndarray) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """(roots with Im s >= 0, errors, warnings) at the family's zeta > 0."""
    zeta = family.zeta
    roots, steps, ok = continue_roots(family.at, MODES_START * zeta, zeta, start,
                                      conjugate_symmetric=True)
    T, dT = family.at(zeta)
    warnings = []
    lost = 0
    for i in np.flatnonzero(~ok):  # a lost branch (near-collision): deflated Newton at zeta
        known = np.concatenate([roots[ok], roots[ok].conj()])  # roots pair up: T(conj s) = conj T(s)
        out = newton(T, dT, roots[i], known=known)
        near = np.min(np.abs(known - out[0]), initial=np.inf) if out is not None else 0.0
        if out is None or near <= 1e-5 * abs(out[0]) or singular_ratio(T, out[0]) > SINGULAR_RTOL:
            lost += 1
            continue
        roots[i], steps[i] = out
        ok[i] = True
    if lost:
        warnings.append(f"{lost} of the {roots.size} mode branches could not be followed to "
                        f"zeta = {zeta:g} and no further root was found near their last position")
    roots, steps = roots[ok], steps[ok]
    roots = np.where(roots.imag < 0, roots.conj(), roots)
    keep = [i for i in range(roots.size)
            if not np.any(np.abs(roots[:i] - roots[i]) <= 1e-8 * abs(roots[i]))]
    if len(keep) < roots.size:
        warnings.append(f"{roots.size - len(keep)} branch(es) merged with a conjugate branch")
    roots, steps = roots[keep], steps[keep]
    warnings += _completeness(family, T, dT, roots, steps)
    return roots, steps, warnings


def _completeness(family: ModeFamily, T, dT, roots: np.ndarray, steps: np.ndarray) -> list[str]:
    """Warnings unless the winding number of det T around the family's contour equals the number
    of modes found inside it (see the module notes)."""
    zeta = family.zeta
    radius = 2.0 * float(np.abs(roots).max(initial=0.0)) + 1.0
    depth = min(zeta, radius) / 4.0
    real = np.abs(roots.imag) <= steps
    mirrored = (~real) & (roots.real > -zeta) & (roots.real < 0) & (roots.imag < depth)
    expected = int(roots.size + mirrored.sum())
    try:
        counted = count_by_winding(T, family.contour(zeta, radius, depth), dT=dT)
    except ConvergenceError as exc:
        return [f"completeness not checked: {exc}"]
    if counted == expected:
        return []
    return [f"the winding number of det T counts {counted} modes with Im s >= 0 and |s| < "
            f"{radius:.3g} on the physical sheet where {expected} were found: "
            + ("some were missed" if counted > expected else "some found roots are spurious")]


def _polish(family: ModeFamily, roots: np.ndarray, precision: int, unit: float):
    """(roots, errors, gamma digits, |double - polished| in gamma): every root s of det T
    polished to ``precision`` digits; gamma = unit gamma_scale s, the scale and zeta taken in
    mpmath from the family's (zeta is given to the residual as an mpmath number)."""
    with mpmath.workdps(precision + 10):
        zeta = family.zeta_mp()
        polished = [polish_root(lambda s: family.residual_mp(s, zeta), complex(r),
                                precision=precision) for r in roots]
        factor = mpmath.mpf(unit) * family.gamma_scale_mp()
        digits = tuple((mpmath.nstr(s.real * factor, precision),
                        mpmath.nstr(s.imag * factor, precision)) for s, _ in polished)
        double_error = np.array([float(abs(s - r) * factor) for (s, _), r in zip(polished, roots)])
        return (np.array([complex(s) for s, _ in polished]),
                np.array([float(e) for _, e in polished]), digits, double_error)
