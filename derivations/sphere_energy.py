#!/usr/bin/env python3
"""Energy of one degree of the linearised sphere: the formulas of discretise/sphere_stepping.py.

For a field of one (complex orthonormal) harmonic Y of degree m, c = m(m+1):

  A. angular integrals over the unit sphere: int |Y|^2 = 1, int |Psi|^2 = int |Phi|^2 = c,
     Y, Psi, Phi mutually orthogonal (Psi = r grad Y, Phi = rhat x Psi);
  B. poloidal u = u^Y Y rhat + u^Psi Psi with u^Y = c psi/r^2, u^Psi = psi'/r:
     int |u|^2 dOmega = c^2 |psi|^2/r^4 + c |psi'|^2/r^2 and
     int |curl u|^2 dOmega = c |L_m psi|^2 / r^2   (L_m = d^2/dr^2 - c/r^2);
  C. toroidal u = g Phi: int |u|^2 dOmega = c |g|^2 and
     int |curl u|^2 dOmega = c^2 |g|^2/r^2 + c |(r g)'|^2/r^2;
  D. the dissipation: 2 nu int e:e dV = nu int |curl u|^2 dV + 2 nu int div((u.grad) u) dV, and on
     each side of r = 1 the flux of (u.grad)u through the sphere is
     (u.grad u).rhat = u_r d(u_r)/dr + (tangential derivatives of u) - |u_t|^2/r,
     which is continuous across r = 1 when u and d(u_r)/dr are ([[psi]] = [[psi']] = 0 imply
     [[u^Y']] = 0); with decay at infinity the two fluxes cancel, so D = nu int |curl u|^2 dV.
  E. the elastic energy: the membrane load -K q1 X per VSH component (q1 = (m-1)(m+2)) does work
     int u.F dA = -K q1 d/dt (1/2) int |X|^2 dA on the fluid, so at constant K
     E_el = (K q1 / 2)(|X^Y|^2 + c |X^Psi|^2 + c |X^Phi|^2) and d/dt (E_kin + E_el) = -D
     (the fluid energy balance d E_kin/dt = int u.F dA - D, stress jump [[sigma n]] = -F).

A-C are checked on explicit real harmonics (m = 2, k = 0 and m = 3, k = 2, orthonormal) with a
generic radial function; D symbolically for the same fields; E is the statement tested numerically
by tests/test_stepper_sphere.py (energy balance of time-stepped runs).

Run ``python3 derivations/sphere_energy.py`` (about 20 s); exit status 0 only if all checks pass.
"""

from __future__ import annotations

import sys

import sympy as sp

from _checks import check, section, summary  # derivations/_checks.py

r = sp.Symbol("r", positive=True)
th, ph = sp.symbols("theta phi", real=True)   # polar, azimuth


def real_harmonic(m: int, k: int):
    """Orthonormal real harmonic sqrt(2) N P_m^k(cos theta) cos(k phi) (k > 0), N P_m^0 (k = 0)."""
    norm = sp.sqrt(sp.Rational(2 * m + 1, 4) / sp.pi * sp.factorial(m - k) / sp.factorial(m + k))
    Y = norm * sp.assoc_legendre(m, k, sp.cos(th)) * (sp.sqrt(2) * sp.cos(k * ph) if k else 1)
    return sp.simplify(Y)


def sphere_integral(f):
    return sp.integrate(sp.integrate(sp.expand(f) * sp.sin(th), (ph, 0, 2 * sp.pi)), (th, 0, sp.pi))


def curl(A):
    Ar, At, Ap = A
    return (sp.diff(sp.sin(th) * Ap, th) / (r * sp.sin(th)) - sp.diff(At, ph) / (r * sp.sin(th)),
            sp.diff(Ar, ph) / (r * sp.sin(th)) - sp.diff(r * Ap, r) / r,
            sp.diff(r * At, r) / r - sp.diff(Ar, th) / r)


def dot(A, B):
    return sum(a * b for a, b in zip(A, B))


def fields(m, k):
    Y = real_harmonic(m, k)
    Psi = (0, sp.diff(Y, th), sp.diff(Y, ph) / sp.sin(th))
    Phi = (0, -sp.diff(Y, ph) / sp.sin(th), sp.diff(Y, th))
    return Y, Psi, Phi


def part_abc():
    for m, k in ((2, 0), (3, 2)):
        c = m * (m + 1)
        Y, Psi, Phi = fields(m, k)
        section(f"A-C. m = {m}, k = {k}")
        ok = (sp.simplify(sphere_integral(Y**2) - 1) == 0
              and sp.simplify(sphere_integral(dot(Psi, Psi)) - c) == 0
              and sp.simplify(sphere_integral(dot(Phi, Phi)) - c) == 0
              and sp.simplify(sphere_integral(dot(Psi, Phi))) == 0
              and sp.simplify(sphere_integral(Y * Psi[1])) == 0)
        check("int Y^2 = 1, int |Psi|^2 = int |Phi|^2 = c, Psi.Phi and Y Psi integrate to 0", ok)
        psi = sp.Function("psi")(r)
        uY, uP = c * psi / r**2, sp.diff(psi, r) / r
        u = (uY * Y, uP * Psi[1], uP * Psi[2])
        ke = sphere_integral(dot(u, u))
        check("poloidal: int |u|^2 dOmega = c^2 psi^2/r^4 + c psi'^2/r^2",
              sp.simplify(ke - (c**2 * psi**2 / r**4 + c * sp.diff(psi, r)**2 / r**2)) == 0)
        w = curl(u)
        Lm = sp.diff(psi, r, 2) - c * psi / r**2
        check("poloidal: int |curl u|^2 dOmega = c (L_m psi)^2 / r^2",
              sp.simplify(sphere_integral(dot(w, w)) - c * Lm**2 / r**2) == 0)
        g = sp.Function("g")(r)
        ut = (0, g * Phi[1], g * Phi[2])
        check("toroidal: int |u|^2 dOmega = c g^2",
              sp.simplify(sphere_integral(dot(ut, ut)) - c * g**2) == 0)
        wt = curl(ut)
        want = c**2 * g**2 / r**2 + c * sp.diff(r * g, r)**2 / r**2
        check("toroidal: int |curl u|^2 dOmega = c^2 g^2/r^2 + c ((r g)')^2/r^2",
              sp.simplify(sphere_integral(dot(wt, wt)) - want) == 0)


def part_d():
    section("D. The flux of (u.grad)u through r = 1 depends only on u and u_r' (poloidal, m = 2)")
    m, k = 2, 0
    c = m * (m + 1)
    Y, Psi, _ = fields(m, k)
    psi = sp.Function("psi")(r)
    uY, uP = c * psi / r**2, sp.diff(psi, r) / r
    u = (uY * Y, uP * Psi[1], uP * Psi[2])
    # (u.grad u).rhat in spherical components
    ur, ut, up = u
    conv_r = (ur * sp.diff(ur, r) + ut * sp.diff(ur, th) / r
              + up * sp.diff(ur, ph) / (r * sp.sin(th)) - (ut**2 + up**2) / r)
    # it must depend on psi, psi', psi'' only through u (psi, psi') and u_r' (psi, psi')
    free = sp.simplify(sp.diff(conv_r, sp.Derivative(psi, (r, 2))))
    check("(u.grad u).rhat has no psi'' term: continuous when [[psi]] = [[psi']] = 0", free == 0)
    # identity 2 e:e = |curl u|^2 + 2 div((u.grad) u) for div u = 0 (Cartesian, generic field)
    x, y, z = sp.symbols("x y z")
    X = (x, y, z)
    a = [sp.Function(f"a{i}")(x, y, z) for i in range(3)]
    # a divergence-free field: a = curl of a generic potential
    A = [sp.Function(f"A{i}")(x, y, z) for i in range(3)]
    a = [sp.diff(A[2], y) - sp.diff(A[1], z), sp.diff(A[0], z) - sp.diff(A[2], x),
         sp.diff(A[1], x) - sp.diff(A[0], y)]
    grad = [[sp.diff(a[i], X[j]) for j in range(3)] for i in range(3)]
    e = [[(grad[i][j] + grad[j][i]) / 2 for j in range(3)] for i in range(3)]
    ee = sum(e[i][j]**2 for i in range(3) for j in range(3))
    w = [grad[2][1] - grad[1][2], grad[0][2] - grad[2][0], grad[1][0] - grad[0][1]]
    conv = [sum(a[j] * grad[i][j] for j in range(3)) for i in range(3)]
    div_conv = sum(sp.diff(conv[i], X[i]) for i in range(3))
    check("2 e:e = |curl u|^2 + 2 div((u.grad) u) for div u = 0",
          sp.expand(2 * ee - sum(wi**2 for wi in w) - 2 * div_conv) == 0)


def main() -> int:
    part_abc()
    part_d()
    return summary()


if __name__ == "__main__":
    sys.exit(main())
