"""Eigenvalues of a nonlinear matrix function: det T(s) = 0 (natural modes of block models).

Model-agnostic: the solver sees callables T(s) -> (b, b) and T'(s) -> (b, b), analytic in a
region, and starting points; never the physics. It serves models whose unforced operator D(s) of
:mod:`spectralshell.models.base` is a matrix with non-polynomial (e.g. square-root) dependence on
s, where neither a linearisation nor a scalar dispersion relation is available.

Method
------
Newton's method on f(s) = det T(s) in the trace form f/f' = 1/tr(T(s)^{-1} T'(s)) (Lancaster),
which needs no determinant (no overflow for large b) and converges quadratically to simple
eigenvalues. Roots already found are deflated implicitly: the step uses
tr(T^{-1} T') - sum_j 1/(s - s_j), the logarithmic derivative of f(s) / prod(s - s_j), so a
seed near a found root is driven to a new one or fails. A converged s is accepted only if T(s) is
singular to working accuracy: its smallest singular value is below ``SINGULAR_RTOL`` times its
largest; the right singular vector is the mode shape. The error estimate is the last Newton step
(floored at 64 eps |s|).

Completeness
------------
:func:`count_by_winding` counts the eigenvalues inside a closed polygon from the winding of the
phase of det T along it (the argument principle); comparing it with the roots found inside says
whether every eigenvalue there was found. It needs T only continuous up to the contour: edges may
run along a branch cut (one-sided limit) and through branch points.

Continuation
------------
:func:`continue_roots` follows eigenvalues along a parameter; the branches advance together
(the one at the smallest parameter moves next), so each step is judged against the neighbours
at the same parameter. For T(conj s) = conj T(s) a conjugate pair that meets on the real axis
is followed on as the two real roots it becomes there.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

import numpy as np

from ..errors import ConvergenceError

SINGULAR_RTOL = 1e-10
DUPLICATE_RTOL = 1e-8
_FLOOR = 64 * np.finfo(float).eps

Matrix = Callable[[complex], np.ndarray]


@runtime_checkable
class StructuredMatrix(Protocol):
    """A matrix function T(s) that evaluates the phase of det T and tr(T^{-1} T') itself, at
    many points s at once and with its own derivative T' (e.g. from a block LU that uses a
    sparsity the dense matrix hides). Calling it gives the dense matrix. Where a solver here is
    given one, it uses these methods instead of dense solves and determinants (and the ``dT``
    passed with it is not called for them)."""

    def __call__(self, s: complex) -> np.ndarray: ...

    def phases(self, s: np.ndarray) -> np.ndarray:
        """det T(s) / |det T(s)| at each point (0 where singular)."""
        ...

    def log_derivatives(self, s: np.ndarray) -> np.ndarray:
        """tr(T(s)^{-1} T'(s)) at each point."""
        ...

    def phases_and_log_derivatives(self, s: np.ndarray) -> np.ndarray:
        """(2, len(s)): both of the above at each point, from one factorisation."""
        ...


@dataclass(frozen=True, kw_only=True, eq=False)
class NonlinearEigenvalues:
    """Eigenvalues s of det T(s) = 0 found from the seeds, in the order found.

    Attributes
    ----------
    values : complex eigenvalues.
    error_estimate : last Newton step of each (>= 64 eps |s|).
    vectors : (b, count) right null vectors of T(s) (unit 2-norm).
    singular_ratio : sigma_min / sigma_max of T at each eigenvalue (<= SINGULAR_RTOL).
    seeds_tried, failed : seeds drawn and seeds that did not give a new eigenvalue.
    """

    values: np.ndarray
    error_estimate: np.ndarray
    vectors: np.ndarray
    singular_ratio: np.ndarray
    seeds_tried: int
    failed: int


def _log_derivative(T: Matrix, dT: Matrix, s: complex) -> complex:
    """tr(T(s)^{-1} T'(s)) = d/ds log det T(s)."""
    if isinstance(T, StructuredMatrix):
        return complex(T.log_derivatives(np.array([s], dtype=complex))[0])
    return complex(np.trace(np.linalg.solve(T(s), dT(s))))


def singular_ratio(T: Matrix, s: complex) -> float:
    """sigma_min / sigma_max of T(s): <= SINGULAR_RTOL at an eigenvalue (to working accuracy)."""
    sv = np.linalg.svd(T(s), compute_uv=False)
    return float(sv[-1] / sv[0])


def newton(T: Matrix, dT: Matrix, s: complex, *, known: Iterable[complex] = (), tol: float = 1e-13,
           max_iter: int = 60) -> tuple[complex, float] | None:
    """Newton's method on det T from s, deflating ``known`` roots; (root, last step) or None.

    The step is capped at |s|/2 + 1 (a trust region against jumps far from the seed).
    """
    known = np.asarray(list(known), dtype=complex)
    previous = np.inf
    for _ in range(max_iter):
        try:
            g = _log_derivative(T, dT, s)
        except np.linalg.LinAlgError:
            return s, _FLOOR * max(abs(s), 1.0)  # exactly singular: s is a root
        if known.size:
            g -= np.sum(1.0 / (s - known))
        if g == 0 or not np.isfinite(g):
            return None
        step = 1.0 / g
        cap = 0.5 * abs(s) + 1.0
        if abs(step) > cap:
            step *= cap / abs(step)
        s = s - step
        size = abs(step)
        if size <= tol * max(abs(s), 1.0) or (size >= previous and size <= 1e-9 * max(abs(s), 1.0)):
            return s, max(size, _FLOOR * abs(s))
        previous = size
    return None


def nonlinear_eigenvalues(T: Matrix, dT: Matrix, seeds: Iterable[complex], *, tol: float = 1e-13,
                          max_iter: int = 60, accept: Callable[[complex], bool] | None = None,
                          max_roots: int | None = None) -> NonlinearEigenvalues:
    """Eigenvalues of T(s) from the seeds, each verified by the smallest singular value.

    Parameters
    ----------
    T, dT : the matrix function and its derivative, (b, b) complex for complex s.
    seeds : starting points, best first.
    accept : optional filter of converged roots (e.g. a physical sheet or half plane).
    max_roots : stop after this many roots.
    """
    found, errors, vectors, ratios = [], [], [], []
    tried = failed = 0
    for seed in seeds:
        if max_roots is not None and len(found) >= max_roots:
            break
        tried += 1
        out = newton(T, dT, complex(seed), known=found, tol=tol, max_iter=max_iter)
        if out is None:
            failed += 1
            continue
        s, err = out
        if any(abs(s - r) <= DUPLICATE_RTOL * max(abs(s), 1.0) for r in found) or \
                (accept is not None and not accept(s)):
            failed += 1
            continue
        _, sv, vh = np.linalg.svd(T(s))
        ratio = sv[-1] / sv[0]
        if ratio > SINGULAR_RTOL:
            failed += 1
            continue
        found.append(s)
        errors.append(err)
        vectors.append(vh[-1].conj())
        ratios.append(ratio)
    b = np.asarray(T(complex(1j))).shape[0] if not vectors else len(vectors[0])
    return NonlinearEigenvalues(values=np.array(found, dtype=complex), error_estimate=np.array(errors),
                                vectors=np.array(vectors, dtype=complex).T.reshape(b, len(found)),
                                singular_ratio=np.array(ratios), seeds_tried=tried, failed=failed)


def det_phases(T: Matrix, s: np.ndarray) -> np.ndarray:
    """det T(s) / |det T(s)| at each point (the sign of slogdet: no overflow for large b); 0
    where singular."""
    if isinstance(T, StructuredMatrix):
        return T.phases(np.asarray(s, dtype=complex))
    return np.array([np.linalg.slogdet(T(x))[0] for x in s], dtype=complex)


def _remembered(T: Matrix, slopes: bool = False) -> Callable[[np.ndarray], np.ndarray]:
    """s -> :func:`det_phases` of T at s (with ``slopes``, of a StructuredMatrix: (2, len(s)), the
    phases and tr(T^{-1} T')), each distinct point (bitwise: +0 and -0 in Im s are two sides of
    a cut) evaluated once however often it is asked for."""
    seen: dict[bytes, np.ndarray] = {}

    def values(s: np.ndarray) -> np.ndarray:
        s = np.asarray(s, dtype=complex)
        keys = [x.tobytes() for x in s]
        new = {k: x for k, x in zip(keys, s) if k not in seen}
        if new:
            points = np.array(list(new.values()), dtype=complex)
            got = T.phases_and_log_derivatives(points) if slopes else det_phases(T, points)[None]
            seen.update(zip(new, got.T))
        out = np.array([seen[k] for k in keys], dtype=complex).T
        return out if slopes else out[0]

    return values


def _turn(dz: complex, p: tuple[complex, complex], f: tuple[complex, complex] | None,
          max_phase: float, max_bend: float) -> float | None:
    """The turn of arg det T over a sub-interval dz with phases ``p`` at its ends, or None
    (refine it). Without the log-derivatives ``f`` at the ends: the sampled turn, if at most
    ``max_phase``. With them: the sampled turn plus the multiple of 2 pi that brings it within
    ``max_phase``/2 of the trapezoid rule Im(dz (f_0 + f_1) / 2), if dz f changes by at most
    ``max_bend`` along it (so that the rule errs by much less than pi): a zero pair between the
    ends, which a sampled phase sees as no turn, makes f vary like 1/distance there; the many
    far zeros of a large determinant turn the phase fast but smoothly, and are accepted. A
    sampled turn of at most ``max_phase`` that the rule confirms is accepted while dz f bends
    by up to 4 ``max_bend``: a hidden pair of zeros within a tenth of the length of the
    sub-interval bends it by ~8 or more, and f that oscillates along a cut without turning the
    phase (the fibre's fluid) would otherwise be refined 4 times as often; f not finite (a
    branch point, or where T' is not accurate) leaves the sampled turn alone to judge."""
    turn = float(np.angle(p[1] / p[0]))
    if f is None or not (np.isfinite(f[0]) and np.isfinite(f[1])):
        return turn if abs(turn) <= max_phase else None
    bend = abs(dz * (f[1] - f[0]))
    predicted = (dz * 0.5 * (f[0] + f[1])).imag
    if abs(turn) <= max_phase and abs(turn - predicted) <= max_phase / 2 and \
            bend <= 4 * max_bend:
        return turn
    if bend > max_bend:
        return None
    turn += 2 * np.pi * round((predicted - turn) / (2 * np.pi))
    return turn if abs(turn - predicted) <= max_phase / 2 else None


def count_by_winding(T: Matrix, vertices: Iterable[complex], *, dT: Matrix | None = None,
                     n_start: int = 16, n_max: int = 1024, max_phase: float = 0.5,
                     max_bend: float = 1.0, min_width: float = 1e-14,
                     pieces: int | None = None, near_zeros: bool = False) -> int:
    """Number of eigenvalues (with multiplicity) inside the closed polygon ``vertices``
    (counter-clockwise) from the winding number of det T along it.

    Notes
    -----
    The change of arg det T (the sign of slogdet: no overflow for large b) is summed over the
    edges, each cut into ``n_start`` equal sub-intervals that are refined until the phase turns by
    at most ``max_phase`` across each (a point met again, e.g. at the next ``n_start``, is not
    evaluated again). A sampled phase cannot tell a turn theta from
    theta + 2 pi n (clustered eigenvalues near the contour alias that way, and so do the many
    far eigenvalues of a large determinant: the cochlea's Hill truncation at M = 32, N = 40
    counted 32 of 64). With ``dT`` the turn is also predicted from tr(T^{-1} T'), which follows
    the full turn: for a plain matrix function each sub-interval must agree to ``max_phase``/2
    with the midpoint rule Im(ds tr(T^{-1} T')); for a :class:`StructuredMatrix` (whose
    ``phases_and_log_derivatives`` gives both from one factorisation) the log-derivative is
    taken at the nodes and the trapezoid rule fixes the multiple of 2 pi (:func:`_turn`; a
    sub-interval may then turn by more than ``max_phase``). The count is repeated with
    ``n_start`` doubled until two successive values agree. An eigenvalue at distance d from the
    contour turns the phase by ~pi over a length ~d, so refinement finds it. A sub-interval is
    refined into ``pieces`` equal parts, all of a level's new points evaluated together (default
    4 for a :class:`StructuredMatrix`, whose batched phases cost little more than one, so that
    fewer levels reach a nearby eigenvalue; 2, a bisection, otherwise).
    ``near_zeros`` (with ``dT``): a sub-interval of length h must also have |h tr(T^{-1} T')| <=
    2 ``max_phase`` (at its midpoint, or at both nodes for a :class:`StructuredMatrix`), the
    modulus rather than the imaginary part, so that any eigenvalue (or pole) within about h/2 of
    it forces a refinement: a turn that aliases by 2 pi needs one that close, which the
    imaginary part alone can miss where the turns of a nearby zero and pole cancel.
    It needs T only continuous up to the contour (and dT only at the midpoints or nodes): an
    edge may run along a branch cut, evaluated as its limit from one side (for
    a principal square root in T, points x + 0j with a positive-zero imaginary part give the limit
    from Im s > 0), and a vertex may sit on a branch point, where tr(T^{-1} T') is infinite (a
    sub-interval that ends there is judged by its sampled turn alone).

    Raises
    ------
    ConvergenceError : det T vanishes on the contour (a sub-interval shrinks below
        ``min_width`` times its edge with the phase still turning), or the counts do not settle
        by ``n_max`` sub-intervals per edge.
    """
    v = [complex(z) for z in vertices]
    structured = isinstance(T, StructuredMatrix)
    slopes = dT is not None and structured
    values_at = _remembered(T, slopes)  # the grid of n sub-intervals holds that of n / 2
    if pieces is None:
        pieces = 4 if structured else 2
    cuts = np.linspace(0.0, 1.0, pieces + 1)
    edges = list(zip(v, v[1:] + v[:1]))
    n, previous = n_start, None

    def nodes(points: np.ndarray, rows: int, cols: int) -> tuple[np.ndarray, np.ndarray | None]:
        """(phases, log-derivatives or None) at ``points``, each shaped (rows, cols)."""
        got = values_at(points)
        if slopes:
            return got[0].reshape(rows, cols), got[1].reshape(rows, cols)
        return got.reshape(rows, cols), None

    while n <= n_max:
        total = 0.0
        t = np.linspace(0.0, 1.0, n + 1)
        phases, logd = nodes(np.concatenate([a + (b - a) * t for a, b in edges]), len(edges), n + 1)
        pending = [(a, b, t[j], t[j + 1], phases[i, j:j + 2],
                    None if logd is None else logd[i, j:j + 2])
                   for i, (a, b) in enumerate(edges) for j in range(n)]
        while pending:  # sub-intervals refined level by level, each level's phases in one batch
            split = []
            for a, b, lo, hi, p, f in pending:
                if p[0] == 0 or p[1] == 0:
                    raise ConvergenceError(f"det T vanishes on the contour near s = {a + (b - a) * lo!r}")
                dz = (b - a) * (hi - lo)
                turn = _turn(dz, p, f, max_phase, max_bend)
                if turn is not None and dT is not None and not slopes:
                    change = dz * _log_derivative(T, dT, a + (b - a) * 0.5 * (lo + hi))
                    turn = turn if abs(turn - change.imag) <= max_phase / 2 and \
                        (not near_zeros or abs(change) <= 2 * max_phase) else None
                if turn is not None and near_zeros and slopes and \
                        not all(abs(dz * g) <= 2 * max_phase for g in f if np.isfinite(g)):
                    turn = None
                if turn is not None:
                    total += turn
                    continue
                if hi - lo < min_width:
                    raise ConvergenceError(f"an eigenvalue lies on the contour near s = {a + (b - a) * lo!r}")
                split.append((a, b, lo, hi, p, f))
            if not split:
                break
            inner = np.array([[lo + (hi - lo) * c for c in cuts[1:-1]] for _, _, lo, hi, _, _ in split])
            new = np.concatenate([a + (b - a) * x for (a, b, *_), x in zip(split, inner)])
            middle, slope = nodes(new, len(split), pieces - 1)
            pending = []
            for i, ((a, b, lo, hi, p, f), x) in enumerate(zip(split, inner)):
                x = np.concatenate([[lo], x, [hi]])
                p = np.concatenate([[p[0]], middle[i], [p[1]]])
                f = None if slope is None else np.concatenate([[f[0]], slope[i], [f[1]]])
                pending += [(a, b, x[j], x[j + 1], p[j:j + 2], None if f is None else f[j:j + 2])
                            for j in range(pieces)]
        value = total / (2 * np.pi)
        if previous is not None and abs(value - previous) < 1e-6 and abs(value - round(value)) < 1e-6:
            return int(round(value))
        previous, n = value, 2 * n
    raise ConvergenceError(f"the winding count did not settle by {n_max} sub-intervals per edge "
                           f"(last value {previous:.6g})")


def _real_partner(T: Matrix, dT: Matrix, before: complex, real: complex, tol: float) -> complex | None:
    """The second real root left where a conjugate pair (``before`` one step earlier) met on the
    real axis and Newton's method returned the real root ``real``: deflated Newton from the mirror
    image of ``real`` about Re ``before``; None unless it converges to a real root other than
    ``real`` within twice the pair's reach |real - before| + |Im before| of Re ``before``."""
    centre = before.real
    reach = abs(real - before) + abs(before.imag)
    out = newton(T, dT, complex(2 * centre - real.real, 0.0), known=[real], tol=tol)
    if out is None or abs(out[0].imag) > out[1] or abs(out[0] - centre) > 2 * reach or \
            abs(out[0] - real) <= DUPLICATE_RTOL * abs(real):
        return None
    return complex(out[0].real, 0.0)


def _nearest_copy(z: np.ndarray, to: complex, period: complex) -> np.ndarray:
    """Each of ``z`` moved by a whole number of ``period`` (0: not moved) to lie nearest ``to``."""
    if period == 0:
        return z
    return z - period * np.round(((z - to) / period).real)


def continue_roots(family: Callable[[float], Any], start: float, stop: float,
                   roots: Iterable[complex], *, first_ratio: float = 1.5, min_ratio: float = 1e-6,
                   max_move: float = 0.25, tol: float = 1e-13,
                   conjugate_symmetric: bool = False, frames: Sequence[complex] | None = None,
                   group: Iterable[int] | None = None, period: complex = 0j
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Follow each eigenvalue of T(s; p) from p = ``start`` (where ``roots`` are its eigenvalues)
    to p = ``stop`` > start > 0, in geometric steps with step control.

    The branches advance in turn, always the one at the smallest p, each with its own step
    p -> p r. A step is accepted when Newton's method (at most 12 iterations, from the linear
    extrapolation in log p of the last two points) converges and the root moves by at most
    ``max_move`` times its distance to the nearest other branch *at the same p*; otherwise
    r -> sqrt(r). The other branches' positions at p are interpolated linearly in log p on their
    last step, which brackets p because the branch at the smallest p moves next. (Comparing with
    the other branches at their start or end values instead lets a branch jump onto a neighbour's
    root where two branches pass close.) A branch whose ratio falls below 1 + ``min_ratio`` is
    abandoned (a fold, a collision or a branch cut).

    ``conjugate_symmetric``: T(conj s) = conj T(s), so the mirror images of the other branches are
    branches too (they enter the guard), and a root that Newton's method returns across the real
    axis is replaced by its mirror image when that is nearer the previous value (it is the same
    mode). A complex branch whose step lands on the real axis (|Im s| within the Newton error)
    marks a conjugate pair that has met there and split into two real roots: the second one is
    found by deflated Newton from the mirror image of the first about the pair's last real part
    and followed on as a new branch.

    ``frames``: several matrix functions T_j(s; p) whose eigenvalues are those of one problem
    in shifted variables, z = s + frames[j] (modulo ``period`` if not 0), each branch followed
    in its own (``group``: the index j of each root; ``family(p)`` then gives one (T, dT) per
    frame). The guard then compares the branches in z, so that a branch of one frame cannot
    jump onto the eigenvalue another frame follows (two frames each find it; the eigenvalue
    that branch followed is lost). (The Floquet exponents' two windows: a pair of exponents near
    the line between them, Im z = 1/4, came out twice and another pair not at all.)

    Every branch is then polished by a full Newton solve at ``stop``. Returns (roots at ``stop``,
    last Newton steps, ok), one entry per branch (the given ones first, then any split off), the
    roots in z = s + frames[j] if ``frames`` are given: ``ok`` is False for an abandoned branch
    (its root is then the last accepted value, at a smaller p) or for two branches that meet (or
    mirror each other).
    """
    s = np.array(list(roots), dtype=complex)
    n = s.size
    shift = np.zeros(1, dtype=complex) if frames is None else np.asarray(frames, dtype=complex)
    grp = np.zeros(n, dtype=int) if group is None else np.array(list(group), dtype=int)

    def at(p: float, j: int) -> tuple[Matrix, Matrix]:
        return family(p) if frames is None else family(p)[j]

    previous = s.copy()                        # position at the start of each branch's last step
    lp = np.full(n, np.log(start))             # log p of each branch
    lp_previous = lp.copy()
    ratio = np.full(n, float(first_ratio))
    slope = np.zeros(n, dtype=complex)         # ds / d log p on the last step
    steps = np.full(n, _FLOOR)
    ok = np.ones(n, dtype=bool)
    log_stop = np.log(stop)
    while True:
        moving = np.flatnonzero(ok & (lp < log_stop))
        if not moving.size:
            break
        i = int(moving[np.argmin(lp[moving])])
        others = np.flatnonzero(ok & (np.arange(n) != i))
        span = lp[others] - lp_previous[others]
        weight = np.divide(lp[i] - lp_previous[others], span, out=np.ones(others.size), where=span > 0)
        at_p = previous[others] + (s[others] - previous[others]) * weight
        if conjugate_symmetric:
            at_p, moved = np.concatenate([at_p, at_p.conj()]), np.tile(shift[grp[others]], 2)
        else:
            moved = shift[grp[others]]
        at_p = _nearest_copy(at_p + moved - shift[grp[i]], s[i], period)  # in branch i's frame
        guard = np.min(np.abs(at_p - s[i])) if at_p.size else abs(s[i]) + 1.0
        lq = min(lp[i] + np.log(ratio[i]), log_stop)
        T, dT = at(stop if lq == log_stop else float(np.exp(lq)), grp[i])
        out = newton(T, dT, s[i] + slope[i] * (lq - lp[i]), tol=tol, max_iter=12)
        if out is not None and conjugate_symmetric and abs(out[0].conjugate() - s[i]) < abs(out[0] - s[i]):
            out = (out[0].conjugate(), out[1])
        if out is not None and abs(out[0] - s[i]) <= max_move * guard:
            if conjugate_symmetric and abs(s[i].imag) > steps[i] and abs(out[0].imag) <= out[1]:
                partner = _real_partner(T, dT, s[i], out[0], tol)  # a pair met on the real axis
                if partner is not None:
                    s, previous, steps, slope = (np.append(a, v) for a, v in
                                                 ((s, partner), (previous, partner),
                                                  (steps, _FLOOR * abs(partner)), (slope, 0j)))
                    lp, lp_previous, ratio, ok = (np.append(a, v) for a, v in
                                                  ((lp, lq), (lp_previous, lq), (ratio, first_ratio),
                                                   (ok, True)))
                    grp = np.append(grp, grp[i])
                    n += 1
            slope[i] = (out[0] - s[i]) / (lq - lp[i])
            previous[i], lp_previous[i] = s[i], lp[i]
            s[i], steps[i], lp[i] = out[0], out[1], lq
            ratio[i] = min(ratio[i] ** 1.5, 10.0)
            continue
        ratio[i] = np.sqrt(ratio[i])
        if ratio[i] < 1.0 + min_ratio:
            ok[i] = False
    for j in np.unique(grp):
        T, dT = at(stop, j)
        for i in np.flatnonzero(ok & (grp == j)):  # polish at ``stop``: merged branches coincide
            out = newton(T, dT, s[i], tol=tol)
            if out is None:
                ok[i] = False
            else:
                s[i], steps[i] = out
    z = s + shift[grp]
    for i in range(n):
        for j in range(i):
            twins = np.array([s[j], s[j].conjugate()] if conjugate_symmetric else [s[j]])
            twins = _nearest_copy(twins + shift[grp[j]], z[i], period)
            close = np.min(np.abs(z[i] - twins)) <= DUPLICATE_RTOL * max(abs(s[i]), 1.0)
            if ok[i] and ok[j] and close:
                ok[i] = ok[j] = False
    return (s if frames is None else z), steps, ok
