#!/usr/bin/env python3
"""Checks of the radial formulation of the sphere in spectralshell/discretise/sphere_radial.py.

The module discretises the linearised model of ``derivations/sphere_linear_result.md`` in r. This
script verifies, independently of the discretisation, every equation and boundary row it uses:

  A. poloidal scalar: u^Y = c psi/r^2, u^Psi = psi'/r (c = m(m+1)) is divergence-free; with
     omega = L_m psi and p = nu omega' - s psi' the Psi momentum row holds identically and the Y
     row reduces to nu L_m omega - s omega = 0, so s omega = nu L_m omega is the whole
     momentum equation; the L_m^2 expansion; the traction rows -[[p]] + nu [[u^Y']] = -nu [[omega']]
     and nu [[u^Psi']] = nu [[omega]] given [[psi]] = [[psi']] = 0; toroidal rows;
  B. the exact fields of the result file (p = a r^m, b r^-(m+1); u from i_m, k_m) written as psi:
     consistency with u^Psi, omega = beta^2 x (vortical part), the pressure formula; parity of
     the inner psi, omega (regularity at r = 0) and their limits at xi = 1/r = 0;
  C. the exterior map r = 1 + c (1/xi - 1): d^k x/dr^k and the Faa di Bruno chain rule;
  D. numerically (mpmath, 30 digits): the rows of the discretisation evaluated on the exact
     radial solutions reproduce the load H(s), D(s) and D_Phi(s) of the result file.

Run ``python3 derivations/sphere_radial.py``; it prints each check and exits with status 0 only if
all pass (about 10 s).
"""

from __future__ import annotations

import sys

import mpmath as mp
import sympy as sp

from _checks import check, section, summary  # derivations/_checks.py
from _radial import interface_jumps, ode_reduce  # derivations/_radial.py

r, xi = sp.symbols("r xi", positive=True)
m = sp.Symbol("m", positive=True, integer=True)
s, nu, beta = sp.symbols("s nu beta")
c = m * (m + 1)


# VSH component operators of the result file (verified there on explicit harmonics, (6.20))
def c_div(uY, uP):
    return sp.diff(r**2 * uY, r) / r**2 - c * uP / r


def c_lapY(uY, uP):
    return sp.diff(uY, r, 2) + 2 * sp.diff(uY, r) / r - (c + 2) * uY / r**2 + 2 * c * uP / r**2


def c_lapP(uY, uP):
    return sp.diff(uP, r, 2) + 2 * sp.diff(uP, r) / r - c * uP / r**2 + 2 * uY / r**2


def c_lapF(uF):
    return sp.diff(uF, r, 2) + 2 * sp.diff(uF, r) / r - c * uF / r**2


def Lm(f):
    return sp.diff(f, r, 2) - c * f / r**2


def part_a():
    section("A. Poloidal scalar, momentum rows, traction rows (general m, generic psi)")
    psi = sp.Function("psi")(r)
    uY, uP = c * psi / r**2, sp.diff(psi, r) / r
    check("div u = 0 identically", sp.simplify(c_div(uY, uP)) == 0)
    omega = Lm(psi)
    p = nu * sp.diff(omega, r) - s * sp.diff(psi, r)
    res_psi = s * uP + p / r - nu * c_lapP(uY, uP)
    check("Psi row s u^Psi = -p/r + nu [Lap u]^Psi holds with p = nu omega' - s psi'",
          sp.simplify(res_psi) == 0)
    res_y = s * uY + sp.diff(p, r) - nu * c_lapY(uY, uP)
    target = nu * Lm(omega) - s * omega
    check("Y row residual s u^Y + p' - nu [Lap u]^Y = nu L_m omega - s omega",
          sp.simplify(res_y - target) == 0)
    lm2 = (sp.diff(psi, r, 4) - 2 * c * sp.diff(psi, r, 2) / r**2 + 4 * c * sp.diff(psi, r) / r**3
           + (c**2 - 6 * c) * psi / r**4)
    check("L_m^2 psi = psi'''' - 2c psi''/r^2 + 4c psi'/r^3 + (c^2 - 6c) psi/r^4",
          sp.simplify(Lm(Lm(psi)) - lm2) == 0)
    # traction at r = 1 from the two one-sided jets of psi (outside minus inside)
    jump, cont, jets = interface_jumps(psi, r, "p")
    p_static = nu * sp.diff(omega, r) - s * sp.diff(psi, r)  # s psi' has no jump once [[psi']] = 0
    normal = (-jump(p_static) + nu * jump(sp.diff(uY, r))).subs(cont)
    tangential = (nu * jump(sp.diff(uP, r))).subs(cont)
    check("normal traction -[[p]] + nu [[u^Y']] = -nu [[omega']] given [[psi]] = [[psi']] = 0",
          sp.simplify(normal - (-nu * jump(sp.diff(omega, r))).subs(cont)) == 0)
    check("tangential traction nu [[u^Psi']] = nu [[omega]] given [[psi]] = [[psi']] = 0",
          sp.simplify(tangential - (nu * jump(omega)).subs(cont)) == 0)
    check("tangential traction nu [[u^Psi']] = nu [[psi'']] given [[psi]] = [[psi']] = 0",
          sp.simplify(tangential - nu * (jets["o"][2] - jets["i"][2])) == 0)
    g = sp.Function("g")(r)
    check("toroidal: Phi row of the vector Laplacian is g'' + 2g'/r - c g/r^2 (6.20c)",
          sp.simplify(c_lapF(g) - (sp.diff(g, r, 2) + 2 * sp.diff(g, r) / r - c * g / r**2)) == 0)


def bessel_reduce(expr, f):
    """Eliminate f'', f''', f'''' with the ODE r^2 f'' + 2 r f' = (beta^2 r^2 + c) f."""
    return ode_reduce(expr, f, r, -2 * sp.diff(f, r) / r + (beta**2 + c / r**2) * f)


def part_b():
    section("B. Exact fields of the result file as psi; parity; limits at infinity")
    f = sp.Function("f")(r)
    a, A = sp.symbols("a A")
    ok = True
    for pres in (a * r**m, a * r**(-m - 1)):
        uY = -sp.diff(pres, r) / s + A * c * f / r
        uP = -pres / (r * s) + A * (f / r + sp.diff(f, r))
        psi = r**2 * uY / c
        ok &= sp.simplify(sp.diff(psi, r) / r - uP) == 0
        omega = bessel_reduce(Lm(psi), f)
        ok &= sp.simplify(omega - beta**2 * A * r * f) == 0
        ok &= bessel_reduce(s * omega - nu * Lm(omega), f).subs(s, nu * beta**2).simplify() == 0
        p = bessel_reduce(nu * sp.diff(omega, r) - s * sp.diff(psi, r), f)
        ok &= sp.simplify(p.subs(s, nu * beta**2) - pres) == 0
    check("psi = r^2 u^Y/c gives u^Psi = psi'/r, omega = beta^2 A r f, s omega = nu L_m omega, "
          "p = nu omega' - s psi' (inside r^m and outside r^-(m+1))", ok)
    z = sp.Symbol("z")
    i_m = [sp.sinh(z) / z, (z * sp.cosh(z) - sp.sinh(z)) / z**2]
    k_m = [sp.exp(-z) / z, sp.exp(-z) * (1 / z + 1 / z**2)]
    for n in range(1, 4):
        i_m.append(sp.simplify(i_m[n - 1] - (2 * n + 1) / z * i_m[n]))
        k_m.append(sp.simplify(k_m[n - 1] + (2 * n + 1) / z * k_m[n]))
    b = sp.Symbol("b", positive=True)
    ok_par, ok_inf = True, True
    for mm in (2, 3, 4):
        psi_in = (r * i_m[mm]).subs(z, b * r)
        ok_par &= sp.simplify(psi_in.subs(r, -r) - (-1) ** (mm + 1) * psi_in) == 0
        ok_par &= sp.limit(psi_in / r ** (mm + 1), r, 0) != 0
        vort = (k_m[mm]).subs(z, b / xi) / xi               # psi_out vortical part, xi = 1/r
        ok_inf &= sp.limit(vort, xi, 0, "+") == 0
        ok_inf &= sp.limit(sp.diff(vort, xi), xi, 0, "+") == 0
        ok_inf &= sp.limit(b**2 * vort, xi, 0, "+") == 0   # omega_out
    check("inner psi = r i_m(beta r) ~ r^(m+1), parity (-1)^(m+1) (m = 2, 3, 4): no row at r = 0",
          ok_par)
    check("outer vortical psi and omega -> 0 with d psi/dxi -> 0 at xi = 0 (Re beta > 0; "
          "potential part b xi^m, m >= 2): rows psi = 0, omega = 0 at xi = 0", ok_inf)


def part_c():
    section("C. Exterior map r = 1 + c (1/xi - 1), xi = (1 + x)/2")
    cc, x = sp.symbols("c x")
    rr = sp.Symbol("rho")
    x_of_r = 2 * cc / (rr - 1 + cc) - 1
    xi_of_r = (1 + x_of_r) / 2
    ok = all(sp.simplify(sp.diff(x_of_r, rr, k)
                         - 2 * (-1) ** k * sp.factorial(k) * xi_of_r ** (k + 1) / cc**k) == 0
             for k in range(1, 5))
    check("d^k x/dr^k = 2 (-1)^k k! xi^(k+1) / c^k, k = 1..4", ok)
    check("1/r = xi/(xi + c(1 - xi))",
          sp.simplify(1 / rr - (xi_of_r / (xi_of_r + cc * (1 - xi_of_r)))) == 0)
    F = sp.Function("F")
    X = sp.Function("X")(rr)
    d = [sp.diff(X, rr, k) for k in range(1, 5)]
    Fd = [sp.Subs(sp.Derivative(F(x), (x, k)), x, X) for k in range(1, 5)]
    faa = [d[0] * Fd[0],
           d[0]**2 * Fd[1] + d[1] * Fd[0],
           d[0]**3 * Fd[2] + 3 * d[0] * d[1] * Fd[1] + d[2] * Fd[0],
           d[0]**4 * Fd[3] + 6 * d[0]**2 * d[1] * Fd[2] + (3 * d[1]**2 + 4 * d[0] * d[2]) * Fd[1]
           + d[3] * Fd[0]]
    ok = all(sp.simplify((sp.diff(F(X), rr, k + 1) - faa[k]).doit()) == 0 for k in range(4))
    check("Faa di Bruno d^k/dr^k F(x(r)), k = 1..4 (chebyshev.radial_derivatives)", ok)


def part_d():
    section("D. Rows on exact radial solutions reproduce H(s), D(s), D_Phi(s) (mpmath, 30 digits)")
    mp.mp.dps = 30

    def sph_i(n, zz):
        return mp.sqrt(mp.pi / (2 * zz)) * mp.besseli(n + mp.mpf(1) / 2, zz)

    def sph_k(n, zz):
        return mp.sqrt(mp.pi / (2 * zz)) * mp.besselk(n + mp.mpf(1) / 2, zz)

    def closed_D(mm, ss, vv, kap):
        bb = mp.sqrt(ss / vv)
        P = bb * sph_i(mm + 1, bb) / sph_i(mm, bb)
        Q = bb * sph_k(mm - 1, bb) / sph_k(mm, bb)
        q = kap * (mm - 1) * (mm + 2)
        yy = ss**2 * (mp.mpf(2 * mm + 1) / (mm * (mm + 1)) + mm / ((mm + 1) * Q)
                      + (mm + 1) / (mm * P)) + q
        yp = ss**2 * (mm / Q - (mm + 1) / P)
        pp = ss**2 * (1 / Q + 1 / P) + q
        return mp.matrix([[yy, yp], [yp / (mm * (mm + 1)), pp]]), vv * ss * (2 * mm + 1 + P + Q) + q

    worst_p = worst_t = mp.mpf(0)
    for mm, ss, vv, kap in ((2, mp.mpc(-0.3, 2.1), 0.01, 1.0), (3, mp.mpc(0.2, 0.7), 0.5, 0.3),
                            (4, mp.mpc(-1.0, 5.0), 0.001, 2.0)):
        cc, q1 = mm * (mm + 1), (mm - 1) * (mm + 2)
        bb = mp.sqrt(ss / vv)
        fin = [lambda t: t * sph_i(mm, bb * t)]                  # vortical psi, inside
        fout = [lambda t: t * sph_k(mm, bb * t)]
        D = closed_D(mm, ss, vv, kap)
        cols = []
        for X in ([1, 0], [0, 1]):
            # psi_in = al r^{m+1} + A fin, psi_out = be r^{-m} + B fout; kinematics and continuity
            rhs = mp.matrix([ss * X[0] / cc, ss * X[1]])
            al, A = mp.lu_solve(mp.matrix([[1, fin[0](1)], [mm + 1, mp.diff(fin[0], 1)]]), rhs)
            be, B = mp.lu_solve(mp.matrix([[1, fout[0](1)], [-mm, mp.diff(fout[0], 1)]]), rhs)
            w_in = [bb**2 * A * fin[0](1), bb**2 * A * mp.diff(fin[0], 1)]      # omega, omega'
            w_out = [bb**2 * B * fout[0](1), bb**2 * B * mp.diff(fout[0], 1)]
            # stress rows: -nu [[omega']] - K q1 X^Y = 0, nu [[omega]] - K q1 X^Psi = 0,
            # i.e. H X = (nu [[omega']], -nu [[omega]]) and D X = H X + q X
            HX = [vv * (w_out[1] - w_in[1]), -vv * (w_out[0] - w_in[0])]
            cols.append([HX[k] + kap * q1 * X[k] for k in range(2)])
        worst_p = max(worst_p, max(abs(cols[j][k] - D[0][k, j]) / mp.mnorm(D[0], 1)
                                   for j in range(2) for k in range(2)))
        # toroidal: g = C_in i_m(beta r), C_out k_m(beta r), g(1) = s X; H_Phi X = -nu [[g']]
        Ci, Co = ss / sph_i(mm, bb), ss / sph_k(mm, bb)
        dg = (Co * mp.diff(lambda t: sph_k(mm, bb * t), 1)
              - Ci * mp.diff(lambda t: sph_i(mm, bb * t), 1))
        worst_t = max(worst_t, abs(-vv * dg + kap * q1 - D[1]) / abs(D[1]))
    check("poloidal rows give D(s) of the result file (3 cases)", worst_p < 1e-20,
          f"max rel. difference {mp.nstr(worst_p, 3)}")
    check("toroidal rows give D_Phi(s) of the result file (3 cases)", worst_t < 1e-20,
          f"max rel. difference {mp.nstr(worst_t, 3)}")


def main() -> int:
    part_a()
    part_b()
    part_c()
    part_d()
    return summary()


if __name__ == "__main__":
    sys.exit(main())
