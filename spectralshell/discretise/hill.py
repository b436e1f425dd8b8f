"""Hill matrices: the truncated generalised eigenproblem A v = tau B v for any model.

One assembler serves every model. The model supplies D(s) and G of
D(s_n) u_n = i tau G (u_{n-1} - u_{n+1}) (see :mod:`spectralshell.models.base`; thesis (2.6)), so
A is block diagonal with the blocks D(s_n) and B is block tridiagonal, coupling n only to n +- 1.
Both are stored as arrays of equal-size blocks: ``diag`` (K, s, s) for A, and for B ``lower``
(coupling of row block k to k - 1), ``upper`` (to k + 1) and, where present, ``self_coupling``.

Two forms, with identical finite spectra (packing in :mod:`spectralshell.discretise.fourier`):

* ``"real"``: reality conditions (2.7)/(2.8) applied, n = 0..N, blocks of size s = 2b acting on
  [Re u_n, Im u_n]. With D = D_r + i D_i and J = [[0, -1], [1, 0]], splitting (2) into real and
  imaginary parts gives A_n = [[D_r, -D_i], [D_i, D_r]], lower = kron(J, G), upper = -kron(J, G).
  At n = 0 the reflected neighbour enters:
  harmonic, u_{-1} = conj u_1: D(0) Re u_0 = 2 G Im u_1, so upper_0 = [[0, 2G], [0, 0]]; u_0 is real,
  and the slot of Im u_0 carries the row Im u_0 = 0 (A_0 = diag(D(0), I), B row zero: one infinite
  eigenvalue, as in the thesis's A_0 = I_2 with the zero second row of its B-hat/B-tilde);
  subharmonic, u_{-1} = conj u_0: i G conj(u_0) gives self_coupling_0 = [[0, G], [G, 0]].
  (The thesis's blocks are these multiplied by -i/kappa, a row scaling that leaves tau unchanged.)
* ``"two-sided"``: complex, k = -N..N (harmonic) or -N-1..N (subharmonic), s = b,
  lower = i G, upper = -i G, no self-coupling. An independent check of the packing, and, being
  bipartite for both kinds, the form of the fast subharmonic solver. With a ``shift`` g the
  blocks are D(g + s_k): the pencil at the Floquet exponent gamma = g + i GAMMA[kind], whose
  singular points in g at a given tau are the exponents (:mod:`spectralshell.solvers.hill_exponents`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from ..models.base import HillSystem
from .fourier import check_kind, truncation_frequencies

FORMS = ("real", "two-sided")


@dataclass(frozen=True, kw_only=True, eq=False)
class HillMatrices:
    """A truncated Hill pencil A v = tau B v in block-tridiagonal storage.

    Attributes
    ----------
    kind, form, n_temporal : what was assembled.
    diag : (K, s, s) diagonal blocks of A.
    lower, upper : (K - 1, s, s) blocks B_{k,k-1} and B_{k,k+1}.
    self_coupling : (K, s, s) diagonal blocks of B, or None when they all vanish (then B couples
        only neighbouring Fourier indices and the pencil is bipartite).
    parent : the pencil this one was cut out of (:meth:`truncated`), or None; a structure
        checked on the parent (:attr:`reflected`, :attr:`mirrored`, :attr:`negated`) holds for
        the cut, which then skips its own check.
    """

    kind: str
    form: str
    n_temporal: int
    diag: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    self_coupling: np.ndarray | None
    # not an init field: dataclasses.replace (other blocks) must not inherit the parent's checks
    parent: HillMatrices | None = field(default=None, init=False, repr=False)

    @cached_property
    def reflected(self) -> bool:
        """Whether A_{K-1-k} = conj(A_k) exactly for every k, on complex blocks: the two-sided
        form of a model with D(conj s) = conj D(s) (the index reflection maps s_k to conj s_k:
        harmonic k -> -k, subharmonic k -> -k-1). Checked on the data, never assumed; a central
        cut (two-sided :meth:`truncated`) of a reflected pencil is reflected."""
        if self._central_cut_of("reflected"):
            return True
        K = len(self.diag)  # pairs (K-1-k, k) for k < K/2: the rest are the same comparisons
        return np.iscomplexobj(self.diag) and _blocks_equal(
            (self.diag[K - 1 - k], self.diag[k].conj()) for k in range(K // 2))

    @cached_property
    def mirrored(self) -> bool:
        """Whether the pencil is its own conjugate reflection: :attr:`reflected`, bipartite, and
        B_{K-1-k,K-2-k} = conj(B_{k,k+1}) exactly (then C-_{K-1-k} = conj(C+_k) and
        C+_{K-1-k} = conj(C-_k) for C-+_k = A_k^{-1} B_{k,k-+1})."""
        if self._central_cut_of("mirrored"):
            return True
        return self.bipartite and self.reflected and _blocks_equal(
            (low, up.conj()) for low, up in zip(self.lower[::-1], self.upper))

    @cached_property
    def negated(self) -> bool:
        """Whether B_{k,k+1} = -B_{k,k-1} exactly for every 0 < k < K - 1 (the forcing's
        i G, -i G); every cut of a negated pencil is negated."""
        if self.parent is not None and self.parent.negated:
            return True
        return _blocks_equal((up, -low) for up, low in zip(self.upper[1:], self.lower[:-1]))

    def _central_cut_of(self, structure: str) -> bool:
        """Whether this pencil is a central cut (two-sided form) of one with ``structure``."""
        return self.parent is not None and not self.is_real and getattr(self.parent, structure)

    @property
    def is_real(self) -> bool:
        return self.form == "real"

    @property
    def bipartite(self) -> bool:
        return self.self_coupling is None

    @cached_property
    def A(self) -> sp.csr_matrix:
        """A as a sparse matrix."""
        K, s, _ = self.diag.shape
        return sp.bsr_matrix((self.diag, np.arange(K), np.arange(K + 1)), shape=(K * s,) * 2).tocsr()

    @cached_property
    def B(self) -> sp.csr_matrix:
        """B as a sparse matrix."""
        K, s, _ = self.diag.shape
        rows = np.concatenate([np.arange(1, K), np.arange(K - 1)])
        cols = np.concatenate([np.arange(K - 1), np.arange(1, K)])
        data = [self.lower, self.upper]
        if self.self_coupling is not None:
            rows, cols = np.concatenate([rows, np.arange(K)]), np.concatenate([cols, np.arange(K)])
            data.append(self.self_coupling)
        data = np.concatenate(data)
        order = np.lexsort((cols, rows))
        indptr = np.searchsorted(rows[order], np.arange(K + 1))
        return sp.bsr_matrix((data[order], cols[order], indptr), shape=(K * s,) * 2).tocsr()

    def dense(self, tau: float) -> np.ndarray:
        """A - tau B as a dense (K s, K s) array."""
        K, s, _ = self.diag.shape
        out = np.zeros((K, s, K, s), dtype=np.result_type(self.diag, self.lower, 1j * tau))
        k = np.arange(K)
        out[k, :, k, :] = self.diag
        out[k[1:], :, k[:-1], :] = -tau * self.lower
        out[k[:-1], :, k[1:], :] = -tau * self.upper
        if self.self_coupling is not None:
            out[k, :, k, :] -= tau * self.self_coupling
        return out.reshape(K * s, K * s)

    def block_range(self, n_temporal: int) -> slice:
        """Block positions of the truncation ``n_temporal`` <= N inside this one: the leading
        blocks n = 0..n_temporal (real form) or the central ones (two-sided form)."""
        if not 1 <= n_temporal <= self.n_temporal:
            raise ValueError(f"n_temporal = {n_temporal!r} is invalid: "
                             f"must be in 1..{self.n_temporal}")
        if self.is_real:
            return slice(0, n_temporal + 1)
        K = len(self.diag) - 2 * (self.n_temporal - n_temporal)
        return slice(self.n_temporal - n_temporal, self.n_temporal - n_temporal + K)

    def truncated(self, n_temporal: int) -> HillMatrices:
        """The pencil ``assemble`` gives at the truncation ``n_temporal`` <= N, cut out of this
        one: every block depends only on its own Fourier index(es), so the smaller pencil is the
        sub-pencil on :meth:`block_range` (views, no copies)."""
        rows = self.block_range(n_temporal)
        couple = slice(rows.start, rows.stop - 1)
        self_coupling = None if self.self_coupling is None else self.self_coupling[rows]
        cut = HillMatrices(kind=self.kind, form=self.form, n_temporal=int(n_temporal),
                           diag=self.diag[rows], lower=self.lower[couple],
                           upper=self.upper[couple], self_coupling=self_coupling)
        object.__setattr__(cut, "parent", self)  # frozen: set once, here
        return cut


def _blocks_equal(pairs) -> bool:
    """Whether every pair of blocks is exactly equal; block by block, stopping at the first
    difference (one s x s temporary at a time: comparing whole stacks allocated K of them, 2-3x
    slower on the cochlea's M = 256 pencils)."""
    return all(np.array_equal(a, b) for a, b in pairs)


def realify(d: np.ndarray) -> np.ndarray:
    """Real 2b x 2b blocks [[Re d, -Im d], [Im d, Re d]] of complex (k, b, b) blocks."""
    k, b, _ = d.shape
    out = np.empty((k, 2 * b, 2 * b), dtype=d.real.dtype)
    out[:, :b, :b] = out[:, b:, b:] = d.real
    out[:, :b, b:] = -d.imag
    out[:, b:, :b] = d.imag
    return out


def _rotation_kron(G: np.ndarray) -> np.ndarray:
    """kron(J, G) = [[0 G, -G], [G, 0 G]], J = [[0, -1], [1, 0]], entry by entry as np.kron
    forms it (0 G keeps its signed zeros) at a fraction of np.kron's call overhead."""
    b = len(G)
    out = np.empty((2 * b, 2 * b))
    out[:b, :b] = out[b:, b:] = 0.0 * G
    out[:b, b:] = -G
    out[b:, :b] = G
    return out


def assemble(system: HillSystem, kind: str, n_temporal: int, form: str = "real", *,
             shift: complex = 0.0) -> HillMatrices:
    """Assemble the truncated Hill pencil of ``system`` for one Floquet ``kind``; with a
    ``shift`` g (two-sided form only) at the exponent g + i GAMMA[kind] instead.

    Notes
    -----
    Implements thesis (2.6) with the reality conditions (2.7)/(2.8) for a general block model; the
    module docstring derives each block. Cost: K evaluations of D(s) and O(K s^2) memory.
    """
    check_kind(kind)
    if form not in FORMS:
        raise ValueError(f"form = {form!r} is invalid: must be one of {FORMS}")
    if int(n_temporal) < 1:
        raise ValueError(f"n_temporal = {n_temporal!r} is invalid: must be an integer >= 1")
    if shift != 0 and form != "two-sided":
        raise ValueError(f"shift = {shift!r} is invalid for form = {form!r}: must be 0 (the real "
                         "form holds only the marginal exponents)")
    b = system.block_size
    G = np.asarray(system.forcing, dtype=float)
    self_coupling = None
    if form == "two-sided":
        s_k = truncation_frequencies(kind, n_temporal, two_sided=True)
        # C order: a model may return a strided stack (e.g. a broadcast cast), which every
        # block operation downstream would otherwise copy or walk with a large stride
        diag = np.ascontiguousarray(system.unforced(s_k + shift if shift != 0 else s_k),
                                    dtype=complex)
        lower = np.empty((len(s_k) - 1, b, b), dtype=complex)
        lower[...] = 1j * G
        upper = -lower
    else:
        D = np.asarray(system.unforced(truncation_frequencies(kind, n_temporal, two_sided=False)),
                       dtype=complex)
        JG = _rotation_kron(G)
        diag = realify(D)
        lower = np.broadcast_to(JG, (n_temporal, 2 * b, 2 * b))
        upper = np.full((n_temporal, 2 * b, 2 * b), -JG)
        if kind == "harmonic":  # diag[0] = [[D_r(0), 0], [0, I]], upper[0] = [[0, 2G], [0, 0]]
            diag[0, :b, b:] = diag[0, b:, :b] = 0.0
            diag[0, b:, b:] = np.eye(b)
            upper[0] = 0.0
            upper[0, :b, b:] = 2 * G
        else:  # self_coupling[0] = [[0, G], [G, 0]]
            self_coupling = np.zeros_like(diag)
            self_coupling[0, :b, b:] = self_coupling[0, b:, :b] = G
    return HillMatrices(kind=kind, form=form, n_temporal=int(n_temporal), diag=diag,
                        lower=lower, upper=upper, self_coupling=self_coupling)
