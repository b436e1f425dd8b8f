#!/usr/bin/env python3
"""Linear oscillations of an elastic fibre on the unit circle in 2D unsteady Stokes flow.

This script re-derives the per-mode system of thesis chapter 4 (the 2D immersed circular fibre,
(4.1)-(4.27)) without using the printed algebra. The target is the form the Floquet engine needs:

    D(d/dt) X + 2 tau sin(t) G X = 0    <=>    D(s_n) X_n = i tau G (X_{n-1} - X_{n+1}),

where s_n = gamma + i n. Run ``python3 derivations/fibre_linear.py``. It prints every check with
its verdict and exits with status 0 only if all checks pass. The results, and the verdicts on the
chapter-4 errata, are written up in ``derivations/fibre_linear_result.md``.

Conventions (restated in the result file):
  * Unit circle, density 1, kinematic viscosity nu. Time is scaled so that the pumping period is
    2 pi. The stiffness is K(t) = kappa (1 + 2 tau sin t).
  * One angular wavenumber m, written with real trigonometric modes as in the thesis's (4.18):
    u^r, p, X^r go with cos(m theta); u^theta, X^theta go with +sin(m theta).
  * [[q]] = q(1+) - q(1-), i.e. outside minus inside.
  * I_m, K_m are the modified Bessel functions of DLMF 10.25, with beta = sqrt(s/nu) and
    Re beta > 0. The ratios are P = beta I_{m+1}(beta)/I_m(beta) = L_i - m and
    Q = beta K_{m-1}(beta)/K_m(beta) = -(L_k + m), where L_i = beta I_m'/I_m, L_k = beta K_m'/K_m.
"""

from __future__ import annotations

import sys

import mpmath as mp
import numpy as np
import scipy.linalg as sla
import scipy.special as sc
import sympy as sp
from scipy.integrate import solve_ivp

from _checks import check, section, summary  # noqa: E402  (derivations/_checks.py)

mp.mp.dps = 40



r = sp.Symbol("r", positive=True)
th, sv, eps = sp.symbols("theta s_lag epsilon", real=True)
m_ = sp.Symbol("m", positive=True, integer=True)
s_, nu_, beta_, kap_, K_ = sp.symbols("s nu beta kappa K")
Xr, Xt = sp.symbols("X_r X_theta")
P_, Q_, Li_, Lk_ = sp.symbols("P Q L_i L_k")


def rhat(a):
    return sp.Matrix([sp.cos(a), sp.sin(a)])


def that(a):
    return sp.Matrix([-sp.sin(a), sp.cos(a)])


def E_matrix(m):
    """The elastic load matrix: membrane force on the fluid = -K(t) E (X^r, X^theta)."""
    return sp.Matrix([[m**2, m], [m, m**2]])


# ---------------------------------------------------------------------------------------------
# Part 1. Geometry and membrane force law (thesis 4.1.3)
# ---------------------------------------------------------------------------------------------
def part1():
    section("Part 1. Linearised normal, force density (4.3), prestress and the elastic load")
    fr, ft = sp.Function("fr")(sv), sp.Function("ft")(sv)
    X = rhat(sv) + eps * (fr * rhat(sv) + ft * that(sv))
    Xs = sp.diff(X, sv)
    N = sp.Matrix([Xs[1], -Xs[0]])                     # |X_s| n: X_s turned clockwise (outward)
    N1 = sp.diff(N, eps).subs(eps, 0)
    N1_claim = (fr + sp.diff(ft, sv)) * rhat(sv) - (sp.diff(fr, sv) - ft) * that(sv)
    check("O(eps) of |X_s| n equals (X^r + X^th_s) r - (X^r_s - X^th) theta (thesis, after (4.12))",
          sp.simplify(N1 - N1_claim) == sp.zeros(2, 1))
    F = K_ * sp.diff(X, sv, 2)                          # (4.3)
    F0 = F.subs(eps, 0)
    F1 = sp.diff(F, eps).subs(eps, 0)
    F1_claim = K_ * ((sp.diff(fr, sv, 2) - 2 * sp.diff(ft, sv) - fr) * rhat(sv)
                     + (sp.diff(ft, sv, 2) + 2 * sp.diff(fr, sv) - ft) * that(sv))
    check("F = K X_ss: F0 = -K r (so [[p0]] = -K, (4.13)) and F1 as printed before (4.13)",
          sp.simplify(F0 + K_ * rhat(sv)) == sp.zeros(2, 1) and sp.simplify(F1 - F1_claim) == sp.zeros(2, 1))
    # O(eps) of (4.12): -[[p1]] r - [[p0]] N1 + nu [[d_r u1]] + F1 = 0 with [[p0]] = -K
    load = F1 + K_ * N1                                  # elastic part of the O(eps) balance
    load_claim = K_ * ((sp.diff(fr, sv, 2) - sp.diff(ft, sv)) * rhat(sv)
                       + (sp.diff(ft, sv, 2) + sp.diff(fr, sv)) * that(sv))
    check("F1 - [[p0]] N1 = K[(X^r_ss - X^th_s) r + (X^th_ss + X^r_s) theta]: the elastic part of (4.14)",
          sp.simplify(load - load_claim) == sp.zeros(2, 1))
    # one mode: X^r = A cos(ms), X^theta = B sin(ms)
    A, B = sp.symbols("A B")
    mode = {fr: A * sp.cos(m_ * sv), ft: B * sp.sin(m_ * sv)}
    L = load_claim.subs(mode).doit()
    Lr = sp.simplify((L.T * rhat(sv))[0] / sp.cos(m_ * sv))
    Lt = sp.simplify((L.T * that(sv))[0] / sp.sin(m_ * sv))
    Em = E_matrix(m_)
    ok = sp.simplify(Lr + K_ * (Em[0, 0] * A + Em[0, 1] * B)) == 0 and \
        sp.simplify(Lt + K_ * (Em[1, 0] * A + Em[1, 1] * B)) == 0
    check("mode (X^r cos ms, X^th sin ms): elastic load = -K E X with E = [[m^2, m], [m, m^2]]", ok,
          f"r: {Lr}, theta: {Lt}")
    # the printed jumps (4.15)-(4.16) per mode need opposite signs of X^theta
    mode_minus = {fr: A * sp.cos(m_ * sv), ft: -B * sp.sin(m_ * sv)}
    Lm = load_claim.subs(mode_minus).doit()
    pr_minus = sp.simplify((Lm.T * rhat(sv))[0] / (K_ * sp.cos(m_ * sv)))
    check("the printed pressure jump (-m^2 X^r + m X^th) before (4.24) is K(X^r_ss - X^th_s) only if X^theta "
          "multiplies -sin(ms); with +sin (4.18e) it is -m^2 X^r - m X^th",
          sp.simplify(pr_minus - (-m_**2 * A + m_ * B)) == 0 and sp.simplify(Lr / K_ - (-m_**2 * A - m_ * B)) == 0)
    check("the printed tangential jump (-(b+a) = m K X^r + m^2 K X^th) matches -nu[[u^th']]=K(X^th_ss + X^r_s) "
          "with X^theta on +sin(ms) (as (4.18e) says)", sp.simplify(-Lt / K_ - (m_ * A + m_**2 * B)) == 0)

    # rigid motions and the role of the prestress term
    trans = {fr: sp.cos(sv), ft: -sp.sin(sv)}           # X1 = e_x
    rot = {fr: sp.Integer(0), ft: sp.Integer(1)}         # X1 = theta-hat (rigid rotation)
    dil = {fr: sp.Integer(1), ft: sp.Integer(0)}         # uniform dilation (m = 0, changes the area)
    full = lambda d: sp.simplify(load_claim.subs(d).doit())  # noqa: E731
    naive = lambda d: sp.simplify(F1.subs(d).doit())  # noqa: E731
    check("m = 1 rigid translation (X^r, X^th) = (1, -1) is load-free; det E(1) = 0",
          full(trans) == sp.zeros(2, 1) and E_matrix(1).det() == 0)
    check("rigid rotation (m = 0 tangential) is load-free with the prestress term and loaded without it "
          "(so the term -[[p0]] N1 is required)", full(rot) == sp.zeros(2, 1) and naive(rot) != sp.zeros(2, 1))
    check("m = 0 dilation: load-free (tension K|X_s| of a circle of radius R is K R, Laplace's law gives "
          "[[p0]] = -K for every R); it changes the enclosed area, which incompressibility forbids",
          full(dil) == sp.zeros(2, 1))
    ev = sorted(E_matrix(m_).eigenvals().keys(), key=str)
    print(f"  eigenvalues of E: {ev}  (eigenvectors (1, 1) and (1, -1)); E > 0 exactly for m >= 2")
    return Em


# ---------------------------------------------------------------------------------------------
# Part 2. Polar calculus and the unsteady Stokes fields of one mode
# ---------------------------------------------------------------------------------------------
def part2():
    section("Part 2. Polar component formulas; fields p ~ r^(+-m), vortical part I_m / K_m(beta r)")
    ur, ut, pp = (sp.Function(n)(r, th) for n in ("ur", "ut", "pp"))
    c, s = sp.cos(th), sp.sin(th)
    dx = lambda f: c * sp.diff(f, r) - s / r * sp.diff(f, th)  # noqa: E731
    dy = lambda f: s * sp.diff(f, r) + c / r * sp.diff(f, th)  # noqa: E731
    lap = lambda f: sp.diff(f, r, 2) + sp.diff(f, r) / r + sp.diff(f, th, 2) / r**2  # noqa: E731
    ux, uy = ur * c - ut * s, ur * s + ut * c
    to_r = lambda vx, vy: vx * c + vy * s  # noqa: E731
    to_t = lambda vx, vy: -vx * s + vy * c  # noqa: E731
    div = dx(ux) + dy(uy)
    ok_div = sp.simplify(div - (sp.diff(r * ur, r) / r + sp.diff(ut, th) / r)) == 0
    lr = to_r(lap(ux), lap(uy))
    lt = to_t(lap(ux), lap(uy))
    ok_lap = (sp.simplify(lr - (lap(ur) - ur / r**2 - 2 * sp.diff(ut, th) / r**2)) == 0
              and sp.simplify(lt - (lap(ut) - ut / r**2 + 2 * sp.diff(ur, th) / r**2)) == 0)
    ok_grad = (sp.simplify(to_r(dx(pp), dy(pp)) - sp.diff(pp, r)) == 0
               and sp.simplify(to_t(dx(pp), dy(pp)) - sp.diff(pp, th) / r) == 0)
    # strain-rate traction on r = const: e_ij n_j with e = grad u + grad u^T
    J = sp.Matrix([[dx(ux), dy(ux)], [dx(uy), dy(uy)]])
    tr = (J + J.T) * sp.Matrix([c, s])
    ok_tr = (sp.simplify(to_r(tr[0], tr[1]) - 2 * sp.diff(ur, r)) == 0
             and sp.simplify(to_t(tr[0], tr[1]) - (sp.diff(ut, r) - ut / r + sp.diff(ur, th) / r)) == 0)
    check("polar grad, div, vector Laplacian (4.17a-c) and traction, from Cartesian differentiation",
          ok_div and ok_lap and ok_grad and ok_tr, f"div {ok_div}, lap {ok_lap}, grad {ok_grad}, traction {ok_tr}")

    # per-mode fields, general m; F solves the modified Bessel ODE r^2F'' + rF' - (beta^2 r^2 + m^2)F = 0
    F = sp.Function("F")(r)
    a, A = sp.symbols("a A")
    F2 = -sp.diff(F, r) / r + (beta_**2 + m_**2 / r**2) * F

    def reduce(e):
        e = e.subs(sp.Derivative(F, (r, 3)), sp.diff(F2, r)).subs(sp.Derivative(F, (r, 2)), F2)
        e = e.subs(sp.Derivative(F, (r, 2)), F2)
        return sp.simplify(sp.expand(e.subs(beta_, sp.sqrt(s_ / nu_))))

    res = {}
    for region, P in (("inside", a * r**m_), ("outside", a * r**(-m_))):
        p = P * sp.cos(m_ * th)
        psi = A * F * sp.sin(m_ * th)                     # u = -grad p / s + curl(psi z)
        u_r = -sp.diff(p, r) / s_ + sp.diff(psi, th) / r
        u_t = -sp.diff(p, th) / (r * s_) - sp.diff(psi, r)
        mom_r = s_ * u_r + sp.diff(p, r) - nu_ * (lap(u_r) - u_r / r**2 - 2 * sp.diff(u_t, th) / r**2)
        mom_t = s_ * u_t + sp.diff(p, th) / r - nu_ * (lap(u_t) - u_t / r**2 + 2 * sp.diff(u_r, th) / r**2)
        cont = sp.diff(r * u_r, r) / r + sp.diff(u_t, th) / r
        res[region] = [reduce(sp.expand(mom_r / sp.cos(m_ * th))), reduce(sp.expand(mom_t / sp.sin(m_ * th))),
                       reduce(sp.expand(cont / sp.cos(m_ * th))), sp.simplify(lap(P) - m_**2 * P / r**2)]
        # also: U = u_r/cos, V = u_t/sin; incompressibility gives V = -(r U)'/m
        U = sp.simplify(u_r / sp.cos(m_ * th))
        V = sp.simplify(u_t / sp.sin(m_ * th))
        res[region].append(sp.simplify(V + sp.diff(r * U, r) / m_))
    ok = all(sp.simplify(e) == 0 for v in res.values() for e in v)
    check("general m: p = a r^(+-m) cos(m th) with u = -grad p/s + curl(A F(r) sin(m th) z) satisfies "
          "s u = -grad p + nu Lap u and div u = 0 exactly when F solves the modified Bessel ODE "
          "(F = I_m(beta r) inside, K_m(beta r) outside)", ok, "" if ok else str(res))
    print("  Per mode: u^r = U cos(m th), u^th = V sin(m th), with V = -(r U)'/m from continuity.")
    print("  The thesis's (4.20) u^th = +(r u^r)'/m therefore holds only if u^theta multiplies -sin(m th).")
    return ok


# ---------------------------------------------------------------------------------------------
# Part 3. Interface conditions -> load H(s), D(s), G
# ---------------------------------------------------------------------------------------------
def derive_H():
    """Continuity + kinematics at r = 1 (4 equations for a, At, b, Bt), then the load.

    Amplitudes at r = 1: inside p = a r^m, vortical At = A I_m(beta); outside p = b r^-m,
    Bt = B K_m(beta). U = -p'/s + m A F/r, V = m p/(r s) - A F'; F'(1)/F(1) = L (L_i or L_k);
    F''(1)/F(1) = beta^2 + m^2 - L (Bessel ODE at r = 1).
    """
    m = m_
    a, At, b, Bt = sp.symbols("a At b Bt")
    eqs = [-m * a / s_ + m * At - s_ * Xr, m * a / s_ - At * Li_ - s_ * Xt,     # inside: U, V = s X
           m * b / s_ + m * Bt - s_ * Xr, m * b / s_ - Bt * Lk_ - s_ * Xt]      # outside
    sol = sp.solve(eqs, [a, At, b, Bt], dict=True)[0]
    dU_in = -m * (m - 1) * a / s_ + m * At * (Li_ - 1)
    dU_out = -m * (m + 1) * b / s_ + m * Bt * (Lk_ - 1)
    dV_in = m * (m - 1) * a / s_ - At * (beta_**2 + m**2 - Li_)
    dV_out = -m * (m + 1) * b / s_ - Bt * (beta_**2 + m**2 - Lk_)
    # load the membrane exerts on the fluid: h = [[p]] r - nu [[d_r u]]  (from (4.12)/(4.14))
    hr = ((b - a) - nu_ * (dU_out - dU_in)).subs(sol)
    ht = (-nu_ * (dV_out - dV_in)).subs(sol)
    jump_dU = sp.simplify((dU_out - dU_in).subs(sol))
    H = sp.Matrix([[sp.diff(hr, Xr), sp.diff(hr, Xt)], [sp.diff(ht, Xr), sp.diff(ht, Xt)]])
    H = H.subs(beta_**2, s_ / nu_).subs({Li_: m + P_, Lk_: -m - Q_}).applyfunc(sp.factor)
    return sol, H, jump_dU


def H_closed(m, s, P, Q):
    return [[s**2 * (sp.Integer(2) / m + 1 / P + 1 / Q), s**2 * (1 / P - 1 / Q)],
            [s**2 * (1 / P - 1 / Q), s**2 * (1 / P + 1 / Q)]]


def mpPQ(m, s, nu):
    beta = mp.sqrt(mp.mpmathify(s) / nu)
    return beta, beta * mp.besseli(m + 1, beta) / mp.besseli(m, beta), \
        beta * mp.besselk(m - 1, beta) / mp.besselk(m, beta)


def D_num(m, s, nu, kappa):
    """Derived D(s) = H(s) + kappa E in mpmath (X^theta on +sin)."""
    _, P, Q = mpPQ(m, s, nu)
    s = mp.mpmathify(s)
    return mp.matrix([[s**2 * (mp.mpf(2) / m + 1 / P + 1 / Q) + kappa * m**2, s**2 * (1 / P - 1 / Q) + kappa * m],
                      [s**2 * (1 / P - 1 / Q) + kappa * m, s**2 * (1 / P + 1 / Q) + kappa * m**2]])


_BESSEL_MEMO: dict = {}


def bessel_deriv(bes, n, z, k):
    """k-th derivative of I_n or K_n at z (DLMF 10.29.5): 2^-k sum_j C(k,j) I_{n-k+2j}(z), and
    (-1/2)^k sum_j C(k,j) K_{n-k+2j}(z). Bessel values are memoised per (function, order, z, dps)."""
    fac = mp.mpf(1) / 2**k if bes is mp.besseli else (-mp.mpf(1) / 2) ** k
    total = 0
    for j in range(k + 1):
        key = (bes.__name__, n - k + 2 * j, z, mp.mp.dps)
        if key not in _BESSEL_MEMO:
            _BESSEL_MEMO[key] = bes(n - k + 2 * j, z)
        total += mp.binomial(k, j) * _BESSEL_MEMO[key]
    return fac * total


def field_based_H(m, s, nu, X):
    """Independent numerical route: mpmath fields (besseli/besselk and their derivatives by
    DLMF 10.29.5), a 4x4 interface solve, momentum and continuity residuals at interior points,
    and the load from the fields, both as [[p]] r - nu [[d_r u]] and as minus the jump of the full
    viscous traction. Returns (load, -traction jump, (a, b), PDE residual, interface error, |[[U']]|)."""
    s = mp.mpmathify(s)
    beta = mp.sqrt(s / nu)

    def fields(pw, bes, a, A):
        """(p, U, V) and their r-derivatives up to order 2 as lists of callables."""
        g = [lambda x, k=k: beta**k * bessel_deriv(bes, m, beta * x, k) for k in range(4)]
        p = [lambda x: a * x**pw, lambda x: a * pw * x ** (pw - 1)]
        U = [lambda x: -a * pw * x ** (pw - 1) / s + A * m * g[0](x) / x,
             lambda x: -a * pw * (pw - 1) * x ** (pw - 2) / s + A * m * (g[1](x) / x - g[0](x) / x**2),
             lambda x: (-a * pw * (pw - 1) * (pw - 2) * x ** (pw - 3) / s
                        + A * m * (g[2](x) / x - 2 * g[1](x) / x**2 + 2 * g[0](x) / x**3))]
        V = [lambda x: a * m * x ** (pw - 1) / s - A * g[1](x),
             lambda x: a * m * (pw - 1) * x ** (pw - 2) / s - A * g[2](x),
             lambda x: a * m * (pw - 1) * (pw - 2) * x ** (pw - 3) / s - A * g[3](x)]
        return p, U, V

    M = mp.matrix(4, 4)
    for j, (pw, bes, a, A) in enumerate([(m, mp.besseli, 1, 0), (m, mp.besseli, 0, 1),
                                         (-m, mp.besselk, 1, 0), (-m, mp.besselk, 0, 1)]):
        _, U, V = fields(pw, bes, a, A)
        row = 0 if j < 2 else 2
        M[row, j], M[row + 1, j] = U[0](1), V[0](1)
    a, A, b, B = mp.lu_solve(M, mp.matrix([s * X[0], s * X[1], s * X[0], s * X[1]]))
    pi_, Ui, Vi = fields(m, mp.besseli, a, A)
    po, Uo, Vo = fields(-m, mp.besselk, b, B)
    res = 0
    for (p, U, V, x) in [(pi_, Ui, Vi, mp.mpf("0.6")), (po, Uo, Vo, mp.mpf("1.7"))]:
        lapU = U[2](x) + U[1](x) / x - (m * m + 1) * U[0](x) / x**2 - 2 * m * V[0](x) / x**2
        lapV = V[2](x) + V[1](x) / x - (m * m + 1) * V[0](x) / x**2 - 2 * m * U[0](x) / x**2
        r1 = s * U[0](x) + p[1](x) - nu * lapU                     # (4.17a), cos(m theta) part
        r2 = s * V[0](x) - m * p[0](x) / x - nu * lapV              # (4.17b), sin(m theta) part
        r3 = (U[0](x) + x * U[1](x)) / x + m * V[0](x) / x          # (4.17c)
        # the analytic r-derivatives agree with numerical differentiation
        r4 = abs(mp.diff(U[0], x) - U[1](x))
        res = max(res, abs(r1), abs(r2), abs(r3), r4)
    dU = Uo[1](1) - Ui[1](1)
    h = (po[0](1) - pi_[0](1) - nu * dU, -nu * (Vo[1](1) - Vi[1](1)))
    # full stress: sigma_rr = -p + 2 nu U', sigma_rtheta = nu (V' - V/r - m U/r)  (per sin)
    t = (-(po[0](1) - pi_[0](1)) + 2 * nu * dU,
         nu * ((Vo[1](1) - Vo[0](1) - m * Uo[0](1)) - (Vi[1](1) - Vi[0](1) - m * Ui[0](1))))
    cont = max(abs(Ui[0](1) - s * X[0]), abs(Uo[0](1) - s * X[0]), abs(Vi[0](1) - s * X[1]),
               abs(Vo[0](1) - s * X[1]))
    return h, t, (a, b), res, cont, abs(dU)


def part3():
    section("Part 3. Interface conditions at r = 1 -> load H(s), D(s) = H(s) + kappa E, G = kappa E")
    mp.mp.dps = 30
    sol, H, jump_dU = derive_H()
    print("  H(s) X := [[p]] r - nu [[d_r u]] (force per length the membrane exerts on the fluid):")
    for i, j, nm in ((0, 0, "H_rr"), (0, 1, "H_rth"), (1, 0, "H_thr"), (1, 1, "H_thth")):
        print(f"    {nm:7s} = {H[i, j]}")
    cl = H_closed(m_, s_, P_, Q_)
    check("H(s) = s^2 [[2/m + 1/P + 1/Q, 1/P - 1/Q], [1/P - 1/Q, 1/P + 1/Q]]",
          all(sp.simplify(H[i, j] - cl[i][j]) == 0 for i in range(2) for j in range(2)))
    check("[[d_r u^r]] = 0 follows from continuity + incompressibility (4.9)", jump_dU == 0)
    check("Lorentz reciprocity: H symmetric (weights int cos^2 = int sin^2 = pi, so W = pi I)",
          sp.simplify(H[0, 1] - H[1, 0]) == 0)

    print("  Field-based check (mpmath I_m, K_m fields, numerical derivatives, 4x4 interface solve):")
    okF, worst = True, 0
    for (m, s, nu) in [(2, mp.mpc("0.3", "1.7"), mp.mpf("0.05")), (3, mp.mpc("-0.2", "0.9"), mp.mpf("0.3")),
                       (5, mp.mpc("0.1", "-2.5"), mp.mpf("0.01"))]:
        X = [mp.mpc("0.7", "-0.2"), mp.mpc("-0.4", "1.1")]
        h, t, _, res, cont, jd = field_based_H(m, s, nu, X)
        Dm = D_num(m, s, nu, 0)
        pred = [Dm[0, 0] * X[0] + Dm[0, 1] * X[1], Dm[1, 0] * X[0] + Dm[1, 1] * X[1]]
        scale = max(abs(pred[0]), abs(pred[1]))
        err = max(abs(h[0] - pred[0]), abs(h[1] - pred[1])) / scale
        err_t = max(abs(t[0] + h[0]), abs(t[1] + h[1])) / scale
        worst = max(worst, err)
        okF &= err < 1e-15 and res < 1e-15 and cont < 1e-25 and jd < 1e-15 and err_t < 1e-15
        print(f"    m={m} s={mp.nstr(s, 4)} nu={mp.nstr(nu, 3)}: PDE residual {mp.nstr(res, 3)}, interface "
              f"{mp.nstr(cont, 3)}, [[U']] {mp.nstr(jd, 3)}, |H_fields - H_closed| {mp.nstr(err, 3)}, "
              f"full traction vs [[p]] - nu[[u_r]] {mp.nstr(err_t, 3)}")
    check("fields satisfy (4.17a-c) to rounding; the load from the fields equals the closed form; the jump of "
          "the full viscous traction equals that of -p r + nu d_r u", okF, f"worst {mp.nstr(worst, 3)}")
    mp.mp.dps = 40

    okR, okP = True, True
    for m in (2, 3, 7):
        for s in (mp.mpc("0.2", "1.3"), mp.mpc("-0.3", "2.2"), mp.mpc("0.05", "-0.7")):
            A1, A2 = D_num(m, s, 0.02, 0.7), D_num(m, mp.conj(s), 0.02, 0.7)
            okR &= max(abs(A2[i, j] - mp.conj(A1[i, j])) for i in range(2) for j in range(2)) < 1e-25
        for w in (0.3, 1.0, 4.0):
            Hm = D_num(m, 1j * w, 0.01, 0)
            for X in ([1, 0], [0, 1], [0.3 - 0.5j, 1.2 + 0.1j], [1, -1j], [1, 1], [1, -1]):
                f = [Hm[0, 0] * X[0] + Hm[0, 1] * X[1], Hm[1, 0] * X[0] + Hm[1, 1] * X[1]]
                okP &= mp.re(f[0] * mp.conj(1j * w * X[0]) + f[1] * mp.conj(1j * w * X[1])) > 0
    check("real time-domain operator: D(conj s) = conj D(s) (principal beta)", okR)
    check("passivity: Re(f . conj u) > 0 on s = i omega for every X (viscous dissipation)", okP)
    return H


# ---------------------------------------------------------------------------------------------
# Part 4. Limits: nu -> 0 (inviscid, Mathieu), s -> 0 (beta = 0), natural modes
# ---------------------------------------------------------------------------------------------
def part4a():
    section("Part 4a. Inviscid limit nu -> 0 (singular: tangential stress balance)")
    m = m_
    pt, qt, Bb = sp.symbols("ptilde qtilde B", positive=True)
    cl = H_closed(m, s_, Bb * pt, Bb * qt)
    lim = [[sp.limit(sp.expand(cl[i][j]), Bb, sp.oo) for j in range(2)] for i in range(2)]
    ok = sp.simplify(lim[0][0] - 2 * s_**2 / m) == 0 and lim[0][1] == lim[1][0] == lim[1][1] == 0
    check("P, Q ~ beta -> oo: H -> diag(2 s^2/m, 0); H_rth, H_thth = O(s^2/beta) = O(sqrt(nu s^3))", ok, str(lim))
    Em = E_matrix(m)
    xt = sp.solve(Em[1, 0] * Xr + Em[1, 1] * Xt, Xt)[0]
    red = sp.factor((Em[0, 0] * Xr + Em[0, 1] * xt) / Xr)
    lam2 = sp.factor(kap_ * red / (2 / m))
    check("tangential row -> K(t)(m X^r + m^2 X^th) = 0, so X^th = -X^r/m (tau < 1/2); radial row -> "
          "(2/m) X'' + K(t)(m^2 - 1) X = 0", sp.simplify(xt + Xr / m) == 0 and sp.simplify(red - (m**2 - 1)) == 0)
    check("inviscid limit is the Mathieu equation X'' + lambda0^2 (1 + 2 tau sin t) X = 0, "
          "lambda0^2 = kappa m (m^2 - 1)/2 (Rayleigh's capillary-column frequency with tension K and equal "
          "densities, T m(m^2-1)/((rho_in + rho_out) R^3))",
          sp.simplify(lam2 - kap_ * m * (m**2 - 1) / 2) == 0, f"lambda0^2 = {lam2}")
    # naive force law (no prestress): different lambda0
    En = sp.Matrix([[m**2 + 1, 2 * m], [2 * m, m**2 + 1]])
    xtn = sp.solve(En[1, 0] * Xr + En[1, 1] * Xt, Xt)[0]
    redn = sp.factor((En[0, 0] * Xr + En[0, 1] * xtn) / Xr)
    print(f"  (without the prestress term the load would be -K {list(En)} X, the inviscid radial stiffness "
          f"{redn} instead of m^2 - 1:\n   it disagrees with Rayleigh's frequency, unlike the 3D case.)")
    # forcing split in the inviscid limit
    print("  forcing = 'pressure': K(t) only in the radial row -> the same Mathieu equation (the tangential")
    print("  row still slaves X^th = -X^r/m). forcing = 'tangential': the radial row has constant kappa and")
    print("  the slaving holds for tau < 1/2 -> an unforced oscillator (no instability for tau < 1/2).")
    print("  Small nu: the slaved combination relaxes on the fast scale |s| ~ (kappa^2 m^4/(4 nu))^(1/3)")
    print("  (s^2 (1/P + 1/Q) ~ 2 sqrt(nu) s^(3/2) against kappa m^2): the limit is singular.")
    return ok


def part4b():
    section("Part 4b. beta = 0 (s = 0, harmonic n = 0 term): D(0) = kappa E; small-s Stokes limit")
    m = m_
    # small beta: P = beta^2/(2(m+1)) + ..., Q = beta^2/(2(m-1)) + ... (m >= 2)
    ok_series = True
    for mm in (2, 3, 5):
        x = mp.mpf("1e-4")
        Pn = x * mp.besseli(mm + 1, x) / mp.besseli(mm, x)
        Qn = x * mp.besselk(mm - 1, x) / mp.besselk(mm, x)
        ok_series &= abs(Pn / (x**2 / (2 * (mm + 1))) - 1) < 1e-7 and abs(Qn / (x**2 / (2 * (mm - 1))) - 1) < 1e-6
    check("P ~ beta^2/(2(m+1)), Q ~ beta^2/(2(m-1)) as beta -> 0 (m >= 2; DLMF 10.25.2, 10.31.1; "
          "mpmath at beta = 1e-4)", ok_series)
    R0 = sp.Matrix([[2 * (m + 1) + 2 * (m - 1), 2 * (m + 1) - 2 * (m - 1)], [4, 2 * (m + 1) + 2 * (m - 1)]])
    R0 = R0.applyfunc(sp.expand)
    print(f"  => H(s) = nu s R0 + o(s), R0 = {list(R0)} -> 0: D(0) = kappa E (the s -> 0 limit), G = kappa E.")
    # independent steady Stokes (beta = 0) solution: polynomial fields, prescribed velocity (Vr, Vt) at r = 1
    a, c1, bb, c2, Vr, Vt = sp.symbols("a c1 b c2 V_r V_theta")
    Ui = a * m * r**(m + 1) / (4 * nu_ * (m + 1)) + c1 * r**(m - 1)      # nu (Lap u)_r = p' (see Part 6)
    Uo = bb * m * r**(1 - m) / (4 * nu_ * (m - 1)) + c2 * r**(-m - 1)
    Vi, Vo = -sp.diff(r * Ui, r) / m, -sp.diff(r * Uo, r) / m
    eqs = [Ui.subs(r, 1) - Vr, Uo.subs(r, 1) - Vr, Vi.subs(r, 1) - Vt, Vo.subs(r, 1) - Vt]
    so = sp.solve(eqs, [a, c1, bb, c2], dict=True)[0]
    hr = (bb - a - nu_ * (sp.diff(Uo, r) - sp.diff(Ui, r))).subs(r, 1).subs(so)
    ht = (-nu_ * (sp.diff(Vo, r) - sp.diff(Vi, r))).subs(r, 1).subs(so)
    Rs = sp.Matrix([[sp.diff(hr, Vr), sp.diff(hr, Vt)], [sp.diff(ht, Vr), sp.diff(ht, Vt)]]).applyfunc(sp.simplify)
    # check the steady fields solve nu Lap u = grad p
    okst = True
    for mm in (2, 3, 4):
        for (U, P) in ((Ui, a * r**m), (Uo, bb * r**(-m))):
            U, P = U.subs(m, mm), P.subs(m, mm)
            V = -sp.diff(r * U, r) / mm
            lapU = sp.diff(U, r, 2) + sp.diff(U, r) / r - (mm**2 + 1) * U / r**2 - 2 * mm * V / r**2
            okst &= sp.simplify(nu_ * lapU - sp.diff(P, r)) == 0
    check("steady Stokes (polynomial fields, independent of the Bessel route): load = nu R0 V with the same R0",
          okst and sp.simplify(Rs - nu_ * R0) == sp.zeros(2, 2), f"nu R0 = {list(Rs)}")


def part4c():
    section("Part 4c. Natural modes det D(s) = 0 at tau = 0")
    mp.mp.dps = 25
    kappa = mp.mpf(1)
    ok_all = True
    for m in (2, 3):
        lam0 = mp.sqrt(kappa * m * (m * m - 1) / 2)
        guess, devs = 1j * lam0, []
        for nu in ("1e-6", "1e-5", "1e-4", "1e-3"):
            root = mp.findroot(lambda s: mp.det(D_num(m, s, mp.mpf(nu), kappa)), guess)
            guess = root
            devs.append(abs(root - 1j * lam0))
            ok_all &= mp.re(root) < 0
            print(f"    m={m} nu={nu:6s} s = {mp.nstr(root, 12):30s} |s - i lambda0| = {mp.nstr(devs[-1], 3)}")
        ratio = devs[1] / devs[0]
        ok_all &= 2.6 < ratio < 3.7 and devs[0] < 1e-2
        print(f"    deviation ratio per decade of nu: {mp.nstr(ratio, 4)} (sqrt(10) = 3.16: Stokes-layer damping)")
    mp.mp.dps = 40
    check("oscillatory natural mode -> +-i lambda0, lambda0^2 = kappa m(m^2-1)/2, with O(sqrt nu) correction "
          "and Re s < 0", ok_all)


# ---------------------------------------------------------------------------------------------
# Part 5. The printed (4.24)-(4.25) and the errata
# ---------------------------------------------------------------------------------------------
def printed_system(m, s, nu, kappa):
    """Printed (4.24)-(4.25) with k -> m: M X_n = tau R (X_{n-1} - X_{n+1}), thesis's J, H = H^(1)."""
    s = mp.mpmathify(s)
    beta = mp.sqrt(s / nu)
    w = 1j * beta
    J = lambda n: mp.besselj(n, w)  # noqa: E731
    H = lambda n: mp.hankel1(n, w)  # noqa: E731
    c = nu**2 / kappa
    A = 1j * beta**4 / (2 * m) * c * (2 - H(m + 1) / H(m - 1) - J(m - 1) / J(m + 1)) + 1j * m**2
    B = -1j * beta**4 / (2 * m) * c * (H(m + 1) / H(m - 1) - J(m - 1) / J(m + 1)) - 1j * m
    C = -beta**3 * c * (H(m) / H(m - 1) - J(m) / J(m + 1)) - 1j * m
    D = beta**3 * c * (H(m) / H(m - 1) + J(m) / J(m + 1)) - 1j * m**2
    return mp.matrix([[A, B], [C, D]]), mp.matrix([[-m**2, m], [m, m**2]])


def part5():
    section("Part 5. Comparison with the printed (4.24)-(4.25); chapter-4 ERRATA verdicts")
    verdicts = {}
    ok_map, ok_22 = True, True
    for (m, s, nu, kappa) in [(2, mp.mpc("0.25", "1.3"), mp.mpf("0.01"), mp.mpf("0.3")),
                              (4, mp.mpc("0.5", "-3.0"), mp.mpf("0.004"), mp.mpf("2.0")),
                              (3, mp.mpc("0", "2.5"), mp.mpf("0.02"), mp.mpf("0.02"))]:
        Mp, Rp = printed_system(m, s, nu, kappa)
        Dd = D_num(m, s, nu, kappa)
        Ed = mp.matrix([[m**2, m], [m, m**2]])
        # thesis variables: Xth_thesis = -Xth (the convention of its (4.20)); rows: (i/k) r-row, (-i/k) th-row
        T = mp.matrix([[1, 0], [0, -1]])
        Dt = mp.matrix([[1j / kappa, 0], [0, -1j / kappa]]) * Dd * T
        Gt = mp.matrix([[-1 / kappa, 0], [0, 1 / kappa]]) * (kappa * Ed) * T   # (i/k) i tau G -> -tau G/k
        sc_ = max(abs(Dt[i, j]) for i in range(2) for j in range(2))
        ok_map &= max(abs(Mp[0, 0] - Dt[0, 0]), abs(Mp[0, 1] - Dt[0, 1]), abs(Mp[1, 0] - Dt[1, 0])) < 1e-25 * sc_
        ok_map &= max(abs(Rp[0, 0] - Gt[0, 0]), abs(Rp[0, 1] - Gt[0, 1]), abs(Rp[1, 0] - Gt[1, 0])) < 1e-30
        ok_22 &= abs(Mp[1, 1] + Dt[1, 1]) < 1e-25 * sc_ and abs(Rp[1, 1] + Gt[1, 1]) < 1e-30
    check("printed (4.24)-(4.25) (k -> m) = derived system in the thesis's variables (X^th on -sin, as (4.20) "
          "implies; rows scaled by i/kappa and -i/kappa) in entries (1,1), (1,2), (2,1) of both M_n and R", ok_map)
    check("entry (2,2) -- the X^theta terms of (4.25), D_n and the m^2 tau term -- has the opposite sign "
          "in the print", ok_22)
    # independent evidence that the print is wrong: reciprocity given passivity
    m, nu, kappa = 3, mp.mpf("0.01"), mp.mpf("0.5")
    elastic = mp.matrix([[1j * m**2, -1j * m], [-1j * m, -1j * m**2]])       # printed constant terms
    omegas = (mp.mpf("0.4"), mp.mpf("1.7"), mp.mpf("6"))
    fluid = {w: printed_system(m, 1j * w, nu, kappa)[0] - elastic for w in omegas}
    # row 1 times -i kappa is the radial load (its X^r entry is exactly H_rr); row 2 times
    # sigma (-i kappa), sigma = +-1 chosen so that its diagonal entry is dissipative at every omega
    sig = [g for g in (1, -1)
           if all(mp.re(g * (-1j * kappa) * fluid[w][1, 1] / (1j * w)) > 0 for w in omegas)]
    ratios = [(-1j * kappa * fluid[w][0, 1]) / (sig[0] * (-1j * kappa) * fluid[w][1, 0]) for w in omegas]
    derived = [D_num(m, 1j * w, nu, 0)[0, 1] / D_num(m, 1j * w, nu, 0)[1, 0] for w in omegas]
    passive_derived = all(mp.re(D_num(m, 1j * w, nu, 0)[i, i] / (1j * w)) > 0 for w in omegas for i in range(2))
    check("Lorentz reciprocity: with rows normalised so the diagonal fluid entries are dissipative (a constant "
          "row factor, the only freedom), a reciprocal map has H_12/H_21 = w_2/w_1 = 1 > 0. Derived: +1; "
          "printed: -1 at every omega (violated)",
          len(sig) == 1 and all(abs(q + 1) < 1e-25 for q in ratios) and all(abs(q - 1) < 1e-25 for q in derived)
          and passive_derived, f"printed {[mp.nstr(q, 5) for q in ratios]}")
    Rm1 = mp.matrix([[-1, 1], [1, 1]])
    check("printed elastic matrix [[-m^2, m], [m, m^2]] at m = 1 is non-singular (det = -2): a rigid "
          "translation would be loaded; the derived E(1) is singular", abs(mp.det(Rm1) + 2) < 1e-30)
    verdicts["(4.24)-(4.25) one sign"] = ok_map and ok_22
    # k -> m
    check("ERRATUM '(4.24) RHS k tau(...) should be m tau': the derived G gives m (the only consistent "
          "value) -> CONFIRMED", ok_map)
    verdicts["k -> m"] = ok_map
    return verdicts


def hill_taus(Dfun, G, kind, N):
    """Real tau > 0 of the two-sided Hill pencil D(s_k) X_k = i tau G (X_{k-1} - X_{k+1}) (dense QZ)."""
    ks = np.arange(-N, N + 1) if kind == "harmonic" else np.arange(-N - 1, N + 1)
    shift = 0.0 if kind == "harmonic" else 0.5
    b = G.shape[0]
    K = len(ks)
    A = np.zeros((K * b, K * b), complex)
    Bm = np.zeros_like(A)
    for i, k in enumerate(ks):
        A[i * b:(i + 1) * b, i * b:(i + 1) * b] = Dfun(1j * (k + shift))
        if i > 0:
            Bm[i * b:(i + 1) * b, (i - 1) * b:i * b] = 1j * G
        if i < K - 1:
            Bm[i * b:(i + 1) * b, (i + 1) * b:(i + 2) * b] = -1j * G
    ev = sla.eigvals(A, Bm)
    ev = ev[np.isfinite(ev)]
    return np.sort(ev.real[(np.abs(ev.imag) < 1e-7 * np.maximum(1, abs(ev))) & (ev.real > 1e-12)])


def D_float(m, s, nu, kappa, printed=False):
    """D(s) from scipy's ive/kve (adequate here: |beta| <= 230), derived or printed (2,2)-sign."""
    if s == 0:
        Dd = kappa * np.array([[m * m, m], [m, m * m]], complex)
    else:
        beta = np.sqrt(s / nu)
        P = beta * sc.ive(m + 1, beta) / sc.ive(m, beta)
        Q = beta * sc.kve(m - 1, beta) / sc.kve(m, beta)
        Dd = np.array([[s * s * (2 / m + 1 / P + 1 / Q) + kappa * m * m, s * s * (1 / P - 1 / Q) + kappa * m],
                       [s * s * (1 / P - 1 / Q) + kappa * m, s * s * (1 / P + 1 / Q) + kappa * m * m]])
    if printed:  # the print's (2,2) sign, mapped back to our variables
        Dd[1, 1] = -Dd[1, 1]
    return Dd


def part5b(verdicts):
    section("Part 5b. Table 4.1 / Fig 4.3-4.5 resonances: derived vs printed system (tau = 0.45, m = 2..6)")
    ok, printed_ok = True, []
    for case, (nu, kappa, expect) in {1: (2e-4, 0.02, 3), 2: (2e-4, 0.08, 2)}.items():
        found = {}
        for printed in (False, True):
            unstable = []
            for m in range(2, 7):
                G = kappa * np.array([[m * m, m], [m, m * m]], float)
                if printed:
                    G[1, 1] = -G[1, 1]
                for kind in ("harmonic", "subharmonic"):
                    N = int(np.sqrt(kappa * m * (m * m - 1) / 2)) + 14
                    t = hill_taus(lambda s: D_float(m, s, nu, kappa, printed), G, kind, N)
                    if t.size and t[0] < 0.45:
                        unstable.append((m, kind, round(float(t[0]), 4)))
            found[printed] = unstable
            print(f"  case {case} (nu={nu}, kappa={kappa}) {'printed' if printed else 'derived'}: "
                  f"unstable (m, kind, tau_min) = {unstable}")
        lowest = {k: min(v, key=lambda u: u[2]) for k, v in found.items()}
        ok &= lowest[False][:2] == (expect, "subharmonic")
        printed_ok.append(lowest[True][:2] == (expect, "subharmonic"))
    ok &= not all(printed_ok)
    check("the most unstable mode (smallest tau_min) of the derived system is the thesis's resonant one, by period "
          "doubling (case 1: m = 3, case 2: m = 2; section 4.4, Fig 4.5); the printed sign makes m = 3 (harmonic) "
          "the most unstable in case 2", ok)
    # where the Table 4.1 stiffnesses come from: lambda0 = 1/2 (principal subharmonic resonance)
    k_derived = {m: 1 / (2 * m * (m * m - 1)) for m in (2, 3)}
    k_printed = {m: 1 / (2 * m * (m * m + 1)) for m in (2, 3)}
    print(f"  lambda0 = 1/2 at kappa = 1/(2m(m^2-1)) (derived): {k_derived}; with the printed sign the inviscid")
    print(f"  limit is lambda0^2 = kappa m(m^2+1)/2 and lambda0 = 1/2 needs kappa = {k_printed}. Table 4.1 uses")
    print("  kappa = 0.02 (m = 3) and 0.08 (m = 2): the derived values.")
    Dp = sp.Matrix([[2 * s_**2 / m_ + kap_ * m_**2, kap_ * m_], [kap_ * m_, -kap_ * m_**2]])  # printed, nu -> 0
    lam2p = sp.solve(Dp.det(), s_**2)[0]
    ok2 = sp.simplify(lam2p + kap_ * m_ * (m_**2 + 1) / 2) == 0 and lam2p.subs(m_, 1) != 0
    check("independent: the printed sign's inviscid limit has lambda0^2 = kappa m(m^2+1)/2 -- not Rayleigh's "
          "kappa m(m^2-1)/2, and non-zero at m = 1, where a rigid translation would oscillate", ok2)
    ok &= ok2
    verdicts["(4.24)-(4.25) one sign"] &= ok


def part5c(verdicts):
    section("Part 5c. Display after (4.27) (sign of X_{n-1} - X_{n+1}) and the harmonic n = 0 block")
    # Floquet convention: Hill null vector at the monodromy exponent reproduces the ODE solution
    lam2, tau = 0.3, 0.2
    def rhs(t, y):
        return [y[1], -lam2 * (1 + 2 * tau * np.sin(t)) * y[0]]
    Mono = np.column_stack([solve_ivp(rhs, (0, 2 * np.pi), y0, rtol=1e-12, atol=1e-14).y[:, -1]
                            for y0 in ([1.0, 0.0], [0.0, 1.0])])
    mu = np.linalg.eigvals(Mono)
    gamma = np.log(complex(mu[np.argmax(abs(mu))])) / (2 * np.pi)
    ns = np.arange(-25, 26)
    errs = {}
    for sign in (1, -1):
        K = len(ns)
        A = np.zeros((K, K), complex)
        for i, n in enumerate(ns):
            A[i, i] = (gamma + 1j * n) ** 2 + lam2
            if i > 0:
                A[i, i - 1] = -sign * 1j * tau * lam2
            if i < K - 1:
                A[i, i + 1] = sign * 1j * tau * lam2
        Xn = np.linalg.svd(A)[2][-1].conj()
        x0, v0 = np.sum(Xn), np.sum((gamma + 1j * ns) * Xn)
        sol = solve_ivp(rhs, (0, 5.0), [x0, v0], t_eval=[1.3, 2.9, 5.0], rtol=1e-12, atol=1e-14)
        series = [np.sum(Xn * np.exp((gamma + 1j * ns) * t)) for t in sol.t]
        errs[sign] = max(abs(sol.y[0] - np.array(series))) / abs(x0)
    ok_conv = errs[1] < 1e-8 and errs[-1] > 1e-3
    check("D(s_n) X_n = i tau G (X_{n-1} - X_{n+1}) reproduces the time-domain solution of "
          "D(d/dt)X + 2 tau sin(t) G X = 0 (inviscid Mathieu row); the opposite sign does not",
          ok_conv, f"errors {errs[1]:.1e} vs {errs[-1]:.1e}")
    # (4.24) with (i/kappa) rows: A_n X_n = tau R (X_{n-1} - X_{n+1}); display after (4.27): tau R (X_{n+1} - X_{n-1})
    check("ERRATUM 'display after (4.27) uses the opposite sign': (4.24)-(4.25) and the B matrix (B-check on "
          "n-1, -B-check on n+1) use tau R (X_{n-1} - X_{n+1}), which is what K = kappa(1 - i tau e^{it} + "
          "i tau e^{-it}) gives; the display has tau R (X_{n+1} - X_{n-1}) -> CONFIRMED (harmless: tau -> -tau "
          "is the time shift t -> t + pi, so the marginal |tau| are the same)", ok_conv)
    verdicts["display after (4.27) sign"] = ok_conv
    # n = 0: D(0) = G = kappa E -> X_0 = i tau (X_{-1} - X_1) = 2 tau Im X_1, whatever the (2,2) sign
    X1 = np.array([0.3 - 0.8j, -1.1 + 0.45j])
    X0 = 1j * 0.37 * (X1.conj() - X1)
    print(f"  harmonic n = 0: D(0) = G = kappa E (invertible for m >= 2) gives X_0 = 2 tau Im X_1 = {X0.real}; the "
          "printed A_0 = R with B-tilde = 2 R on the Im slots encodes the same equation.")


# ---------------------------------------------------------------------------------------------
# Part 6. beta = 0 fields (section 4.2 after (4.25))
# ---------------------------------------------------------------------------------------------
def part6(verdicts):
    section("Part 6. The beta = 0 case: Green's function, steady fields, a_0 = b_0 = 0")
    m = m_
    z = sp.Symbol("z", positive=True)
    a0, b0 = sp.symbols("a_0 b_0")
    # Green's function of r^2 G'' + 3 r G' + (1 - m^2) G = delta(r - z), jumps (4.23)
    Gl = -r**(m - 1) / (2 * m * z**m)
    Gr = -z**m / (2 * m * r**(m + 1))
    ok_G = all(sp.simplify(r**2 * sp.diff(g, r, 2) + 3 * r * sp.diff(g, r) + (1 - m**2) * g) == 0 for g in (Gl, Gr))
    ok_G &= sp.simplify((Gl - Gr).subs(r, z)) == 0 and sp.simplify((z**2 * (sp.diff(Gr, r) - sp.diff(Gl, r))).subs(r, z) - 1) == 0
    Gp_l, Gp_r = -r**(m - 1) / (2 * m * z**(m - 1)), -z**(m + 2) / (2 * m * r**(m + 1))   # printed, k -> m
    printed_cont = sp.simplify((Gp_l - Gp_r).subs(r, z))
    check("beta = 0 Green's function: G = -(1/(2m)) r^(m-1)/z^m (r < z), -(1/(2m)) z^m/r^(m+1) (r > z). The "
          "printed one has prefactor -1/(2k) (k -> m) and powers z^(m-1), z^(m+2) that violate continuity at r = z",
          ok_G and printed_cont != 0, f"printed G(z-) - G(z+) = {printed_cont}")
    # u_0^r by (4.21) with the correct G, p = a0 r^m (r < 1), b0 r^-m (r > 1), integrated piecewise
    ok_u, ok_print, ok_theta, ok_cont = True, True, True, True
    for mm in (2, 3, 4):
        Gl_m, Gr_m = Gl.subs(m, mm), Gr.subs(m, mm)
        si = z**2 / nu_ * mm * a0 * z**(mm - 1)
        so = -z**2 / nu_ * mm * b0 * z**(-mm - 1)
        # r < 1: int_0^r Gr si + int_r^1 Gl si + int_1^oo Gl so ; r > 1: int_0^1 Gr si + int_1^r Gr so + int_r^oo Gl so
        u_in = (sp.integrate(Gr_m * si, (z, 0, r)) + sp.integrate(Gl_m * si, (z, r, 1))
                + sp.integrate(Gl_m * so, (z, 1, sp.oo)))
        u_out = (sp.integrate(Gr_m * si, (z, 0, 1)) + sp.integrate(Gr_m * so, (z, 1, r))
                 + sp.integrate(Gl_m * so, (z, r, sp.oo)))
        u_in, u_out = sp.expand(sp.simplify(u_in)), sp.expand(sp.simplify(u_out))
        # the fields are C^1 at r = 1 for every a0, b0: continuity imposes nothing
        ok_u &= sp.simplify((u_in - u_out).subs(r, 1)) == 0
        ok_u &= sp.simplify((sp.diff(u_in, r) - sp.diff(u_out, r)).subs(r, 1)) == 0
        # kinematics u^r(1) = 0 and u^th(1) = -(r u^r)'(1)/m = 0 force a0 = b0 = 0
        v_in = -sp.diff(r * u_in, r) / mm
        solk = sp.solve([u_in.subs(r, 1), v_in.subs(r, 1)], [a0, b0], dict=True)
        ok_u &= solk == [{a0: 0, b0: 0}]
        pr_in = a0 / nu_ * (sp.Rational(mm, 4 * mm + 4) * r**(mm + 1) - r**(mm - 1) / 4) - b0 / nu_ / (4 * mm - 4) * r**(mm - 1)
        pr_out = -a0 / nu_ / (4 * mm + 4) * r**(-mm - 1) + b0 / nu_ * (sp.Rational(mm, 4 * mm - 4) * r**(-mm + 1) - r**(-mm - 1) / 4)
        ok_print &= sp.simplify(pr_out - u_out) == 0 and sp.simplify(pr_in - u_in) != 0
        # printed u_0^theta = +(r u_0^r)'/m of the printed u_0^r (the -sin convention of (4.20))
        pt_in = a0 / nu_ * (sp.Rational(mm + 2, 4 * mm + 4) * r**(mm + 1) - r**(mm - 1) / 4) - b0 / nu_ / (4 * mm - 4) * r**(mm - 1)
        pt_out = a0 / nu_ / (4 * mm + 4) * r**(-mm - 1) - b0 / nu_ * (sp.Rational(mm - 2, 4 * mm - 4) * r**(-mm + 1) - r**(-mm - 1) / 4)
        ok_theta &= all(sp.simplify(pt - sp.diff(r * pu, r) / mm) == 0 for pt, pu in ((pt_in, pr_in), (pt_out, pr_out)))
        # continuity of the printed fields at r = 1 gives b_0 = 0 only, not a_0 = 0
        cont = sp.solve([(pr_in - pr_out).subs(r, 1), (pt_in - pt_out).subs(r, 1)], [a0, b0], dict=True)
        ok_cont &= cont == [{b0: 0}]
        if mm == 2:
            print(f"  m = 2: u_0^r inside = {sp.collect(u_in, [a0, b0])}")
            print(f"         printed      = {sp.collect(sp.expand(pr_in), [a0, b0])}")
    check("u_0^r from (4.21) is C^1 at r = 1 for all a_0, b_0 (continuity imposes nothing); u^r(1) = u^th(1) = 0 "
          "(kinematics, s X = 0) gives a_0 = b_0 = 0", ok_u)
    check("printed u_0^r: outside branch correct; inside branch has the sign of its b_0 term wrong "
          "(+b_0 r^(m-1)/(4 nu (m-1)))", ok_print)
    check("printed u_0^theta = +(r u_0^r)'/m of the printed u_0^r (so it inherits that sign error); continuity of "
          "the printed fields at r = 1 gives only b_0 = 0 and leaves a_0 free", ok_theta and ok_cont)
    verdicts["beta = 0: a0 = b0 = 0 from kinematics"] = ok_u


# ---------------------------------------------------------------------------------------------
# Part 7. The plain-Python expressions the package implements
# ---------------------------------------------------------------------------------------------
EMIT = {
    "beta": "sqrt(s/nu)",
    "P": "beta*ratio_i(m, beta)",
    "Q": "beta/ratio_k(m - 1, beta)",
    "D_rr": "s**2*(2/m + 1/P + 1/Q) + kappa*m**2",
    "D_rt": "s**2*(1/P - 1/Q) + kappa*m",
    "D_tt": "s**2*(1/P + 1/Q) + kappa*m**2",
}


def part7():
    section("Part 7. Final D(s), G as plain Python (m, s, nu, kappa); X = (X^r, X^theta), X^theta on +sin")
    mp.mp.dps = 30
    for k, v in EMIT.items():
        print(f"  {k:5s} = {v}")
    print("  G = kappa*[[m**2, m], [m, m**2]] ('both'); [[m**2, m], [0, 0]]*kappa ('pressure');")
    print("      [[0, 0], [m, m**2]]*kappa ('tangential');  D(0) = kappa*[[m**2, m], [m, m**2]] (limit)")
    env = dict(sqrt=mp.sqrt, ratio_i=lambda n, x: mp.besseli(n + 1, x) / mp.besseli(n, x),
               ratio_k=lambda n, x: mp.besselk(n + 1, x) / mp.besselk(n, x))
    ok = True
    for (m, s, nu, kappa) in [(2, mp.mpc("0.3", "1.7"), mp.mpf("0.05"), mp.mpf("0.8")),
                              (6, mp.mpc("-0.2", "4.1"), mp.mpf("0.002"), mp.mpf("0.1"))]:
        loc = dict(env, m=m, s=s, nu=nu, kappa=kappa)
        for key, expr in EMIT.items():
            loc[key] = eval(expr, {}, loc)
        X = [mp.mpc("0.7", "-0.2"), mp.mpc("-0.4", "1.1")]
        h, *_ = field_based_H(m, s, nu, X)
        e1 = abs(loc["D_rr"] * X[0] + loc["D_rt"] * X[1] - (h[0] + kappa * (m * m * X[0] + m * X[1])))
        e2 = abs(loc["D_rt"] * X[0] + loc["D_tt"] * X[1] - (h[1] + kappa * (m * X[0] + m * m * X[1])))
        ok &= max(e1, e2) < 1e-15 * max(1, abs(h[0]), abs(h[1]))
    check("emitted expressions reproduce the field-based load plus kappa E X", ok)
    mp.mp.dps = 40


def main() -> int:
    print(__doc__.split("\n\n")[0])
    part1()
    part2()
    part3()
    part4a()
    part4b()
    part4c()
    verdicts = part5()
    part5b(verdicts)
    part5c(verdicts)
    part6(verdicts)
    part7()
    section("Summary")
    for k, v in verdicts.items():
        print(f"  erratum '{k}': {'CONFIRMED' if v else 'NOT CONFIRMED'}")
    return summary()


if __name__ == "__main__":
    sys.exit(main())
