"""Floquet exponents gamma at a forcing amplitude tau for models whose D(s) is not a matrix
polynomial (a viscous fluid: the sphere, the fibre, the viscous cochlea).

Problem
-------
gamma is a Floquet exponent at amplitude tau when (2) of :mod:`spectralshell.models.base`,
D(gamma + i n) u_n = i tau G (u_{n-1} - u_{n+1}), has a non-zero solution: the infinite block
tridiagonal Hill operator is singular (thesis (2.4)-(2.6) with gamma free). Truncated at N it is
the two-sided pencil of :func:`spectralshell.discretise.hill.assemble` at a ``shift`` g,
T_N(g) = A(g) - tau B, with gamma = g + i GAMMA[kind]: a nonlinear eigenproblem in g (D depends
on s through Bessel ratios of sqrt(s / nu)), solved by the Newton/continuation/winding machinery
of :mod:`spectralshell.solvers.nonlinear_eigen`. D(s) is taken analytic off the cut
s in (-inf, b], b = ``HillSystem.branch_point`` (principal square roots: b = 0 for the sphere,
fibre and cochlea, b = -nu k^2 for the cylinder's sqrt(s/nu + k^2)). The
companion-form route of :mod:`spectralshell.solvers.exponents` needs a polynomial D and does
not apply.

Method
------
1. Seeds: at tau = 0, T_N(g) is block diagonal and singular exactly at g = s_j - i GAMMA - i n,
   s_j the natural modes (det D(s_j) = 0), which the caller supplies (one per conjugate pair).
2. Each pair is followed from tau = 0 to tau (:func:`~spectralshell.solvers.nonlinear_eigen.
   continue_roots`) in the window ``kind`` whose locking line (Im gamma = 0 harmonic, 1/2
   subharmonic) lies nearer its folded frequency. In that window the index set is symmetric, so
   det T_N(conj g) = conj det T_N(g) exactly: a pair that meets the line there has locked to the
   forcing and splits into two exponents on the line (one of which crosses Re gamma = 0 at
   tau_min of that kind). The two windows' branches are continued together, each in its own
   window but guarded against the other's (compared modulo i): continued apart, a branch of one
   could jump onto an exponent the other follows near the line between them, Im gamma = 1/4
   (the cochlea at M = 32: three exponents found twice, others lost). A branch lost anyway is
   sought by deflated Newton's method from its last value, deflating both windows' exponents.
3. Completeness: the argument principle (:func:`~spectralshell.solvers.nonlinear_eigen.
   count_by_winding`) counts the zeros of det T_N (harmonic window, g = gamma) in the region
   R = {re_lo <= Re gamma <= re_hi, -1/4 <= Im gamma <= 3/4}, a period of the exponents, minus
   the band |Im gamma| < w, Re gamma < b + w along the cut of D(s_0) (the fluid's continuous
   spectrum, with the interior fluid's poles on it; exponents there are not counted and not
   listed, except within w of the branch point gamma = b, which are listed: for b = 0 at the
   harmonic tau_min an exponent passes through it). The half-width w is SLIT, or half the smallest
   |Im gamma| of an exponent found nearer the cut (just below a harmonic tau_min a pair
   approaches the cut from both sides): a conjugate pair inside the band would pass the
   contour on one side within a sampling step and alias its phase by 2 pi. For the same reason the
   contour has a vertex next to each exponent and natural mode close to an edge (at tau = 0 the
   fibre's strongly damped modes lie 1e-9 off the cut, 0.04 apart). When the count exceeds the
   exponents found in R, deflated Newton searches from the sign changes of the real det T
   along each window's locking line (locked pairs; :func:`_on_lines`), then from a grid of
   seeds over R (and next to the branch point, where a harmonic exponent is born at the cut);
   a count still larger raises. The result states R (``complete_in``): every exponent of the
   truncation in it is listed.
4. Convergence: N is raised (N -> N + max(6, N // 2)) from the resonant index + 8 until the
   exponents change by less than ``tol`` (mod i); the change is the error estimate, floored at
   the Newton steps. Step 2 runs at the first truncation only: at the next, each exponent is
   polished by Newton's method from its value at the previous one; step 3 runs where the
   exponents have settled (an exponent it adds means one more truncation; a count unmatched at
   two settled truncations raises).

Cost
----
T_N(g) is block tridiagonal (K = 2N + 1 or 2N + 2 blocks of size b; the couplings do not depend
on g). The phase of det T_N (for the count) and tr(T_N^{-1} T_N') (the Newton step) come from
its block LU (:mod:`spectralshell.solvers.block_tridiagonal`) in O(K b^3) rather than dense
O((K b)^3), with D evaluated at all the points of a step (the count's points of one refinement
level) in one vectorised call. ``dense=True`` runs the dense linear algebra instead: the
reference that ``validation/bench_exponents.py`` times and compares. Measured at tau = 0.3 (one
thread): sphere (m = 3, kappa = 0.02, nu = 0.006) 0.27 s against 0.39 s dense, cochlea (M = 8)
0.94 s against 5.6 s dense, the exponents equal to 3e-16; the first, all-dense version of this
module took 1.2 s and 60 s.

The count is guarded by tr(T^{-1} T') at its nodes (:func:`~spectralshell.solvers.
nonlinear_eigen.count_by_winding`; from the same block LU as the phase, so a node costs about
twice a phase alone, five D evaluations instead of one), which lets it start from COUNT_START
sub-intervals per edge. Sampled alone, the phase of the cochlea's det T at M = 32, N = 40
turned by 2 pi between samples at 16 and at 32 per edge and counted 32 of the 64 exponents
(32 s CPU); guarded it counts 64 in 19 s CPU (64 s from 16 per edge; 138 s with the older
midpoint-rule guard, one unbatched tr(T^{-1} T') per sub-interval). Measured 2026-12-04 on a
loaded 2-core machine (``validation/bench_exponents.py --large``). The whole computation at
M = 32, N = 40 (``n_temporal=40``) now lists the 64 exponents the count proves, in 88 s CPU
(153 s wall, loaded; error estimate 3.4e-10): ~2/3 the continuation at N = 30, then the count
(19 s) and the search, whose line scan (:func:`_on_lines`) found the locked exponents the
continuation missed. Before, it refused after ~100 s ('counts 32 ... but 59 were found');
an earlier version was reported at 1,393 s (loaded), ~600 s in the grid search. At M = 16,
N = 40 the 32 exponents equal the previous version's to 1e-15, in 13.9 s CPU against its
12.2 s (one run each, loaded): no speed-up there. The count mismatch once reported at M = 32,
N = 100 was not run; at N = 60 the count and the list agree (64; 222 s CPU, 290 s wall,
loaded; error estimate 1.7e-9), within 8.4e-10 of the N = 40 list.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..discretise.fourier import GAMMA, KINDS, frequencies, two_sided_indices
from ..discretise.hill import HillMatrices, assemble
from ..errors import ConvergenceError, ParameterError
from ..models.base import HillSystem
from ..results.records import Exponents
from .exponents import N_MAX, distance, first_truncation, fold
from .block_tridiagonal import log_det_phase_and_derivative
from .marginal import coarser, finer
from .nonlinear_eigen import Matrix, continue_roots, count_by_winding, det_phases, newton

#: Im gamma of the counting region: one period of the exponents, both locking lines inside.
STRIP = (-0.25, 0.75)
#: Half-width of the band around the cut that R leaves out: D(s_0) has poles on the cut (the
#: interior fluid's, s = -nu j^2), which a contour along the cut itself would run through.
SLIT = 1e-6
#: An exponent with Re gamma < 0 and |Im gamma| below this lies on the cut (to rounding).
ON_CUT = 1e-12
#: The continuation starts at this fraction of tau, from the natural modes polished there.
START_FRACTION = 1e-3
#: Relative step of the 4-point derivative D'(s) ~ [D(s+h) - D(s-h) - i D(s+ih) + i D(s-ih)] / 4h.
DERIVATIVE_STEP = 1e-3
#: A harmonic exponent is born at the branch point gamma = b (a real one crossing from the
#: cut); Newton's method is always tried from b + BRANCH_SEED.
BRANCH_SEED = 1e-3
#: Where a continued branch is lost (a pair meeting its locking line is a double root there),
#: Newton's method restarts at tau from the branch, its mirror image and the points this far
#: beyond |Im g| on either side along the line; the count then checks nothing was missed.
LOST_REACH = 1e-3
#: Samples of det T along each window's locking line in the search for exponents there.
LINE_SAMPLES = 256
#: Seeds per unit length of the region's edges in the search for exponents the count says are
#: missing.
SEARCH_DENSITY = 8
#: An exponent nearer an edge of the counting contour than this fraction of its length adds a
#: vertex there (:func:`_through`); the count samples each edge at 16 or more points.
NEAR_EDGE = 1 / 16
#: Two Newton results closer than this many times their largest last step are one exponent.
DUPLICATE = 16
#: Sub-intervals per edge that the winding count starts from when it is guarded by
#: tr(T^{-1} T') at its nodes (the count's refinement and 2 pi guard do the rest): 16, as for an
#: unguarded count, took 64 s against 19 s for the same count (the cochlea at M = 32, N = 40).
COUNT_START = 4
#: Memory for the blocks of one batch of shifts in HillPencil.phases / log_derivatives: the
#: winding count evaluates whole refinement levels at once, and unbatched the cochlea at
#: M = 32, N = 40 held 4.9 GB (the stress test's larger draws were killed by the kernel).
BATCH_BYTES = 1 << 28


@dataclass(frozen=True, eq=False)
class HillPencil:
    """T(g) = A(g) - tau B of the two-sided truncation N at shift g (window ``kind``) as a
    structured matrix function (:class:`~spectralshell.solvers.nonlinear_eigen.StructuredMatrix`):
    the phase of det T and tr(T^{-1} T') at many g at once from the block LU of
    :mod:`spectralshell.solvers.block_tridiagonal` (O(N b^3)); calling it gives the dense
    matrix, :meth:`derivative` the dense T'(g)."""

    system: HillSystem
    hill: HillMatrices  # the two-sided truncation at shift 0 (its couplings and frequencies)
    tau: float

    @cached_property
    def _couplings(self) -> tuple[np.ndarray, np.ndarray]:
        """(L, U): the constant off-diagonal blocks -tau lower, -tau upper of T."""
        return -self.tau * self.hill.lower, -self.tau * self.hill.upper

    @cached_property
    def _frequencies(self) -> np.ndarray:
        return frequencies(self.hill.kind, two_sided_indices(self.hill.kind, self.hill.n_temporal))

    def __call__(self, g: complex) -> np.ndarray:
        return assemble(self.system, self.hill.kind, self.hill.n_temporal, "two-sided",
                        shift=g).dense(self.tau)

    def _blocks(self, g: np.ndarray, derivative: bool) -> tuple[np.ndarray, np.ndarray | None]:
        """D(s_k + g_j) and (if ``derivative``) D'(s_k + g_j), each (P, K, b, b), from one call
        of D: D' by the 4-point formula [D(s+h) - D(s-h) - i D(s+ih) + i D(s-ih)] / 4h (error
        ~h^4); next to the cut, where s +- ih would straddle it, the central difference along it."""
        s = (np.asarray(g, dtype=complex)[:, None] + self._frequencies[None, :]).ravel()
        b = self.system.block_size
        shape = (len(g), len(self._frequencies), b, b)
        if not derivative:
            return self.system.unforced(s).reshape(shape), None
        h = DERIVATIVE_STEP * np.maximum(1.0, np.abs(s))
        along = _along_cut(s)
        hi = np.where(along, 0.0, h)
        values = self.system.unforced(np.concatenate([s, s + h, s - h, s + 1j * hi, s - 1j * hi]))
        values = values.reshape(5, len(s), b, b)
        h = h[:, None, None]
        d = np.where(along[:, None, None], (values[1] - values[2]) / (2 * h),
                     (values[1] - values[2] - 1j * (values[3] - values[4])) / (4 * h))
        return values[0].reshape(shape), d.reshape(shape)

    def derivative(self, g: complex) -> np.ndarray:
        """T'(g) as a dense block diagonal matrix, blockdiag D'(s_k + g)."""
        d = self._blocks(np.array([g]), True)[1][0]
        k, b = len(d), self.system.block_size
        out = np.zeros((k, b, k, b), dtype=complex)
        out[np.arange(k), :, np.arange(k), :] = d
        return out.reshape(k * b, k * b)

    def _batches(self, g: np.ndarray, copies: int) -> list[np.ndarray]:
        """``g`` cut into runs whose ``copies`` stacks of blocks D(s_k + g_j) (complex, K b^2
        each) take at most BATCH_BYTES together."""
        g = np.asarray(g, dtype=complex)
        per_shift = copies * len(self._frequencies) * self.system.block_size**2 * 16
        step = max(1, BATCH_BYTES // per_shift)
        return [g[i:i + step] for i in range(0, len(g), step)] or [g]

    def phases(self, g: np.ndarray) -> np.ndarray:
        """det T(g) / |det T(g)| at each g."""
        return np.concatenate([
            log_det_phase_and_derivative(self._blocks(part, False)[0], *self._couplings)[0]
            for part in self._batches(g, 3)])

    def log_derivatives(self, g: np.ndarray) -> np.ndarray:
        """tr(T(g)^{-1} T'(g)) = d/dg log det T(g) at each g."""
        return self._both(g)[1]

    def phases_and_log_derivatives(self, g: np.ndarray) -> np.ndarray:
        """(2, len(g)): det T(g) / |det T(g)| and tr(T(g)^{-1} T'(g)) at each g, from one block
        LU, for the winding count's guard: the log-derivative is nan next to the cut, where D'
        is the central difference along it (:meth:`_blocks`), whose step does not resolve the
        poles of D on the cut that the contour passes within SLIT (the count judges the phase
        alone there, and the log-derivative is not computed)."""
        g = np.asarray(g, dtype=complex)
        near = np.any(_along_cut(g[:, None] + self._frequencies[None, :]), axis=1)
        out = np.full((2, len(g)), np.nan, dtype=complex)
        if np.any(near):
            out[0, near] = self.phases(g[near])
        if not np.all(near):
            out[:, ~near] = self._both(g[~near])
        return out

    def _both(self, g: np.ndarray) -> np.ndarray:
        out = []
        for part in self._batches(g, 10):  # D at five points, D', the block LU's work
            diag, d = self._blocks(part, True)
            sign, found = log_det_phase_and_derivative(diag, *self._couplings, d)
            assert found is not None
            out.append(np.stack([sign, found]))
        return np.concatenate(out, axis=1)


def _along_cut(s: np.ndarray) -> np.ndarray:
    """s is so near the cut Re s < 0 that D(s +- i h) of the 4-point D' would straddle it."""
    return (s.real < 0) & (np.abs(s.imag) <= 2 * DERIVATIVE_STEP * np.maximum(1.0, np.abs(s)))


def pencil_family(system: HillSystem, kind: str, n_temporal: int, dense: bool = False
                  ) -> Callable[[float], tuple[Matrix, Matrix]]:
    """tau -> (T, dT): the :class:`HillPencil` T(g) at tau and its derivative in g; with
    ``dense`` as plain matrix functions (dense LAPACK solves and determinants of the whole
    truncation, O((N b)^3): the reference for the block LU)."""

    hill = assemble(system, kind, n_temporal, "two-sided")

    def at(tau: float) -> tuple[Matrix, Matrix]:
        pencil = HillPencil(system, hill, tau)
        return (pencil.__call__ if dense else pencil), pencil.derivative

    return at


def window(gamma: complex) -> tuple[str, complex]:
    """(kind, g): the window whose locking line lies nearer gamma's folded frequency, and the
    shift g = gamma - i GAMMA[kind] - i n with Im g in [-1/4, 1/4]."""
    offset = gamma.imag - math.floor(gamma.imag)  # in [0, 1)
    kind = "subharmonic" if 0.25 <= offset < 0.75 else "harmonic"
    g = gamma - 1j * GAMMA[kind]
    return kind, complex(g.real, g.imag - round(g.imag))


def _followed(system: HillSystem, tau: float, seeds: Sequence[complex], n_temporal: int,
              tol: float, dense: bool) -> tuple[np.ndarray, float]:
    """Every exponent continued from the natural modes ``seeds`` (one per conjugate pair) to
    ``tau`` at truncation N, both windows together (so that a branch of one cannot jump onto an
    exponent the other follows): (folded exponents, largest Newton step)."""
    windows = [window(g) for g in seeds]
    kinds = [kind for kind in KINDS if any(k == kind for k, _ in windows)]
    families = [pencil_family(system, kind, n_temporal, dense) for kind in kinds]
    group = [kinds.index(k) for k, _ in windows]
    start = [g if g.imag >= 0 else g.conjugate() for _, g in windows]
    tau0 = START_FRACTION * abs(tau)
    polished = []
    for j, family in enumerate(families):
        T, dT = family(math.copysign(tau0, tau))
        polished += [(i, newton(T, dT, start[i], tol=tol)) for i in range(len(start))
                     if group[i] == j]
    if any(p is None for _, p in polished):
        raise ConvergenceError("a natural mode is not a root of the truncated Hill "
                               f"determinant at n_temporal={n_temporal}: raise n_temporal=")
    order = [i for i, _ in polished]
    frames = [1j * GAMMA[kind] for kind in kinds]
    if tau == 0.0:  # the error is the Newton step: a mode on the cut is then one exponent
        roots = np.array([p[0] + frames[group[i]] for i, p in polished])
        err = np.array([p[1] for _, p in polished])
        ok = np.ones(len(roots), bool)
    else:
        roots, err, ok = continue_roots(
            lambda t: [family(math.copysign(t, tau)) for family in families], tau0, abs(tau),
            [p[0] for _, p in polished], tol=tol, conjugate_symmetric=True, frames=frames,
            group=[group[i] for i in order], period=1j)
    found: dict[str, list[complex]] = {kind: [] for kind in kinds}
    steps = [0.0]
    for gamma, e in zip(roots[ok], err[ok]):
        kind, g = window(complex(gamma))
        found.setdefault(kind, [])
        found[kind] += [g] if abs(g.imag) <= e else [g, g.conjugate()]
        steps.append(float(e))
    for gamma in roots[~ok]:  # lost where a pair met the line (a double root) or two merged
        kind, g = window(complex(gamma))
        T, dT = pencil_family(system, kind, n_temporal, dense)(tau)
        reach = abs(g.imag) + LOST_REACH
        other = [z + 1j * (GAMMA[k] - GAMMA[kind]) for k, zs in found.items() if k != kind
                 for z in zs]  # the other window's, deflated too (in this window's variable)
        _newton_from(T, dT, (g, g.conjugate(), complex(g.real + reach),
                             complex(g.real - reach)), found.setdefault(kind, []), steps, tol,
                     other)
    out = [g + 1j * GAMMA[kind] for kind, gs in found.items() for g in gs]
    return fold(np.array(out, dtype=complex)), max(steps)


def _polished(system: HillSystem, tau: float, gamma: np.ndarray, n_temporal: int, tol: float,
              dense: bool) -> tuple[np.ndarray, float]:
    """The exponents ``gamma`` of a neighbouring truncation refined at truncation N by Newton's
    method, each in its window: (folded exponents, largest Newton step). One that does not
    converge to a new root is left out (the count then finds it missing)."""
    out, steps = [], [0.0]
    for kind in KINDS:
        T, dT = pencil_family(system, kind, n_temporal, dense)(tau)
        found: list[complex] = []
        _newton_from(T, dT, [g for k, g in map(window, gamma) if k == kind], found, steps, tol)
        out += [g + 1j * GAMMA[kind] for g in found]
    return fold(np.array(out, dtype=complex)), max(steps)


def _newton_from(T: Matrix, dT: Matrix, seeds: Sequence[complex], found: list[complex],
                 steps: list[float], tol: float, other: Sequence[complex] = ()) -> None:
    """Deflated Newton's method from each seed; a new root (one not in ``found`` nor, modulo
    i, in ``other``: exponents found in another window, deflated too) is appended to ``found``
    and its last step to ``steps``."""
    for seed in seeds:
        known = [*found, *(_nearest(z, seed) for z in other)]
        got = newton(T, dT, seed, known=known, tol=tol)
        if got is not None and _new(got[0], known, max(got[1], *steps)):
            found.append(got[0])
            steps.append(got[1])


def _nearest(z: complex, to: complex) -> complex:
    """The copy z + i k (k integer) nearest ``to``."""
    return complex(z.real, z.imag - round(z.imag - to.imag))


def _new(gamma: complex, found: Sequence[complex], error: float) -> bool:
    """gamma differs (mod i) from every exponent in ``found`` by more than DUPLICATE times
    ``error``, the largest last Newton step of gamma and of ``found``. The scale is the Newton
    error, not a fraction of |gamma|: the two members of a conjugate pair next to the cut can be
    6e-10 apart (the fibre at m = 8, kappa = 0.01, nu = 0.1, tau = 0) and are two exponents."""
    return not found or distance(np.array([gamma]), np.array(found)) > DUPLICATE * error


def region(gamma: np.ndarray) -> tuple[float, float]:
    """(re_lo, re_hi) of the counting region around the exponents ``gamma`` and 0: a margin of
    1/2 + |Re| / 2 to the left, 1 to the right (the slit must end inside)."""
    lo, hi = float(np.min(gamma.real, initial=0.0)), float(np.max(gamma.real, initial=0.0))
    return lo - 0.5 - 0.5 * abs(lo), max(hi + 1.0, 1.0)


def slit_width(gamma: Sequence[complex], branch: float = 0.0) -> float:
    """Half-width w of the band around the cut (-inf, ``branch``] that R leaves out (module
    notes, step 3)."""
    near = [abs(g.imag) for g in gamma if g.real < branch and ON_CUT < abs(g.imag) < SLIT]
    return min([SLIT] + [0.5 * y for y in near])


def _contour(re_lo: float, re_hi: float, slit: float, branch: float,
             marks: Sequence[float] = (), near: Sequence[complex] = ()) -> list[complex]:
    """The counter-clockwise boundary of R slit along [re_lo, b + w] with half-width w = ``slit``
    (module notes, step 3): the slit ends w to the right of the branch point b = ``branch``, so
    that the contour misses an exponent at gamma = b (at b = 0: the harmonic tau_min). The slit
    has a vertex above and below each of ``marks`` in (re_lo, b) (the poles of D on its cut,
    ``HillSystem.cut_poles``), and each exponent of ``near`` close to an edge adds a vertex there
    (:func:`_through`)."""
    bottom, top = STRIP
    path = [complex(re_hi, bottom), complex(re_hi, top), complex(re_lo, top)]
    if re_lo < branch:
        end = branch + slit
        inside = sorted(x for x in marks if re_lo < x < branch)
        path += [complex(re_lo, slit), *(complex(x, slit) for x in inside), complex(end, slit),
                 complex(end, -slit), *(complex(x, -slit) for x in reversed(inside)),
                 complex(re_lo, -slit)]
    return _through(path + [complex(re_lo, bottom)], near)


def _through(path: Sequence[complex], near: Sequence[complex]) -> list[complex]:
    """The closed polygon ``path`` with a vertex added at the foot of the perpendicular from
    each point of ``near`` (and its copies +- i, a period away) that lies within NEAR_EDGE of an
    edge's length from that edge.

    An exponent at distance d from an edge turns the phase of det T by ~pi over a length ~d
    there. A sampling of the edge cannot see that turn when two such exponents (each turning the
    phase by pi the same way) fall into one sampling interval: their 2 pi aliases to 0. The
    exponents next to the cut lie ~1e-9 from the slit's edges, two of them 0.04 apart (the fibre
    at m = 8, kappa = nu = 1, tau = 0: counted 2 exponents of 4). With a vertex at its foot,
    each turn is split between two intervals that end there and is refined to its scale."""
    points = np.concatenate([np.asarray(near, dtype=complex) + k for k in (-1j, 0, 1j)])
    out: list[complex] = []
    for a, b in zip(path, [*path[1:], path[0]]):
        t = ((points - a) / (b - a)).real
        foot = a + (b - a) * t
        close = (t > 0) & (t < 1) & (np.abs(points - foot) < NEAR_EDGE * abs(b - a))
        out += [a, *(a + (b - a) * np.unique(t[close]))]
    return out


def _in_strip(gamma: np.ndarray) -> np.ndarray:
    """The copy (mod i) of each exponent with Im gamma in R's period [-1/4, 3/4)."""
    im = gamma.imag - np.floor(gamma.imag - STRIP[0])  # the copy in [-1/4, 3/4)
    return gamma.real + 1j * im


def _in_slit(gamma: complex, slit: float, branch: float) -> bool:
    """gamma lies in the band of half-width ``slit`` that R leaves out (it is not counted)."""
    return gamma.real < branch + slit and abs(gamma.imag) < slit


def _on_cut(gamma: complex, slit: float, branch: float) -> bool:
    """gamma lies in the band, not within ``slit`` of the branch point (it is not listed)."""
    return _in_slit(gamma, slit, branch) and gamma.real < branch - slit


def _counted(found: Sequence[complex], slit: float, branch: float) -> int:
    """How many of ``found`` the winding count sees (those outside the band)."""
    return sum(not _in_slit(g, slit, branch) for g in found)


def _slit_count(T, re_lo: float, re_hi: float, slit: float, branch: float,
                marks: Sequence[float] = (), near: Sequence[complex] = (),
                dT: Matrix | None = None) -> tuple[float, int]:
    """(slit half-width, winding count of R) with the slit of :func:`slit_width`, or, where an
    exponent lies on that contour to rounding (an exponent a few 1e-11 off the cut makes the
    slit as narrow: the fibre at m = 12, kappa = nu = 1, tau = -1.138), with the default SLIT,
    which leaves such exponents in the band (on the cut to working precision). The exponents
    ``near`` add vertices to the contour (:func:`_through`); ``dT`` (T') guards the count
    against a phase turn of 2 pi between samples (:func:`~spectralshell.solvers.
    nonlinear_eigen.count_by_winding`).

    Raises
    ------
    ConvergenceError : both contours meet an exponent; the message says what to change.
    """
    for width in dict.fromkeys((slit, SLIT)):
        try:
            return width, count_by_winding(T, _contour(re_lo, re_hi, width, branch, marks,
                                                       near), dT=dT,
                                           n_start=16 if dT is None else COUNT_START)
        except ConvergenceError as exc:
            failure = exc
    raise ConvergenceError(f"{failure}, so the Floquet exponents there cannot be counted: give "
                           "a nearby tau or n_temporal=")


def _completed(system: HillSystem, tau: float, gamma: np.ndarray, step: float,
               seeds: Sequence[complex], n_temporal: int, tol: float, dense: bool
               ) -> tuple[np.ndarray, tuple[float, float]]:
    """``gamma`` (largest Newton step ``step``) with any exponent the winding count finds
    missing in R added (module notes, step 3), and R's real extent. The exponents and the
    natural modes ``seeds`` (those on the cut are not listed, but turn the phase along the slit)
    place vertices on the contour (:func:`_through`)."""
    re_lo, re_hi = region(gamma)
    T, dT = pencil_family(system, "harmonic", n_temporal, dense)(tau)
    branch = system.branch_point
    marks = () if system.cut_poles is None else tuple(system.cut_poles(re_lo))
    seeds = np.asarray(seeds, dtype=complex)
    near = _in_strip(np.concatenate([gamma, seeds, seeds.conj()]))
    slit, count = _slit_count(T, re_lo, re_hi, slit_width(gamma, branch), branch, marks, near,
                              dT)
    found = [g for g in _in_strip(gamma) if not _on_cut(g, slit, branch)]
    bottom, top = STRIP
    grid = np.linspace(re_lo, re_hi, max(3, int(SEARCH_DENSITY * (re_hi - re_lo))))
    searched = [complex(x, y) for y in np.linspace(bottom, top, SEARCH_DENSITY + 1)[1:-1]
                for x in grid]
    if _counted(found, slit, branch) < count:
        _on_lines(system, tau, (re_lo, re_hi), branch + slit, n_temporal, tol, dense, found,
                  step)
    branch_seed = complex(branch + BRANCH_SEED, 0.0)
    for seed in [branch_seed] + searched:  # the branch seed always: the count misses its root
        if seed != branch_seed and _counted(found, slit, branch) >= count:
            break
        try:
            out = newton(T, dT, seed, known=found, tol=tol)
        except ParameterError:  # an iterate at the branch point b (beta = 0): D undefined there
            out = None
        if out is not None:
            g = complex(_in_strip(np.array([out[0]]))[0])
            if _new(g, found, max(out[1], step)) and re_lo < g.real < re_hi and \
                    not _on_cut(g, slit, branch):
                found.append(g)
    if _counted(found, slit, branch) != count:
        raise ConvergenceError(
            f"the argument principle counts {count} Floquet exponents with Re gamma in "
            f"[{re_lo:.4g}, {re_hi:.4g}] at n_temporal={n_temporal}, but {_counted(found, slit, branch)} were "
            "found: give n_temporal= or a nearby tau")
    return fold(np.array(found, dtype=complex)), (re_lo, re_hi)


def _on_lines(system: HillSystem, tau: float, bounds: tuple[float, float], cut_end: float,
              n_temporal: int, tol: float, dense: bool, found: list[complex],
              step: float) -> None:
    """Append to ``found`` (exponents in R's period) those on the locking lines that it lacks:
    in each window det T(conj g) = conj det T(g), so det T is real on its line (Im g = 0; in
    the harmonic window right of the cut, Re g > ``cut_end``), and each sign change between
    LINE_SAMPLES samples brackets an exponent there (locked pairs: the cochlea at M = 32, N = 40
    has six on the subharmonic line, three of which the continuation missed), sought by
    deflated Newton's method from the bracket's middle."""
    for kind in KINDS:
        lo = bounds[0] if kind == "subharmonic" else max(bounds[0], cut_end)
        x = np.linspace(lo, bounds[1], LINE_SAMPLES) + 0j
        T, dT = pencil_family(system, kind, n_temporal, dense)(tau)
        sign = np.sign(det_phases(T, x).real)
        for a, b in zip(x[:-1][sign[1:] != sign[:-1]], x[1:][sign[1:] != sign[:-1]]):
            seed = 0.5 * (a + b)
            shift = 1j * GAMMA[kind]
            known = [_nearest(z - shift, seed) for z in found]
            got = newton(T, dT, seed, known=known, tol=tol)
            if got is not None and _new(got[0], known, max(got[1], step)) and \
                    bounds[0] < got[0].real < bounds[1]:
                found.append(complex(_in_strip(np.array([got[0] + shift]))[0]))


def hill_exponents(system: HillSystem, tau: float, seeds: Sequence[complex], *,
                   tol: float = 1e-10, n_temporal: int | None = None,
                   n_max: int = N_MAX, dense: bool = False) -> Exponents:
    """Floquet exponents gamma at forcing amplitude ``tau`` of a model with non-polynomial
    D(s), continued from its natural modes ``seeds`` (tau = 0; one per conjugate pair) and
    counted complete in a region (module notes).

    Returns
    -------
    Exponents : gamma folded to Im in (-1/2, 1/2], decreasing Re; ``complete_in`` the Re gamma
        range of the counting region; ``error_estimate`` the change from the previous
        truncation (floored at the Newton steps).

    ``dense``: dense linear algebra on the whole truncation instead of the block LU (the
    reference it is checked against; O((N b)^3)).

    Raises
    ------
    ConvergenceError : an exponent lost in the continuation, a count the search cannot match,
        or no convergence to ``tol`` by ``n_max``.
    """
    seeds = [complex(s) for s in seeds]
    if not seeds:
        raise ConvergenceError("no natural mode to continue the Floquet exponents from")

    def found(n: int, near: np.ndarray | None = None) -> tuple[np.ndarray, float]:
        """The exponents at truncation n, polished from those of a neighbouring truncation
        (``near``) or continued from the seeds: (exponents, largest Newton step)."""
        if near is None:
            return _followed(system, tau, seeds, n, tol, dense)
        return _polished(system, tau, near, n, tol, dense)

    def counted(gamma: np.ndarray, step: float, n: int) -> tuple[np.ndarray, tuple[float, float]]:
        gamma, bounds = _completed(system, tau, gamma, step, seeds, n, tol, dense)
        return gamma[np.lexsort((gamma.imag, -gamma.real))], bounds

    if n_temporal is not None:
        smaller = found(coarser(n_temporal))[0]
        gamma, step = found(n_temporal, smaller)
        gamma, bounds = counted(gamma, step, n_temporal)
        if len(gamma) != len(smaller):  # the count added some: look for them at the coarser N
            smaller = found(coarser(n_temporal), gamma)[0]
        if len(gamma) != len(smaller):
            raise ConvergenceError(
                f"Floquet exponents at n_temporal={n_temporal}: the comparison truncation "
                f"n_temporal={coarser(n_temporal)} finds {len(smaller)} exponents, this one "
                f"{len(gamma)}, so no error estimate exists: raise n_temporal=")
        return Exponents(gamma=gamma, n_temporal=n_temporal,
                         error_estimate=max(distance(gamma, smaller), step), complete_in=bounds)
    n = first_truncation(system, tau)
    if n >= n_max:
        raise ConvergenceError(f"Floquet exponents need a truncation above n_temporal={n_max} "
                               f"here (resonant Fourier index ~{n - 8}): lower kappa or |tau|")
    previous: np.ndarray | None = None
    change, miscounted = math.inf, False
    while True:
        try:
            gamma, step = found(n, previous)
        except ConvergenceError:  # an under-resolved truncation: the next one may settle it
            if n >= n_max:
                raise
            previous = None
        else:
            settled = previous is not None and len(gamma) == len(previous)
            change = distance(gamma, previous) if settled else math.inf
            if change < tol and previous is not None:  # the (costly) count once settled in N
                try:
                    gamma, bounds = counted(gamma, step, n)
                except ConvergenceError:  # unmatched at two settled truncations: not a matter of N
                    if miscounted or n >= n_max:
                        raise
                    miscounted = True
                else:  # one it added is far from the previous ones; those on the cut it drops
                    change = distance(gamma, previous)
                    if change < tol:
                        return Exponents(gamma=gamma, n_temporal=n,
                                         error_estimate=max(change, step), complete_in=bounds)
            previous = gamma
        if n >= n_max:
            raise ConvergenceError(f"Floquet exponents did not converge to tol={tol:g} by "
                                   f"n_temporal={n_max} (last change {change:.3g}); relax tol=")
        n = min(finer(n), n_max)
