#!/usr/bin/env python3
"""Checks of the radial formulation of the fibre in spectralshell/discretise/fibre_radial.py.

The module discretises the linearised fibre of ``derivations/fibre_linear_result.md`` (thesis
chapter 4) in r, as ``sphere_radial.py`` does for the sphere. This script verifies, independently
of the discretisation, every equation and row it uses:

  A. streamfunction psi = f(r) sin(m th): u^r = (1/r) d_th psi = U cos(m th), U = m f/r, and
     u^th = -d_r psi = V sin(m th), V = -f' (the convention of the result file, V = -(r U)'/m)
     is divergence-free; with omega = L_m f, L_m = d^2/dr^2 + (1/r) d/dr - m^2/r^2, and the
     pressure p = P(r) cos(m th), P = r (nu omega' - s f')/m, the theta momentum row holds
     identically and the r row reduces to (r/m)(nu L_m omega - s omega), so s omega = nu L_m omega
     is the whole momentum equation; the traction rows [[P]] - nu [[U']] = nu [[omega']]/m and
     -nu [[V']] = nu [[omega]] given [[f]] = [[f']] = 0;
  B. the exact fields (potential r^m, r^-m; vortical I_m(beta r), K_m(beta r)): omega = beta^2 x
     the vortical part, the pressure of the potential part, parity (-1)^m of the inner f and
     omega (regularity at r = 0), decay of the outer vortical part at xi = 1/r = 0;
  C. numerically (mpmath, 30 digits): the rows of the discretisation evaluated on the exact
     radial solutions reproduce the load H(s) = D(s) - kappa E of the result file (its
     plain-Python expressions with mpmath Bessel functions), i.e. the interface rows

         nu [[omega']]/m + K (m^2 X^r + m X^th) = 0,   nu [[omega]] + K (m X^r + m^2 X^th) = 0,
         s X^r = m f(1),   s X^th = -f'(1),   [[f]] = [[f']] = 0,

     and det D(s) = 0 at a natural mode is where the 6 x 6 system of these rows is singular.

The exterior map r = 1 + c (1/xi - 1) and its chain rule are those of the sphere (checked in
``derivations/sphere_radial.py``, part C). Polar vector calculus (Laplacian components) was
checked against Cartesian differentiation in ``derivations/fibre_linear.py``.

Run ``python3 derivations/fibre_radial.py``; it prints each check and exits with status 0 only if
all pass (a few seconds).
"""

from __future__ import annotations

import sys

import mpmath as mp
import sympy as sp

from _checks import check, check_singular_at, section, summary  # derivations/_checks.py
from _radial import interface_jumps, ode_reduce  # derivations/_radial.py

r, th = sp.symbols("r theta", positive=True)
m = sp.Symbol("m", positive=True, integer=True)
s, nu, beta = sp.symbols("s nu beta")


def lap_scalar(q):
    """Polar scalar Laplacian."""
    return sp.diff(q, r, 2) + sp.diff(q, r) / r + sp.diff(q, th, 2) / r**2


def lap_vector(ur, ut):
    """Polar components of the vector Laplacian (checked against Cartesian in fibre_linear.py)."""
    return (lap_scalar(ur) - ur / r**2 - 2 * sp.diff(ut, th) / r**2,
            lap_scalar(ut) - ut / r**2 + 2 * sp.diff(ur, th) / r**2)


def Lm(f):
    return sp.diff(f, r, 2) + sp.diff(f, r) / r - m**2 * f / r**2


def part_a():
    section("A. Streamfunction, momentum rows, traction rows (general m, generic f)")
    f = sp.Function("f")(r)
    psi = f * sp.sin(m * th)
    ur, ut = sp.diff(psi, th) / r, -sp.diff(psi, r)
    check("u^r = (m f/r) cos(m th), u^th = -f' sin(m th): V = -(r U)'/m (result file, 2)",
          sp.simplify(ur - m * f / r * sp.cos(m * th)) == 0
          and sp.simplify(-sp.diff(r * m * f / r, r) / m * sp.sin(m * th) - ut) == 0)
    check("div u = 0 identically",
          sp.simplify(sp.diff(r * ur, r) / r + sp.diff(ut, th) / r) == 0)
    omega = Lm(f)
    check("-Lap psi = -omega sin(m th): omega = L_m f is minus the vorticity's amplitude",
          sp.simplify(lap_scalar(psi) - omega * sp.sin(m * th)) == 0)
    P = r * (nu * sp.diff(omega, r) - s * sp.diff(f, r)) / m
    p = P * sp.cos(m * th)
    lr, lt = lap_vector(ur, ut)
    res_t = s * ut + sp.diff(p, th) / r - nu * lt
    check("theta row s u^th = -(1/r) d_th p + nu [Lap u]^th holds with P = r (nu omega' - s f')/m",
          sp.simplify(res_t) == 0)
    res_r = s * ur + sp.diff(p, r) - nu * lr
    target = r / m * (nu * Lm(omega) - s * omega) * sp.cos(m * th)
    check("r row residual s u^r + d_r p - nu [Lap u]^r = (r/m)(nu L_m omega - s omega) cos(m th)",
          sp.simplify(res_r - target) == 0)
    # traction at r = 1 from the two one-sided jets of f (outside minus inside)
    jump, cont, jets = interface_jumps(f, r, "f")
    U, V = m * f / r, -sp.diff(f, r)
    check("[[U']] = 0 given [[f]] = [[f']] = 0 (continuity, as (4.9))",
          sp.simplify(jump(sp.diff(U, r)).subs(cont)) == 0)
    radial = (jump(P) - nu * jump(sp.diff(U, r))).subs(cont)
    check("radial load [[P]] - nu [[U']] = nu [[omega']]/m given [[f]] = [[f']] = 0",
          sp.simplify(radial - (nu * jump(sp.diff(omega, r)) / m).subs(cont)) == 0)
    tangential = (-nu * jump(sp.diff(V, r))).subs(cont)
    check("tangential load -nu [[V']] = nu [[omega]] given [[f]] = [[f']] = 0",
          sp.simplify(tangential - (nu * jump(omega)).subs(cont)) == 0)


def bessel_reduce(expr, g):
    """Eliminate g'', g''' with the modified Bessel ODE g'' = -g'/r + (beta^2 + m^2/r^2) g."""
    return ode_reduce(expr, g, r, -sp.diff(g, r) / r + (beta**2 + m**2 / r**2) * g)


def part_b():
    section("B. Exact fields as f; pressure; parity; limits at infinity")
    g = sp.Function("g")(r)
    a, A = sp.symbols("a A")
    ok = True
    for pot in (a * r**m, a * r**(-m)):
        f = pot + A * g
        omega = bessel_reduce(Lm(f), g)
        ok &= sp.simplify(omega - beta**2 * A * g) == 0
        ok &= bessel_reduce(s * omega - nu * Lm(omega), g).subs(s, nu * beta**2).simplify() == 0
        P = bessel_reduce(r * (nu * sp.diff(omega, r) - s * sp.diff(f, r)) / m, g)
        ok &= sp.simplify((P + s * r * sp.diff(pot, r) / m).subs(s, nu * beta**2)) == 0
    check("f = a r^(+-m) + A g (g a modified Bessel function of beta r): omega = beta^2 A g, "
          "s omega = nu L_m omega, P = -s r (a r^(+-m))'/m (harmonic pressure a' r^(+-m))", ok)
    b = sp.Symbol("b", positive=True)
    ok_par, ok_inf = True, True
    for mm in (2, 3, 4, 5):
        series = sp.series(sp.besseli(mm, b * r), r, 0, mm + 8).removeO()
        ok_par &= sp.simplify(series.subs(r, -r) - (-1) ** mm * series) == 0
        ok_par &= sp.limit(series / r**mm, r, 0) != 0
        xi = sp.Symbol("xi", positive=True)
        tail = sp.besselk(mm, b / xi)
        ok_inf &= sp.limit(tail, xi, 0, "+") == 0
        ok_inf &= sp.limit(sp.diff(tail, xi), xi, 0, "+") == 0
        ok_inf &= sp.simplify((xi**-mm).subs(xi, 1 / r) - r**mm) == 0
    check("inner f, omega ~ r^m I_m-series: parity (-1)^m (m = 2..5): no row at r = 0", ok_par)
    check("outer vortical f, omega = K_m(beta/xi) -> 0 with d/dxi -> 0 at xi = 0; potential "
          "part r^-m = xi^m (m = 2..5): rows f = 0, omega = 0 at xi = 0", ok_inf)


def part_c():
    section("C. Rows on exact radial solutions reproduce H(s) = D(s) - kappa E (mpmath, 30 digits)")
    mp.mp.dps = 30

    def closed_H(mm, ss, vv):
        """The plain-Python expressions of fibre_linear_result.md, section 3, less kappa E."""
        bb = mp.sqrt(ss / vv)
        P = bb * mp.besseli(mm + 1, bb) / mp.besseli(mm, bb)
        Q = bb * mp.besselk(mm - 1, bb) / mp.besselk(mm, bb)
        return mp.matrix([[ss**2 * (mp.mpf(2) / mm + 1 / P + 1 / Q), ss**2 * (1 / P - 1 / Q)],
                          [ss**2 * (1 / P - 1 / Q), ss**2 * (1 / P + 1 / Q)]])

    def rows(mm, ss, vv, kap):
        """The 6 x 6 matrix of the interface rows on (a, A, b, B, X^r, X^th), f_in = a r^m +
        A I_m(beta r)/I_m(beta), f_out = b r^-m + B K_m(beta r)/K_m(beta): [[f]], [[f']], kinematics (2), stress (2)."""
        bb = mp.sqrt(ss / vv)
        i1, k1 = mp.besseli(mm, bb), mp.besselk(mm, bb)      # scales: every part is 1 at r = 1
        fi = [lambda t: t**mm, lambda t: mp.besseli(mm, bb * t) / i1]
        fo = [lambda t: t**-mm, lambda t: mp.besselk(mm, bb * t) / k1]
        w = [0, bb**2]                                          # omega = w f per part
        val = [fn(1) for fn in fi + fo]
        der = [mp.diff(fn, 1) for fn in fi + fo]
        sign = [-1, -1, 1, 1]                                   # outside minus inside
        R = mp.zeros(6, 6)
        for j in range(4):
            R[0, j] = sign[j] * val[j]
            R[1, j] = sign[j] * der[j]
            R[4, j] = vv * sign[j] * w[j % 2] * der[j] / mm     # nu [[omega']]/m
            R[5, j] = vv * sign[j] * w[j % 2] * val[j]          # nu [[omega]]
        R[2, 0], R[2, 1], R[2, 4] = mm * val[0], mm * val[1], -ss       # m f(1-) - s X^r
        R[3, 0], R[3, 1], R[3, 5] = -der[0], -der[1], -ss                # -f'(1-) - s X^th
        R[4, 4], R[4, 5] = kap * mm**2, kap * mm
        R[5, 4], R[5, 5] = kap * mm, kap * mm**2
        return R

    worst = mp.mpf(0)
    for mm, ss, vv in ((2, mp.mpc(-0.3, 2.1), 0.01), (3, mp.mpc(0.2, 0.7), 0.5),
                       (5, mp.mpc(-1.0, 5.0), 0.001)):
        R = rows(mm, ss, vv, 0)
        H = closed_H(mm, ss, vv)
        for col in range(2):
            X = [1, 0] if col == 0 else [0, 1]
            # solve the four continuity/kinematic rows for (a, A, b, B), then read the load rows
            rhs = mp.matrix([0, 0, ss * X[0], ss * X[1]])
            coef = mp.lu_solve(mp.matrix([[R[i, j] for j in range(4)] for i in range(4)]), rhs)
            load = [sum(R[i, j] * coef[j] for j in range(4)) for i in (4, 5)]
            worst = max(worst, max(abs(load[k] - H[k, col]) / mp.mnorm(H, 1) for k in range(2)))
    check("load rows (nu [[omega']]/m, nu [[omega]]) = H(s) X of the result file (3 cases)",
          worst < 1e-20, f"max rel. difference {mp.nstr(worst, 3)}")
    # a natural mode (det D = 0, found with mpmath from the closed form) makes the rows singular
    mm, vv, kap = 3, mp.mpf("2e-4"), mp.mpf("0.02")

    def det_d(ss):
        H = closed_H(mm, ss, vv)
        E = mp.matrix([[mm**2, mm], [mm, mm**2]])
        return mp.det(H + kap * E)

    mode = mp.findroot(det_d, mp.mpc(-0.012, 0.478))
    check_singular_at("at the Rayleigh mode of m = 3, kappa = 0.02, nu = 2e-4 (det D = 0) the 6 x 6 "
                      "rows are singular, and not 0.01 away from it",
                      lambda gamma: rows(mm, gamma, vv, kap), mode)


def main() -> int:
    part_a()
    part_b()
    part_c()
    return summary()


if __name__ == "__main__":
    sys.exit(main())
