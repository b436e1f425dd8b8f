#!/usr/bin/env python3
"""The coupled stiffness operator of the sphere with non-uniform kappa(theta, phi).

spectralshell/discretise/sphere_nonuniform.py (and the time stepper's load in sphere_coupled.py)
take the membrane load pointwise as K F1[X], K = w(theta, phi) (1 + 2 tau sin t),

    F1[X] = -sum_a q_a (X^Y_a Y_a rhat + X^Psi_a Psi_a + X^Phi_a Phi_a),   q_a = (l_a - 1)(l_a + 2),

Psi_a = grad_S Y_a, Phi_a = rhat x Psi_a (real orthonormal harmonics Y_a, L_a = l_a (l_a + 1)),
and project it on the modes: the radial coefficient <F, Y_b rhat>, the spheroidal and toroidal
ones <F, Psi_b> / L_b and <F, Phi_b> / L_b. Writing P[w F1[X]] = -C X, this script derives

  A. the tangential identities: grad Y_a . grad Y_b = (1/2) (Lap(Y_a Y_b) + (L_a + L_b) Y_a Y_b),
     (rhat x u) . (rhat x v) = u . v for tangential u, v, and Psi_a . Phi_b = -Phi_a . Psi_b;
  B. the entries of C in Gaunt coefficients G(c, a, b) = int Y_c Y_a Y_b for w = sum_c w_c Y_c:
       C[bY, aY]     = q_a sum_c w_c G(c, a, b)
       C[bPsi, aPsi] = C[bPhi, aPhi] = q_a / (2 L_b) sum_c w_c (L_a + L_b - L_c) G(c, a, b)
       C[bPhi, aPsi] = q_a / L_b int w Psi_a . Phi_b,  C[bPsi, aPhi] = q_a / L_b int w Phi_a . Psi_b
     each checked against exact integration for sample modes and fields;
  C. a uniform w = kappa0 gives C = kappa0 q I (the per-degree model), and an axisymmetric w
     couples only equal orders |k| (poloidal cos with toroidal sin), an equatorially symmetric
     one only l + k of one parity (poloidal) with the other parity (toroidal);
  D. residual: for w = 1 + eps P_2(cos theta) and a generic displacement X of degrees <= 3 the
     assembled C X plus the projection of w F1[X] (integrated exactly) vanishes;
  E. the Hill form: with H(s) the fluid response, the Fourier coefficients of
     H X + (1 + 2 tau sin t) C X = 0 are D(s_n) X_n = i tau G (X_{n-1} - X_{n+1}) with
     D = H + C, G = C (the uniform form with q I replaced by C).

Run ``python3 derivations/sphere_nonuniform.py``; it exits with status 0 only if all checks pass.
"""

from __future__ import annotations

import sys

import sympy as sp
from _checks import check, section, summary  # derivations/_checks.py
from _harmonics import real_gaunt as G  # derivations/_harmonics.py: int Y_c Y_a Y_b

th, ph = sp.symbols("theta phi", real=True)


def Y(l, k):
    """Real orthonormal harmonic: Y_l0, sqrt2 Re Y_lk (k > 0), sqrt2 Im Y_l|k| (k < 0)."""
    z = sp.expand_complex(sp.expand_func(sp.Ynm(l, abs(k), th, ph)))
    return sp.re(z) if k == 0 else sp.sqrt(2) * (sp.re(z) if k > 0 else sp.im(z))


def grad(f):
    """Surface gradient (theta, phi components) on the unit sphere."""
    return (sp.diff(f, th), sp.diff(f, ph) / sp.sin(th))


def cross_r(u):
    """rhat x u for tangential u = (u_theta, u_phi): rhat x e_theta = e_phi, rhat x e_phi = -e_theta."""
    return (-u[1], u[0])


def dot(u, v):
    return u[0] * v[0] + u[1] * v[1]


def lap(f):
    return sp.diff(sp.sin(th) * sp.diff(f, th), th) / sp.sin(th) + sp.diff(f, ph, 2) / sp.sin(th) ** 2


def integral(f):
    """int f dOmega, exactly."""
    inner = sp.integrate(sp.expand(sp.simplify(f * sp.sin(th))), (ph, 0, 2 * sp.pi))
    return sp.simplify(sp.integrate(sp.expand(inner), (th, 0, sp.pi)))


def L(mode):
    return mode[0] * (mode[0] + 1)


def q(mode):
    return (mode[0] - 1) * (mode[0] + 2)


def is_zero(expr) -> bool:
    return sp.simplify(expr) == 0


# ----------------------------------------------------------------------------------------------
section("A. tangential identities")
fa, fb = sp.Function("f")(th, ph), sp.Function("g")(th, ph)
la, lb = sp.symbols("L_a L_b")
# for eigenfunctions Lap f = -L_a f: grad f . grad g = (Lap(f g) - f Lap g - g Lap f) / 2
check("grad f . grad g = (Lap(fg) - f Lap g - g Lap f)/2 (any f, g)",
      is_zero(dot(grad(fa), grad(fb)) - (lap(fa * fb) - fa * lap(fb) - fb * lap(fa)) / 2))
u, v = (sp.Symbol("u1"), sp.Symbol("u2")), (sp.Symbol("v1"), sp.Symbol("v2"))
check("(rhat x u).(rhat x v) = u.v", is_zero(dot(cross_r(u), cross_r(v)) - dot(u, v)))
check("u.(rhat x v) = -(rhat x u).v", is_zero(dot(u, cross_r(v)) + dot(cross_r(u), v)))
for mode in ((2, 1), (3, -2)):
    check(f"Lap Y{mode} = -L Y", is_zero(lap(Y(*mode)) + L(mode) * Y(*mode)))

# ----------------------------------------------------------------------------------------------
section("B. entries of C against exact integrals")
W = {(0, 0): sp.Rational(3, 2) * sp.sqrt(4 * sp.pi), (2, 0): sp.Rational(1, 3),
     (2, 2): -sp.Rational(1, 5), (1, -1): sp.Rational(1, 4)}
w = sum(c * Y(*m) for m, c in W.items())
PAIRS = (((2, 1), (3, 1)), ((3, -2), (2, 2)), ((3, 0), (2, 1)))
for a, b in PAIRS:
    Ya, Yb = Y(*a), Y(*b)
    radial = q(a) * integral(w * Ya * Yb)
    gaunt_radial = q(a) * sum(c * G(m, a, b) for m, c in W.items())
    check(f"C[{b}Y, {a}Y] = q_a sum w_c G(c, a, b)", is_zero(radial - gaunt_radial))
    sph = q(a) * integral(w * dot(grad(Ya), grad(Yb))) / L(b)
    gaunt_sph = q(a) * sum(c * (L(a) + L(b) - L(m)) * G(m, a, b) for m, c in W.items()) / (2 * L(b))
    check(f"C[{b}Psi, {a}Psi] = q_a/(2 L_b) sum w_c (L_a + L_b - L_c) G", is_zero(sph - gaunt_sph))
# by A: C[bPhi, aPhi] = C[bPsi, aPsi] ((rhat x u).(rhat x v) = u.v) and the poloidal-toroidal
# entries are antisymmetric in the sense int w Psi_a.Phi_b = -int w Phi_a.Psi_b

# ----------------------------------------------------------------------------------------------
section("C. uniform and symmetric fields")
kappa0 = sp.Symbol("kappa0", positive=True)
MODES = [(l, k) for l in (2, 3) for k in range(-l, l + 1)]
uniform_ok = all(is_zero(kappa0 * sp.sqrt(4 * sp.pi) * q(a) * G((0, 0), a, b)
                         - (kappa0 * q(a) if a == b else 0)) for a in MODES for b in MODES)
check("w = kappa0: C[bY, aY] = kappa0 q_a delta_ab (degrees 2, 3)", uniform_ok)
P2 = Y(2, 0)
axi = [(a, b) for a in MODES for b in MODES if abs(a[1]) != abs(b[1]) or a[1] * b[1] < 0]
check("axisymmetric w: no Y-Y coupling of different orders (or cos with sin)",
      all(is_zero(G((2, 0), a, b)) for a, b in axi))
cos_sin = integral(P2 * dot(grad(Y(3, 1)), cross_r(grad(Y(2, -1)))))
check("axisymmetric w: poloidal cos k couples toroidal sin k", cos_sin != 0,
      f"int P2 Psi_(3,1).Phi_(2,-1) = {cos_sin}")
odd = [(a, b) for a in MODES for b in MODES if (a[0] + a[1] + b[0] + b[1]) % 2]
check("equatorially symmetric w: no Y-Y coupling of opposite parity of l + k",
      all(is_zero(G((2, 0), a, b)) and is_zero(G((2, 2), a, b)) for a, b in odd))

# ----------------------------------------------------------------------------------------------
section("D. residual: C X + P[w F1[X]] = 0 for w = 1 + eps P_2")
eps = sp.Symbol("epsilon")
w = 1 + eps * sp.sqrt(4 * sp.pi / 5) * Y(2, 0)      # P_2(cos theta) = sqrt(4 pi / 5) Y_20
weights = {(0, 0): sp.sqrt(4 * sp.pi), (2, 0): eps * sp.sqrt(4 * sp.pi / 5)}
SMALL = [(2, 0), (3, 1), (3, 0)]
X = {(a, n): sp.Symbol(f"X{n}_{a[0]}{a[1]}".replace("-", "m")) for a in SMALL for n in ("Y", "Psi")}
radial_field = -sum(q(a) * X[a, "Y"] * Y(*a) for a in SMALL)
tangential = [-sum(q(a) * X[a, "Psi"] * grad(Y(*a))[i] for a in SMALL) for i in (0, 1)]
worst = 0
for b in SMALL:
    proj_r = integral(w * radial_field * Y(*b))
    CX_r = sum(q(a) * sum(c * G(m, a, b) for m, c in weights.items()) * X[a, "Y"] for a in SMALL)
    proj_s = integral(w * dot(tangential, grad(Y(*b)))) / L(b)
    CX_s = sum(q(a) * sum(c * (L(a) + L(b) - L(m)) * G(m, a, b) for m, c in weights.items())
               * X[a, "Psi"] for a in SMALL) / (2 * L(b))
    worst += int(not is_zero(CX_r + proj_r)) + int(not is_zero(CX_s + proj_s))
check("C X + P[w F1[X]] = 0, radial and spheroidal rows, degrees 2..3", worst == 0)

# ----------------------------------------------------------------------------------------------
section("E. Hill form")
t, tau = sp.symbols("t tau", real=True)
C = sp.Symbol("C")                  # stands for the linear map (only linearity is used)
Xn = {n: sp.Symbol(f"X_{n}".replace("-", "m")) for n in range(-3, 4)}
series = sum(Xn[n] * sp.exp(sp.I * n * t) for n in range(-3, 4))
load = sp.expand(((1 + 2 * tau * sp.sin(t)) * C * series).rewrite(sp.exp))
coefficient = sp.expand(load).coeff(sp.exp(sp.I * t), 1)   # Fourier index n = 1 (a sample)
hill = C * Xn[1] - sp.I * tau * C * (Xn[0] - Xn[2])
check("index n of (1 + 2 tau sin t) C X is C X_n - i tau C (X_{n-1} - X_{n+1}), so "
      "(H + C) X_n = i tau C (X_{n-1} - X_{n+1}): D = H + C, G = C",
      is_zero(sp.expand(coefficient - hill)))

sys.exit(summary())
