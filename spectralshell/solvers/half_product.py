"""T = A^{-1} B of a Hill pencil and its half-size product W, dense or as operators for Arnoldi.

Structure
---------
A Hill pencil A v = tau B v (thesis (2.6); :mod:`spectralshell.discretise.hill`) has A block
diagonal and B block tridiagonal, so T = A^{-1} B, whose eigenvalues are mu = 1/tau, is applied
block by block: (T x)_k = A_k^{-1} (B_{k,k-1} x_{k-1} + B_{k,k} x_k + B_{k,k+1} x_{k+1}), O(K s^2)
once the block inverses are known. When the pencil is bipartite (no B_{k,k}), in an even/odd
ordering T = [[0, X], [Y, 0]] and the eigenvalues of the half-size product W = X Y (acting on
the even block positions) are mu^2, each standing for the pair +-tau. Real tau are the real
mu > 0 of T, or the real mu^2 > 0 of W.

Block inverses
--------------
K inverses of s x s blocks, O(K s^3). Two exact properties of the Hill forms halve that work
(each is checked on the data, never assumed): in the two-sided form the blocks satisfy
A_{K-1-k} = conj(A_k), since D(conj s) = conj D(s) and the index reflection maps s_k to conj(s_k)
(harmonic k -> -k, subharmonic k -> -k-1), so only half are inverted; in the real form the
blocks [[D_r, -D_i], [D_i, D_r]] are realifications of a complex b x b block D, whose complex
inverse (8 b^3 real flops instead of 16 b^3, and half the memory traffic when applied)
realifies to A_k^{-1}. Blocks smaller than SMALL_BLOCK are inverted plainly: there the checks
cost more than they save. Inverses of a smaller truncation's blocks can be reused (``known``).

Arnoldi fast path (:func:`smallest_taus`)
----------------------------------------
On the real form (so that ARPACK runs in real arithmetic and real eigenvalues come out exactly
real): W when the pencil is bipartite (harmonic), else T (subharmonic: the n = 0 self-coupling);
applied as above, no product of blocks is formed. For the subharmonic kind of block models the
caller may pass the two-sided form instead, which is bipartite: ARPACK then runs on its complex
W (k = K_START eigenvalues mu^2, not the 2 K_START of T, which holds each +-mu), and a real mu^2
is one with |Im mu^2| <= REAL_RTOL |mu^2|, the dense subharmonic path's rule. Measured (issue 25,
cochlea at omega = 600 rad/s, N = 8, 10, one BLAS thread, CPU time): 1.7-2.3x faster than T at
M = 40, 80 and 2.5-4.6x at M = 256, the same tau and radius.
ARPACK's implicitly restarted Arnoldi method
(``scipy.sparse.linalg.eigs``, ``which='LM'``, ``tol=0``: residuals at machine precision) returns
the k eigenvalues lambda_1, ..., lambda_k of largest modulus (lambda = mu^2 or mu).
Completeness: every eigenvalue of modulus above |lambda_k|, i.e. every tau with |tau| < r
(r = |lambda_k|^(-1/2) for W, |lambda_k|^(-1) for T), is among them. So

* if a real tau <= r is among them, the smallest real tau of the truncation is the smallest one
  found, and all real tau <= r are listed;
* if none is, and r >= tau_max, the truncation has no real tau <= tau_max;
* otherwise k is doubled (from K_START), and once the Krylov space would exceed
  1/KRYLOV_FRACTION of the operator's order (dense eig is then cheaper) the fast path gives up
  (returns None). With ``max_rounds`` the doubling stops earlier and the radius reached is
  returned with no tau (a partial answer: no real tau up to it), from which the shift-invert
  cover of :mod:`spectralshell.solvers.shift_invert` continues.

Eigenvalues with |lambda| <= 64 eps |lambda_1| are zero to working precision (infinite tau);
reaching one means every other eigenvalue was found (r = inf). The argument rests on ARPACK
returning the k dominant eigenvalues, all converged (it raises otherwise, and the dense path
answers). Like any Krylov method it could in principle miss an eigenvalue whose eigenvector the
starting vector (fixed, pseudo-random: reproducible results) barely contains; this is not a
proof, and it is checked against the dense solve on random block models in the tests. ARPACK's
real Ritz values of a real operator have an exactly zero imaginary part, so real tau are
classified exactly, as on the dense harmonic path.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse.linalg as spla

from ..discretise.hill import HillMatrices, realify
from ._compiled import _schur

COND_LIMIT = 1e8
REAL_RTOL = 1e-9
K_START = 8
SMALL_BLOCK = 32  # below this block size A_k^{-1} are plainly inverted and never reused
KRYLOV_FRACTION = 3  # give up when the Krylov space would exceed (operator order) / KRYLOV_FRACTION


def tau_from_squares(lam: np.ndarray, floor: float, exact_real: bool) -> np.ndarray:
    """tau = 1/sqrt(mu^2) for the real eigenvalues mu^2 of W above ``floor``, ascending."""
    mu2 = lam.real
    if exact_real:
        real = lam.imag == 0.0
    else:
        real = np.abs(lam.imag) <= REAL_RTOL * np.abs(lam)
    tau = 1.0 / np.sqrt(mu2[real & (mu2 > floor)])
    tau.sort()
    return tau


def is_realified(diag: np.ndarray) -> np.ndarray:
    """Mask of the real blocks that are exactly [[D_r, -D_i], [D_i, D_r]]."""
    b = diag.shape[1] // 2
    if diag.shape[1] % 2 or np.iscomplexobj(diag):
        return np.zeros(len(diag), dtype=bool)
    tl, tr, bl, br = diag[:, :b, :b], diag[:, :b, b:], diag[:, b:, :b], diag[:, b:, b:]
    return np.all(tl == br, axis=(1, 2)) & np.all(tr == -bl, axis=(1, 2))


@dataclass(frozen=True, eq=False)
class BlockInverses:
    """A_k^{-1} of every diagonal block of a pencil with K blocks of size s: for the realified
    blocks ``complex_rows`` as the complex b x b inverse ``complex_inv`` (half the storage and
    memory traffic of the real 2b x 2b one), for the other ``rows`` as ``inv``. Both position
    lists are ascending, so that without realified blocks ``inv`` is every A_k^{-1} in order."""

    size: int
    rows: np.ndarray
    inv: np.ndarray
    complex_rows: np.ndarray
    complex_inv: np.ndarray

    def norms(self) -> np.ndarray:
        """1-norm of each A_k^{-1}, k = 0..K-1."""
        plain = np.abs(self.inv).sum(axis=1).max(axis=-1, initial=0.0)
        if not self.complex_rows.size:
            return plain
        out = np.empty(len(self.rows) + len(self.complex_rows))
        out[self.rows] = plain
        c = self.complex_inv
        out[self.complex_rows] = (np.abs(c.real) + np.abs(c.imag)).sum(axis=1).max(axis=-1,
                                                                                  initial=0.0)
        return out

    def full(self) -> np.ndarray:
        """All A_k^{-1} as a (K, s, s) array (``inv`` itself when no block is realified)."""
        if not self.complex_rows.size:
            return self.inv
        K = len(self.rows) + len(self.complex_rows)
        out = np.empty((K, self.size, self.size), dtype=self.inv.dtype)
        out[self.rows] = self.inv
        out[self.complex_rows] = realify(self.complex_inv)
        return out

    def subset(self, rows: slice) -> BlockInverses:
        """The inverses of the contiguous blocks ``rows``, numbered from 0 (views of these)."""

        def cut(positions: np.ndarray, blocks: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            if not positions.size:
                return positions, blocks
            first, stop = positions.searchsorted((rows.start, rows.stop))  # ascending
            return positions[first:stop] - rows.start, blocks[first:stop]

        (kept, inv), (kept_c, complex_inv) = (cut(self.rows, self.inv),
                                              cut(self.complex_rows, self.complex_inv))
        return BlockInverses(size=self.size, rows=kept, inv=inv, complex_rows=kept_c,
                             complex_inv=complex_inv)

    def solver(self, targets: np.ndarray):
        """r -> (A_k^{-1} r_j)_j for k = targets[j], r of shape (len(targets), s)."""
        position = np.full(len(self.rows) + len(self.complex_rows), -1)
        position[self.complex_rows] = np.arange(len(self.complex_rows))
        in_complex = position[targets] >= 0
        c_inv = self.complex_inv[position[targets[in_complex]]]
        position[self.rows] = np.arange(len(self.rows))
        r_inv = self.inv[position[targets[~in_complex]]]
        b = self.size // 2

        def solve(r: np.ndarray) -> np.ndarray:
            out = np.empty(r.shape, dtype=np.result_type(r, self.inv))
            if c_inv.size:
                rc = r[in_complex]
                c = (c_inv @ (rc[:, :b] + 1j * rc[:, b:])[:, :, None])[:, :, 0]
                out[in_complex] = np.concatenate([c.real, c.imag], axis=1)
            if r_inv.size:
                out[~in_complex] = (r_inv @ r[~in_complex][:, :, None])[:, :, 0]
            return out

        return solve


def _inverses(diag: np.ndarray, reflected: bool) -> BlockInverses:
    """A_k^{-1} of every block, using the exact symmetries of the module notes (``reflected``:
    diag[K-1-k] = conj(diag[k]) for every k, checked by the caller)."""
    K, s, _ = diag.shape
    every, none = np.arange(K), np.arange(0)
    empty = np.zeros((0, s // 2, s // 2), dtype=complex)
    if s == 1:  # scalar blocks: reciprocals (np.linalg.inv's call costs more than the division)
        if not diag.all():
            raise np.linalg.LinAlgError("a 1 x 1 block of A is zero")
        return BlockInverses(size=s, rows=every, inv=1.0 / diag, complex_rows=none,
                             complex_inv=empty)
    if s < SMALL_BLOCK:  # the savings below do not pay for their own overhead
        return BlockInverses(size=s, rows=every, inv=np.linalg.inv(diag), complex_rows=none,
                             complex_inv=empty)
    if reflected:
        inv = np.empty_like(diag)
        upper = np.arange(K // 2, K)
        inv[upper] = np.linalg.inv(diag[upper])
        lower = np.arange(K // 2)
        inv[lower] = inv[K - 1 - lower].conj()
        return BlockInverses(size=s, rows=every, inv=inv, complex_rows=none, complex_inv=empty)
    mask = is_realified(diag)
    if mask.sum() < 2:
        return BlockInverses(size=s, rows=every, inv=np.linalg.inv(diag), complex_rows=none,
                             complex_inv=empty)
    b = s // 2
    rows, complex_rows = np.flatnonzero(~mask), np.flatnonzero(mask)
    inv = np.linalg.inv(diag[rows]) if rows.size else np.zeros((0, s, s))
    complex_inv = np.linalg.inv(diag[mask, :b, :b] + 1j * diag[mask, b:, :b])
    return BlockInverses(size=s, rows=rows, inv=inv, complex_rows=complex_rows,
                         complex_inv=complex_inv)


def _norm1(blocks: np.ndarray | None) -> float:
    """Largest 1-norm of a stack of blocks (0 for None); a broadcast stack (stride 0, one block
    repeated, as the real form's forcing) is read once."""
    if blocks is None or not len(blocks):
        return 0.0
    if blocks.strides[0] == 0:
        blocks = blocks[:1]
    return float(np.abs(blocks).sum(axis=1).max())


def _diag_norms(diag: np.ndarray, inverses: BlockInverses) -> np.ndarray:
    """1-norm of each A_k; for the realified blocks [[P, -Q], [Q, P]] (``complex_rows``) from
    their left half, whose column sums |P| + |Q| the right half repeats."""
    out = np.empty(len(diag))
    rows, complex_rows = inverses.rows, inverses.complex_rows
    if rows.size:
        out[rows] = np.abs(diag[rows]).sum(axis=1).max(axis=-1)
    if complex_rows.size:
        half = diag.shape[1] // 2
        out[complex_rows] = np.abs(diag[complex_rows, :, :half]).sum(axis=1).max(axis=-1)
    return out


def _joined(parts: list[tuple[np.ndarray, BlockInverses]], size: int) -> BlockInverses:
    """One BlockInverses from parts, each (its block positions, its inverses numbered from 0)."""
    rows = np.concatenate([at[p.rows] for at, p in parts])
    complex_rows = np.concatenate([at[p.complex_rows] for at, p in parts])
    order, order_c = np.argsort(rows), np.argsort(complex_rows)
    return BlockInverses(size=size, rows=rows[order],
                         inv=np.concatenate([p.inv for _, p in parts])[order],
                         complex_rows=complex_rows[order_c],
                         complex_inv=np.concatenate([p.complex_inv for _, p in parts])[order_c])


def _reusing(diag: np.ndarray, reflected: bool, rows: slice,
             known: BlockInverses) -> BlockInverses:
    """A_k^{-1} of every block, those at positions ``rows`` taken from ``known`` (``reflected``
    as for :func:`_inverses`, of all of ``diag``)."""
    done = np.zeros(len(diag), dtype=bool)
    done[rows] = True
    parts = [(np.flatnonzero(done), known)]
    todo = np.flatnonzero(~done)
    if todo.size:  # the blocks left reflect onto each other where they lie at both ends alike
        symmetric = np.array_equal(todo, len(diag) - 1 - todo[::-1])
        parts.append((todo, _inverses(diag[todo], reflected and symmetric)))
    return _joined(parts, diag.shape[1])


def block_inverses(hill: HillMatrices,
                   known: tuple[slice, BlockInverses] | None = None) -> BlockInverses | None:
    """A_k^{-1} for every diagonal block, or None when a block is singular or ill conditioned:
    1-norm condition above COND_LIMIT, or ||A_k^{-1}|| ||B|| above it (then some tau ~< 1e-8,
    which the squared eigenvalues mu^2 = 1/tau^2 would lose; the caller falls back to QZ).
    ``known``: (block positions, their inverses), reused instead of inverting those blocks."""
    try:
        if known is None or hill.diag.shape[1] < SMALL_BLOCK:
            inv = _inverses(np.ascontiguousarray(hill.diag),  # C order, as full() passes it on
                            hill.diag.shape[1] >= SMALL_BLOCK and hill.reflected)
        else:
            inv = _reusing(hill.diag, hill.reflected, *known)
    except np.linalg.LinAlgError:
        return None
    inv_norm = inv.norms()
    cond = _diag_norms(hill.diag, inv) * inv_norm
    coupling = _norm1(hill.lower) + _norm1(hill.upper) + _norm1(hill.self_coupling)
    if not cond.max() <= COND_LIMIT or inv_norm.max() * coupling > COND_LIMIT:  # NaN, inf: None
        return None
    return inv


def well_conditioned(hill: HillMatrices) -> bool:
    """Whether :func:`block_inverses` would give the inverses (not None), without forming them:
    for 2 x 2 blocks (no self-coupling) the compiled kernel takes ||A_k^{-1}||_1 =
    ||adj A_k||_1 / |det A_k| in closed form (the contour path needs the answer only)."""
    if hill.diag.shape[1] != 2 or hill.self_coupling is not None:
        return block_inverses(hill) is not None
    cond, coupled = _schur.conditioning(np.ascontiguousarray(hill.diag, dtype=complex),
                                        np.ascontiguousarray(hill.lower, dtype=complex),
                                        np.ascontiguousarray(hill.upper, dtype=complex))
    return cond <= COND_LIMIT and coupled <= COND_LIMIT  # NaN: False


def dense_half_product(hill: HillMatrices, inverses: BlockInverses) -> np.ndarray:
    """W = X Y as a dense matrix, from the blocks C-_k = A_k^{-1} B_{k,k-1} and
    C+_k = A_k^{-1} B_{k,k+1}: on even block positions p, W_{p,p} = C-_p C+_{p-1} + C+_p C-_{p+1},
    W_{p,p+2} = C+_p C+_{p+1}, W_{p,p-2} = C-_p C-_{p-1}."""
    if not hill.bipartite:
        raise ValueError("the half product needs a bipartite pencil (no self-coupling in B)")
    K, s, _ = hill.diag.shape
    inv = inverses.full()
    dtype = np.result_type(inv, hill.lower)
    cm, cp = np.zeros((2, K + 1, s, s), dtype=dtype)  # zero blocks at both ends
    np.matmul(inv[1:], np.ascontiguousarray(hill.lower), out=cm[1:K])   # cm[k] = C-_k
    np.matmul(inv[:-1], np.ascontiguousarray(hill.upper), out=cp[1:K])  # cp[k + 1] = C+_k
    m = (K + 1) // 2  # even positions p = 0, 2, ..., K - 1 or K - 2
    W = np.zeros((m * m, s, s), dtype=dtype)  # block (i, j) of W at i m + j
    W[::m + 1] = cm[0:K:2] @ cp[0:K:2] + cp[1:K + 1:2] @ cm[1:K + 1:2]  # (i, i)
    W[1::m + 1] = cp[1:K - 1:2] @ cp[2:K:2]                            # (i, i + 1)
    W[m::m + 1] = cm[2:K:2] @ cm[1:K - 1:2]                            # (i + 1, i)
    return W.reshape(m, m, s, s).transpose(0, 2, 1, 3).reshape(m * s, m * s)


def coupled_solves(hill: HillMatrices):
    """(solve, negated): solve is k -> (C-_k, C+_k) = (A_k^{-1} B_{k,k-1}, A_k^{-1} B_{k,k+1})
    (None outside the pencil) by LAPACK's LU of A_k, one solve for both when
    ``negated`` (:attr:`~spectralshell.discretise.hill.HillMatrices.negated`; then
    C+_k = -C-_k exactly there); None for a block
    whose 1-norm condition exceeds COND_LIMIT (or a singular one)."""
    K = len(hill.diag)
    getrf, gecon, getrs = sla.lapack.get_lapack_funcs(("getrf", "gecon", "getrs"),
                                                      (hill.diag[0], hill.lower[:1]))
    negated = hill.negated

    def solve(k: int) -> tuple[np.ndarray | None, np.ndarray | None] | None:
        a = np.array(hill.diag[k], dtype=np.result_type(hill.diag, hill.lower), order="F")
        norm = np.abs(a).sum(axis=0).max()
        lu, pivots, info = getrf(a, overwrite_a=1)
        if info != 0:
            return None
        rcond, info = gecon(lu, norm)
        if info != 0 or not rcond * COND_LIMIT >= 1.0:  # NaN too
            return None
        parts = ([hill.lower[k - 1]] if k >= 1 else []) + \
            ([hill.upper[k]] if k + 1 < K and not (negated and k >= 1) else [])
        x, info = getrs(lu, pivots, np.concatenate(parts, axis=1))
        if info != 0 or not np.all(np.isfinite(x)):
            return None
        s = len(a)
        if k == 0:
            return None, x
        if k + 1 == K:
            return x, None
        return (x, -x) if negated else (x[:, :s], x[:, s:])

    return solve, negated


def cut_solves(solve, rows: slice):
    """The ``solve`` of :func:`coupled_solves` for the truncation on the block positions
    ``rows`` of a larger pencil, from that pencil's ``solve``: the same blocks of A and the
    same couplings inside, the couplings that leave the cut dropped (None). Where the larger
    pencil is ``negated``, its C+_k = -C-_k at the cut's first block equals the cut's own
    A_k^{-1} B_{k,k+1} = A_k^{-1} (-B_{k,k-1}) exactly (LU solves commute with a sign)."""
    last = rows.stop - rows.start - 1

    def solve_cut(k: int) -> tuple[np.ndarray | None, np.ndarray | None] | None:
        here = solve(rows.start + k)
        if here is None:
            return None
        return (None if k == 0 else here[0]), (None if k == last else here[1])

    return solve_cut


def mirrored_solves(solve, K: int):
    """The ``solve`` of :func:`coupled_solves` for a mirrored pencil
    (:attr:`~spectralshell.discretise.hill.HillMatrices.mirrored`) of K blocks with
    the blocks past the middle taken from their reflections: C-_k = conj(C+_{K-1-k}),
    C+_k = conj(C-_{K-1-k}); only the first ceil(K / 2) blocks of A are solved. Exact: LU and
    triangular solves commute with conjugation (the pivot choice |Re| + |Im| included)."""

    def solve_mirrored(k: int) -> tuple[np.ndarray | None, np.ndarray | None] | None:
        if 2 * k < K:
            return solve(k)
        here = solve(K - 1 - k)
        if here is None:
            return None
        cm, cp = here
        return (None if cp is None else cp.conj()), (None if cm is None else cm.conj())

    return solve_mirrored


def free_radius(hill: HillMatrices, solves=None) -> float:
    """A radius r such that no eigenvalue tau of the bipartite pencil has |tau| < r, from norms
    of the blocks of W (0 when a block of A is singular or ill conditioned: no bound).

    Notes
    -----
    For a matrix W of blocks W_ij and the matrix N_ij = ||W_ij|| of their norms in one induced
    norm, ||(W^k)_ij|| <= (N^k)_ij, so rho(W) <= rho(N); W of :func:`dense_half_product` is
    block tridiagonal over the even positions, so N is a nonnegative tridiagonal m x m matrix,
    similar to the symmetric one with off-diagonal sqrt(N_{i,i+1} N_{i+1,i}), whose largest
    eigenvalue is rho(N) (LAPACK ?stev). With the smaller rho(N) of the 1- and inf-norms,
    every eigenvalue mu^2 = 1/tau^2 of W has |mu^2| <= rho(N): r = rho(N)^(-1/2). The blocks
    C-_k, C+_k of T are formed by one LU per block of A (blocks with 1-norm condition above
    COND_LIMIT give r = 0, so that their rounding, <~ M eps COND_LIMIT relative, stays far below
    a caller's margin); each block of W is formed, never W itself: O(K s^3), about 3.7 K s^3
    complex flops, and O(s^2) memory beyond the pencil's. ``solves``: the (solve, negated) of
    :func:`coupled_solves` for ``hill`` (e.g. kept from a larger truncation, :func:`cut_solves`),
    in place of its own. Where C+_k = -C-_k (``negated``,
    the cochlea's forcing), the blocks of W come in pairs that differ in sign only,
    W_{p,p} = -(C-_p C-_{p-1} + C-_p C-_{p+1}) and W_{p,p+-2} = C-_p C-_{p+-1} away from the
    ends: one product per block of A instead of two, about 2.7 K s^3, with the same numbers
    (negating a factor negates a product exactly). Where the pencil is mirrored (the
    two-sided form), the blocks past the middle are solved as conjugates of their reflections
    (:func:`mirrored_solves`), and with K odd (the harmonic kind: even positions reflect onto
    even ones, p -> K - 1 - p) W_{K-1-p,K-1-p} = conj(W_{p,p}) and W_{K-1-p,K-3-p} =
    conj(W_{p,p+2}), so only the blocks of W up to the middle are formed and the other norms
    are their reflections': half the work, the same numbers. Issue 25.
    """
    if not hill.bipartite:
        raise ValueError("free_radius needs a bipartite pencil (no self-coupling in B)")
    K = len(hill.diag)
    if K == 1:  # B = 0: no finite eigenvalue
        return np.inf
    solve, negated = coupled_solves(hill) if solves is None else solves
    mirror = hill.mirrored
    if mirror:
        solve = mirrored_solves(solve, K)
    # norms (1-norm, inf-norm) of W_{p,p}, W_{p,p-2}, W_{p,p+2} by even position p
    diag: dict[int, tuple[float, float]] = {}
    low: dict[int, tuple[float, float]] = {}
    up: dict[int, tuple[float, float]] = {}

    def measure(block: np.ndarray | None) -> tuple[float, float]:
        if block is None:
            return 0.0, 0.0
        size = np.abs(block)
        return float(size.sum(axis=0).max()), float(size.sum(axis=1).max())

    reflected = mirror and K % 2 == 1
    previous = pending = None  # (C-, C+) of k - 1; the partial W_{p,p} of the even p = k - 1
    for k in range(min(K, K // 2 + 2) if reflected else K):
        here = solve(k)
        if here is None:
            return 0.0
        cm, cp = here
        if k % 2 == 0:  # even p = k: W_{p,p} starts with C-_p C+_{p-1}; W_{p,p-2} = C-_p C-_{p-1}
            w_low = cm @ previous[0] if k >= 2 else None
            pending = None if k == 0 else -w_low if negated else cm @ previous[1]
            if k >= 2:
                low[k] = measure(w_low)
            if k + 1 == K:
                diag[k] = measure(pending)
        else:  # odd k = p + 1: W_{p,p} += C+_p C-_{p+1}; W_{p,p+2} = C+_p C+_{p+1}
            term = previous[1] @ cm
            diag[k - 1] = measure(term if pending is None else pending + term)
            if cp is not None and k + 1 < K:
                up[k - 1] = measure(-term if negated else previous[1] @ cp)
        previous = here
    positions = range(0, K, 2)
    if reflected:  # the norms past the middle: those of the reflected blocks
        for p in positions:
            q = K - 1 - p
            if p not in diag:
                diag[p] = diag[q]
            if p >= 2 and p not in low:
                low[p] = up[q]
            if p + 2 < K and p not in up:
                up[p] = low[q]
    radius = 0.0
    for which in (0, 1):  # either norm bounds rho(W): the larger radius holds
        d = np.array([diag[p][which] for p in positions])
        off = np.sqrt(np.array([low[p + 2][which] * up[p][which] for p in positions
                                if p + 2 < K]))
        rho = float(np.abs(sla.eigvalsh_tridiagonal(d, off)).max()) if len(d) > 1 else d[0]
        if not np.isfinite(rho):
            return 0.0
        radius = max(radius, np.inf if rho == 0.0 else rho ** -0.5)
    return radius


def tridiagonal_half_product(hill: HillMatrices,
                             inverses: BlockInverses) -> tuple[np.ndarray, np.ndarray]:
    """W of a pencil with 1 x 1 blocks (a scalar model in the two-sided form) as its diagonal d
    and off-diagonal products p_i = W_{i,i+1} W_{i+1,i}, which fix its eigenvalues: with
    pi_k = C+_k C-_{k+1} (the product of T's entries (k, k+1) and (k+1, k)) the formulas of
    :func:`dense_half_product` become W_{p,p} = pi_{p-1} + pi_p and
    W_{p,p+2} W_{p+2,p} = pi_p pi_{p+1} on even positions p (pi = 0 outside the pencil)."""
    if not hill.bipartite or hill.diag.shape[1] != 1:
        raise ValueError("the tridiagonal half product needs a bipartite pencil of 1 x 1 blocks")
    K = len(hill.diag)
    inv = inverses.full()[:, 0, 0]
    pi = np.zeros(K + 1, dtype=np.result_type(inv, hill.lower))  # pi[k + 1] = pi_k
    pi[1:K] = inv[:-1] * hill.upper[:, 0, 0] * inv[1:] * hill.lower[:, 0, 0]
    m = (K + 1) // 2
    return pi[0:2 * m:2] + pi[1:2 * m:2], pi[1:2 * m - 2:2] * pi[2:2 * m - 1:2]


def _right_product(block: np.ndarray):
    """x -> x @ block.T (block applied to each row of x); half the flops when the block is
    [[0, P], [Q, 0]], as the real form's forcing kron(J, G) is."""
    s = len(block)
    b = s // 2
    if s % 2 == 0 and not np.any(block[:b, :b]) and not np.any(block[b:, b:]):
        P, Q = np.ascontiguousarray(block[:b, b:].T), np.ascontiguousarray(block[b:, :b].T)
        return lambda x: np.concatenate([x[:, b:] @ P, x[:, :b] @ Q], axis=1)
    M = np.ascontiguousarray(block.T)
    return lambda x: x @ M


def _equal_to(blocks: np.ndarray, idx: np.ndarray, ref: np.ndarray) -> np.ndarray:
    """Mask of blocks[idx] == ref (a broadcast stack, stride 0, repeats one block)."""
    if blocks.strides[0] == 0:
        return np.full(idx.size, np.array_equal(blocks[0], ref))
    return np.all(blocks[idx] == ref, axis=(1, 2))


def coupling_rows(hill: HillMatrices, targets: np.ndarray):
    """padded x -> blocks ``targets`` of B x, where padded[k + 1] = x_k (zero at both ends).

    B repeats one lower and one upper block (the forcing), usually with upper = -lower:
    those rows take one product, (B x)_k = B_low (x_{k-1} - x_{k+1}); rows with other
    blocks (n = 0 of the real form) are done block by block."""
    K, s, _ = hill.diag.shape
    low, up = np.ascontiguousarray(hill.lower[-1]), np.ascontiguousarray(hill.upper[-1])
    has_low, has_up = targets >= 1, targets + 1 < K
    regular = np.ones(targets.size, dtype=bool)
    regular[has_low] &= _equal_to(hill.lower, targets[has_low] - 1, low)
    regular[has_up] &= _equal_to(hill.upper, targets[has_up], up)
    if hill.self_coupling is not None:
        regular &= ~np.any(hill.self_coupling[targets], axis=(1, 2))
    reg, odd = targets[regular], targets[~regular]
    zero = np.zeros((s, s), dtype=hill.lower.dtype)
    odd_low = np.array([hill.lower[t - 1] if t >= 1 else zero for t in odd]).reshape(-1, s, s)
    odd_up = np.array([hill.upper[t] if t + 1 < K else zero for t in odd]).reshape(-1, s, s)
    odd_self = np.array([zero if hill.self_coupling is None else hill.self_coupling[t]
                         for t in odd]).reshape(-1, s, s)
    difference = np.array_equal(up, -low)
    low_product, up_product = _right_product(low), _right_product(up)

    def apply(padded: np.ndarray) -> np.ndarray:
        r = np.empty((targets.size, s), dtype=padded.dtype)
        if difference:
            r[regular] = low_product(padded[reg] - padded[reg + 2])
        else:
            r[regular] = low_product(padded[reg]) + up_product(padded[reg + 2])
        if odd.size:
            r[~regular] = (odd_low @ padded[odd, :, None] + odd_up @ padded[odd + 2, :, None]
                           + odd_self @ padded[odd + 1, :, None])[:, :, 0]
        return r

    return apply


def _t_rows(hill: HillMatrices, inverses: BlockInverses, targets: np.ndarray):
    """padded x -> blocks ``targets`` of T x = A^{-1} B x (padded as in :func:`coupling_rows`)."""
    rows, solve = coupling_rows(hill, targets), inverses.solver(targets)
    return lambda padded: solve(rows(padded))


def krylov_operator(hill: HillMatrices,
                    inverses: BlockInverses) -> tuple[spla.LinearOperator, bool]:
    """(operator, squared): W on the even block positions if the pencil is bipartite
    (eigenvalues mu^2, squared = True), else T (eigenvalues mu); O(K s^2) per product."""
    K, s, _ = hill.diag.shape
    dtype = np.result_type(inverses.inv, hill.lower)
    if not hill.bipartite:
        rows = _t_rows(hill, inverses, np.arange(K))

        def t_matvec(v: np.ndarray) -> np.ndarray:
            padded = np.zeros((K + 2, s), dtype=dtype)
            padded[1:-1] = np.reshape(v, (K, s))
            return rows(padded).ravel()

        return spla.LinearOperator((K * s, K * s), matvec=t_matvec, dtype=dtype), False
    even, odd = np.arange(0, K, 2), np.arange(1, K, 2)
    to_odd, to_even = _t_rows(hill, inverses, odd), _t_rows(hill, inverses, even)

    def w_matvec(v: np.ndarray) -> np.ndarray:
        padded = np.zeros((K + 2, s), dtype=dtype)
        padded[even + 1] = np.reshape(v, (len(even), s))
        padded[odd + 1] = to_odd(padded)  # to_even reads only the odd positions
        return to_even(padded).ravel()

    n = len(even) * s
    return spla.LinearOperator((n, n), matvec=w_matvec, dtype=dtype), True


@dataclass(frozen=True, kw_only=True, eq=False)
class SmallestTaus:
    """Real tau >= 0 of one truncation found by :func:`smallest_taus`.

    tau : ascending; every real tau <= ``complete_to`` of the pencil is listed, and only those.
    complete_to : the radius r of the module notes (inf when every nonzero eigenvalue was found).
    n_eigenvalues : number of eigenvalues computed (the final k).
    """

    tau: np.ndarray
    complete_to: float
    n_eigenvalues: int


def arpack_restarts(products: float, k: int, ncv: int) -> int | None:
    """ARPACK's ``maxiter`` (implicit restarts) that keeps a run of ``eigs(k=k, ncv=ncv)``
    within about ``products`` operator products: ncv for the first Arnoldi factorisation, then
    ncv - k per restart; 0 when not even the first fits, None (ARPACK's default) for inf."""
    if not np.isfinite(products):
        return None
    if products < ncv:
        return 0
    return max(1, int((products - ncv) // max(ncv - k, 1)))


def _dominant(op: spla.LinearOperator, k: int, ncv: int,
              maxiter: int | None = None) -> np.ndarray | None:
    """The k (or k + 1, a conjugate pair) eigenvalues of largest modulus, by modulus descending;
    None when ARPACK has not converged within ``maxiter`` restarts (default: its own, 10 n)."""
    n = op.shape[0]
    v0 = np.random.default_rng(20240611).standard_normal(n).astype(op.dtype)
    try:
        lam = spla.eigs(op, k=k, which="LM", v0=v0, tol=0.0, ncv=ncv, maxiter=maxiter,
                        return_eigenvectors=False)
    except spla.ArpackNoConvergence:
        return None
    return lam[np.argsort(-np.abs(lam), kind="stable")]


class Counted(spla.LinearOperator):
    """A LinearOperator that counts its products (``products``)."""

    def __init__(self, op: spla.LinearOperator):
        super().__init__(dtype=op.dtype, shape=op.shape)
        self.op, self.products = op, 0

    def _matvec(self, x: np.ndarray) -> np.ndarray:
        self.products += 1
        return self.op.matvec(x)


def smallest_taus(hill: HillMatrices, *, tau_max: float = np.inf,
                  inverses: BlockInverses | None = None,
                  max_rounds: int | None = None,
                  max_products: float | None = None) -> SmallestTaus | None:
    """The smallest real tau >= 0 of a real-form Hill pencil by Arnoldi iteration; or of a
    bipartite complex one (the two-sided form of the subharmonic kind) by Arnoldi on its complex
    W, whose real mu^2 are classified as on the dense path (|Im mu^2| <= REAL_RTOL |mu^2|).

    Returns the real tau up to a radius r >= min(tau_min, tau_max), with every real tau <= r
    (module notes), or None when A is ill conditioned (see :func:`block_inverses`) or the Krylov
    space needed exceeds 1/KRYLOV_FRACTION of the operator's order (use dense eig then).
    ``max_rounds``: after that many values of k, return what is certified so far even if it is
    short of min(tau_min, tau_max): no real tau up to ``complete_to`` (a partial answer, the
    start of an interval cover, :mod:`spectralshell.solvers.shift_invert`).
    ``max_products``: give up (None) rather than apply the operator more often than this over
    all rounds (ARPACK's restarts are capped accordingly, :func:`arpack_restarts`). Uncapped,
    ARPACK may restart 10 n times where the dominant eigenvalues cluster: on one Fig 5.18
    point (gerbil, 116.9 Hz, sigma = 1.16e9; no real tau <= 1/2, so N rose to 141) 23 such runs
    took 290 s of the point's 392 s, most of them ending in the dense solve anyway.
    Cost: O(K s^3) for the block inverses (``inverses``, if already known), O(K s^2) per step.
    """
    if not (hill.is_real or hill.bipartite):
        raise ValueError("smallest_taus works on the real form (real arithmetic, exact real tau) "
                         "or on a bipartite complex one (W)")
    inverses = block_inverses(hill) if inverses is None else inverses
    if inverses is None:
        return None
    op, squared = krylov_operator(hill, inverses)
    n = op.shape[0]
    counted = Counted(op)
    k = K_START if squared else 2 * K_START  # T has each +-mu pair, W one mu^2
    rounds = 0
    while True:
        ncv = max(2 * k + 1, 4 * K_START)
        if KRYLOV_FRACTION * ncv > n:
            return None
        maxiter = arpack_restarts(np.inf if max_products is None
                                  else max_products - counted.products, k, ncv)
        if maxiter == 0:
            return None
        lam = _dominant(counted, k, ncv, maxiter)
        if lam is None:
            return None
        floor = 64 * np.finfo(float).eps * abs(lam[0])
        smallest = abs(lam[-1])
        radius = np.inf if smallest <= floor else smallest ** (-0.5 if squared else -1.0)
        if squared:
            tau = tau_from_squares(lam, floor, exact_real=hill.is_real)
        else:
            tau = np.sort(1.0 / lam.real[(lam.imag == 0.0) & (lam.real > floor)])
        if tau.size:  # every computed mu has |mu| >= the smallest: its tau lies within the
            radius = max(radius, float(tau[-1]))  # radius up to rounding (it may be the k-th)
        rounds += 1
        if tau.size or radius >= tau_max or rounds == max_rounds:
            return SmallestTaus(tau=tau, complete_to=float(radius), n_eigenvalues=len(lam))
        k *= 2
