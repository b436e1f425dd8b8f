#!/usr/bin/env python3
"""Checks of the vertical formulation of the cochlea (spectralshell/discretise/cochlea_vertical.py).

The module discretises the linearised box cochlea of ``derivations/cochlea_linear_result.md``
(thesis chapter 5) in y, per cosine mode, as ``fibre_radial.py`` does for the fibre in r. This
script verifies, independently of the discretisation, every equation and row it uses:

  A. streamfunction psi = f(y) sin(k x): u = psi_y = f' sin(k x), v = -psi_x = -k f cos(k x) is
     divergence-free and meets the walls (u = 0, v_x = 0 at x = 0, pi); with omega = L_k f,
     L_k = d^2/dy^2 - k^2, and p = P(y) cos(k x), P = (s f' - nu omega')/k, the x momentum row
     holds identically and the y row reduces to (s omega - nu L_k omega) cos(k x)/k, so
     s omega = nu L_k omega is the whole momentum equation; with f'(0) = 0 (u = 0) the normal
     viscous stress 2 nu v_y vanishes at y = 0 and P(0) = -nu omega'(0)/k;
  B. the reflection (u, v, p)(x, y) -> (-u, v, -p)(x, -y) maps Stokes solutions to Stokes
     solutions and keeps u = 0, v = h_t at y = 0: the flow is antisymmetric, [[p]] = 2 p(0+);
     the exact fields f = e^{-k y} (omega = 0, harmonic pressure) and e^{-beta y}
     (omega = (s/nu) f, beta^2 = s/nu + k^2) solve the rows, and both vanish with their xi
     derivative at xi = 0 of the map y = L (1/xi - 1) (rows f = 0, omega = 0 there);
  C. numerically (mpmath, 30 digits): the rows of the discretisation evaluated on the exact
     fields reproduce the transfer function Z_k(s) of the result file (its closed form
     2 s^2 beta / (k (beta - k)), not the code), i.e. with the rows

         f'(0) = 0,   s h_k = -k f(0),   -2 nu omega'(0)/k + K (C h)_k = 0,

     the load -2 nu omega'(0)/k = [[p]] per unit h_k is Z_k(s); and at a natural mode of the coupled
     system (det(diag(Z_k) + kappa C) = 0, found by mpmath from the closed form with C from the
     quadrature definition (2/pi) int_0^pi e^{-alpha x} cos(k x) cos(j x) dx) the (3M x 3M)
     matrix of these rows is singular, and not 0.01 away from it.

Run ``python3 derivations/cochlea_vertical.py``; it prints each check and exits with status 0
only if all pass (a few seconds).
"""

from __future__ import annotations

import sys

import mpmath as mp
import sympy as sp

from _checks import check, check_singular_at, section, summary  # derivations/_checks.py

x, y = sp.symbols("x y", real=True)
k = sp.Symbol("k", positive=True, integer=True)
s, nu = sp.symbols("s nu")
beta = sp.Symbol("beta", positive=True)


def lap(q):
    return sp.diff(q, x, 2) + sp.diff(q, y, 2)


def Lk(f):
    return sp.diff(f, y, 2) - k**2 * f


def part_a():
    section("A. Streamfunction, momentum rows, membrane stress (general k, generic f)")
    f = sp.Function("f")(y)
    psi = f * sp.sin(k * x)
    u, v = sp.diff(psi, y), -sp.diff(psi, x)
    check("u = f' sin(kx), v = -k f cos(kx); div u = 0 identically",
          sp.simplify(u - sp.diff(f, y) * sp.sin(k * x)) == 0
          and sp.simplify(v + k * f * sp.cos(k * x)) == 0
          and sp.simplify(sp.diff(u, x) + sp.diff(v, y)) == 0)
    walls = [u.subs(x, 0), u.subs(x, sp.pi), sp.diff(v, x).subs(x, 0), sp.diff(v, x).subs(x, sp.pi)]
    check("walls x = 0, pi: no penetration u = 0 and no shear v_x = 0",
          all(sp.simplify(w) == 0 for w in walls))
    omega = Lk(f)
    check("Lap psi = omega sin(kx): omega = L_k f (minus the vorticity v_x - u_y)",
          sp.simplify(lap(psi) - omega * sp.sin(k * x)) == 0
          and sp.simplify(sp.diff(v, x) - sp.diff(u, y) + omega * sp.sin(k * x)) == 0)
    P = (s * sp.diff(f, y) - nu * sp.diff(omega, y)) / k
    p = P * sp.cos(k * x)
    check("x row s u = -p_x + nu Lap u holds with P = (s f' - nu omega')/k",
          sp.simplify(s * u + sp.diff(p, x) - nu * lap(u)) == 0)
    res_y = s * v + sp.diff(p, y) - nu * lap(v)
    check("y row residual s v + p_y - nu Lap v = (s omega - nu L_k omega) cos(kx)/k",
          sp.simplify(res_y - (s * omega - nu * Lk(omega)) * sp.cos(k * x) / k) == 0)
    a0, a2, a3, a4, a5 = sp.symbols("a0 a2 a3 a4 a5")
    g = a0 + a2 * y**2 + a3 * y**3 + a4 * y**4 + a5 * y**5      # a generic f with f'(0) = 0
    vy0 = sp.diff(-k * g * sp.cos(k * x), y).subs(y, 0)
    check("with f'(0) = 0 the viscous normal stress 2 nu v_y vanishes at y = 0",
          sp.simplify(vy0) == 0)
    wg = Lk(g)
    P0 = ((s * sp.diff(g, y) - nu * sp.diff(wg, y)) / k).subs(y, 0)
    check("P(0) = -nu omega'(0)/k when f'(0) = 0 (at all times, so s f'(0) = 0 too)",
          sp.simplify(P0 + nu * sp.diff(wg, y).subs(y, 0) / k) == 0)
    check("membrane law [[p]] = 2 P(0) = -K h (normal stress; result file, section 1) is the "
          "row -2 nu omega'(0)/k + (K h)_k = 0",
          sp.simplify(2 * P0 - (-2 * nu * sp.diff(wg, y).subs(y, 0) / k)) == 0)


def part_b():
    section("B. Antisymmetry; exact fields; limits at infinity of the map")
    U, V, Pf = (sp.Function(n)(x, y) for n in ("U", "V", "Pf"))
    mom_x = s * U + sp.diff(Pf, x) - nu * lap(U)
    mom_y = s * V + sp.diff(Pf, y) - nu * lap(V)
    div = sp.diff(U, x) + sp.diff(V, y)
    R = {U: -U.subs(y, -y), V: V.subs(y, -y), Pf: -Pf.subs(y, -y)}
    refl_x = (s * R[U] + sp.diff(R[Pf], x) - nu * lap(R[U])).doit()
    refl_y = (s * R[V] + sp.diff(R[Pf], y) - nu * lap(R[V])).doit()
    refl_d = (sp.diff(R[U], x) + sp.diff(R[V], y)).doit()
    check("reflection (u, v, p)(x, y) -> (-u, v, -p)(x, -y): the Stokes residuals map to "
          "(-r_x, r_y, -div)(x, -y)",
          sp.simplify(refl_x + mom_x.subs(y, -y)) == 0
          and sp.simplify(refl_y - mom_y.subs(y, -y)) == 0
          and sp.simplify(refl_d + div.subs(y, -y)) == 0,
          "with u(0) = 0, v(0) = h_t kept, uniqueness makes the flow antisymmetric: "
          "[[p]] = p(0+) - p(0-) = 2 p(0+)")
    ok = True
    for f, w in ((sp.exp(-k * y), 0), (sp.exp(-beta * y), s / nu)):
        omega = Lk(f).subs(beta**2, s / nu + k**2)
        omega = sp.simplify(omega.subs(beta, sp.sqrt(s / nu + k**2)))
        fb = f.subs(beta, sp.sqrt(s / nu + k**2))
        ok &= sp.simplify(omega - w * fb) == 0
        ok &= sp.simplify(s * omega - nu * Lk(omega)) == 0
    check("f = e^{-ky} (omega = 0) and e^{-beta y} (omega = (s/nu) f, beta^2 = s/nu + k^2) "
          "solve L_k f = omega, s omega = nu L_k omega", ok)
    xi, c = sp.symbols("xi c", positive=True)
    ok_inf = True
    for b in (1, 2, 5, sp.Rational(7, 2)):
        g = sp.exp(-b * c * (1 / xi - 1))
        ok_inf &= sp.limit(g, xi, 0, "+") == 0 and sp.limit(sp.diff(g, xi), xi, 0, "+") == 0
    check("e^{-b y}, y = c (1/xi - 1), and its xi derivative vanish at xi = 0 (b = 1, 2, 5, 7/2): "
          "rows f = 0, omega = 0 at xi = 0", ok_inf)


def part_c():
    section("C. Rows on exact fields reproduce Z_k(s) and are singular at a natural mode (mpmath)")
    mp.mp.dps = 30

    def closed_Z(kk, ss, vv):
        """Z_k(s) = 2 s^2 beta/(k (beta - k)) of cochlea_linear_result.md, section 3."""
        bb = mp.sqrt(ss / vv + kk * kk)
        return 2 * ss**2 * bb / (kk * (bb - kk))

    def rows(kk, ss, vv):
        """The 3 x 3 rows (f'(0) = 0; s h - (-k f(0)) = 0; load -2 nu omega'(0)/k) on
        (a, b, h), f = a e^{-k y} + b e^{-beta y}, omega = b (s/nu) e^{-beta y}."""
        bb = mp.sqrt(ss / vv + kk * kk)
        fs = [lambda t: mp.exp(-kk * t), lambda t: mp.exp(-bb * t)]
        ws = [lambda t: 0 * t, lambda t: ss / vv * mp.exp(-bb * t)]
        R = mp.zeros(3, 3)
        for j in range(2):
            R[0, j] = mp.diff(fs[j], 0)
            R[1, j] = kk * fs[j](0)
            R[2, j] = -2 * vv * mp.diff(ws[j], 0) / kk
        R[1, 2] = ss
        return R

    worst = mp.mpf(0)
    for kk, ss, vv in ((1, mp.mpc(-0.01, 0.19), 1e-3), (3, mp.mpc(0.2, 0.7), 0.05),
                       (6, mp.mpc(-0.3, 2.0), 1e-4)):
        R = rows(kk, ss, vv)
        coef = mp.lu_solve(mp.matrix([[R[i, j] for j in range(2)] for i in range(2)]),
                           mp.matrix([0, -ss]))             # h = 1
        load = R[2, 0] * coef[0] + R[2, 1] * coef[1]
        Z = closed_Z(kk, ss, vv)
        worst = max(worst, abs(load - Z) / abs(Z))
    check("load row -2 nu omega'(0)/k = [[p]] = Z_k(s) h on the exact fields (3 cases)",
          worst < 1e-25,
          f"max rel. difference {mp.nstr(worst, 3)}")

    Mm, kap, vv, al = 3, mp.mpf("0.5"), mp.mpf("1e-3"), mp.mpf(1)
    C = mp.matrix(Mm, Mm)
    for a in range(Mm):
        for b in range(Mm):
            C[a, b] = 2 / mp.pi * mp.quad(lambda t: mp.exp(-al * t) * mp.cos((a + 1) * t)
                                          * mp.cos((b + 1) * t), [0, mp.pi])

    def det_d(ss):
        D = kap * C
        for a in range(Mm):
            D[a, a] += closed_Z(a + 1, ss, vv)
        return mp.det(D)

    def system(ss):
        A = mp.zeros(3 * Mm, 3 * Mm)
        for a in range(Mm):
            R = rows(a + 1, ss, vv)
            for i in range(3):
                for j in range(2):
                    A[3 * a + i, 3 * a + j] = R[i, j]
            A[3 * a + 1, 3 * a + 2] = ss
            for b in range(Mm):
                A[3 * a + 2, 3 * b + 2] = kap * C[a, b]
        return A

    mode = mp.findroot(det_d, mp.mpc(-0.0095, 0.19))
    check_singular_at("at the least damped mode of M = 3, kappa = 0.5, nu = 1e-3, alpha = 1 the "
                      "coupled 3M x 3M rows are singular, and not 0.01 away from it", system, mode)


def main() -> int:
    part_a()
    part_b()
    part_c()
    return summary()


if __name__ == "__main__":
    sys.exit(main())
