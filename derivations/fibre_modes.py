#!/usr/bin/env python3
"""Natural modes of the unforced immersed fibre (tau = 0): dispersion relation and its limits.

Starting point: the per-mode load of ``derivations/fibre_linear.py`` (checked there against fields
that satisfy the primitive equations),

    D(s) = s^2 [[2/m + y + x, y - x], [y - x, y + x]] + kappa E,   E = [[m^2, m], [m, m^2]],

with x = 1/Q, y = 1/P, P = beta I_{m+1}(beta)/I_m(beta), Q = beta K_{m-1}(beta)/K_m(beta),
beta = sqrt(s/nu). A natural mode X ~ exp(gamma t) is a root of det D(gamma) = 0. This script
derives what ``spectralshell.models.fibre`` uses to find the roots (the scaled relation Delta(beta),
its Newton derivative, the second-sheet continuation of Q, and the asymptotic seeds) and checks each
piece against mpmath's own Bessel functions at 30 digits. Run ``python3 derivations/fibre_modes.py``;
it exits with status 0 only if every check passes. The results are written up in
``derivations/fibre_linear_result.md`` (section "Natural modes").

Notation: zeta = nu/sqrt(kappa), sigma = gamma/sqrt(kappa) = zeta beta^2, S = sigma^2,
lambda^2 = m(m^2 - 1)/2 (so lambda0 = sqrt(kappa) lambda), gamma_E = Euler's constant.
"""

from __future__ import annotations

import sys

import mpmath as mp
import sympy as sp

from _checks import check, section, summary  # noqa: E402  (derivations/_checks.py)

mp.mp.dps = 30

m_ = sp.Symbol("m", positive=True)
S_, x_, y_, kap = sp.symbols("S x y kappa")
t_, z_ = sp.symbols("t z")


def delta_product(m, S, x, y):
    """Delta = A+ A- - S^2/m^2 (any number type)."""
    return (S * (1 / m + 2 * y) + m * (m + 1)) * (S * (1 / m + 2 * x) + m * (m - 1)) - S * S / (m * m)


def mp_pq(m, beta):
    beta = mp.mpc(beta)
    return (beta * mp.besseli(m + 1, beta) / mp.besseli(m, beta),
            beta * mp.besselk(m - 1, beta) / mp.besselk(m, beta))


def mp_delta(m, zeta, beta):
    """Delta(beta) with mpmath's besseli/besselk (principal branch, both sides of Re beta = 0)."""
    P, Q = mp_pq(m, beta)
    S = (mp.mpf(zeta) * beta * beta) ** 2
    return delta_product(mp.mpf(m), S, 1 / Q, 1 / P)


def mp_root(m, zeta, sigma_guess):
    """sigma of the root of Delta nearest the guess (mpmath findroot in beta)."""
    b = mp.findroot(lambda b: mp_delta(m, zeta, b), mp.sqrt(mp.mpc(sigma_guess) / zeta), tol=1e-25)
    return zeta * b * b


# ---------------------------------------------------------------------------------------------
def part1():
    section("Part 1. det D in the basis e+- = (1, +-1)/sqrt(2)")
    m = m_
    H = sp.Matrix([[2 / m + y_ + x_, y_ - x_], [y_ - x_, y_ + x_]])
    E = sp.Matrix([[m**2, m], [m, m**2]])
    s2 = S_ * kap  # s^2 = kappa sigma^2
    det = sp.expand((s2 * H + kap * E).det())
    check("det D / kappa^2 = A+ A- - S^2/m^2, A+ = S(1/m + 2y) + m(m+1), A- = S(1/m + 2x) + m(m-1)",
          sp.simplify(det / kap**2 - delta_product(m, S_, x_, y_)) == 0)
    expanded = S_**2 * (2 * (x_ + y_) / m + 4 * x_ * y_) + 2 * m * S_ * (1 + (m + 1) * x_ + (m - 1) * y_) \
        + m**2 * (m**2 - 1)
    check("expanded form S^2 (2(x+y)/m + 4xy) + 2mS(1 + (m+1)x + (m-1)y) + m^2(m^2-1)",
          sp.simplify(expanded - delta_product(m, S_, x_, y_)) == 0)
    R = sp.Matrix([[1, 1], [1, -1]]) / sp.sqrt(2)
    Hr = sp.simplify(R.T * H * R)
    check("e+- diagonalise E (m(m+1), m(m-1)); the fluid couples them only through the potential term 1/m",
          sp.simplify(R.T * E * R - sp.diag(m * (m + 1), m * (m - 1))) == sp.zeros(2, 2)
          and sp.simplify(Hr - sp.Matrix([[1 / m + 2 * y_, 1 / m], [1 / m, 1 / m + 2 * x_]])) == sp.zeros(2, 2))


def part2():
    section("Part 2. Riccati derivatives, Newton multiplier, second-sheet continuation of Q")
    ok_r, ok_g = True, True
    for m, beta in [(2, mp.mpc(0.7, 1.1)), (5, mp.mpc(3, 8)), (12, mp.mpc(0.05, 0.3)), (3, mp.mpc(-0.4, 2))]:
        P, Q = mp_pq(m, beta)
        dP = mp.diff(lambda b: mp_pq(m, b)[0], beta)
        dQ = mp.diff(lambda b: mp_pq(m, b)[1], beta)
        ok_r &= abs(beta * dP - (beta**2 - 2 * m * P - P * P)) < 1e-20 * abs(beta * dP)
        ok_r &= abs(beta * dQ - (Q * Q + 2 * m * Q - beta**2)) < 1e-20 * abs(beta * dQ)
        g = lambda b: mp.besseli(m + 1, b) * mp.besselk(m - 1, b) / b**2  # noqa: E731
        dlog = beta * mp.diff(g, beta) / g(beta)
        ok_g &= abs(dlog - (beta**2 * (1 / P - 1 / Q) - 4)) < 1e-20 * abs(dlog)
    check("beta P' = beta^2 - 2mP - P^2 and beta Q' = Q^2 + 2mQ - beta^2 (Riccati form of DLMF 10.25.1)", ok_r)
    check("g = I_{m+1} K_{m-1}/beta^2: beta g'/g = beta^2 (1/P - 1/Q) - 4 (DLMF 10.29.2); g Delta is pole-free",
          ok_g)
    ok_c = True
    for m, beta in [(2, mp.mpc(-0.01, 0.5)), (3, mp.mpc(-1e-3, 0.2)), (4, mp.mpc(-2, 5)), (5, mp.mpc(-0.3, -2))]:
        w = -beta
        e = -1j * mp.pi if mp.im(beta) >= 0 else 1j * mp.pi
        rho = mp.besseli(m, w) / mp.besselk(m, w)
        r = mp.besseli(m, w) / mp.besseli(m - 1, w)
        Qw = w * mp.besselk(m - 1, w) / mp.besselk(m, w)
        Qc = (Qw - (-1) ** m * e * w * rho / r) / (1 + (-1) ** m * e * rho)
        ok_c &= abs(Qc - mp_pq(m, beta)[1]) < 1e-25 * abs(Qc)
    check("Re beta < 0: Q(-w) = (Q(w) - (-1)^m e w rho/r)/(1 + (-1)^m e rho), e = -+ i pi, rho = I_m/K_m(w) "
          "(DLMF 10.34.2), equals mpmath's principal-branch Q", ok_c)


def part3():
    section("Part 3. Large-beta (Hankel) and small-beta expansions of P and Q")
    a = sp.symbols("a0:4")
    ok = True
    for sign, name in ((1, "I"), (-1, "K")):
        L = sign * z_ + sum(a[k] / z_**k for k in range(4))
        eq = sp.expand((z_ * sp.diff(L, z_) - (z_**2 + m_**2 - L**2)) * z_**3)
        sol = sp.solve([eq.coeff(z_, k) for k in range(4, 0, -1)], a, dict=True)[0]
        coeffs = [sp.factor(sol[a[k]]) for k in range(3)]
        want = [-sp.Rational(1, 2), sign * (4 * m_**2 - 1) / 8]
        ok &= sp.simplify(coeffs[0] - want[0]) == 0 and sp.simplify(coeffs[1] - want[1]) == 0
        print(f"    z {name}_m'/{name}_m = {sign}z {coeffs[0]} + ({coeffs[1]})/z + ...")
    check("z I_m'/I_m ~ z - 1/2 + (4m^2-1)/(8z), z K_m'/K_m ~ -z - 1/2 - (4m^2-1)/(8z): "
          "P ~ beta - m - 1/2 + (4m^2-1)/(8 beta), Q ~ beta - m + 1/2 + (4m^2-1)/(8 beta)", ok)
    ok_n = True
    for m in (2, 3, 7):
        beta = mp.mpc(300, 400)
        P, Q = mp_pq(m, beta)
        ok_n &= abs(P - (beta - m - 0.5 + (4 * m * m - 1) / (8 * beta))) < 5 * m**4 / abs(beta) ** 2
        ok_n &= abs(Q - (beta - m + 0.5 + (4 * m * m - 1) / (8 * beta))) < 5 * m**4 / abs(beta) ** 2
    check("large-beta expansions against mpmath at |beta| = 500 (remainder O(beta^-2))", ok_n)
    ok_s = True
    for m in (2, 3, 6):
        for beta in (mp.mpc(0, 1e-3), mp.mpc(1e-4, 2e-3)):
            P, Q = mp_pq(m, beta)
            cp = mp.mpf(1) / (2 * (m + 2))
            cm = (-mp.log(beta / 2) - mp.euler) if m == 2 else mp.mpf(1) / (2 * (m - 2))
            ok_s &= abs(1 / P - 2 * (m + 1) / beta**2 - cp) < 1e-4
            ok_s &= abs(1 / Q - 2 * (m - 1) / beta**2 - cm) < 1e-4 * (1 + abs(mp.log(beta)))
    check("small beta: 1/P = 2(m+1)/beta^2 + 1/(2(m+2)) + O(beta^2), 1/Q = 2(m-1)/beta^2 + c-, "
          "c- = 1/(2(m-2)) (m >= 3), -log(beta/2) - gamma_E (m = 2)", ok_s)


def _large_beta_delta():
    """Delta with x, y replaced by their large-beta series in t = 1/beta (to t^4)."""
    P = sp.expand(1 / t_ - m_ - sp.Rational(1, 2) + (4 * m_**2 - 1) / 8 * t_)
    Q = sp.expand(1 / t_ - m_ + sp.Rational(1, 2) + (4 * m_**2 - 1) / 8 * t_)
    x = sp.series(1 / Q, t_, 0, 4).removeO()
    y = sp.series(1 / P, t_, 0, 4).removeO()
    return delta_product(m_, S_, x, y)


def part4(delta):
    section("Part 4. nu -> 0: the Rayleigh mode with its Stokes-layer corrections")
    eps, c1, c2, om = sp.symbols("epsilon c1 c2 omega")  # eps = sqrt(zeta), omega^2 = i lambda
    lam2 = m_ * (m_**2 - 1) / 2
    sig = om**2 + c1 * eps + c2 * eps**2
    t = eps / (om * sp.sqrt(1 + (c1 * eps + c2 * eps**2) / om**2))  # 1/beta = sqrt(zeta/sigma)
    ser = sp.series(delta.subs(t_, t).subs(S_, sig**2), eps, 0, 3).removeO()
    ser = sp.expand(sp.expand(ser).subs(om**4, -lam2))
    co = [sp.simplify(ser.coeff(eps, k)) for k in range(3)]
    s1 = sp.solve(co[1], c1)[0]
    s2 = sp.factor(sp.simplify(sp.expand(sp.solve(co[2].subs(c1, s1), c2)[0]).subs(om**4, -lam2)))
    s1 = sp.factor(sp.expand(s1).subs(om**5, -lam2 * om))
    print(f"    sigma = i lambda + c1 sqrt(zeta) + c2 zeta:  c1 = {s1},  c2 = {s2}")
    check("order zeta^0: sigma^2 = -lambda^2, lambda^2 = m(m^2-1)/2 (Rayleigh)", sp.simplify(co[0]) == 0)
    check("c1 = -(m^2+1)/(2m) sqrt(i lambda), i.e. gamma = i lambda0 - (m^2+1)/(2m) sqrt(i lambda0 nu)",
          sp.simplify(s1 + (m_**2 + 1) / (2 * m_) * om) == 0)
    check("c2 = -(m^4 - 3)/(4 m^2): the O(nu) term of gamma is -(m^4-3)/(4m^2) nu",
          sp.simplify(s2 + (m_**4 - 3) / (4 * m_**2)) == 0)
    ok = True
    for m in (2, 3):
        lam = mp.sqrt(mp.mpf(m) * (m * m - 1) / 2)
        rem = []
        for zeta in (mp.mpf("1e-8"), mp.mpf("1e-6")):
            two = 1j * lam - mp.mpf(m * m + 1) / (2 * m) * mp.sqrt(1j * lam * zeta) - mp.mpf(m**4 - 3) / (4 * m * m) * zeta
            rem.append(abs(mp_root(m, zeta, two) - two))
        slope = mp.log(rem[1] / rem[0]) / mp.log(100)
        print(f"    m = {m}: |root - two-term formula| = {mp.nstr(rem[0], 3)}, {mp.nstr(rem[1], 3)} "
              f"(zeta = 1e-8, 1e-6): slope {mp.nstr(slope, 4)}")
        ok &= abs(slope - 1.5) < 0.05
    check("mpmath roots follow the two-term formula with an O(zeta^(3/2)) remainder", ok)


def part5(delta):
    section("Part 5. nu -> 0: the fast (Stokes-layer) mode")
    eps, al, b = sp.symbols("epsilon alpha b")  # eps = zeta^(1/3), sigma = alpha^2 (1 + b eps^2)/eps
    sig = al**2 / eps * (1 + b * eps**2)
    t = eps**2 / (al * sp.sqrt(1 + b * eps**2))
    ser = sp.expand(sp.series(delta.subs(t_, t).subs(S_, sig**2) * eps**4, eps, 0, 5).removeO())
    co = [sp.factor(ser.coeff(eps, k)) for k in range(5)]

    def reduce(e):  # alpha^3 = -m^2/2
        e = sp.expand(e)
        for _ in range(4):
            e = sp.expand(e.subs(al**3, -m_**2 / 2))
        return sp.expand(e.subs(al**4, -m_**2 / 2 * al).subs(al**5, -m_**2 / 2 * al**2)
                         .subs(al**6, m_**4 / 4).subs(al**7, m_**4 / 4 * al))
    lead = co[2]
    bsol = sp.solve(reduce(co[4]), b)[0]
    print(f"    leading order: {lead} = 0;  b = {sp.factor(reduce(bsol))}")
    check("leading balance 2 alpha^3 + m^2 = 0: sigma = alpha^2 zeta^(-1/3), alpha = (m^2/2)^(1/3) e^{i pi/3} "
          "(|gamma| = (kappa^2 m^4/(4 nu))^(1/3), arg 2 pi/3; Re beta > 0)",
          sp.simplify(lead / (2 * al**4 / m_) - (2 * al**3 + m_**2)) == 0 and reduce(co[3]) == 0)
    check("first correction b = -2(m^2-1)/(3 m alpha): sigma = alpha^2 zeta^(-1/3) - 2(m^2-1)/(3m) alpha zeta^(1/3)",
          sp.simplify(reduce(bsol) + 2 * (m_**2 - 1) / (3 * m_ * al)) == 0)
    ok = True
    for m in (2, 4):
        a = (mp.mpf(m * m) / 2) ** (mp.mpf(1) / 3) * mp.expj(mp.pi / 3)
        rel = []
        for zeta in (mp.mpf("1e-9"), mp.mpf("1e-6")):
            approx = a * a * zeta ** (-mp.mpf(1) / 3) - 2 * mp.mpf(m * m - 1) / (3 * m) * a * zeta ** (mp.mpf(1) / 3)
            rel.append(abs(mp_root(m, zeta, approx) - approx) / abs(approx))
        slope = mp.log(rel[1] / rel[0]) / mp.log(1000)
        print(f"    m = {m}: relative error {mp.nstr(rel[0], 3)}, {mp.nstr(rel[1], 3)} (zeta = 1e-9, 1e-6): "
              f"slope {mp.nstr(slope, 4)}")
        ok &= abs(slope - sp.Rational(4, 3)) < 0.05
    check("mpmath roots follow the two-term fast-mode formula with relative error O(zeta^(4/3)) "
          "(absolute O(zeta): the expansion is in zeta^(2/3))", ok)


def part6():
    section("Part 6. nu -> infinity: the steady-Stokes double root and its splitting")
    sg, zt = sp.symbols("sigma zeta")
    cp, cm = sp.symbols("c_p c_m")
    # S (1/m + 2y) with y = 2(m+1)/beta^2 + c+, beta^2 = sigma/zeta, S = sigma^2
    ap = sp.expand(sg**2 * (1 / m_ + 2 * (2 * (m_ + 1) * zt / sg + cp)) + m_ * (m_ + 1))
    am = sp.expand(sg**2 * (1 / m_ + 2 * (2 * (m_ - 1) * zt / sg + cm)) + m_ * (m_ - 1))
    check("A+ = sigma^2 (1/m + 2c+) + 4(m+1) zeta sigma + m(m+1), A- likewise with m-1, c-",
          sp.simplify(ap - (sg**2 * (1 / m_ + 2 * cp) + 4 * (m_ + 1) * zt * sg + m_ * (m_ + 1))) == 0)
    lead = [sp.solve(sp.expand(e.subs({cp: 0, cm: 0}) - sg**2 / m_), sg) for e in (ap, am)]
    check("leading order (zeta -> infinity): both A+ and A- vanish at sigma0 = -m/(4 zeta), i.e. "
          "gamma0 = -kappa m/(4 nu), a double root", all(sp.Rational(-1, 4) * m_ / zt in sol for sol in lead))
    ok, ok_im = True, True
    for m, zeta in [(2, 10), (2, 30), (3, 10), (5, 10)]:
        sigma0 = -mp.mpf(m) / (4 * zeta)
        cpv = mp.mpf(1) / (2 * (m + 2))
        cmv = (-mp.log(mp.sqrt(mp.mpc(sigma0) / zeta) / 2) - mp.euler) if m == 2 else mp.mpf(1) / (2 * (m - 2))
        poly = [lambda s, c=c, k=k: s**2 * (1 / mp.mpf(m) + 2 * c) + 4 * (m + k) * zeta * s + m * (m + k)
                for c, k in ((cpv, 1), (cmv, -1))]
        quartic = lambda s: poly[0](s) * poly[1](s) - s**4 / m**2  # noqa: E731
        model = [mp.findroot(quartic, sigma0 * (1 + d)) for d in (mp.mpf("1e-4"), mp.mpc("1e-2", "1e-3"))]
        exact = [mp_root(m, zeta, g) for g in model]
        err = max(abs(a - b) for a, b in zip(model, exact)) / abs(sigma0)
        split = abs(exact[0] - exact[1]) / abs(sigma0)
        print(f"    m = {m}, zeta = {zeta}: roots {mp.nstr(exact[0], 8)}, {mp.nstr(exact[1], 8)}; "
              f"quartic model error {mp.nstr(err, 3)}, split {mp.nstr(split, 3)}")
        ok &= err < 0.05 * split and abs(exact[0] - exact[1]) > 1e-15
        if m == 2:
            want = mp.pi * m**2 / (64 * mp.mpf(zeta) ** 3)
            ok_im &= abs(max(mp.im(e) for e in exact) - want) < 0.05 * want
    check("the quartic model A+ A- - sigma^4/m^2 locates both mpmath roots to within 5 % of their split", ok)
    check("m = 2: the logarithm of the 2D Stokes paradox gives one overdamped mode a frequency "
          "Im sigma ~ pi m^2/(64 zeta^3) (Im gamma ~ pi m^2 kappa^2/(64 nu^3))", ok_im)


def main() -> int:
    print(__doc__.split("\n\n")[0])
    part1()
    part2()
    part3()
    delta = _large_beta_delta()
    part4(delta)
    part5(delta)
    part6()
    section("Summary")
    return summary()


if __name__ == "__main__":
    sys.exit(main())
