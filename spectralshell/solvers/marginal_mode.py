"""The Floquet solution at a marginal amplitude: the null vector of the Hill pencil A - tau B.

Model-agnostic. At a marginal tau (from :func:`spectralshell.solvers.marginal.marginal_tau`) the
truncated pencil of the two-sided complex form (:mod:`spectralshell.discretise.hill`) has a null
vector v = (u_k), k the two-sided Fourier indices; the periodic (harmonic) or antiperiodic
(subharmonic) solution is u(t) = sum_k u_k exp(i (gamma + k) t), gamma = 0 or 1/2, real up to a
constant complex factor (the reality conditions (2.7)/(2.8) map the null space onto itself).

Method: inverse iteration with the sparse LU factors of A - tau B (scipy.sparse.linalg.splu),
v <- (A - tau B)^{-1} B v, normalised, from a fixed pseudo-random start, until successive vectors
agree (up to phase) to 1e-10; tau is the marginal value itself, so one or two steps suffice. The
relative residual ||(A - tau B) v|| / (||A|| + |tau| ||B||) is reported.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse.linalg as spla

from ..discretise.fourier import GAMMA, two_sided_indices
from ..discretise.hill import assemble
from ..errors import ConvergenceError, ParameterError
from ..models.base import HillSystem


@dataclass(frozen=True, kw_only=True, eq=False)
class MarginalMode:
    """Fourier coefficients of the solution at a marginal tau.

    Attributes
    ----------
    kind, tau, n_temporal : what was solved.
    indices : two-sided Fourier indices k; coefficients : (len(indices), block_size) complex u_k,
        scaled so that the largest |u_k| entry is 1 and the solution is real.
    gamma : 0 (harmonic) or 1/2 (subharmonic): u(t) = sum_k u_k exp(i (gamma + k) t).
    residual : relative residual of the null vector.
    """

    kind: str
    tau: float
    n_temporal: int
    indices: np.ndarray
    coefficients: np.ndarray
    gamma: float
    residual: float

    def evaluate(self, t: np.ndarray) -> np.ndarray:
        """u(t) for times t, shape (len(t), block_size), real."""
        t = np.asarray(t, dtype=float)
        phase = np.exp(1j * np.outer(t, self.gamma + self.indices))
        return (phase @ self.coefficients).real


def _pencil(system: HillSystem, kind: str, n_temporal: int):
    """A and B of the two-sided form, complex CSC."""
    hill = assemble(system, kind, n_temporal, "two-sided")
    return hill.A.tocsc().astype(complex), hill.B.tocsc().astype(complex)


def _null_vector(A, B, tau: float, max_iter: int) -> tuple[np.ndarray, float]:
    """(v, relative residual): the unit null vector of A - tau B by inverse iteration.

    Raises ConvergenceError when the residual stays above 1e-8 (tau is not an eigenvalue)."""
    lu = spla.splu((A - tau * B).tocsc())
    v = np.random.default_rng(1).standard_normal(A.shape[0]) + 0j
    v /= np.linalg.norm(v)
    for _ in range(max_iter):
        w = lu.solve(B @ v)
        if not np.all(np.isfinite(w)) or not np.any(w):
            raise ConvergenceError(f"inverse iteration at tau = {tau:g} failed (singular B v)")
        w /= np.linalg.norm(w)
        change = min(np.linalg.norm(w - v * (np.vdot(v, w) / abs(np.vdot(v, w)))), 2.0) \
            if np.vdot(v, w) != 0 else 2.0
        v = w
        if change < 1e-10:
            break
    scale = spla.norm(A, 1) + abs(tau) * spla.norm(B, 1)
    residual = float(np.linalg.norm(A @ v - tau * (B @ v)) / scale)
    if residual > 1e-8:
        raise ConvergenceError(f"no null vector of A - tau B at tau = {tau:g} (relative residual "
                               f"{residual:.1e}): tau is not a marginal value of this truncation")
    return v, residual


def marginal_sensitivity(system: HillSystem, derivative: HillSystem, kind: str, tau: float,
                         n_temporal: int, *, max_iter: int = 8) -> float:
    """d tau / d eps at a simple marginal ``tau`` of a system D(s; eps), G(eps) whose derivative
    in eps is the system ``derivative`` (D' independent of s, G'), by the eigenvector formula

        d tau / d eps = w^H (A' - tau B') v / (w^H B v),

    v and w the right and left null vectors of the two-sided pencil A - tau B and A', B' the
    pencil of ``derivative`` (the assembly is linear in D and G).

    Raises
    ------
    ConvergenceError : tau is not a marginal value of this truncation; a complex result (tau
        not simple).
    """
    A, B = _pencil(system, kind, n_temporal)
    dA, dB = _pencil(derivative, kind, n_temporal)
    v, _ = _null_vector(A, B, tau, max_iter)
    w, _ = _null_vector(A.conj().T.tocsc(), B.conj().T.tocsc(), tau, max_iter)
    value = np.vdot(w, dA @ v - tau * (dB @ v)) / np.vdot(w, B @ v)
    if abs(value.imag) > 1e-6 * max(abs(value), 1e-300):
        raise ConvergenceError(f"d tau / d eps = {value:.6g} at tau = {tau:g} is not real: tau is "
                               "not a simple marginal value")
    return float(value.real)


def marginal_mode(system: HillSystem, kind: str, tau: float, n_temporal: int, *,
                  max_iter: int = 8) -> MarginalMode:
    """The solution at the marginal amplitude ``tau`` of ``kind`` (see the module docstring).

    Raises
    ------
    ConvergenceError : the inverse iteration did not settle (tau is not a simple marginal value
        of this truncation).
    """
    A, B = _pencil(system, kind, n_temporal)
    v, residual = _null_vector(A, B, tau, max_iter)
    return _real_mode(system, kind, tau, n_temporal, v, residual)


def _real_mode(system: HillSystem, kind: str, tau: float, n_temporal: int, v: np.ndarray,
               residual: float) -> MarginalMode:
    """The MarginalMode of a null vector v: rotated by the phase that maximises the norm of
    the solution's real part (then real), largest |u_k| entry 1."""
    k = two_sided_indices(kind, n_temporal)
    coef = v.reshape(len(k), system.block_size)
    t = np.linspace(0.0, 4 * np.pi, 64, endpoint=False)
    field = np.exp(1j * np.outer(t, GAMMA[kind] + k)) @ coef
    theta = 0.5 * np.angle(np.sum(field * field))
    coef = coef * np.exp(-1j * theta)
    coef /= np.abs(coef).max()
    return MarginalMode(kind=kind, tau=float(tau), n_temporal=int(n_temporal), indices=k,
                        coefficients=coef, gamma=GAMMA[kind], residual=residual)


def floquet_mode(system: HillSystem, tau: float, exponent: complex,
                 n_temporal: int) -> MarginalMode:
    """The periodic part p(t) of the Floquet solution exp(Re gamma t) p(t) of a locked exponent
    gamma (Im gamma = 0 harmonic, 1/2 subharmonic, mod 1) at amplitude ``tau``: the null
    vector of the truncated Hill matrix T_N(g) = A(g) - tau B at g = Re gamma (the right
    singular vector of its smallest singular value; dense SVD).

    Raises
    ------
    ParameterError : gamma is not locked (Im gamma not 0 or 1/2 mod 1 to 1e-9).
    ConvergenceError : T_N(g) is not singular to 1e-8 relative (gamma is not an exponent of
        this truncation).
    """
    offset = float(np.mod(exponent.imag, 1.0))
    locked = {kind: min(abs(offset - GAMMA[kind]), abs(offset - GAMMA[kind] - 1.0))
              for kind in GAMMA}
    kind = min(locked, key=locked.get)
    if locked[kind] > 1e-9:
        raise ParameterError(f"exponent = {exponent:.6g} is invalid: its Floquet solution is not "
                             "periodic up to exp(Re gamma t) (Im gamma must be 0 or 1/2 mod 1)")
    T = assemble(system, kind, n_temporal, "two-sided", shift=exponent.real).dense(tau)
    _, singular, vh = np.linalg.svd(T)
    residual = float(singular[-1] / singular[0])
    if residual > 1e-8:
        raise ConvergenceError(f"no null vector of the Hill matrix at gamma = {exponent:.6g}, "
                               f"tau = {tau:g} (relative residual {residual:.1e})")
    return _real_mode(system, kind, tau, n_temporal, vh[-1].conj(), residual)
