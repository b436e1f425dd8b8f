"""Immersed spherical membrane, one degree m: Hill-system physics (thesis chapter 6, 7.1).

Derived in ``derivations/sphere_linear.py`` (results in ``derivations/sphere_linear_result.md``),
independently of the printed algebra. With beta = sqrt(s/nu) (principal branch),
q = kappa (m-1)(m+2), P = beta i_{m+1}(beta)/i_m(beta), Q = beta k_{m-1}(beta)/k_m(beta):

    D_YY     = s^2 ((2m+1)/(m(m+1)) + m/((m+1) Q) + (m+1)/(m P)) + q
    D_YPsi   = s^2 (m/Q - (m+1)/P),      D_PsiY = D_YPsi / (m(m+1))
    D_PsiPsi = s^2 (1/Q + 1/P) + q,      G = q I        (poloidal X^Y, X^Psi)
    D_Phi    = nu s (2m+1 + P + Q) + q,  G_Phi = q      (toroidal X^Phi, decoupled, (6.29))

in D(s_n) X_n = i tau G (X_{n-1} - X_{n+1}). The linear membrane load is -K(t)(m-1)(m+2) X in
every component once the prestress term of (6.16) is kept. Agrees with (6.27)-(6.33) and
(7.8)-(7.12); the derivation confirms the ERRATA items: entry (1,4) of the 4x4 block after (6.34)
is -Im B_n (printed -Im A_n); the kinematic X^Psi expression uses j only; the harmonic n = 0 block
needs A_0 = I (here D(0) = q I, the s -> 0 limit, since the fluid load H(s) = D(s) - q I -> 0);
(B.5) swaps the Psi/Phi labels. It also finds that the beta = 0 steady fields of 6.3 lack a
factor 1/2 (see the result file).

Inviscid limit nu -> 0 (P, Q ~ beta -> infinity): the Y row becomes the Mathieu equation
X'' + lambda0^2 (1 + 2 tau sin t) X = 0 with lambda0^2 = kappa m(m+1)(m-1)(m+2)/(2m+1) ((6.23),
(7.4)) and the Psi row forces X^Psi = 0; ``nu = 0`` therefore reuses the Mathieu model.
"""

from __future__ import annotations

import functools

import numpy as np

from .._validate import REAL_MAX, REAL_MIN
from ..errors import ParameterError
from ..params.physical import SPHERE_MODE_INPUTS, sphere_mode_scale
from ..params.registry import Model, register
from ..params.simulation import SPHERE_STEPPING
from ..params.sphere import SphereParams
from ..special.spherical import M_MAX, ratio_i, ratio_k, ratio_pair
from . import mathieu
from .base import HillSystem, boundary_layer
from .sphere_modes import lambda0_squared, modal_system  # noqa: F401 (lambda0_squared: API)


def _p_q(m: int, s: np.ndarray, nu: float,
         checked: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """(P, Q) of the module notes at s != 0; ``checked=False`` where beta is known to lie in
    the Bessel kernels' domain (:func:`~spectralshell.special.spherical.ratio_pair`)."""
    beta = np.sqrt(s / nu)
    with boundary_layer(nu):
        if checked:
            return beta * ratio_i(m, beta), beta / ratio_k(m - 1, beta)
        r_i, r_k = ratio_pair(m, beta)
        return beta * r_i, beta / r_k


#: Fluid-load tables kept per process (:func:`_fluid_table`): a Fig 6.13 worker meets each of
#: its 200 beat rates x 5 degrees once per stiffness line, ~1000 keys of ~10-40 kB (both kinds).
FLUID_CACHE = 4096
#: A table covers the Fourier indices k = -top-1..top of s_k = i (gamma + k), top = FLUID_STEP
#: times a power of 2 (the truncations of neighbouring cells, and of neighbouring stiffnesses,
#: share it), at most FLUID_TOP.
FLUID_STEP = 16
FLUID_TOP = 512
#: The offsets gamma of the two kinds' frequencies (harmonic, subharmonic), one table each.
FLUID_GAMMAS = (0.0, 0.5)
#: The 2 x 2 identity of the poloidal forcing G = q I (read-only).
IDENTITY = np.eye(2)
IDENTITY.setflags(write=False)


def poloidal_unforced(s: np.ndarray, *, m: int, kappa: float, nu: float) -> np.ndarray:
    """D(s) of the poloidal pair (X^Y, X^Psi), shape (len(s), 2, 2); D(0) = q I (limit)."""
    s = np.asarray(s, dtype=complex).ravel()
    q = kappa * (m - 1) * (m + 2)
    out = _fluid_load(m, float(nu), s)
    out.reshape(-1, 4)[:, ::3] += q  # the entries (0, 0) and (1, 1) of each block
    return out


def _fluid_load(m: int, nu: float, s: np.ndarray) -> np.ndarray:
    """D(s) - q I of the poloidal pair (a new array): cut out of a cached table where s is a run
    of a Hill truncation's frequencies s_k = i (gamma + k), gamma 0 or 1/2 (a run of the
    table's own s, bitwise), else computed afresh."""
    s0 = s.item(0) if s.size else 0.5j  # a Python complex: cheaper arithmetic than numpy's
    x = s0.imag
    gamma = x % 1.0
    if s.size and gamma in FLUID_GAMMAS and s0.real == 0.0:  # the bytes check does the rest
        first = int(round(x - gamma))
        need = max(-first - 1, first + s.size - 1, 1)
        top = FLUID_STEP
        while top < need:
            top *= 2
        if top <= FLUID_TOP:
            table_s, table = _fluid_table(m, nu, top)[FLUID_GAMMAS.index(gamma)]
            start = first + top + 1
            if table_s[start:start + s.size].tobytes() == s.tobytes():
                return table[start:start + s.size].copy()
    return _fluid_values(m, nu, s)


@functools.lru_cache(maxsize=FLUID_CACHE)
def _fluid_table(m: int, nu: float, top: int) -> tuple[tuple[np.ndarray, np.ndarray], ...]:
    """(s_k, D(s_k) - q I) for k = -top-1..top, s_k = i (gamma + k) as a Hill truncation forms
    them (read-only), for each gamma of FLUID_GAMMAS: the part of D that does not depend on
    kappa, so that the cells of a map that share a beat rate (nu) evaluate the Bessel ratios
    once, for both kinds in one call (its cost is mostly per call: ~0.15-0.2 ms for 34 or 260
    frequencies). Each value depends only on its own s (elementwise numpy and the compiled
    continued fraction), so a cut-out run equals the values computed afresh at the
    truncation's s (tests/test_sphere_fluid_cache.py)."""
    runs = [1j * (gamma + np.arange(-top - 1, top + 1, dtype=float)) for gamma in FLUID_GAMMAS]
    # 1/2 <= |s| <= FLUID_TOP + 1 and nu in [REAL_MIN, REAL_MAX] (as validated) keep
    # beta = sqrt(s / nu) in the Bessel kernels' domain: their per-call checks are skipped
    known = REAL_MIN <= nu <= REAL_MAX and 1 <= m <= M_MAX
    values = _fluid_values(m, nu, np.concatenate(runs), checked=not known)
    out = []
    for j, s in enumerate(runs):
        table = values[j * s.size:(j + 1) * s.size]
        s.setflags(write=False)
        table.setflags(write=False)
        out.append((s, table))
    return tuple(out)


def _fluid_values(m: int, nu: float, s: np.ndarray, checked: bool = True) -> np.ndarray:
    """D(s) - q I of the poloidal pair at the complex128 s, computed (``checked``: see
    :func:`_p_q`)."""
    out = np.zeros((s.size, 2, 2), dtype=complex)
    live = s != 0
    if live.any():
        sl = s[live]
        P, Q = _p_q(m, sl, nu, checked)
        s2 = sl * sl
        out[live, 0, 0] = s2 * ((2 * m + 1) / (m * (m + 1)) + m / ((m + 1) * Q) + (m + 1) / (m * P))
        out[live, 0, 1] = s2 * (m / Q - (m + 1) / P)
        out[live, 1, 0] = out[live, 0, 1] / (m * (m + 1))
        out[live, 1, 1] = s2 * (1 / Q + 1 / P)
    return out


def toroidal_unforced(s: np.ndarray, *, m: int, kappa: float, nu: float) -> np.ndarray:
    """D(s) of the toroidal component X^Phi, shape (len(s), 1, 1); D(0) = q."""
    s = np.asarray(s, dtype=complex).ravel()
    q = kappa * (m - 1) * (m + 2)
    out = np.full(s.size, q, dtype=complex)
    live = s != 0
    if live.any():
        P, Q = _p_q(m, s[live], nu)
        out[live] += nu * s[live] * (2 * m + 1 + P + Q)
    return out.reshape(-1, 1, 1)


def hill_system(*, m: int, kappa: float, nu: float, component: str = "poloidal") -> HillSystem:
    """Hill-system physics of degree m of the spherical membrane (see the module docstring)."""
    q = kappa * (m - 1) * (m + 2)
    lam2 = lambda0_squared(m, kappa)
    if nu == 0.0:
        if component == "toroidal":  # no fluid stress: X^Phi = 0, nothing oscillates
            return HillSystem(name="sphere", block_size=1, forcing=np.zeros((1, 1)),
                              unforced=lambda s: np.full((np.size(s), 1, 1), q, dtype=complex))
        return mathieu.hill_system(kappa=lam2, nu=0.0)
    if component == "toroidal":
        return HillSystem(name="sphere", block_size=1, forcing=np.array([[q]]),
                          unforced=lambda s: toroidal_unforced(s, m=m, kappa=kappa, nu=nu))
    return HillSystem(name="sphere", block_size=2, forcing=q * IDENTITY,
                      unforced=lambda s: poloidal_unforced(s, m=m, kappa=kappa, nu=nu),
                      n_resonant=float(np.sqrt(lam2)))


def _hill_system(p: SphereParams) -> HillSystem:
    return hill_system(m=p.m, kappa=p.kappa, nu=p.nu, component=p.component)


def _modal_system(p: SphereParams):
    return modal_system(m=p.m, kappa=p.kappa, nu=p.nu, component=p.component)


def _inviscid_modes(p: SphereParams, kappa):
    """lambda0^2 of (7.4) at nu = 0 (kappa may be an mpmath number)."""
    if p.component == "toroidal":
        raise ParameterError("nu = 0 is invalid for toroidal modes: without viscosity the "
                             "toroidal component carries no mode")
    return lambda0_squared(p.m, kappa)


MODEL = register(Model(
    name="sphere",
    summary="spherical membrane in viscous fluid, one degree m (thesis 6-7)",
    params=SphereParams, hill_system=_hill_system, modal_system=_modal_system,
    inviscid_modes=_inviscid_modes, inviscid_method="closed form (7.4)",
    mode_inputs=SPHERE_MODE_INPUTS, mode_scale=sphere_mode_scale,
    time_stepping=SPHERE_STEPPING))
