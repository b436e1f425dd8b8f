"""Nonlinear inviscid oscillation of a radially displaced spherical membrane: the pointwise equations.

Model of thesis 7.3, (7.15)-(7.19), restated in physical variables (derivation and checks:
``derivations/lindstedt_sphere.py``). Density 1 inside and outside, irrotational inviscid flow,
u = grad psi, Lap psi = 0; the membrane is displaced RADIALLY ONLY: the material point of reference
angles (theta, phi) is at X = R(theta, phi, t) rhat, R = 1 + x (no tangential membrane motion; every
result of this module and of the frequency coefficients is for this radial-only model).

With tau = lambda t, psi = lambda Phi, Lambda = lambda^2/lambda0^2 and kappa' = kappa/lambda0^2,
lambda0^2 = kappa m(m+1)(m-1)(m+2)/(2m+1) (7.4), the equations at r = R are

    kinematic (7.18), each side:  R_tau - Phi_r + grad_S R . grad_S Phi / R^2 = 0
    normal stress (7.17) + Bernoulli (7.16):
        Lambda [Phi_tau + |grad Phi|^2/2]_in - Lambda [Phi_tau + |grad Phi|^2/2]_out
            = kappa' (G(R) + 2)

(an interior Bernoulli function of time is carried by the interior degree-0 potential). The
membrane force is F = kappa Delta_S X (7.1e), Delta_S of the unit reference sphere applied to the
Cartesian components, so Delta_S X = (Delta_S R - 2R) rhat + 2 grad_S R, and the normal balance
[[p]] |N| = n.F sin(theta) of (7.17) (N = X_theta x X_phi, [[.]] = outside - inside) gives

    "normal" (the thesis's law):  G = (R Delta_S R - 2R^2 - 2g) / (R (R^2 + g)),  g = |grad_S R|^2.

Correction to the printed (7.19b): it multiplies the stress by |N|^2 but then writes |grad psi|^2/(2X^2)
for the velocity term and omits kappa in front of Delta_S X; after the change of variables
r = X r* both the time derivative at fixed r* and the gradient pick up terms in grad_S X, which the
printed form drops. The form above avoids the change of variables.

Findings on the printed 7.3 (details and evidence: the generator's docstring and output): the
enclosed volume (degree 0) must be kept, degree 1 never enters at O(eps^2); (7.21) does not give
(7.22a); (7.22a)'s constant has the wrong sign and (7.22b)'s cos 2t coefficient is 439/378, not
403/378; the printed c_2 (7061 vs the 7062 implied by lambda2), c_3 and c_4 all differ from the
exact c_{m,k} of :mod:`.nonlinear_coefficients` (e.g. c_2 = -0.2112, not -0.7167), which the
direct orbit solve confirms; |grad_S Y_{m,k}|^2 is band-limited (degrees <= 2m).

"radial" (not the thesis's; the virtual work of F on radial displacements, [[p]] R^2 = rhat.F):
G = (Delta_S R - 2R)/R^2. It agrees with "normal" to O(x^2) and differs by
g Delta_S R / (R^2 (R^2 + g)) = O(x^3), which changes the eps^2 frequency coefficient.
"""

from __future__ import annotations

import numpy as np

from .._validate import require_choice

FORCE_LAWS = ("normal", "radial")


def kappa_prime(m: int) -> float:
    """kappa/lambda0^2 = (2m+1)/(m(m+1)(m-1)(m+2)) from (7.4)."""
    return (2 * m + 1) / (m * (m + 1) * (m - 1) * (m + 2))


def membrane_load(R, lap_R, g, *, law: str = "normal"):
    """G(R) + 2, with [[p]] = kappa G(R) the membrane's pressure jump (module docstring).

    Raises ParameterError for an unknown ``law``.
    """
    require_choice("law", law, FORCE_LAWS)
    if law == "normal":
        return (R * lap_R - 2 * R * R - 2 * g) / (R * (R * R + g)) + 2
    return (lap_R - 2 * R) / (R * R) + 2


def kinematic_residual(R_tau, phi_r, gradR_dot_gradphi, R):
    """R_tau - Phi_r + grad_S R . grad_S Phi / R^2 at r = R ((7.18), radial-only membrane)."""
    return R_tau - phi_r + gradR_dot_gradphi / (R * R)


def bernoulli_head(phi_tau, phi_r, grad_s_phi_sq, R):
    """Phi_tau + |grad Phi|^2/2 at r = R, |grad Phi|^2 = Phi_r^2 + |grad_S Phi|^2 / r^2 (7.16)."""
    return phi_tau + 0.5 * (phi_r * phi_r + grad_s_phi_sq / (R * R))


def stress_residual(Lam, head_in, head_out, load, kp):
    """Lambda (head_in - head_out) - kappa' (G + 2): zero on a solution ((7.16)-(7.17))."""
    return Lam * (head_in - head_out) - kp * load


def lambda0_over_sqrt_kappa(m: int) -> float:
    """lambda0/sqrt(kappa) = sqrt(m(m+1)(m-1)(m+2)/(2m+1)) (7.4)."""
    return float(np.sqrt(m * (m + 1) * (m - 1) * (m + 2) / (2 * m + 1)))
