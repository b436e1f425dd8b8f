"""Periodic cylindrical membrane, one Fourier mode (m, k): Hill-system physics (thesis 8.1).

Derived in ``derivations/cylinder.py`` (fields and residuals checked there). The membrane law is
the sphere's (6.1) on the reference cylinder, F = K(t) (X_thetatheta + X_zz), about the
pressurised cylinder ([[p0]] = -K). Unknowns X = (X^r, X^theta, X^z) with
X^r cos(phi) r-hat + X^theta sin(phi) theta-hat + X^z sin(phi) z-hat, phi = m theta + k z
(k = k R). With q = m^2 + k^2,

    E = [[q, m, -k], [m, q, 0], [-k, 0, q]],     D(s) = H(s) + kappa E,     G = kappa E

in D(s_n) X_n = i tau G (X_{n-1} - X_{n+1}); H(s) is the fluid's load per unit displacement
(symmetric: reciprocity). It comes from the interface matrices of each side: V (velocity) and
T (traction sigma . r-hat) at r = 1 per amplitude of the pressure a g(r) and the vortical
potentials A F(r), C F(r) (u = -grad p/s + curl(psi z) + curl curl(chi z)), which depend only on
Lambda = g'(1) (g = I_m(k r)/I_m(k) inside, K_m(k r)/K_m(k) outside) and L = F'(1) (the same
with beta = sqrt(s/nu + k^2)); H(s) = s S^-1 (T_in V_in^-1 - T_out V_out^-1) S with
S = diag(1, -i, -i) (the complex amplitudes of the real basis). D(0) = kappa E (limit).

Decoupling: m = 0 splits torsion X^theta from the sausage pair (X^r, X^z); k = 0 splits X^z from
(X^r, X^theta), which is the 2D fibre (thesis 4) per unit length. ``component`` selects the set.

Inviscid limit nu -> 0: the tangential rows slave X^theta = -m X^r/q, X^z = k X^r/q and the radial
row is the Mathieu equation with lambda0^2 = kappa (q - 1)/M(m, k),
M = I_m(k)/(k I_m'(k)) - K_m(k)/(k K_m'(k)) (added mass; 2/m at k = 0, the fibre's Rayleigh
frequency kappa m (m^2 - 1)/2). ``nu = 0`` therefore reuses the Mathieu model.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..params.cylinder import CYLINDER_UNITS, CylinderParams, cylinder_physical
from ..params.registry import Model, PhysicalInput, register
from ..special.cylindrical import logderiv_i, logderiv_k
from . import mathieu
from .base import HillSystem, boundary_layer

_S = np.array([1.0, -1j, -1j])  # complex amplitude of (cos, sin, sin) per real coefficient


def elastic_matrix(m: int, k: float) -> np.ndarray:
    """E(m, k): the membrane load on (X^r, X^theta, X^z) is -K(t) E X (prestress included).

    Notes
    -----
    Eigenvalues q and q +- sqrt(q), q = m^2 + k^2. A rigid translation (m = 1, k = 0,
    X = (1, -1, 0)), a rigid rotation and a rigid axial shift (m = k = 0) are in its kernel.
    """
    q = m * m + k * k
    return np.array([[q, m, -k], [m, q, 0.0], [-k, 0.0, q]], dtype=float)


def components(m: int, k: float, component: str = "coupled") -> list[int]:
    """Indices into (X^r, X^theta, X^z) of the decoupled set ``component`` at (m, k)."""
    if component == "torsion":
        return [1]
    if component == "axial":
        return [2]
    if m == 0:
        return [0, 2]
    if k == 0:
        return [0, 1]
    return [0, 1, 2]


def _interface(m: int, k: float, s: np.ndarray, nu: float, lam: np.ndarray | float,
               L: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """V, T (shape (len(s), 3, 3)): velocity and traction at r = 1 per amplitude (a, A, C)."""
    n = s.size
    b2 = s / nu + k * k
    one = np.ones(n, dtype=complex)
    zero = np.zeros(n, dtype=complex)
    lam = lam * one
    V = np.stack([np.stack([-lam / s, 1j * m * one, 1j * k * L], -1),
                  np.stack([-1j * m / s, -L, -m * k * one], -1),
                  np.stack([-1j * k / s, zero, -b2], -1)], -2)
    du = np.stack([np.stack([-(k * k + m * m - lam) / s, 1j * m * (L - 1), 1j * k * (b2 + m * m - L)], -1),
                   np.stack([-1j * m * (lam - 1) / s, -(b2 + m * m - L), -m * k * (L - 1)], -1),
                   np.stack([-1j * k * lam / s, zero, -b2 * L], -1)], -2)
    T = np.empty_like(V)
    T[:, 0] = 2 * nu * du[:, 0]
    T[:, 0, 0] -= 1.0
    T[:, 1] = nu * (du[:, 1] - V[:, 1] + 1j * m * V[:, 0])
    T[:, 2] = nu * (du[:, 2] + 1j * k * V[:, 0])
    return V, T


def _pressure_logderivs(m: int, k: float) -> tuple[float, float]:
    """(Lambda_in, Lambda_out) = k I_m'(k)/I_m(k), k K_m'(k)/K_m(k); (m, -m) at k = 0, m >= 1."""
    if k == 0.0:
        return float(m), -float(m)
    return float(np.real(logderiv_i(m, k))), float(np.real(logderiv_k(m, k)))


def fluid_load(s: np.ndarray, *, m: int, k: float, nu: float) -> np.ndarray:
    """H(s) (shape (len(s), 3, 3), s != 0): the fluid's load on (X^r, X^theta, X^z) in the real basis.

    Notes
    -----
    As s -> 0 (beta -> k) the pressure and vortical fields nearly coincide, and the relative
    error of H grows like eps nu k^2 / |s| (measured against 40-digit mpmath); H itself is O(s),
    so D = H + kappa E keeps its accuracy relative to kappa E.

    Raises
    ------
    ParameterError : an s whose beta = sqrt(s/nu + k^2) leaves the Bessel kernels' domain.
    """
    s = np.asarray(s, dtype=complex).ravel()
    beta = np.sqrt(s / nu + k * k)
    lam_in, lam_out = _pressure_logderivs(m, k)
    with boundary_layer(nu):
        L_in, L_out = logderiv_i(m, beta), logderiv_k(m, beta)
    Vi, Ti = _interface(m, k, s, nu, lam_in, np.atleast_1d(L_in))
    Vo, To = _interface(m, k, s, nu, lam_out, np.atleast_1d(L_out))
    # Z = T V^-1 on each side, as (V^T)^-1 T^T transposed
    Z = (np.linalg.solve(np.swapaxes(Vi, 1, 2), np.swapaxes(Ti, 1, 2))
         - np.linalg.solve(np.swapaxes(Vo, 1, 2), np.swapaxes(To, 1, 2)))
    Z = np.swapaxes(Z, 1, 2)
    return s[:, None, None] * Z * _S[None, None, :] / _S[None, :, None]


def unforced(s: np.ndarray, *, m: int, k: float, kappa: float, nu: float,
             component: str = "coupled") -> np.ndarray:
    """D(s) = H(s) + kappa E on the set ``component``, shape (len(s), b, b); D(0) = kappa E."""
    idx = components(m, k, component)
    s = np.asarray(s, dtype=complex).ravel()
    E = kappa * elastic_matrix(m, k)[np.ix_(idx, idx)]
    out = np.broadcast_to(E, (s.size, len(idx), len(idx))).astype(complex)
    live = s != 0
    if live.any():
        out[live] += fluid_load(s[live], m=m, k=k, nu=nu)[:, idx][:, :, idx]
    return out


def added_mass(m: int, k: float) -> float:
    """M(m, k) = I_m(k)/(k I_m'(k)) - K_m(k)/(k K_m'(k)): inviscid fluid inertia per radial
    displacement (2/m at k = 0)."""
    lam_in, lam_out = _pressure_logderivs(m, k)
    return 1.0 / lam_in - 1.0 / lam_out


def lambda0_squared(m: int, k: float, kappa: float) -> float:
    """Inviscid natural frequency squared, kappa (m^2 + k^2 - 1)/M(m, k) (forcing frequency = 1)."""
    return kappa * ((m * m - 1.0) + k * k) / added_mass(m, k)


def hill_system(*, m: int, k: float, kappa: float, nu: float,
                component: str = "coupled") -> HillSystem:
    """Hill-system physics of the mode (m, k) of the cylinder (see the module docstring).

    Raises
    ------
    ParameterError : invalid m, k, kappa, nu or component (:class:`CylinderParams`).
    """
    p = CylinderParams(m=m, k=k, kappa=kappa, nu=nu, component=component)
    idx = components(p.m, p.k, p.component)
    if p.nu == 0.0:
        lam2 = lambda0_squared(p.m, p.k, p.kappa)
        return dataclasses.replace(mathieu.hill_system(kappa=lam2, nu=0.0), name="cylinder")
    G = p.kappa * elastic_matrix(p.m, p.k)[np.ix_(idx, idx)]
    resonant = np.sqrt(lambda0_squared(p.m, p.k, p.kappa)) if p.component == "coupled" else 0.0
    m_, k_, kappa_, nu_, c_ = p.m, p.k, p.kappa, p.nu, p.component
    return HillSystem(name="cylinder", block_size=len(idx), forcing=G,
                      unforced=lambda s: unforced(s, m=m_, k=k_, kappa=kappa_, nu=nu_, component=c_),
                      n_resonant=float(resonant))


def _hill_system(p: CylinderParams) -> HillSystem:
    return hill_system(m=p.m, k=p.k, kappa=p.kappa, nu=p.nu, component=p.component)


MODEL = register(Model(
    name="cylinder",
    summary="periodic cylindrical membrane in viscous fluid, one mode (m, k R) (thesis 8.1)",
    params=CylinderParams, hill_system=_hill_system,
    physical=PhysicalInput(units=CYLINDER_UNITS, convert=cylinder_physical,
                           note="rho, mu, radius, sigma, omega required together; period L with "
                                "j gives k = 2 pi j R/L")))
