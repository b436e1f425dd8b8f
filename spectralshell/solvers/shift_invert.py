"""Every real tau in [0, tau_max] of a real-form Hill pencil by shift-invert Arnoldi, with the
interval certified complete by a cover of disks.

Why
---
:func:`~spectralshell.solvers.half_product.smallest_taus` finds the eigenvalues of smallest |tau|
and certifies the real ones up to the modulus reached. When many complex tau have |tau| below the
smallest real one (the cochlea at low forcing frequency: hundreds with |tau| < tau_min), that
radius never reaches tau_min and the truncation falls back to dense eig. Here the real interval
[0, tau_max] is covered by disks centred on it instead, each found by Arnoldi at a real shift,
so only the eigenvalues near the interval are computed.

One disk
--------
For a real shift sigma, S = A - sigma B is real and block tridiagonal, and the operator
S^{-1} B has the eigenvalues theta = 1 / (tau - sigma) (B v = 0 gives theta = 0, tau = inf).
ARPACK (``scipy.sparse.linalg.eigs``, ``which='LM'``, real arithmetic, residuals below
ARPACK_TOL |theta|) returns its k eigenvalues of largest |theta|, i.e. the k tau nearest to
sigma; the k-th distance d_k = 1/|theta_k| bounds every other one, so every eigenvalue inside
the disk |tau - sigma| < r = (1 - RADIUS_MARGIN) d_k is among those found (r = inf when theta_k
is zero to working precision, 64 eps max |theta|: then every finite tau was found). Real tau are
the exactly real theta (ARPACK's real Ritz values of a real operator have a zero imaginary
part, as on the dense harmonic path), tau = sigma + 1/theta. As for :func:`smallest_taus`, this
rests on ARPACK returning the k dominant eigenvalues, all converged (it raises otherwise, and
the caller falls back to the dense path); a Krylov method could in principle miss an
eigenvector the fixed pseudo-random start vector barely contains, so it is checked against
closed forms and dense QZ in the tests, not proved.

Rounding in S^{-1} is relative to ||S^{-1} B|| = max |theta|, so an eigenvalue at distance d_1
from sigma blurs the others by ~ eps d_j^2 / d_1: a disk whose nearest eigenvalue is closer
than d_k / CLOSE_LIMIT is discarded and its shift moved by 1 % of its radius; a ``hint`` (often
an eigenvalue itself, e.g. the previous truncation's tau_min) is used as the shift
hint (1 - HINT_OFFSET).

Factorisation of S
------------------
Block elimination from the last Fourier block to the first (no pivoting across blocks; LAPACK's
within a block): S_{K-1} = D_{K-1}, S_k = D_k - U_k S_{k+1}^{-1} L_{k+1}, with D, L, U the
diagonal, lower and upper blocks of S; the inverses S_k^{-1} are kept. O(K s^3) once per shift,
O(K s^2) per solve. In the real form every block row n >= 1 consists of realified blocks
[[P, -Q], [Q, P]] (the complex b x b matrix P + iQ; only row n = 0 carries the reality
condition): that part is eliminated in complex b x b arithmetic (half the flops and half the
memory of the real 2b x 2b blocks), and only the last Schur complement, of row 0, is real
2b x 2b (checked on the data; otherwise every block is eliminated as it is). Repeated couplings
(the forcing) are stored once. Each factorisation is checked by the backward error of one solve
(above BACKWARD_LIMIT: the block elimination was unstable, and the caller falls back to dense).
The two passes of a solve (backward through the S_k^{-1}, forward through the couplings) run in
the compiled kernel (``_schur.sweep``: one zgemv of SciPy's BLAS per block product, the
products of the numpy loop they replaced, rounded alike up to the BLAS build's summation order;
row 0 stays in numpy): the blocks are small, and from
Python each of the ~4 K block products cost a call of ~2 us. Measured on the cochlea of a
Fig 5.18 cell (human, 63.6 Hz, sigma = 1.85e9; N = 51, K = 52 blocks, one BLAS thread, CPU
time): 0.44 -> 0.05 ms per solve at M = 16, 0.48 -> 0.11 ms at M = 32, 0.95 -> 0.49 ms at
M = 64; a plain C loop instead of zgemv was 2x slower than numpy at M = 64, a sparse LU
(SuperLU, natural order) 1.5-9x slower per solve than the block elimination.

Cover
-----
[0, none_below] may be known to hold no real tau (the radius of a short smallest-|tau| Arnoldi
run, as :func:`~spectralshell.solvers.marginal.truncation_taus` does first). Shifts are then
placed until the disks cover [0, tau_max]: first at the hint and at the shifts of ``plan`` (the
previous truncation's, each with its k; one already covered is skipped); then, on the leftmost
uncovered piece [a, c], at its middle if the last radius r would cover it, else at a + 0.8 r.
k starts at K_START and doubles (up to K_MAX) while the uncovered length would need more than
SHIFTS_TARGET disks of the last radius. ``smallest_only``: the target shrinks to the smallest
real tau found so far (only [0, tau_min] must be covered to certify tau_min).

The work is counted in products with S^{-1} B of the truncation: a model of CPU seconds (one
BLAS thread) divided by that of one product, so that the limit compares like with like
(:func:`cover_costs`). A product costs P0 + K (q0 + q2 s^2) (a fixed Python cost, the compiled
sweeps' per-block call and block products), Arnoldi's own work per product R0 + r K s ncv
(ARPACK's reverse communication and orthogonalisation), a factorisation K (f0 + f3 s^3), and
the dense eig that the caller falls back to c2 n^2 + c3 n^3 for the real W of order
n = K s / 2 of a bipartite real-form pencil (2.5 times that otherwise: the complex W of the
two-sided form); the constants are least-squares fits (relative error) to timings of the
cochlea of a Fig 5.18 cell (human, 63.6 Hz, sigma = 1.85e9; s = 32..128, K = 16..115, both
kinds; each within ~1.4x). The work is capped at ``work_limit``, by default WORK_FRACTION of
the dense estimate (:func:`dense_work`), within each disk too (ARPACK's restarts are capped by
what is left); past it (or past MAX_SHIFTS disks) the function returns None and the caller
solves the truncation densely; when the limit is below one disk it returns None at once.
The model before (issue 25) priced the numpy loop that the compiled sweeps replaced: a
product K (137^2 + s^2), Arnoldi's work 2.5 K s ncv, a factorisation 2 + s^2 / 1000 products,
dense eig K^2 s^3 / 7.6. Measured since on the cell above (unlimited cover against dense eig
of the same truncation, CPU time), the cover takes 0.55-0.2 of the dense time for the
subharmonic kind at s = 32 and the harmonic at s = 64, where that model gave up and sent it
to dense eig (it charged dense eig 2-5x too little there), and about as long as dense for the
harmonic kind at s = 32, where both models give up. Outside the fit, at s = 4 (the sphere,
m = 6, N = 150 and 300, both kinds, one disk each) the cover took 0.06-1.2 of the dense time;
the model before gave up there at once (its limit below one disk), this one covers.

A real tau found by two overlapping disks is reported once: real tau within MERGE_RTOL of each
other form a cluster, counted with the largest multiplicity any single disk found in it, with
the values of the disk whose shift is nearest.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse.linalg as spla

from ..discretise.hill import HillMatrices, realify
from ._compiled import _schur
from .half_product import Counted, arpack_restarts, coupling_rows, is_realified

RADIUS_MARGIN = 1e-3
K_START = 24
K_MAX = 48
NCV_EXTRA = 16          # Arnoldi space of 2k + NCV_EXTRA vectors
ARPACK_TOL = 1e-12      # relative residual of each Ritz value theta
SHIFTS_TARGET = 6
BACKWARD_LIMIT = 1e-10
WORK_FRACTION = 0.6
MERGE_RTOL = 1e-8
#: Cost model (module notes, "Cover"), CPU seconds with one BLAS thread: a product
#: P0 + K (q0 + q2 s^2), Arnoldi's own work per product R0 + r K s ncv, a factorisation
#: K (f0 + f3 s^3), dense eig c2 n^2 + c3 n^3 (n = K s / 2, real W).
PRODUCT_SECONDS = (5.7e-5, 9.3e-8, 7.8e-10)    # P0, q0, q2
ARNOLDI_SECONDS = (9.9e-5, 8.4e-10)            # R0, r
FACTOR_SECONDS = (4.1e-5, 3.5e-10)             # f0, f3
DENSE_SECONDS = (6.8e-7, 1.36e-10)             # c2, c3
COMPLEX_DENSE = 2.5     # dense eig of the complex W of a pencil that is not bipartite and real
MAX_SHIFTS = 200
CLOSE_LIMIT = 1e4       # a shift closer to an eigenvalue than 1/CLOSE_LIMIT of the radius is moved
HINT_OFFSET = 1e-3      # the hint's shift sits this fraction below it (a hint is often an eigenvalue)


@dataclass(frozen=True, kw_only=True)
class Shift:
    """One disk of the cover: the shift ``sigma``, the number ``n_eigenvalues`` (k) asked of
    Arnoldi there, and the certified ``radius``: every eigenvalue with |tau - sigma| < radius
    was found."""

    sigma: float
    n_eigenvalues: int
    radius: float


@dataclass(frozen=True, kw_only=True, eq=False)
class IntervalTaus:
    """Real tau of one truncation found by :func:`interval_taus`.

    tau : ascending real tau in [0, complete_to]: every one of the pencil, and only those.
    complete_to : the cover reaches this far (tau_max, or with ``smallest_only`` at least the
        smallest real tau).
    shifts : the disks used, in the order computed (a plan for the next truncation).
    work : matrix-vector products spent (factorisations included, see the module notes).
    """

    tau: np.ndarray
    complete_to: float
    shifts: tuple[Shift, ...]
    work: float


def _product_seconds(K: int, s: int) -> float:
    """Modelled CPU seconds of one product with S^{-1} B of K blocks of size s."""
    p0, q0, q2 = PRODUCT_SECONDS
    return p0 + K * (q0 + q2 * s * s)


def cover_costs(hill: HillMatrices, ncv: int) -> tuple[float, float]:
    """(Arnoldi's own work per product, one factorisation), in products with S^{-1} B of
    this truncation (module notes, "Cover"), for an Arnoldi space of ``ncv`` vectors."""
    K, s, _ = hill.diag.shape
    r0, r = ARNOLDI_SECONDS
    f0, f3 = FACTOR_SECONDS
    product = _product_seconds(K, s)
    return (r0 + r * K * s * ncv) / product, K * (f0 + f3 * s**3) / product


def dense_work(hill: HillMatrices) -> float:
    """Estimated cost of dense eig of the half product W of this truncation (what the caller
    falls back to), in products with S^{-1} B (module notes, "Cover"): c2 n^2 + c3 n^3
    seconds for the real W of order n = K s / 2 of a bipartite real-form pencil, COMPLEX_DENSE
    times that otherwise (the complex W of the two-sided form), over the seconds of one
    product."""
    K, s, _ = hill.diag.shape
    n = K * s / 2
    c2, c3 = DENSE_SECONDS
    seconds = (c2 + c3 * n) * n * n * (1.0 if hill.bipartite and hill.is_real else COMPLEX_DENSE)
    return seconds / _product_seconds(K, s)


def _inner(blocks: np.ndarray, packed: bool, factor: float = 1.0) -> np.ndarray:
    """factor * blocks, as the complex b x b matrices P + iQ of realified blocks [[P, -Q], [Q, P]]
    when ``packed``; a repeated block is converted once and broadcast (no copies)."""
    b = blocks.shape[1] // 2
    part = ((lambda x: factor * (x[..., :b, :b] + 1j * x[..., b:, :b])) if packed
            else (lambda x: factor * x))
    if len(blocks) > 1 and (blocks.strides[0] == 0 or np.all(blocks == blocks[:1])):
        one = part(blocks[0])
        return np.broadcast_to(one, (len(blocks),) + one.shape)
    return part(blocks)


def _complex_rows(hill: HillMatrices) -> bool:
    """True when every block of rows n >= 1 of A and B is realified."""
    if len(hill.diag) < 2 or hill.diag.shape[1] % 2:
        return False
    parts = [hill.diag[1:], hill.lower, hill.upper[1:]]
    if hill.self_coupling is not None:
        parts.append(hill.self_coupling[1:])
    return all(np.all(is_realified(p)) for p in parts if len(p))


def shifted_solver(hill: HillMatrices, sigma: float):
    """r -> (A - sigma B)^{-1} r for the real vector r of the pencil (module notes), or None
    when a Schur complement is singular."""
    K, s, _ = hill.diag.shape
    packed = _complex_rows(hill)
    b = s // 2 if packed else s
    D = _inner(hill.diag[1:], packed)
    if hill.self_coupling is not None:
        D = D - _inner(hill.self_coupling[1:], packed, sigma)
    low = _inner(hill.lower, packed, -sigma)          # row n to n - 1, n = 1..K-1
    up = _inner(hill.upper[1:], packed, -sigma)       # row n to n + 1, n = 1..K-2
    m = K - 1
    inv = np.empty((m, b, b), dtype=complex if packed else float)
    try:
        for j in range(m - 1, -1, -1):  # block n = j + 1
            S = D[j] if j == m - 1 else D[j] - up[j] @ (inv[j + 1] @ low[j + 1])
            inv[j] = np.linalg.inv(S)
        coupling0 = inv[0] @ low[0]
        D0 = hill.diag[0] - (0.0 if hill.self_coupling is None else sigma * hill.self_coupling[0])
        up0 = -sigma * hill.upper[0]
        inv0 = np.linalg.inv(D0 - up0 @ (realify(coupling0[None])[0] if packed else coupling0))
    except np.linalg.LinAlgError:
        return None
    if not (np.all(np.isfinite(inv)) and np.all(np.isfinite(inv0))):
        return None

    # the sweeps run in the compiled kernel, on complex blocks (a repeated coupling once)
    inv_c, up_c, low_c = (np.array(c[:1] if c.strides[0] == 0 else c, dtype=complex)
                          for c in (inv, up, low))

    def to_inner(x: np.ndarray) -> np.ndarray:
        return x[..., :b] + 1j * x[..., b:] if packed else x

    def solve(r: np.ndarray) -> np.ndarray:
        r = r.reshape(K, s)
        g = np.array(to_inner(r[1:]), dtype=complex)
        _schur.sweep(inv_c, up_c if len(up_c) else low_c[:1], g, None)
        g1 = np.concatenate([g[0].real, g[0].imag]) if packed else g[0].real
        x0 = inv0 @ (r[0] - up0 @ g1)
        _schur.sweep(inv_c, low_c, g, np.array(to_inner(x0), dtype=complex))
        out = np.empty((K, s))
        out[0] = x0
        if packed:
            out[1:, :b], out[1:, b:] = g.real, g.imag
        else:
            out[1:] = g.real
        return out.ravel()

    return solve


def _b_product(hill: HillMatrices):
    """x -> B x (real form, flat vectors), block by block."""
    K, s, _ = hill.diag.shape
    rows = coupling_rows(hill, np.arange(K))

    def product(x: np.ndarray) -> np.ndarray:
        padded = np.zeros((K + 2, s))
        padded[1:-1] = x.reshape(K, s)
        return rows(padded).ravel()

    return product


def _backward_error(hill: HillMatrices, sigma: float, solve, b_product) -> float:
    """||S y - r|| / (||A y|| + |sigma| ||B y|| + ||r||) for y = S^{-1} r, r pseudo-random."""
    K, s, _ = hill.diag.shape
    r = np.random.default_rng(7).standard_normal(K * s)
    y = solve(r)
    ay = (hill.diag @ y.reshape(K, s, 1)).ravel()
    by = b_product(y)
    scale = np.linalg.norm(ay) + abs(sigma) * np.linalg.norm(by) + np.linalg.norm(r)
    return float(np.linalg.norm(ay - sigma * by - r) / scale)


@dataclass(frozen=True)
class _Disk:
    """One computed disk (the real tau found in it, its work, and whether sigma was too close
    to an eigenvalue)."""

    shift: Shift
    tau: np.ndarray  # the real tau found (any sign), ascending
    work: float
    close: bool      # sigma nearly on an eigenvalue: the others lost accuracy (module notes)


def _disk(hill: HillMatrices, sigma: float, k: int, b_product,
          work_left: float = np.inf) -> _Disk | None:
    """The k eigenvalues nearest to sigma by shift-invert Arnoldi (module notes), or None when
    the factorisation is unstable or ARPACK does not converge within ``work_left`` (the work
    model's units; its restarts are capped accordingly)."""
    K, s, _ = hill.diag.shape
    n = K * s
    ncv = min(n - 1, 2 * k + NCV_EXTRA)
    orthogonalisation, factorisation = cover_costs(hill, ncv)
    maxiter = arpack_restarts((work_left - factorisation) / (1.0 + orthogonalisation), k, ncv)
    if maxiter == 0:
        return None
    solve = shifted_solver(hill, sigma)
    if solve is None or _backward_error(hill, sigma, solve, b_product) > BACKWARD_LIMIT:
        return None
    op = Counted(spla.LinearOperator((n, n), matvec=lambda x: solve(b_product(np.ravel(x))),
                                     dtype=float))
    v0 = np.random.default_rng(20240611).standard_normal(n)
    try:
        theta = spla.eigs(op, k=k, which="LM", v0=v0, tol=ARPACK_TOL, ncv=ncv, maxiter=maxiter,
                          return_eigenvectors=False)
    except spla.ArpackNoConvergence:
        return None
    size = np.abs(theta)
    floor = 64 * np.finfo(float).eps * size.max()
    smallest = size.min()
    radius = np.inf if smallest <= floor else (1.0 - RADIUS_MARGIN) / smallest
    real = (theta.imag == 0.0) & (size > floor)
    finite = size[size > floor]
    close = bool(finite.max() > CLOSE_LIMIT * finite.min())
    tau = np.sort(sigma + 1.0 / theta.real[real])
    work = op.products * (1.0 + orthogonalisation) + factorisation
    return _Disk(shift=Shift(sigma=float(sigma), n_eigenvalues=k, radius=float(radius)),
                 tau=tau[np.abs(tau - sigma) < radius], work=work, close=close)


def _first_gap(covered: list[tuple[float, float]], target: float) -> tuple[float, float] | None:
    """The leftmost piece [a, c] of [0, target] outside every interval of ``covered``."""
    a = 0.0
    for lo, hi in sorted(covered):
        if lo > a:
            break
        a = max(a, hi)
    if a > target:
        return None
    later = [lo for lo, _ in covered if lo > a]
    return a, min([target, *later])


def _prefix_end(covered: list[tuple[float, float]]) -> float:
    """Right end of the covered piece that starts at 0 (0 when 0 is not covered)."""
    end = 0.0
    for lo, hi in sorted(covered):
        if lo > end:
            break
        end = max(end, hi)
    return end


def _merged(disks: list[_Disk]) -> np.ndarray:
    """The real tau of all disks, each eigenvalue once (module notes)."""
    values = [(t, i) for i, d in enumerate(disks) for t in d.tau]
    if not values:
        return np.empty(0)
    values.sort()
    tau = np.array([t for t, _ in values])
    owner = np.array([i for _, i in values])
    breaks = np.flatnonzero(np.diff(tau) > MERGE_RTOL * np.maximum(1.0, np.abs(tau[1:]))) + 1
    out = []
    for cluster, who in zip(np.split(tau, breaks), np.split(owner, breaks)):
        counts = np.bincount(who)
        best = np.flatnonzero(counts == counts.max())
        nearest = best[np.argmin([abs(disks[i].shift.sigma - cluster.mean()) for i in best])]
        out.append(cluster[who == nearest])
    return np.concatenate(out)


def interval_taus(hill: HillMatrices, tau_max: float, *, hint: float | None = None,
                  plan: Sequence[Shift] = (), smallest_only: bool = False,
                  none_below: float = 0.0,
                  work_limit: float | None = None) -> IntervalTaus | None:
    """Every real tau in [0, tau_max] of a real-form Hill pencil by shift-invert Arnoldi.

    Parameters
    ----------
    hill : the pencil, real form (real arithmetic, exactly real tau).
    tau_max : finite right end of the interval.
    hint : a real tau expected nearby (e.g. a neighbour's tau_min): the first shift.
    plan : shifts to try first, in order (e.g. the previous truncation's ``shifts``), each with
        its k; one is skipped if the disks before it already cover it.
    smallest_only : cover only up to the smallest real tau found (module notes).
    none_below : [0, none_below] is known to hold no real tau (e.g. the radius of an Arnoldi
        run for the smallest |tau|, :func:`~spectralshell.solvers.half_product.smallest_taus`):
        the cover starts there.
    work_limit : products with S^{-1} B allowed (default WORK_FRACTION * dense_work(hill)).

    Returns None (use dense eig then) when the work limit is reached, a factorisation is
    unstable, or ARPACK does not converge. Cost: O(K s^3) per shift, O(K s^2) per product.
    """
    if not hill.is_real:
        raise ValueError("interval_taus works on the real form (real arithmetic, exact real tau)")
    if not 0.0 <= tau_max < np.inf:
        raise ValueError(f"tau_max = {tau_max!r} is invalid: must be finite and >= 0")
    K, s, _ = hill.diag.shape
    limit = WORK_FRACTION * dense_work(hill) if work_limit is None else work_limit
    if limit < 2 * K_START + NCV_EXTRA:  # less than one disk
        return None
    b_product = _b_product(hill)
    planned = [(p.sigma, p.n_eigenvalues) for p in plan]
    if hint is not None and 0.0 <= hint <= tau_max:
        planned.insert(0, (float(hint) * (1.0 - HINT_OFFSET), K_START))
    disks: list[_Disk] = []
    covered = [(0.0, float(none_below))] if none_below > 0.0 else []
    target, k, work = float(tau_max), K_START, 0.0
    radius = none_below if none_below > 0.0 else np.inf  # the last disk's
    while (gap := _first_gap(covered, target)) is not None:
        planned = [(p, j) for p, j in planned if not any(lo < p < hi for lo, hi in covered)]
        if planned:
            sigma, k_here = planned.pop(0)
        else:
            a, c = gap
            sigma = 0.5 * (a + c) if c - a <= 1.6 * radius else a + 0.8 * radius
            k_here = k
        k_here = min(k_here, K * s // 4)
        disk = _disk(hill, sigma, k_here, b_product, limit - work)
        if disk is not None and disk.close:  # move off the eigenvalue by 1 % of the radius
            work += disk.work
            sigma -= 0.01 * min(disk.shift.radius, max(abs(sigma), 1e-3))
            disk = _disk(hill, sigma, k_here, b_product, limit - work)
        if disk is None or disk.close or len(disks) == MAX_SHIFTS:
            return None
        work += disk.work
        if work > limit:
            return None
        disks.append(disk)
        radius = disk.shift.radius
        covered.append((sigma - radius, sigma + radius))
        positive = disk.tau[disk.tau >= 0.0]
        if smallest_only and positive.size:
            target = min(target, float(positive[0]))
        if target - _prefix_end(covered) > SHIFTS_TARGET * 1.6 * radius:
            k = min(max(2 * k_here, k), K_MAX)
    complete_to = min(_prefix_end(covered), tau_max)
    tau = _merged(disks)
    tau = tau[(tau >= 0.0) & (tau <= complete_to)]
    return IntervalTaus(tau=tau, complete_to=float(complete_to),
                        shifts=tuple(d.shift for d in disks), work=work)
