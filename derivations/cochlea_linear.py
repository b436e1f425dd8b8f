#!/usr/bin/env python3
"""Linear oscillations of the 2D box cochlea model (thesis chapter 5): membrane at y = 0 between two
half-strips of unsteady Stokes fluid.

This script re-derives, without using the printed algebra, what ``spectralshell.models.cochlea``
implements:

    D(s_n) h_n = i tau G (h_{n-1} - h_{n+1}),    D(s) = diag(Z_k(s)) + kappa C,    G = kappa C,

for the cosine amplitudes h = (h_1, ..., h_M) of the membrane displacement h(x, t) = sum h_k cos(k x),
with Z_k(s) the transfer function (pressure jump per unit displacement) of one cosine mode and C
the cosine-Galerkin matrix of the stiffness profile e^{-alpha |x|}. Run
``python3 derivations/cochlea_linear.py``; it prints every check and exits 0 only if all pass.
The results are written up in ``derivations/cochlea_linear_result.md``.

Conventions (restated in the result file):
  * Dimensionless variables of thesis 5.2: x in [0, pi], y in R, time unit 1/omega; unsteady Stokes
    u_t = -grad p + nu Lap u, div u = 0 above and below y = 0 (5.4).
  * Membrane at y = 0 moves vertically only: u(x, 0, t) = 0, v(x, 0, t) = h_t (5.5b,c), and the
    pressure jump [[p]] = p(0+) - p(0-) = -K h (5.5a), K = kappa e^{-alpha x}(1 + 2 tau sin t).
  * Walls x = 0, pi: no penetration and no shear (the Neumann condition of 5.2), i.e. cosine
    modes for v, p and sine modes for u. Fields decay as |y| -> infinity.
  * One mode: e^{s t} times cos(k x) (p, v, h) or sin(k x) (u); beta = sqrt(s/nu + k^2) with
    Re beta > 0, k = 1, 2, ...
"""

from __future__ import annotations

import random
import sys

import mpmath as mp
import numpy as np
import sympy as sp
from scipy.integrate import quad

from _checks import check, section, summary  # noqa: E402  (derivations/_checks.py)

mp.mp.dps = 40

x, y = sp.symbols("x y", real=True)
k = sp.Symbol("k", positive=True)
s, nu, beta, h, a, b, Cu, Cl = sp.symbols("s nu beta h a b C_u C_l")
alpha = sp.Symbol("alpha", positive=True)
j_ = sp.Symbol("j", integer=True, nonnegative=True)
BETA2 = {beta**2: s / nu + k**2}


def on_shell(expr):
    """Simplify with beta^2 = s/nu + k^2 (beta is the only place sqrt enters)."""
    expr = sp.expand(expr)
    expr = expr.subs(nu, s / (beta**2 - k**2))
    return sp.simplify(expr)


def lap(f):
    return sp.diff(f, x, 2) + sp.diff(f, y, 2)


# ---------------------------------------------------------------------------------------------
# Part 1. Scalings (thesis 5.2) and Table 5.1
# ---------------------------------------------------------------------------------------------
def part1():
    section("Part 1. Nondimensionalisation of (5.1)-(5.3) and the Table 5.1 ranges")
    rho, mu, sig, L, lam, om, t = sp.symbols("rho mu sigma L lambda_c omega t", positive=True)
    # x = L xt/pi, t = tt/omega, u = L omega ut/pi, p = rho L^2 omega^2 pt/pi^2; the 2D delta
    # function scales as (pi/L)^2 and ds = L dst/pi, so f = K (L/pi)^-... per unit area.
    U, P, Xs = L * om / sp.pi, rho * L**2 * om**2 / sp.pi**2, L / sp.pi
    inertia = rho * U * om                      # rho du/dt
    pressure = P / Xs                           # grad p
    viscous = mu * U / Xs**2                    # mu Lap u
    force = sig * Xs * (1 / Xs**2) * Xs         # K (X0 - X) delta ds with K ~ sigma
    nu_ = sp.simplify(viscous / inertia)
    kappa_ = sp.simplify(force / inertia)
    check("pressure scale balances inertia (p = rho L^2 omega^2 pt / pi^2)",
          sp.simplify(pressure / inertia) == 1)
    check("nu = mu pi^2 / (rho L^2 omega), kappa = sigma pi / (rho L omega^2) (thesis 5.2)",
          sp.simplify(nu_ - mu * sp.pi**2 / (rho * L**2 * om)) == 0
          and sp.simplify(kappa_ - sig * sp.pi / (rho * L * om**2)) == 0)
    check("alpha = lambda_c L / pi (e^{-lambda_c s} with s = L st/pi)",
          sp.simplify(lam * Xs - lam * L / sp.pi) == 0)
    zeta = sp.simplify(nu_ / sp.sqrt(kappa_))
    check("zeta = nu/sqrt(kappa) = mu / sqrt(rho sigma (L/pi)^3) is independent of omega (5.4)",
          sp.simplify(zeta - mu / sp.sqrt(rho * sig * (L / sp.pi)**3)) == 0)

    vals = {rho: 1.0, mu: 0.02, sig: 6e5, L: 3.5, lam: 1.4}
    fn = sp.lambdify(om, nu_.subs(vals))
    fk = sp.lambdify(om, kappa_.subs(vals))
    a_val = float((lam * L / sp.pi).subs(vals))
    check("Table 5.1: alpha = 1.56", abs(a_val - 1.56) < 5e-3, f"alpha = {a_val:.6f}")
    stated = {"nu": (8.06e-6, 1.61e-4), "kappa": (0.135, 53.9)}
    at_400_1600 = {"nu": (fn(1600.0), fn(400.0)), "kappa": (fk(1600.0), fk(400.0))}
    at_100_2000 = {"nu": (fn(2000.0), fn(100.0)), "kappa": (fk(2000.0), fk(100.0))}
    print(f"  omega in [400, 1600]: nu in [{at_400_1600['nu'][0]:.4g}, {at_400_1600['nu'][1]:.4g}], "
          f"kappa in [{at_400_1600['kappa'][0]:.4g}, {at_400_1600['kappa'][1]:.4g}]")
    print(f"  omega in [100, 2000]: nu in [{at_100_2000['nu'][0]:.4g}, {at_100_2000['nu'][1]:.4g}], "
          f"kappa in [{at_100_2000['kappa'][0]:.4g}, {at_100_2000['kappa'][1]:.4g}]")
    close = lambda p, q: all(abs(u / v - 1) < 3e-3 for u, v in zip(p, q))  # noqa: E731
    check("ERRATA: the printed nu and kappa ranges are omega in [100, 2000] s^-1, not [400, 1600]",
          close(at_100_2000["nu"], stated["nu"]) and close(at_100_2000["kappa"], stated["kappa"])
          and not close(at_400_1600["kappa"], stated["kappa"]))
    z = float(zeta.subs(vals))
    check("zeta of Table 5.1 = 2.2e-5 (the thesis rounds it to 2e-5 in Fig 5.7)",
          abs(z - 2.2e-5) < 0.05e-5, f"zeta = {z:.4g}")


# ---------------------------------------------------------------------------------------------
# Part 2. Fields of one cosine mode; Z_k(s)
# ---------------------------------------------------------------------------------------------
def fields():
    """Upper (y > 0) and lower (y < 0) fields with pressure amplitudes b, a and vortical
    amplitudes C_u, C_l; the x dependence is cos(kx) for p, v and sin(kx) for u."""
    up = {"p": b * sp.exp(-k * y) * sp.cos(k * x),
          "u": (k * b / s * sp.exp(-k * y) + beta * Cu / k * sp.exp(-beta * y)) * sp.sin(k * x),
          "v": (k * b / s * sp.exp(-k * y) + Cu * sp.exp(-beta * y)) * sp.cos(k * x)}
    lo = {"p": a * sp.exp(k * y) * sp.cos(k * x),
          "u": (k * a / s * sp.exp(k * y) - beta * Cl / k * sp.exp(beta * y)) * sp.sin(k * x),
          "v": (-k * a / s * sp.exp(k * y) + Cl * sp.exp(beta * y)) * sp.cos(k * x)}
    return up, lo


def residuals(f):
    """Momentum (x, y) and continuity residuals of s u = -grad p + nu Lap u, div u = 0."""
    rx = s * f["u"] + sp.diff(f["p"], x) - nu * lap(f["u"])
    ry = s * f["v"] + sp.diff(f["p"], y) - nu * lap(f["v"])
    rc = sp.diff(f["u"], x) + sp.diff(f["v"], y)
    return rx, ry, rc


def part2():
    section("Part 2. Unsteady Stokes fields of one cosine mode, boundary conditions, Z_k(s)")
    up, lo = fields()
    for name, f in (("upper", up), ("lower", lo)):
        rx, ry, rc = residuals(f)
        check(f"{name} fields satisfy s u = -grad p + nu Lap u and div u = 0 (beta^2 = s/nu + k^2)",
              all(on_shell(r) == 0 for r in (rx, ry, rc)))
    walls = [up["u"].subs(x, 0), up["u"].subs(x, sp.pi), sp.diff(up["v"], x).subs(x, 0),
             sp.diff(up["v"], x).subs(x, sp.pi), sp.diff(up["p"], x).subs(x, sp.pi)]
    check("walls x = 0, pi: u = 0 (no penetration), v_x = p_x = 0 (Neumann; u_y + v_x = 0: no shear) "
          "for integer k", all(sp.simplify(w.subs(k, 3)) == 0 for w in walls))
    # boundary conditions at y = 0: u = 0 on both sides, v = s h on both sides
    eqs = [sp.simplify(up["u"].subs(y, 0) / sp.sin(k * x)), sp.simplify(lo["u"].subs(y, 0) / sp.sin(k * x)),
           sp.simplify(up["v"].subs(y, 0) / sp.cos(k * x)) - s * h,
           sp.simplify(lo["v"].subs(y, 0) / sp.cos(k * x)) - s * h]
    sol = sp.solve(eqs, [a, b, Cu, Cl], dict=True)
    check("u(x, 0±) = 0, v(x, 0±) = s h determine a, b, C_u, C_l uniquely", len(sol) == 1)
    sol = sol[0]
    jump = sp.simplify((up["p"] - lo["p"]).subs(y, 0).subs(sol) / (sp.cos(k * x) * h))
    Z = jump  # [[p]] = Z h; with (5.5a) [[p]] = -K h this gives (Z + K) h = 0
    forms = {
        "2 s^2 beta / (k (beta - k))": 2 * s**2 * beta / (k * (beta - k)),
        "2 nu s beta (beta + k) / k": 2 * nu * s * beta * (beta + k) / k,
        "2 s^2/k + 2 nu s (k + beta)": 2 * s**2 / k + 2 * nu * s * (k + beta),
        "thesis (5.9): 2 nu^2 (beta - k)(beta + k)^2 beta / k": 2 * nu**2 * (beta - k) * (beta + k)**2 * beta / k,
    }
    for name, form in forms.items():
        check(f"pressure jump of one mode: [[p]] = Z h with Z = {name}", on_shell(Z - form) == 0)
    check("b = -a (odd pressure) and a = -nu s beta (beta + k) h / k (the printed a_k^n, b_k^n)",
          on_shell(sol[b] + sol[a]) == 0 and on_shell(sol[a] + nu * s * beta * (beta + k) * h / k) == 0)
    check("the normal viscous stress 2 nu v_y vanishes at y = 0± (u = 0 along y = 0 gives "
          "v_y = -u_x = 0), so the normal stress jump is -[[p]] alone",
          all(sp.simplify(sp.diff(f["v"], y).subs(y, 0).subs(sol)) == 0 for f in (up, lo)))
    shear = sp.simplify((nu * (sp.diff(up["u"], y) - sp.diff(lo["u"], y))).subs(y, 0).subs(sol) / sp.sin(k * x))
    odd = [on_shell((up[n].subs(sol) + sg * lo[n].subs(sol).subs(y, -y))) for n, sg in
           (("p", 1), ("u", 1), ("v", -1))]
    check("the flow is antisymmetric about y = 0 (p, u odd, v even in y), so the tangential stress "
          "jump nu [[u_y]] vanishes: the no-slip constraint u(0) = 0 costs no horizontal force",
          all(o == 0 for o in odd) and on_shell(shear) == 0)
    return up, lo, sol, Z


# ---------------------------------------------------------------------------------------------
# Part 3. The fields numerically at random points (mpmath, 40 digits)
# ---------------------------------------------------------------------------------------------
def part3(up, lo, sol):
    section("Part 3. The solved fields at random points: PDE, boundary and decay residuals (mpmath)")
    rng = random.Random(5)
    worst_pde = worst_bc = worst_decay = mp.mpf(0)
    for _ in range(6):
        kv = rng.randint(1, 40)
        nuv = mp.mpf(10) ** rng.uniform(-6, 0)
        sv = mp.mpc(rng.uniform(-0.2, 1.0), rng.uniform(0.1, 30.0))
        bv = mp.sqrt(sv / nuv + kv**2)
        assert mp.re(bv) > 0
        hv = mp.mpc(rng.uniform(-1, 1), rng.uniform(-1, 1))
        subs = {k: kv, nu: nuv, s: sv, beta: bv, h: hv}
        coef = {key: sp.N(val.subs(subs), 40) for key, val in sol.items()}
        p_at_0 = {}
        for f, sign in ((up, 1), (lo, -1)):
            g = {n: sp.lambdify((x, y), e.subs(coef).subs(subs), "mpmath") for n, e in f.items()}
            scale = max(abs(g[n](mp.mpf("0.3"), 0)) for n in ("p", "u", "v")) + abs(g["v"](0, 0))
            for _ in range(3):
                xv = mp.mpf(rng.uniform(0, float(mp.pi)))
                yv = sign * mp.mpf(rng.uniform(0.01, 2.0)) / kv
                d = lambda n, dx, dy: mp.diff(lambda X, Y: g[n](X, Y), (xv, yv), (dx, dy))  # noqa: E731
                lap_u, lap_v = d("u", 2, 0) + d("u", 0, 2), d("v", 2, 0) + d("v", 0, 2)
                r = [sv * g["u"](xv, yv) + d("p", 1, 0) - nuv * lap_u,
                     sv * g["v"](xv, yv) + d("p", 0, 1) - nuv * lap_v,
                     d("u", 1, 0) + d("v", 0, 1)]
                worst_pde = max(worst_pde, max(abs(q) for q in r) / (abs(sv) * scale))
            xv = mp.mpf(rng.uniform(0, float(mp.pi)))
            bc = [g["u"](xv, 0), g["v"](xv, 0) - sv * hv * mp.cos(kv * xv)]
            worst_bc = max(worst_bc, max(abs(q) for q in bc) / scale)
            far = sign * mp.mpf(60) / min(kv, mp.re(bv))
            worst_decay = max(worst_decay, max(abs(g[n](xv, far)) for n in ("p", "u", "v")) / scale)
            p_at_0[sign] = g["p"](mp.mpf(0), mp.mpf(0))
        Zv = 2 * sv**2 / kv + 2 * nuv * sv * (kv + bv)
        worst_bc = max(worst_bc, abs(p_at_0[1] - p_at_0[-1] - Zv * hv) / abs(Zv * hv))
    check("PDE residuals at random points (6 random s, k, nu; 3 points per side) < 1e-25",
          worst_pde < 1e-25, f"max relative residual {mp.nstr(worst_pde, 3)}")
    check("boundary residuals u = 0, v = s h cos kx and [[p]] = Z h, Z = 2 s^2/k + 2 nu s (k + beta), "
          "at y = 0 < 1e-25",
          worst_bc < 1e-25, f"{mp.nstr(worst_bc, 3)}")
    check("fields decay as |y| -> infinity (value at |y| = 60/min(k, Re beta) < 1e-20 of y = 0)",
          worst_decay < 1e-20, f"{mp.nstr(worst_decay, 3)}")


# ---------------------------------------------------------------------------------------------
# Part 4. The printed v_k^n, u_k^n, special cases k = 0 and s = 0
# ---------------------------------------------------------------------------------------------
def part4(sol):
    section("Part 4. The printed fields of 5.3 (complex e^{ikx} form) and the special cases")
    # complex form: v_k(y) e^{ikx}, u_k(y) e^{ikx} with i k u_k + v_k' = 0
    A, B = sol[a], sol[b]
    v_lo = -k * A / s * sp.exp(k * y) + sol[Cl] * sp.exp(beta * y)
    v_up = k * B / s * sp.exp(-k * y) + sol[Cu] * sp.exp(-beta * y)
    pre = 1 / (2 * nu * beta)
    printed_lo = pre * (-2 * k * beta * A / (beta**2 - k**2) * sp.exp(k * y)
                        + (k * A / (beta - k) + k * B / (beta + k)) * sp.exp(beta * y))
    printed_up = pre * (2 * beta * B / (beta**2 - k**2) * sp.exp(-k * y)
                        - (k * B / (beta - k) + k * A / (beta + k)) * sp.exp(-beta * y))
    printed_up_fixed = pre * (2 * k * beta * B / (beta**2 - k**2) * sp.exp(-k * y)
                              - (k * B / (beta - k) + k * A / (beta + k)) * sp.exp(-beta * y))
    check("printed v_k^n, y < 0 branch, equals the derived field", on_shell(printed_lo - v_lo) == 0)
    check("ERRATA confirmed: printed v_k^n, y > 0 branch, lacks a factor k in the e^{-ky} term "
          "(with it, it equals the derived field)",
          on_shell(printed_up - v_up) != 0 and on_shell(printed_up_fixed - v_up) == 0)
    pu = -sp.I / (2 * k * nu)
    printed_u_lo = pu * (-2 * k**2 * A / (beta**2 - k**2) * sp.exp(k * y)
                         + (k * A / (beta - k) + k * B / (beta + k)) * sp.exp(beta * y))
    printed_u_up = pu * (-2 * k * B / (beta**2 - k**2) * sp.exp(-k * y)
                         + (k * B / (beta - k) + k * A / (beta + k)) * sp.exp(-beta * y))
    # continuity i k u + v' = 0 gives u = i v'/k
    check("printed u_k^n = -i v'/k of the printed v_k^n on both branches: the same missing k on the "
          "y > 0 e^{-ky} term, and the opposite overall sign to continuity (i k u + v' = 0 needs "
          "u = +i v'/k); harmless, since only u(0±) = 0 is used",
          on_shell(printed_u_lo + sp.I / k * sp.diff(printed_lo, y)) == 0
          and on_shell(printed_u_up + sp.I / k * sp.diff(printed_up, y)) == 0
          and on_shell(printed_u_lo - sp.I / k * sp.diff(v_lo, y)) != 0)
    # |k|: for k < 0 the decaying exponentials are e^{|k| y} (y < 0) and e^{-|k| y} (y > 0)
    kn = sp.Symbol("kn", positive=True)
    zk = 2 * s**2 / kn + 2 * nu * s * (kn + beta)
    z_printed_neg = (2 * nu**2 * (beta + kn) * (beta - kn)**2 * beta / (-kn))  # k -> -kn in (5.9)
    check("(5.9) with k < 0 (e^{ky} kept literally) is not Z_{|k|}: the coefficient needs |k| "
          "(ERRATA 'e^{ky} needs |k|'); the cosine system uses k >= 1 only",
          on_shell(z_printed_neg - zk.subs(kn, k)) != 0)
    # k = 0, s != 0: p piecewise constant; div u = v_y = 0 and s v = nu v_yy give v = 0
    v0 = sp.Function("v0")
    ode = sp.dsolve(sp.Eq(s * v0(y), nu * sp.diff(v0(y), y, 2)))
    gen = ode.rhs
    c1, c2 = sorted(gen.free_symbols - {s, nu, y}, key=str)
    vy = sp.diff(gen, y)
    sol0 = sp.solve([vy.subs(y, 0), sp.diff(vy, y).subs(y, 0)], [c1, c2], dict=True)
    check("k = 0, s != 0: div u = 0 forces v_y = 0, hence v = 0 and h_0 = 0 (the thesis drops k = 0)",
          len(sol0) == 1 and sp.simplify(gen.subs(sol0[0])) == 0)
    # s = 0, k != 0: steady Stokes, p = a e^{ky}; v = (A + B y) e^{ky}
    Av, Bv, pa = sp.symbols("A_v B_v p_a")
    v_st = (Av + Bv * y) * sp.exp(k * y)
    eq_st = sp.simplify((nu * (sp.diff(v_st, y, 2) - k**2 * v_st) - k * pa * sp.exp(k * y)) / sp.exp(k * y))
    Bsol = sp.solve(eq_st, Bv)[0]
    check("s = 0 (steady Stokes): v = (A + y p_a/(2 nu)) e^{ky} below; the printed k a/(2 nu) has an "
          "extra factor k", sp.simplify(Bsol - pa / (2 * nu)) == 0)
    u_st = sp.I / k * sp.diff(v_st.subs(Bv, Bsol), y)
    sol_st = sp.solve([v_st.subs(Bv, Bsol).subs(y, 0), u_st.subs(y, 0)], [Av, pa], dict=True)
    check("s = 0: u = v = 0 at y = 0 force p_a = 0: no steady pressure jump, so D(0) = kappa C "
          "(the s -> 0 limit of Z is 0) as in (5.10)",
          len(sol_st) == 1 and sol_st[0][pa] == 0 and sp.limit(2 * s**2 / k + 2 * s * sp.sqrt(nu * s + nu**2 * k**2), s, 0) == 0)


# ---------------------------------------------------------------------------------------------
# Part 5. Z_k(s): limits and cancellation-free evaluation
# ---------------------------------------------------------------------------------------------
def transfer_float(sv: complex, kv: float, nuv: float) -> complex:
    """Z = 2 s^2/k + 2 s (nu k + sqrt(nu) sqrt(s + nu k^2)) in double precision: no difference
    of nearly equal terms (what spectralshell.models.cochlea.transfer evaluates)."""
    return 2 * sv * sv / kv + 2 * sv * (nuv * kv + np.sqrt(nuv) * np.sqrt(sv + nuv * kv * kv))


def transfer_naive(sv: complex, kv: float, nuv: float) -> complex:
    """The printed form 2 nu^2 (beta - k)(beta + k)^2 beta / k in double precision."""
    bv = np.sqrt(sv / nuv + kv * kv)
    return 2 * nuv**2 * (bv - kv) * (bv + kv)**2 * bv / kv


def transfer_mp(sv, kv, nuv, digits=30):
    """Reference: 2 s^2 beta / (k (beta - k)) at ``digits`` digits (beta with Re beta > 0);
    an mpc at 40 digits, a complex otherwise."""
    with mp.workdps(digits):
        sv, nuv = mp.mpc(sv), mp.mpf(nuv)
        bv = mp.sqrt(sv / nuv + kv * kv)
        z = 2 * sv**2 * bv / (kv * (bv - kv))
        return +z if digits == 40 else complex(z)


def part5():
    section("Part 5. Z_k(s): inviscid and s -> 0 limits, evaluation without cancellation")
    Zs = 2 * s**2 / k + 2 * nu * s * k + 2 * s * sp.sqrt(nu) * sp.sqrt(s + nu * k**2)
    zs_mp = sp.lambdify((s, k, nu), Zs, "mpmath")
    pts = [(mp.mpc(0, "0.5"), 3, mp.mpf("1e-3")), (mp.mpc("0.3", 2), 7, mp.mpf("0.1")),
           (mp.mpc("-0.01", 1), 1, mp.mpf(2)), (mp.mpc(0, 5), 40, mp.mpf("1e-6")),
           (mp.mpc("-0.5", "-3"), 2, mp.mpf("0.01"))]
    check("Z = 2 s^2/k + 2 nu s k + 2 s sqrt(nu) sqrt(s + nu k^2) equals 2 s^2 beta/(k (beta - k)) "
          "with Re beta > 0 (principal roots; 40 digits)",
          all(abs(zs_mp(sv, kv, nv) - transfer_mp(sv, kv, nv, digits=40)) < 1e-35 * abs(zs_mp(sv, kv, nv))
              for sv, kv, nv in pts))
    zeta, gt, kap = sp.symbols("zeta gamma_t kappa", positive=True)
    root = sp.sqrt(gt / zeta + k**2)
    printed_514 = 2 * zeta * gt / k * root * (k + root)       # (5.14), gamma = sqrt(kappa) gamma_t
    ours = (2 * nu * s * beta * (beta + k) / k / kap).subs({beta: sp.sqrt(s / nu + k**2)})
    ours = ours.subs({s: sp.sqrt(kap) * gt, nu: zeta * sp.sqrt(kap)})
    check("(5.14): Z/kappa in gamma_t = gamma/sqrt(kappa) and zeta = nu/sqrt(kappa) is the printed "
          "2 zeta gamma_t/k sqrt(gamma_t/zeta + k^2)(k + sqrt(...)): the natural modes depend on zeta "
          "and alpha only", sp.simplify(ours - printed_514) == 0)
    inv = sp.limit(Zs, nu, 0)
    check("inviscid limit nu -> 0: Z -> 2 s^2/k (added mass 1/k on each side), so (Z + kappa) h = 0 "
          "is h'' + (kappa k / 2) h = 0: natural frequency sqrt(kappa k/2) (uniform stiffness)",
          sp.simplify(inv - 2 * s**2 / k) == 0)
    lead = sp.limit((Zs - 2 * s**2 / k) / sp.sqrt(nu), nu, 0)
    check("first viscous correction: Z - 2 s^2/k = 2 s^(3/2) sqrt(nu) + O(nu) (Stokes layers)",
          sp.simplify(lead - 2 * s**sp.Rational(3, 2)) == 0)
    check("Z(conj s) = conj Z(s) (real in the time domain) and Z -> 0 as s -> 0",
          abs(transfer_float(0.3 - 2j, 4, 1e-3) - np.conj(transfer_float(0.3 + 2j, 4, 1e-3))) < 1e-15
          and abs(transfer_float(1e-300j, 4, 1e-3)) < 1e-290)
    worst_ours = worst_naive = 0.0
    for nuv in np.logspace(-9, 1, 11):
        for kv in (1, 2, 7, 40, 250):
            for sv in (0.5j, 1j, 2.5j, 20j, 40.5j, 0.2 + 3j):
                want = transfer_mp(sv, kv, nuv)
                worst_ours = max(worst_ours, abs(transfer_float(sv, kv, nuv) - want) / abs(want))
                worst_naive = max(worst_naive, abs(transfer_naive(sv, kv, nuv) - want) / abs(want))
    check("cancellation-free form agrees with 30-digit mpmath to 1e-14 for nu = 1e-9..10, k <= 250, "
          "|s| <= 40", worst_ours < 1e-14, f"worst relative error {worst_ours:.2e}")
    check("the printed product (beta - k)(beta + k)^2 beta evaluated directly loses digits "
          "(beta - k cancels when nu k^2 >> |s|)", worst_naive > 1e-10, f"worst {worst_naive:.2e}")


# ---------------------------------------------------------------------------------------------
# Part 6. Stiffness coupling: cosine coefficients of e^{-alpha |x|}
# ---------------------------------------------------------------------------------------------
def c_literal(jv, av):
    """c_j = alpha (1 - (-1)^j e^{-alpha pi}) / (pi (alpha^2 + j^2)) (thesis, after (5.8)), literally."""
    return av * (1 - (-1)**jv * np.exp(-av * np.pi)) / (np.pi * (av * av + jv * jv))


def c_closed(jv, av):
    """The same c_j without cancellation: 1 - e^{-alpha pi} = -expm1(-alpha pi) for even j."""
    jv = np.asarray(jv)
    one_minus = np.where(jv % 2 == 0, -np.expm1(-av * np.pi), 1 + np.exp(-av * np.pi))
    return av * one_minus / (np.pi * (av * av + jv * jv))


def part6():
    section("Part 6. Coupling: Fourier coefficients c_j of e^{-alpha|x|} and the cosine matrix C")
    cj = sp.integrate(sp.exp(-alpha * x) * sp.cos(j_ * x), (x, 0, sp.pi)) / sp.pi
    cj = sp.simplify(cj.subs(sp.cos(sp.pi * j_), (-1)**j_).subs(sp.sin(sp.pi * j_), 0))
    printed = alpha * (1 - (-1)**j_ * sp.exp(-alpha * sp.pi)) / (sp.pi * (alpha**2 + j_**2))
    check("c_j = (1/2pi) int_{-pi}^{pi} e^{-alpha|x|} e^{-ijx} dx = the printed closed form",
          all(sp.simplify((cj - printed).subs(j_, jv)) == 0 for jv in range(0, 6)))
    kk, jj = sp.symbols("k_c j_c", integer=True, positive=True)
    prod = sp.cos(kk * x) * sp.cos(jj * x)
    ok = True
    for kv in range(1, 4):
        for jv in range(1, 4):
            galerkin = sp.integrate(sp.exp(-alpha * x) * prod.subs({kk: kv, jj: jv}), (x, 0, sp.pi)) * 2 / sp.pi
            ok &= sp.simplify(galerkin - printed.subs(j_, abs(kv - jv)) - printed.subs(j_, kv + jv)) == 0
    check("e^{-alpha x} cos(jx) = c_{|k-j|} + c_{k+j} times cos(kx) + ...: C_kj = (2/pi) int_0^pi "
          "e^{-alpha x} cos kx cos jx dx = c_{k-j} + c_{k+j} (k, j = 1..3, symbolic)", ok)
    worst = 0.0
    for av in (1e-8, 0.3, 1.56, 4.3, 20.0):
        for kv in (1, 2, 9, 40):
            for jv in (1, 3, 40, 41):
                # cos kx cos jx = (cos (k-j)x + cos (k+j)x)/2; QAWO (weight='cos') for each
                num = sum(quad(lambda t: np.exp(-av * t), 0, np.pi, weight="cos", wvar=w,
                               epsabs=1e-14, epsrel=1e-12)[0] for w in (kv - jv, kv + jv)) / np.pi
                got = c_closed(abs(kv - jv), av) + c_closed(kv + jv, av)
                worst = max(worst, abs(got - num))
    check("C_kj against scipy quad (alpha = 1e-8..20, k, j up to 41) to 1e-12", worst < 1e-12,
          f"max |difference| {worst:.1e}")
    lim0 = sp.limit(printed.subs(j_, 0), alpha, 0)
    check("alpha -> 0: c_0 -> 1, c_j -> 0 (j >= 1): C -> I, the modes decouple",
          lim0 == 1 and all(sp.limit(printed.subs(j_, jv), alpha, 0) == 0 for jv in (1, 2, 3)))
    Mn = 60
    idx = np.arange(1, Mn + 1)
    C = c_closed(np.abs(idx[:, None] - idx[None, :]), 1.56) + c_closed(idx[:, None] + idx[None, :], 1.56)
    ev = np.linalg.eigvalsh(C)
    check("C symmetric positive definite (the stiffness e^{-alpha x} > 0 weights a Gram matrix): "
          "eigenvalues of the 60 x 60 matrix at alpha = 1.56 lie in (e^{-alpha pi}, 1]",
          np.allclose(C, C.T) and ev.min() > np.exp(-1.56 * np.pi) * 0.999 and ev.max() < 1.0,
          f"[{ev.min():.4g}, {ev.max():.4g}]")
    # small alpha: c_0 = -expm1(-alpha pi)/(alpha pi) avoids 1 - e^{-alpha pi} cancellation
    av = 1e-12
    check("small alpha: c_0 = -expm1(-alpha pi)/(alpha pi) is accurate (1 - 1e-12 pi/2 ...), the "
          "literal formula is not", abs(c_closed(0, av) - (1 - av * np.pi / 2)) < 1e-15
          and abs(c_literal(0, av) - (1 - av * np.pi / 2)) > 1e-6)


# ---------------------------------------------------------------------------------------------
# Part 7. Assembly: D(s_n) h_n = i tau G (h_{n-1} - h_{n+1}) and the inviscid ODE
# ---------------------------------------------------------------------------------------------
def part7():
    section("Part 7. Floquet-Fourier form and the sign of the coupling (against time integration)")
    tau, kap, t = sp.symbols("tau kappa t", real=True)
    n = sp.Symbol("n", integer=True)
    hm, h0, hp = sp.symbols("h_m h_0 h_p")
    # K(t) h(t) with h = sum h_n e^{(gamma + i n) t}: coefficient of e^{i n t} of
    # (1 + 2 tau sin t)(h_m e^{-it} + h_0 + h_p e^{it})
    expr = sp.expand((1 + 2 * tau * sp.sin(t)).rewrite(sp.exp) * (hm * sp.exp(-sp.I * t) + h0 + hp * sp.exp(sp.I * t)))
    c0 = sp.simplify(sum(term for term in expr.as_ordered_terms() if not term.has(t)))
    check("[(1 + 2 tau sin t) h]_n = h_n - i tau (h_{n-1} - h_{n+1}), so (Z(s_n) + kappa C) h_n = "
          "i tau kappa C (h_{n-1} - h_{n+1}): D = diag Z + kappa C, G = kappa C (matches (5.9))",
          sp.simplify(c0 - (h0 - sp.I * tau * (hm - hp))) == 0)
    # the inviscid system (2/k) h_k'' + kappa (1 + 2 tau sin t) (C h)_k = 0 is an ODE: check the
    # Hill form (engine convention) against its monodromy at a marginal tau (alpha = 1.56, M = 4)
    from scipy.integrate import solve_ivp
    from scipy.linalg import eig
    M_, kv, av = 4, 0.35, 1.56
    idx = np.arange(1, M_ + 1)
    C = c_closed(np.abs(idx[:, None] - idx[None, :]), av) + c_closed(idx[:, None] + idx[None, :], av)
    mass = np.diag(2.0 / idx)
    Nn = 40
    ns = np.arange(-Nn - 1, Nn + 1) + 0.5            # subharmonic two-sided form
    size = len(ns) * M_
    A = np.zeros((size, size), complex)
    B = np.zeros((size, size), complex)
    for i, nv in enumerate(ns):
        sl = slice(i * M_, (i + 1) * M_)
        A[sl, sl] = (1j * nv)**2 * mass + kv * C
        if i > 0:
            B[sl, slice((i - 1) * M_, i * M_)] = 1j * kv * C
        if i < len(ns) - 1:
            B[sl, slice((i + 1) * M_, (i + 2) * M_)] = -1j * kv * C
    w = eig(A, B, right=False)
    w = w[np.isfinite(w)]
    real = np.sort(w.real[(np.abs(w.imag) < 1e-9) & (w.real > 1e-6)])
    tau_min = real[0]
    Minv = np.linalg.inv(mass)

    def rhs(t_, z):
        return np.concatenate([z[M_:], -kv * (1 + 2 * tau_min * np.sin(t_)) * Minv @ C @ z[:M_]])

    mono = np.column_stack([solve_ivp(rhs, (0, 2 * np.pi), e, method="DOP853", rtol=1e-12,
                                      atol=1e-14).y[:, -1] for e in np.eye(2 * M_)])
    mult = np.linalg.eigvals(mono)
    check("inviscid coupled system (alpha = 1.56, M = 4): at the smallest subharmonic tau of the Hill "
          "pencil the monodromy of the ODE has a multiplier -1",
          np.min(np.abs(mult + 1)) < 1e-6, f"tau = {tau_min:.10f}, min |q + 1| = {np.min(np.abs(mult + 1)):.1e}")


def main() -> int:
    part1()
    up, lo, sol, _ = part2()
    part3(up, lo, sol)
    part4(sol)
    part5()
    part6()
    part7()
    return summary()


if __name__ == "__main__":
    sys.exit(main())
