#!/usr/bin/env python3
"""Checks of the polynomial-coefficient rows of spectralshell/discretise/sphere_banded.py.

The banded discretisation reuses the equations of ``derivations/sphere_radial.py`` (psi relation
L_m psi = omega, vorticity s omega = nu L_m omega, toroidal s g = nu Lap_m g, the interface and
kinematic rows) and only rewrites them so that every coefficient is a polynomial. This script
verifies each rewrite symbolically (generic m and functions):

  A. interior: L_m(r^(m+1) p) = r^(m+1) B p and Lap_m(r^m q) = r^m B q with
     B = d^2/dr^2 + (2(m+1)/r) d/dr; the rows r B p = r w, s r w = nu r B w, s r q = nu r B q;
     the interface values psi'(1) = (m+1) p(1) + p'(1), g'(1) = m q(1) + q'(1); the exact regular
     fields (r i_m(beta r), r^(m+1); i_m(beta r), r^m) satisfy them (m = 2, 3);
  B. exterior r = 1 + L (1/xi - 1) = rho/xi, rho = L + (1 - L) xi: d/dr = -(xi^2/L) d/dxi;
     L^2 rho^2 L_m f = rho^2 (xi^4 f'' + 2 xi^3 f') - c L^2 xi^2 f, and with omega = xi^2 Omega
     the psi relation divided by xi^2 and the vorticity equation divided by xi^2 are the rows of
     the module; toroidal L^2 rho^2 Lap_m g; the interface slope of omega from Omega; the exact
     decaying fields (r k_m(beta r), r^-m; k_m(beta r)) satisfy the rows (m = 2, 3).

Run ``python3 derivations/sphere_banded.py``; it exits with status 0 only if all checks pass.
"""

from __future__ import annotations

import sys

import sympy as sp

from _checks import check, section, summary  # derivations/_checks.py

r, xi, L = sp.symbols("r xi L", positive=True)
m = sp.Symbol("m", positive=True, integer=True)
s, nu, beta = sp.symbols("s nu beta", positive=True)
c = m * (m + 1)


def Lm(f, var=r):          # sphere_radial: L_m = d^2/dr^2 - c/r^2
    return sp.diff(f, var, 2) - c * f / var**2


def lap_m(f, var=r):       # sphere_radial: Lap_m = d^2/dr^2 + (2/r) d/dr - c/r^2 (Phi row)
    return sp.diff(f, var, 2) + 2 * sp.diff(f, var) / var - c * f / var**2


def B(f):
    return sp.diff(f, r, 2) + 2 * (m + 1) * sp.diff(f, r) / r


def zero(expr) -> bool:
    return sp.simplify(sp.expand(expr)) == 0


POINTS = ({r: sp.Rational(3, 7), xi: sp.Rational(2, 5), L: sp.Rational(7, 4),
           beta: sp.Rational(9, 4), nu: sp.Rational(1, 30)},
          {r: sp.Rational(5, 6), xi: sp.Rational(5, 6), L: sp.Rational(1, 2),
           beta: sp.Rational(5, 2), nu: sp.Rational(1, 7)})


def vanishes(expr, scale) -> bool:
    """Zero at two rational points to 40 digits, relative to ``scale`` there (exact fields)."""
    return all(abs(sp.N(expr.subs(pt), 40)) <= sp.Float("1e-30") * abs(sp.N(scale.subs(pt), 40))
               for pt in POINTS)


def spherical_i(n, z):     # modified spherical Bessel i_n (regular), n = 2, 3
    return {2: ((3 / z**2 + 1) * sp.sinh(z) - 3 * sp.cosh(z) / z) / z,
            3: ((15 / z**3 + 6 / z) * sp.sinh(z) - (15 / z**2 + 1) * sp.cosh(z)) / z}[n]


def spherical_k(n, z):     # modified spherical Bessel k_n (decaying), up to a constant factor
    return {2: sp.exp(-z) * (1 / z + 3 / z**2 + 3 / z**3),
            3: sp.exp(-z) * (1 / z + 6 / z**2 + 15 / z**3 + 15 / z**4)}[n]


def part_a():
    section("A. Interior rows (regular at r = 0)")
    p, q, w = (sp.Function(name)(r) for name in ("p", "q", "w"))
    check("L_m(r^(m+1) p) = r^(m+1) B p", zero(Lm(r ** (m + 1) * p) - r ** (m + 1) * B(p)))
    check("Lap_m(r^m q) = r^m B q", zero(lap_m(r**m * q) - r**m * B(q)))
    check("r B = r d^2/dr^2 + 2(m+1) d/dr (polynomial coefficients)",
          zero(r * B(p) - (r * sp.diff(p, r, 2) + 2 * (m + 1) * sp.diff(p, r))))
    check("psi relation L_m psi = omega with psi = r^(m+1) p, omega = r^(m+1) w is r B p = r w",
          zero(r * (Lm(r ** (m + 1) * p) - r ** (m + 1) * w) / r ** (m + 1) - (r * B(p) - r * w)))
    check("s omega = nu L_m omega is s r w = nu r B w (times r / r^(m+1))",
          zero(r * (s * r ** (m + 1) * w - nu * Lm(r ** (m + 1) * w)) / r ** (m + 1)
               - (s * r * w - nu * r * B(w))))
    check("psi'(1) = (m+1) p(1) + p'(1)",
          zero(sp.diff(r ** (m + 1) * p, r).subs(r, 1) - ((m + 1) * p.subs(r, 1)
                                                        + sp.diff(p, r).subs(r, 1))))
    check("g'(1) = m q(1) + q'(1)",
          zero(sp.diff(r**m * q, r).subs(r, 1) - (m * q.subs(r, 1) + sp.diff(q, r).subs(r, 1))))
    for n in (2, 3):
        sub = {m: n}
        pot = r ** (n + 1)                                   # potential psi, omega = 0
        vort = r * spherical_i(n, beta * r)                  # vortical psi = omega / beta^2
        check(f"m = {n}: potential p = 1 solves r B p = 0",
              zero((r * B(pot / r ** (n + 1))).subs(sub)))
        wv = vort / r ** (n + 1)
        check(f"m = {n}: vortical w = r i_m(beta r) / r^(m+1) solves s r w = nu r B w at "
              "s = nu beta^2", vanishes((nu * beta**2 * r * wv - nu * r * B(wv)).subs(sub),
                                        nu * beta**2 * r * wv))
        qv = spherical_i(n, beta * r) / r**n
        check(f"m = {n}: toroidal q = i_m(beta r) / r^m solves s r q = nu r B q",
              vanishes((nu * beta**2 * r * qv - nu * r * B(qv)).subs(sub), nu * beta**2 * r * qv))


def part_b():
    section("B. Exterior rows on r = 1 + L (1/xi - 1)")
    rho = L + (1 - L) * xi
    r_of_xi = 1 + L * (1 / xi - 1)
    check("r = rho / xi", zero(r_of_xi - rho / xi))
    check("dr/dxi = -L / xi^2, so d/dr = -(xi^2/L) d/dxi", zero(sp.diff(r_of_xi, xi) + L / xi**2))
    f, Om, g = (sp.Function(name)(xi) for name in ("f", "Omega", "g"))

    def d_r(h):
        return -(xi**2 / L) * sp.diff(h, xi)

    def Lm_xi(h):
        return d_r(d_r(h)) - c * h / r_of_xi**2

    def lap_xi(h):
        return d_r(d_r(h)) + 2 * d_r(h) / r_of_xi - c * h / r_of_xi**2

    psi_row = rho**2 * (xi**4 * sp.diff(f, xi, 2) + 2 * xi**3 * sp.diff(f, xi)) \
        - c * L**2 * xi**2 * f
    check("L^2 rho^2 L_m f = rho^2 (xi^4 f'' + 2 xi^3 f') - c L^2 xi^2 f",
          zero(L**2 * rho**2 * Lm_xi(f) - psi_row))
    omega = xi**2 * Om
    check("psi relation / xi^2 (omega = xi^2 Omega): rho^2 (xi^2 psi'' + 2 xi psi') - c L^2 psi "
          "= L^2 rho^2 Omega",
          zero((L**2 * rho**2 * (Lm_xi(f) - omega)) / xi**2
               - (rho**2 * (xi**2 * sp.diff(f, xi, 2) + 2 * xi * sp.diff(f, xi)) - c * L**2 * f
                  - L**2 * rho**2 * Om)))
    omega_row = xi**2 * (rho**2 * (xi**2 * sp.diff(Om, xi, 2) + 6 * xi * sp.diff(Om, xi) + 6 * Om)
                         - c * L**2 * Om)
    check("vorticity / xi^2: s L^2 rho^2 Omega = nu xi^2 [rho^2 (xi^2 Omega'' + 6 xi Omega' + "
          "6 Omega) - c L^2 Omega]",
          zero(L**2 * rho**2 * (s * omega - nu * Lm_xi(omega)) / xi**2
               - (s * L**2 * rho**2 * Om - nu * omega_row)))
    tor_row = rho**2 * (xi**4 * sp.diff(g, xi, 2) + 2 * xi**3 * sp.diff(g, xi)) \
        - 2 * L * rho * xi**3 * sp.diff(g, xi) - c * L**2 * xi**2 * g
    check("L^2 rho^2 Lap_m g = rho^2 (xi^4 g'' + 2 xi^3 g') - 2 L rho xi^3 g' - c L^2 xi^2 g",
          zero(L**2 * rho**2 * lap_xi(g) - tor_row))
    check("omega'(r = 1) = -(1/L)(2 Omega(1) + Omega_xi(1))",
          zero(d_r(omega).subs(xi, 1) + (2 * Om.subs(xi, 1) + sp.diff(Om, xi).subs(xi, 1)) / L))
    for n in (2, 3):
        sub = {m: n}
        rr = r_of_xi
        pot = rr ** (-n)
        check(f"m = {n}: potential psi = r^-m solves the psi relation with Omega = 0",
              zero((rho**2 * (xi**2 * sp.diff(pot, xi, 2) + 2 * xi * sp.diff(pot, xi))
                    - c * L**2 * pot).subs(sub)))
        vort = rr * spherical_k(n, beta * rr)                    # psi = omega / beta^2
        Ov = beta**2 * vort / xi**2
        row = xi**2 * (rho**2 * (xi**2 * sp.diff(Ov, xi, 2) + 6 * xi * sp.diff(Ov, xi) + 6 * Ov)
                       - c * L**2 * Ov)
        check(f"m = {n}: Omega = beta^2 r k_m(beta r) / xi^2 solves the vorticity row at "
              "s = nu beta^2", vanishes((nu * beta**2 * L**2 * rho**2 * Ov - nu * row).subs(sub),
                                        nu * beta**2 * L**2 * rho**2 * Ov))
        check(f"m = {n}: psi = r k_m(beta r) solves the psi relation with that Omega",
              vanishes((rho**2 * (xi**2 * sp.diff(vort, xi, 2) + 2 * xi * sp.diff(vort, xi))
                        - c * L**2 * vort - L**2 * rho**2 * Ov).subs(sub), L**2 * rho**2 * Ov))
        gv = spherical_k(n, beta * rr)
        trow = rho**2 * (xi**4 * sp.diff(gv, xi, 2) + 2 * xi**3 * sp.diff(gv, xi)) \
            - 2 * L * rho * xi**3 * sp.diff(gv, xi) - c * L**2 * xi**2 * gv
        check(f"m = {n}: toroidal g = k_m(beta r) solves s L^2 rho^2 g = nu (row)",
              vanishes((nu * beta**2 * L**2 * rho**2 * gv - nu * trow).subs(sub),
                       nu * beta**2 * L**2 * rho**2 * gv))


def main() -> int:
    part_a()
    part_b()
    return summary()


if __name__ == "__main__":
    sys.exit(main())
