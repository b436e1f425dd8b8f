"""Fixed-step IMEX integration of M dv/dt = L v + f(t) N v (model-agnostic).

The system is anything with attributes ``M``, ``L`` (dense arrays or scipy sparse matrices, n x n),
``N`` (same, or None) and ``forcing`` (a callable f(t) -> float, or None): L is treated implicitly,
f(t) N v explicitly, with a scheme of :mod:`spectralshell.solvers.imex`. Several explicit terms
sum_j f_j(t) N_j v can be given instead as ``explicit_terms`` = ((f_1, N_1), ...); an N_j needs
only ``shape`` and ``@`` (e.g. a matrix-free operator). M may be singular (an index-1
differential-algebraic system); no scheme needs M^{-1}.

Every step solves (a M - h b L) v = rhs with one of a few fixed matrices per scheme and step
size. They are factorised once and cached by content (a hash of M, L and the two coefficients), so
repeated runs of the same degree at the same step, e.g. the columns of a monodromy matrix or the
k = -m..m orders of one degree m, factorise once. A dense matrix of size <= ``INVERSE_MAX`` is
inverted explicitly (to working precision, see ``_inverse``), so that a solve is one
matrix-vector product: the same n^2 multiply-adds as the two triangular solves of its LU factor,
but 1.5 to 2 times faster per step on the sphere's systems (sizes 31..511, measured in
validation/bench_stepper.py); its set-up costs 2 to 10 times the LU factor's, repaid after about
100-400 steps at size 31 and 1000-4000 steps at sizes 255-383, so INVERSE_MAX covers the sizes the
sphere's automatic radial resolution chooses (<= 319). Larger dense matrices keep their LU factor
(LAPACK getrs), sparse ones a SuperLU factor, computed first in the matrices' own order without
row interchanges (``_sparse_factor``: O(nnz) fill for the almost-banded systems of
discretise/sphere_banded.py, whose rows and unknowns are stored for it) and checked by its
backward error, else with COLAMD and partial pivoting; their products with M, L and N are sparse,
so a step costs O(nnz). The state v may be a matrix: its columns are independent solutions
stepped together.

Singular M. Every scheme is allowed on an index-1 DAE: a multistep step solves
(a_0 M - h b_0 L) v_{n+1} = rhs, whose algebraic rows impose the constraints on v_{n+1} (SBDF;
CNAB2/MCNAB2 the average of the constraint over the step, which keeps a consistent state
consistent: their first step is the starter's), with an explicit term extrapolated as in the
differential rows; the Runge-Kutta schemes (the multistep starter included) are stiffly
accurate with invertible diagonal AI_ii, so every stage solves its constraints likewise and
v_{n+1} is the last stage. An inconsistent v0 is projected by the first step. Observed orders on
the sphere's DAEs: tests/test_stepper.py (collocation, tau = 0) and tests/test_sphere_banded.py
(banded, forced).

Per-step work. A multistep step keeps the last s values of M v (v itself when M = I), of L v (only
for schemes with b_j != 0, j >= 1) and of F (only with explicit terms) as consecutive rows of one
array each, so its right-hand side is one (s weights) x (s rows) product per kind, and the new
state is written into the next row in place. Without explicit terms (tau = 0) nothing else is
evaluated: SBDFk costs one small product and one solve per step. A Runge-Kutta stage obtains
h AI_ii L v_i from its own implicit equation, h AI_ii L v_i = M v_i - rhs_i, instead of a
product with L (equal in exact arithmetic; the rounding is that of the solve), and the last
stage's value is carried into the next step's stage 0 (v_{n+1} = v_s, stiffly accurate schemes).
"""

from __future__ import annotations

import hashlib
import math
from collections import OrderedDict
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sparse
import scipy.sparse.linalg as spla
from scipy.linalg.lapack import dgetri, dgetrs

try:                                    # SciPy's CSR product kernels (y += A x), used in place
    from scipy.sparse._sparsetools import csr_matvec as _csr_matvec
    from scipy.sparse._sparsetools import csr_matvecs as _csr_matvecs
except ImportError:                     # pragma: no cover - private module moved: A @ x instead
    _csr_matvec = _csr_matvecs = None

from .._threads import one_blas_thread
from .._validate import require_int_in_range, require_positive, require_real
from ..errors import ConvergenceError, ParameterError
from .imex import STARTER, Multistep, RungeKutta, scheme as get_scheme

CACHE_SIZE = 64
MAX_STEPS = 50_000_000
INVERSE_MAX = 320       # dense implicit matrices up to this size are inverted explicitly
HISTORY_ROWS = 256      # multistep history rows written before the last s are moved to the front,
HISTORY_BYTES = 1 << 22  # ... fewer for large states (matrix states): at most ~4 MB per history
SPARSE_BACKWARD = 1e-13  # backward error accepted from a sparse LU without row interchanges


@dataclass(frozen=True, kw_only=True, eq=False)
class Run:
    """A fixed-step run: observed values at the saved times and the final state.

    Attributes
    ----------
    times : (n_saved,) saved times t0, t0 + every h, ..., always ending at t_end.
    values : (n_saved, ...) ``observe(v)`` at those times (v itself by default).
    final : the state at t_end.
    dt : the step h actually used ((t_end - t0) / steps).
    steps : number of steps. scheme : the scheme's name.
    """

    times: np.ndarray
    values: np.ndarray
    final: np.ndarray
    dt: float
    steps: int
    scheme: str


def _leading_bits(A: np.ndarray, bits: int, axis: int) -> np.ndarray:
    """The part of A on a grid of 2^(e + 1 - bits), e the exponent (max |A| < 2^e) of each row
    (axis=1) or column (axis=0): at most ``bits`` significant bits per entry. Extraction
    fl(fl(A + sigma) - sigma), sigma = 2^(e + 53 - bits) (Rump, Ogita and Oishi 2008); A minus it
    is exact."""
    _, e = np.frexp(np.max(np.abs(A), axis=axis, keepdims=True))
    sigma = np.ldexp(1.0, e + 53 - bits)
    return (A + sigma) - sigma


def _inverse(A: np.ndarray, lu: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """A^{-1} to working precision: X from LAPACK getri, then one correction X + X R with the
    residual R = I - A X evaluated free of the cancellation that spoils it in double precision.

    With A1, X1 the leading ``bits`` bits of A (row i: |A1| <= 2^a_i) and X (column j:
    |X1| <= 2^x_j), 2 bits + log2 n <= 53, every product A1_ik X1_kj and every partial sum of
    them in entry (i, j) is an integer multiple of 2^(a_i + x_j + 2 - 2 bits) and below 2^51 such
    units, so the BLAS product A1 @ X1 is exact in any summation order; the rest,
    A1 (X - X1) + (A - A1) X, is 2^-bits smaller and its rounding negligible. A plain getri
    inverse is as accurate per solve as the LU factor, but its error is the same every step and
    adds up: on a 31-unknown sphere system (tests) it moved an SBDF3 trajectory 1.5e-12 (relative)
    from a 40-digit one, the corrected inverse 2e-15 and the LU solves 4e-13."""
    X, info = dgetri(*lu)
    if info != 0:                                  # pragma: no cover - singular A is refused before
        raise ConvergenceError(f"LAPACK getri failed (info = {info})")
    n = A.shape[0]
    bits = (53 - int(np.ceil(np.log2(max(n, 2))))) // 2
    A1, X1 = _leading_bits(A, bits, 1), _leading_bits(X, bits, 0)
    R = (np.eye(n) - A1 @ X1) - (A1 @ (X - X1) + (A - A1) @ X)
    corrected = X + X @ R
    return np.ascontiguousarray(corrected if np.all(np.isfinite(corrected)) else X)


class _Solver:
    """x = A^{-1} rhs for one fixed implicit matrix A = a M - h b L (real), factorised once:
    explicit inverse (dense, size <= INVERSE_MAX), LU factor (larger dense) or SuperLU (sparse)."""

    def __init__(self, A, a: float, hb: float) -> None:
        self.inverse = self.lu = self.sparse_lu = None
        if sparse.issparse(A):
            self.sparse_lu = _sparse_factor(sparse.csc_matrix(A, dtype=float))
            return
        lu = sla.lu_factor(np.asarray(A))
        if not np.all(np.isfinite(lu[0])) or np.min(np.abs(np.diag(lu[0]))) == 0.0:
            raise ConvergenceError(f"the implicit matrix a M - h b L (a = {a:g}, h b = {hb:g}) "
                                   "is singular: the system is not an index-1 DAE at this step")
        if lu[0].shape[0] <= INVERSE_MAX:
            self.inverse = _inverse(np.asarray(A, dtype=float), lu)
        else:
            self.lu = lu

    def __call__(self, rhs: np.ndarray) -> np.ndarray:
        """A^{-1} rhs for rhs of shape (n,) or (n, k), real or complex (by parts)."""
        if np.iscomplexobj(rhs):
            return self(rhs.real) + 1j * self(rhs.imag)
        if self.inverse is not None:
            return np.dot(self.inverse, rhs)
        if self.lu is not None:
            x, info = dgetrs(self.lu[0], self.lu[1], rhs)
            if info != 0:                          # pragma: no cover - LAPACK argument error
                raise ConvergenceError(f"LAPACK getrs failed (info = {info})")
            return x
        return self.sparse_lu.solve(np.asarray(rhs, dtype=float))

    def into(self, rhs: np.ndarray, out: np.ndarray) -> None:
        """out = A^{-1} rhs for real C-contiguous rhs and out of shape (n,) or (n, k)."""
        if self.inverse is not None:
            np.dot(self.inverse, rhs, out=out)
        else:
            out[...] = self(rhs)


def _sparse_factor(A: sparse.csc_matrix):
    """SuperLU factor of a sparse A: first in the given order with diagonal pivots (no row
    interchanges), which keeps the fill O(nnz) for matrices stored banded with their few dense
    boundary rows last (discretise/sphere_banded.py: partial pivoting there would pick the dense
    rows and fill the factor with O(n^2) entries), kept if a solve of a random right-hand side
    has a normwise backward error <= ``SPARSE_BACKWARD``; otherwise (unstable or singular
    without pivoting) the default COLAMD order with partial pivoting."""
    n = A.shape[0]
    try:
        lu = spla.splu(A, permc_spec="NATURAL", diag_pivot_thresh=0.0)
        b = np.random.default_rng(0).standard_normal(n)
        x = lu.solve(b)
        scale = spla.norm(A, np.inf) * np.max(np.abs(x)) + np.max(np.abs(b))
        if np.all(np.isfinite(x)) and np.max(np.abs(A @ x - b)) <= SPARSE_BACKWARD * scale:
            return lu
    except RuntimeError:                          # exactly singular without row interchanges
        pass
    try:
        return spla.splu(A)
    except RuntimeError as exc:
        raise ConvergenceError(f"the sparse implicit matrix is singular ({exc}): the system is "
                               "not an index-1 DAE at this step") from exc


class _Factorisations:
    """LRU cache of the solvers of a M - h b L, keyed by content."""

    def __init__(self, size: int) -> None:
        self.size = size
        self.store: OrderedDict = OrderedDict()
        self.hits = 0
        self.misses = 0

    @staticmethod
    def _digest(A) -> bytes:
        h = hashlib.blake2b(digest_size=16)
        if sparse.issparse(A):
            A = A.tocsr()
            for part in (A.data, A.indices, A.indptr):
                h.update(np.ascontiguousarray(part).tobytes())
            h.update(str(A.shape).encode())
        else:
            A = np.ascontiguousarray(A)
            h.update(A.tobytes())
            h.update(str((A.shape, A.dtype)).encode())
        return h.digest()

    def solver(self, M, L, a: float, hb: float, digests: tuple[bytes, bytes]) -> _Solver:
        key = (digests, float(a), float(hb))
        if key in self.store:
            self.hits += 1
            self.store.move_to_end(key)
            return self.store[key]
        self.misses += 1
        solve = _Solver(a * M - hb * L, a, hb)
        self.store[key] = solve
        while len(self.store) > self.size:
            self.store.popitem(last=False)
        return solve


_CACHE = _Factorisations(CACHE_SIZE)


def cache_info() -> dict[str, int]:
    """Hits, misses (= factorisations computed) and current size of the factorisation cache."""
    return {"hits": _CACHE.hits, "misses": _CACHE.misses, "size": len(_CACHE.store)}


def cache_clear() -> None:
    """Drop every cached factorisation (e.g. to time runs that factorise afresh)."""
    _CACHE.store.clear()


def _is_identity(M) -> bool:
    n = M.shape[0]
    if sparse.issparse(M):
        return (M != sparse.identity(n, format="csr")).nnz == 0
    return np.array_equal(M, np.eye(n, dtype=np.asarray(M).dtype))


class _Problem:
    """The system's matrices and explicit term, with content digests for the cache."""

    def __init__(self, system: Any) -> None:
        self.M, self.L = system.M, system.L
        n = self.M.shape[0]
        if self.M.shape != (n, n) or self.L.shape != (n, n):
            raise ParameterError(f"system matrices M {self.M.shape} and L {self.L.shape} are "
                                 "invalid: must be square and of equal size")
        terms = getattr(system, "explicit_terms", None)
        if terms is None:
            N, f = getattr(system, "N", None), getattr(system, "forcing", None)
            terms = () if N is None or f is None else ((f, N),)
        for _, N in terms:
            if tuple(N.shape) != (n, n):
                raise ParameterError(f"system matrix N {N.shape} is invalid: must be {n} x {n}")
        self.terms = tuple(terms)
        self.n = n
        self.identity_M = _is_identity(self.M)
        self.digests = (_Factorisations._digest(self.M), _Factorisations._digest(self.L))

    def solver(self, a: float, hb: float) -> _Solver:
        return _CACHE.solver(self.M, self.L, a, hb, self.digests)

    def mass(self, v: np.ndarray) -> np.ndarray:
        """M v (v itself when M = I)."""
        return v if self.identity_M else self.M @ v

    def explicit(self, t: float, v: np.ndarray) -> np.ndarray | None:
        """sum_j f_j(t) N_j v, or None without explicit terms."""
        out = None
        for f, N in self.terms:
            term = f(t) * (N @ v)
            out = term if out is None else out + term
        return out


class _RungeKutta:
    """Steps of an IMEX Runge-Kutta scheme, with its stage solvers fetched once.

    Stage i solves (M - h AI_ii L) v_i = rhs_i; then h L v_i = (M v_i - rhs_i) / AI_ii feeds the
    later stages, and h L v_s (v_s = v_{n+1}) the next step's stage 0."""

    def __init__(self, prob: _Problem, sch: RungeKutta, h: float) -> None:
        self.prob, self.h = prob, h
        AE, AI, self.c = sch.arrays()
        self.s = AE.shape[0] - 1
        self.solvers = [None] + [prob.solver(1.0, h * AI[i, i]) for i in range(1, self.s + 1)]
        # per stage i, (j, weight) pairs: AI_ij on h L v_j, h AE_ij on F_j
        self.implicit = [[(j, AI[i, j]) for j in range(i) if AI[i, j]] for i in range(self.s + 1)]
        self.explicit = [[(j, h * AE[i, j]) for j in range(i) if AE[i, j]]
                         for i in range(self.s + 1)]
        self.diagonal = AI.diagonal()
        self._last: tuple[np.ndarray, np.ndarray] | None = None     # (v_n, h L v_n)

    def step(self, t: float, v: np.ndarray) -> np.ndarray:
        prob = self.prob
        Mv0 = prob.mass(v)
        hLv = [self._last[1] if self._last is not None and self._last[0] is v
               else self.h * (prob.L @ v)]
        F: list = [prob.explicit(t, v)]
        stage = v
        for i in range(1, self.s + 1):
            rhs = Mv0.copy()
            for j, w in self.implicit[i]:
                rhs += w * hLv[j]
            if F[0] is not None:
                for j, w in self.explicit[i]:
                    rhs += w * F[j]
            stage = self.solvers[i](rhs)
            hLv.append((prob.mass(stage) - rhs) / self.diagonal[i])
            if i < self.s and F[0] is not None:
                F.append(prob.explicit(t + self.c[i] * self.h, stage))
        self._last = (stage, hLv[-1])
        return stage

    def advance(self, t: float, v: np.ndarray, count: int) -> np.ndarray:
        """The state after ``count`` steps from v(t)."""
        for i in range(count):
            v = self.step(t + i * self.h, v)
        return v


class _Rows:
    """A history array (rows = flattened states) and, for the BLAS calls, each row viewed as a
    real (n,) or (n, width) array (complex columns as pairs of real ones)."""

    def __init__(self, rows: int, n: int, template: np.ndarray) -> None:
        self.data = np.zeros((rows, template.size), dtype=template.dtype)
        width = (1 if template.ndim == 1 else template.shape[1]) * (
            2 if np.iscomplexobj(template) else 1)
        flat = (n,) if width == 1 else (n, width)
        self.real = [row.view(float).reshape(flat) for row in self.data]
        self.shape = template.shape

    def state(self, k: int) -> np.ndarray:
        return self.data[k].reshape(self.shape)


def _product(A, x: _Rows, out: _Rows) -> Callable[[int, int], None]:
    """(k, j) -> (out row j = A x row k): in place for a real dense A and, by SciPy's CSR kernels
    (``csr_matvec(s)``, which accumulate into the row), for a real CSR matrix: A @ costs ~5-10 us
    of dispatch and allocation per call, more than the product on the sphere's banded systems;
    otherwise by A @ (other sparse formats, operators)."""
    if isinstance(A, np.ndarray) and A.dtype == float:
        dot, xs, outs = np.dot, x.real, out.real
        return lambda k, j: dot(A, xs[k], out=outs[j])
    if _csr_matvecs is not None and sparse.issparse(A) and A.format == "csr" \
            and A.dtype == float:
        (rows, cols), xs, outs = A.shape, x.real, out.real
        ptr, idx, val = A.indptr, A.indices, A.data

        def product(k: int, j: int) -> None:
            target, source = outs[j], xs[k]
            target.fill(0.0)
            if source.ndim == 1:
                _csr_matvec(rows, cols, ptr, idx, val, source, target)
            else:
                _csr_matvecs(rows, cols, source.shape[1], ptr, idx, val, source, target)
        return product
    return lambda k, j: out.data.__setitem__(j, np.asarray(A @ x.state(k)).reshape(-1))


class _Multistepper:
    """A multistep scheme on a sliding history: rows k-s..k-1 of each history hold M v (the states
    themselves when M = I), L v and F at t_{n+1-s}..t_n (oldest first), so that

        rhs = sum_j (-a_j M v + h b_j L v + h c_j F)_{n+1-j}

    is one (weights) x (rows) product per history, and v_{n+1} is solved into row k of the states.
    After HISTORY_ROWS steps (fewer for states above HISTORY_BYTES / HISTORY_ROWS bytes) the last s
    rows move to the front. The first s - 1 steps are taken by the STARTER Runge-Kutta scheme."""

    def __init__(self, prob: _Problem, sch: Multistep, h: float, t0: float,
                 v0: np.ndarray) -> None:
        a, b, c = sch.arrays()
        s = self.s = len(a) - 1
        self.prob, self.h, self.t0 = prob, h, t0
        self.cap = s + max(1, min(HISTORY_ROWS, HISTORY_BYTES // v0.nbytes))
        self.states = _Rows(self.cap, prob.n, v0)
        self.solve = prob.solver(a[0], h * b[0])
        # weight of v_{n+1-j} at row position s - j (oldest first); each history: (weights, rows,
        # what fills a row: None for the states themselves, a matrix, or "F")
        histories = [(-a[:0:-1], None if prob.identity_M else prob.M)]
        if np.any(b[1:]):
            histories.append((h * b[:0:-1], prob.L))
        if prob.terms:
            histories.append((h * c[:0:-1], "F"))
        self.histories = [(w.astype(v0.dtype), self.states if what is None
                           else _Rows(self.cap, prob.n, v0), what) for w, what in histories]
        self.rhs = _Rows(1, prob.n, v0)
        self.tmp = _Rows(1, prob.n, v0)
        self.writers = [self._writer(rows, what) for _, rows, what in self.histories
                        if what is not None]
        self.starter = _RungeKutta(prob, get_scheme(STARTER), h)
        self.done = 0
        self.k = 0
        self.states.data[0] = v0.reshape(-1)
        self._fill(0)

    def _writer(self, rows: _Rows, what) -> Callable[[int, float], None]:
        """(k, t) -> row k of a history (M v, L v or F at time t) from state row k."""
        if not isinstance(what, str):
            product = _product(what, self.states, rows)
            return lambda k, t: product(k, k)
        (f, N), *more = self.prob.terms            # F = sum_j f_j(t) N_j v
        first = _product(N, self.states, rows)
        others = [(g, _product(B, self.states, self.tmp)) for g, B in more]
        data, extra = rows.data, self.tmp.data[0]

        def write(k: int, t: float) -> None:
            first(k, k)
            data[k] *= f(t)
            for g, product in others:
                product(k, 0)                        # into the one row of tmp
                data[k] += g(t) * extra
        return write

    def _fill(self, k: int) -> None:
        """Rows k of the M v, L v and F histories from state row k (at t0 + done h)."""
        t = self.t0 + self.done * self.h
        for write in self.writers:
            write(k, t)
        self.k = k + 1

    def current(self) -> np.ndarray:
        """The newest state (a view into the history)."""
        return self.states.state(self.k - 1)

    def advance(self, count: int) -> np.ndarray:
        """The state after ``count`` further steps."""
        while count > 0 and self.done < self.s - 1:
            v = self.starter.step(self.t0 + self.done * self.h, self.current())
            self.done += 1
            self.states.data[self.k] = v.reshape(-1)
            self._fill(self.k)
            count -= 1
        if count > 0:
            self._steps(count)
        return self.current()

    def _steps(self, count: int) -> None:
        s, cap, dot = self.s, self.cap, np.dot
        rhs, tmp, solve = self.rhs.data[0], self.tmp.data[0], self.solve.into
        rhs_real, rows_real = self.rhs.real[0], self.states.real
        (w0, first, _), *rest = self.histories
        writers, t0, h, done = self.writers, self.t0, self.h, self.done
        k = self.k
        for _ in range(count):
            if k == cap:                          # move the last s rows to the front
                for _, rows, _ in self.histories:
                    rows.data[:s] = rows.data[cap - s:]
                k = s
            dot(w0, first.data[k - s:k], out=rhs)
            for w, rows, _ in rest:
                dot(w, rows.data[k - s:k], out=tmp)
                rhs += tmp
            solve(rhs_real, rows_real[k])
            done += 1
            for write in writers:
                write(k, t0 + done * h)
            k += 1
        self.k, self.done = k, done


def integrate(system: Any, v0, *, scheme: str, dt: float, t_end: float, t0: float = 0.0,
              every: int = 1, observe: Callable[[np.ndarray], np.ndarray] | None = None,
              progress: Callable[[int], None] | None = None) -> Run:
    """Step M dv/dt = L v + f(t) N v from v(t0) = v0 to t_end with a fixed step.

    Parameters
    ----------
    system : object with ``M``, ``L``, ``N``, ``forcing`` (see the module docstring).
    v0 : initial state, shape (n,) or (n, columns). For a DAE it should satisfy the algebraic rows
        (otherwise the first step projects it).
    scheme : a name of :data:`spectralshell.solvers.imex.SCHEMES`.
    dt : requested step; the step used is (t_end - t0) / ceil((t_end - t0) / dt), so that the run
        ends exactly at t_end.
    every : save every ``every``-th step (t0 and t_end are always saved).
    observe : what to save, a function of the state (default: the state); its result is copied.
    progress : called with the number of steps done since the last call (e.g. tqdm.update).

    Notes
    -----
    Multistep schemes take their first s - 1 steps with the one-step scheme
    :data:`~spectralshell.solvers.imex.STARTER`.

    Raises
    ------
    ParameterError : bad dt, interval, every, scheme or shapes.
    ConvergenceError : the state stopped being finite (the step is beyond the scheme's stability
        limit for the explicit term), or the implicit matrix is singular.

    The run uses one BLAS thread (the matrices are small: threads only add synchronisation).
    """
    with one_blas_thread(), np.errstate(over="ignore", invalid="ignore"):
        return _integrate(system, v0, scheme=scheme, dt=dt, t_end=t_end, t0=t0, every=every,
                          observe=observe, progress=progress)   # overflow is checked, reported


def _finite(v: np.ndarray) -> bool:
    """All entries finite (sum |v_i|^2 first: one BLAS pass for the usual finite case)."""
    return math.isfinite(abs(np.vdot(v, v))) or bool(np.all(np.isfinite(v)))


def _integrate(system: Any, v0, *, scheme, dt, t_end, t0, every, observe, progress) -> Run:
    sch = get_scheme(scheme)
    dt = require_positive("dt", dt)
    t0, t_end = require_real("t0", t0), require_real("t_end", t_end)
    if not t_end > t0:
        raise ParameterError(f"t_end = {t_end!r} is invalid: must be > t0 = {t0!r}")
    steps = int(np.ceil((t_end - t0) / dt * (1 - 1e-12)))
    steps = require_int_in_range("number of steps (t_end - t0) / dt", max(steps, 1), 1, MAX_STEPS)
    every = require_int_in_range("every", every, 1)
    h = (t_end - t0) / steps
    prob = _Problem(system)
    v = np.array(v0, dtype=float if np.isrealobj(v0) else complex)
    if v.shape[0] != prob.n or v.ndim > 2:
        raise ParameterError(f"v0 shape {v.shape} is invalid: must be ({prob.n},) or "
                             f"({prob.n}, columns)")
    observe = observe or (lambda x: x)
    times, values = [t0], [np.array(observe(v))]
    if isinstance(sch, RungeKutta):
        rk = _RungeKutta(prob, sch, h)
        advance = lambda n, v, count: rk.advance(t0 + n * h, v, count)  # noqa: E731
    else:
        ms = _Multistepper(prob, sch, h, t0, v)
        advance = lambda n, v, count: ms.advance(count)                 # noqa: E731
    chunk = max(1, steps // 100)
    n = 0
    while n < steps:       # step to the next save or progress point
        stop = min(steps, (n // every + 1) * every, (n // chunk + 1) * chunk)
        v = advance(n, v, stop - n)
        n = stop
        if n % every == 0 or n == steps:
            if not _finite(v):
                raise ConvergenceError(
                    f"the state is no longer finite at t = {t0 + n * h:.6g} ({sch.name}, "
                    f"dt = {h:.3g}): the step exceeds the stability limit of the explicit term; "
                    "reduce dt")
            times.append(t0 + n * h)
            values.append(np.array(observe(v)))
        if progress is not None and (n % chunk == 0 or n == steps):
            progress(chunk if n % chunk == 0 else n % chunk)
    return Run(times=np.array(times), values=np.array(values), final=np.array(v), dt=h,
               steps=steps, scheme=sch.name)
