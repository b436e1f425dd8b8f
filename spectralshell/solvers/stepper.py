"""Fixed-step IMEX integration of M dv/dt = L v + f(t) N v (model-agnostic).

The system is anything with attributes ``M``, ``L`` (dense arrays or scipy sparse matrices, n x n),
``N`` (same, or None) and ``forcing`` (a callable f(t) -> float, or None): L is treated implicitly,
f(t) N v explicitly, with a scheme of :mod:`spectralshell.solvers.imex`. Several explicit terms
sum_j f_j(t) N_j v can be given instead as ``explicit_terms`` = ((f_1, N_1), ...); an N_j needs
only ``shape`` and ``@`` (e.g. a matrix-free operator). M may be singular (an index-1
differential-algebraic system); no scheme needs M^{-1}.

Every step solves (a M - h b L) v = rhs with one of a few fixed matrices per scheme and step
size. Their LU factorisations are cached by content (a hash of M, L and the two coefficients), so
repeated runs of the same degree at the same step, e.g. the columns of a monodromy matrix or the
k = -m..m orders of one degree m, factorise once. The state v may be a matrix: its columns are
independent solutions stepped together.
"""

from __future__ import annotations

import functools
import hashlib
from collections import OrderedDict
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sparse
import scipy.sparse.linalg as spla
from scipy.linalg.lapack import dgetrs
from threadpoolctl import threadpool_limits

from .._validate import require_int_in_range, require_positive, require_real
from ..errors import ConvergenceError, ParameterError
from .imex import STARTER, Multistep, RungeKutta, scheme as get_scheme

CACHE_SIZE = 64
MAX_STEPS = 50_000_000


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


class _Factorisations:
    """LRU cache of LU factorisations of a M - h b L, keyed by content."""

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

    def solver(self, M, L, a: float, hb: float, digests: tuple[bytes, bytes]) -> Callable:
        key = (digests, float(a), float(hb))
        if key in self.store:
            self.hits += 1
            self.store.move_to_end(key)
            return self.store[key]
        self.misses += 1
        A = a * M - hb * L
        if sparse.issparse(A):
            lu = spla.splu(sparse.csc_matrix(A))
            solve = lu.solve
        else:
            lu = sla.lu_factor(np.asarray(A))
            if not np.all(np.isfinite(lu[0])) or np.min(np.abs(np.diag(lu[0]))) == 0.0:
                raise ConvergenceError(f"the implicit matrix a M - h b L (a = {a:g}, h b = {hb:g}) "
                                       "is singular: the system is not an index-1 DAE at this step")
            solve = functools.partial(_lu_solve, lu)
        self.store[key] = solve
        while len(self.store) > self.size:
            self.store.popitem(last=False)
        return solve


_CACHE = _Factorisations(CACHE_SIZE)


def _lu_solve(lu: tuple[np.ndarray, np.ndarray], rhs: np.ndarray) -> np.ndarray:
    """LAPACK getrs with a real LU factor (complex right-hand sides by parts); calling it
    directly saves most of scipy.linalg.lu_solve's per-call overhead on small systems."""
    if np.iscomplexobj(rhs):
        return _lu_solve(lu, rhs.real) + 1j * _lu_solve(lu, rhs.imag)
    x, info = dgetrs(lu[0], lu[1], rhs)
    if info != 0:                                  # pragma: no cover - LAPACK argument error
        raise ConvergenceError(f"LAPACK getrs failed (info = {info})")
    return x


def cache_info() -> dict[str, int]:
    """Hits, misses (= factorisations computed) and current size of the factorisation cache."""
    return {"hits": _CACHE.hits, "misses": _CACHE.misses, "size": len(_CACHE.store)}


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
        self.identity_M = (not sparse.issparse(self.M)
                           and np.array_equal(self.M, np.eye(n, dtype=np.asarray(self.M).dtype)))
        self.digests = (_Factorisations._digest(self.M), _Factorisations._digest(self.L))

    def solver(self, a: float, hb: float) -> Callable:
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
    """One step of an IMEX Runge-Kutta scheme, with its stage solvers fetched once."""

    def __init__(self, prob: _Problem, sch: RungeKutta, h: float) -> None:
        self.prob, self.h = prob, h
        self.AE, self.AI, self.c = sch.arrays()
        self.solvers = [None] + [prob.solver(1.0, h * self.AI[i, i])
                                 for i in range(1, self.AE.shape[0])]

    def step(self, t: float, v: np.ndarray) -> np.ndarray:
        prob, h, AE, AI = self.prob, self.h, self.AE, self.AI
        s = AE.shape[0]
        Mv0 = prob.mass(v)
        Fs: list = [prob.explicit(t, v)]
        Ls: list = [prob.L @ v]
        stage = v
        for i in range(1, s):
            rhs = Mv0.copy()
            for j in range(i):
                if AI[i, j]:
                    rhs += (h * AI[i, j]) * Ls[j]
                if AE[i, j] and Fs[j] is not None:
                    rhs += (h * AE[i, j]) * Fs[j]
            stage = self.solvers[i](rhs)
            if i < s - 1:
                Ls.append(prob.L @ stage)
                Fs.append(prob.explicit(t + self.c[i] * h, stage))
        return stage


class _Multistepper:
    """Ring buffers of M v, L v and F of the last s steps, and one step of a multistep scheme:
    rhs = sum_j (-a_j M v + h b_j L v + h c_j F)_{n+1-j} as one weighted sum per buffer."""

    def __init__(self, prob: _Problem, sch: Multistep, h: float) -> None:
        self.prob = prob
        a, b, c = sch.arrays()
        self.s = len(a) - 1
        self.solve = prob.solver(a[0], h * b[0])
        self.weights = {"M": -a[1:], "L": h * b[1:], "F": h * c[1:]}
        if not np.any(b[1:]):
            del self.weights["L"]
        if not prob.terms:
            del self.weights["F"]
        # lags[p][q]: age (0 = newest) of buffer slot q when the newest value sits in slot p
        self.lags = [(p - np.arange(self.s)) % self.s for p in range(self.s)]
        self.buffers: dict[str, np.ndarray] = {}
        self.count = 0

    def push(self, t: float, v: np.ndarray) -> None:
        """Record the newest value v = v(t)."""
        p = self.count % self.s
        if not self.buffers:
            self.buffers = {k: np.zeros((self.s,) + v.shape, dtype=v.dtype) for k in self.weights}
        for key, buf in self.buffers.items():
            buf[p] = (self.prob.mass(v) if key == "M" else self.prob.L @ v if key == "L"
                      else self.prob.explicit(t, v))
        self.count += 1

    def step(self) -> np.ndarray:
        lag = self.lags[(self.count - 1) % self.s]
        rhs = None
        for key, buf in self.buffers.items():
            term = np.tensordot(self.weights[key][lag], buf, axes=1)
            rhs = term if rhs is None else rhs + term
        return self.solve(rhs)


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
    observe : what to save, a function of the state (default: the state).
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
    with threadpool_limits(limits=1), np.errstate(over="ignore", invalid="ignore"):
        return _integrate(system, v0, scheme=scheme, dt=dt, t_end=t_end, t0=t0, every=every,
                          observe=observe, progress=progress)   # overflow is checked, reported


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
    observe = observe or (lambda x: x.copy())
    times, values = [t0], [observe(v)]
    if isinstance(sch, RungeKutta):
        rk = _RungeKutta(prob, sch, h)
    else:
        starter = _RungeKutta(prob, get_scheme(STARTER), h)
        ms = _Multistepper(prob, sch, h)
        ms.push(t0, v)
    chunk = max(1, steps // 100)
    for n in range(1, steps + 1):
        t = t0 + (n - 1) * h
        if isinstance(sch, RungeKutta):
            v = rk.step(t, v)
        elif n < sch.steps:
            v = starter.step(t, v)
            ms.push(t + h, v)
        else:
            v = ms.step()
            ms.push(t + h, v)
        if n % every == 0 or n == steps:
            if not np.all(np.isfinite(v)):
                raise ConvergenceError(
                    f"the state is no longer finite at t = {t + h:.6g} ({sch.name}, dt = {h:.3g}): "
                    "the step exceeds the stability limit of the explicit term; reduce dt")
            times.append(t0 + n * h)
            values.append(observe(v))
        if progress is not None and (n % chunk == 0 or n == steps):
            progress(chunk if n % chunk == 0 else n % chunk)
    return Run(times=np.array(times), values=np.array(values), final=v, dt=h, steps=steps,
               scheme=sch.name)
