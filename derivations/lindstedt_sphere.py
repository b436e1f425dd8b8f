#!/usr/bin/env python3
"""Nonlinear (Lindstedt-Poincare) frequency correction of an inviscid spherical membrane (thesis 7.3).

Re-derives, independently of the printed algebra of thesis section 7.3, the coefficient c_{m,k} in

    lambda = lambda0 (1 + c_{m,k} eps^2 + O(eps^4)),   lambda0^2 = kappa m(m+1)(m-1)(m+2)/(2m+1)  (7.4)

for the free oscillation of amplitude eps of the membrane about the unit sphere started in the
shape 1 + eps Y, Y the orthonormal (real) harmonic Y_{m,0} (k = 0) or sqrt(2) Re Y_{m,k} (k > 0).
It writes the exact values into ``spectralshell/models/nonlinear_coefficients.py``.

Run ``python3 derivations/lindstedt_sphere.py`` (checks, thesis comparison, no writing),
``... --write`` (also regenerate the package file) or ``... --m 2 3 --k 0`` (subset).
Exit status 0 only if every check passes.

Model (thesis (7.15)-(7.19), restated without the change of variables r = X r*)
-----------------------------------------------------------------------------------
* Fluid of density 1 inside and outside, irrotational, inviscid: u = grad psi, Lap psi = 0 (7.15);
  psi_in = sum a_n(t) r^n Y_n, psi_out = sum b_n(t) r^-(n+1) Y_n; psi_out -> 0 at infinity.
* Bernoulli (7.16): p = C - psi_t - |grad psi|^2/2 in each fluid (C_out = 0 at infinity; the
  interior constant C_in(t) is absorbed into the degree-0 interior potential a_0(t)).
* Membrane RADIAL ONLY (thesis: "we are only concerned with the radial component"): the material
  point of reference angles (theta, phi) sits at X = R(theta, phi, t) rhat(theta, phi),
  R = 1 + eps x. There is no tangential membrane displacement; the tangential part of the membrane
  force is not balanced by anything (inviscid fluid). Every coefficient below is for this
  radial-only model.
* Force law (7.1e)/(6.2): F = kappa Delta_S X, Delta_S the Laplace-Beltrami operator of the UNIT
  (reference) sphere applied to each Cartesian component of X (zero-rest-length "Terzopoulos"
  membrane; it contains the prestress: F = -2 kappa rhat at equilibrium, [[p0]] = -2 kappa).
  For X = R rhat:  Delta_S X = (Delta_S R - 2R) rhat + 2 grad_S R.
* Normal stress balance (7.17) (from (6.16)): [[p]] |N| = n.F sin(theta), N = X_theta x X_phi,
  [[q]] = q_out - q_in. With N/sin(theta) = R (R rhat - grad_S R) and |N|^2/sin^2 = R^2 (R^2 + g),
  g = |grad_S R|^2, this is the exact law

      [[p]] = kappa G(R),   G(R) = (R Delta_S R - 2 R^2 - 2 g) / (R (R^2 + g))          (A)

  (checked below by explicit vector calculus). Linear limit: G = -2 + eps (Delta_S + 2) x, i.e.
  [[p1]] = -kappa (m-1)(m+2) x for degree m, as in (6.17).
  Variant kept for discussion only ("radial" law, the virtual work of F on radial displacements):
  [[p]] R^2 = rhat.F, G_rad = (Delta_S R - 2R)/R^2; it differs from (A) by kappa g Delta_S R/(R^2(R^2+g)),
  i.e. at O(eps^3), and so changes c_m.
* Kinematic condition (7.18) on both sides, at r = R:  R_t = psi_r - grad_S R . grad_S psi / R^2.
* Enclosed volume conserved; its value is the unit sphere's, 4 pi/3 (the fluid inside is the
  equilibrium's; the O(eps^2) degree-0 part of the shape follows from this). The variant
  "literal" takes the initial shape 1 + eps Y exactly, whose volume is 4 pi/3 (1 + 3 eps^2/(4 pi)).

Results (radial-only membrane; every value also checked by the direct nonlinear orbit solve of
spectralshell.solvers.nonlinear_orbit, agreement 1e-9 to 1e-10 relative for m = 2, 3, 4 and (3, 3))
------------------------------------------------------------------------------------------------
  c_2 = -81161/(122304 pi)                       = -0.211230611202925780781305192293
  c_3 = -56307454453/(38760733440 pi)            = -0.462406611731891088397813570411
  c_4 = -767309533458687/(306666814854400 pi)    = -0.796441605130747768774466385280
* Degree 0 matters: it carries the volume constraint. Dropping it (the thesis's sums) gives
  c_2 = -0.28086; taking the initial shape literally (volume 4 pi/3 + eps^2) shifts every c by
  exactly -3/(8 pi) (uniform dilation, lambda ~ R^(-3/2)). Degree 1 never occurs at O(eps^2)
  (Gaunt parity: m + m + 1 is odd) and is forced at O(eps^3) only at odd harmonics: no effect on c.
* Thesis 7.3 (ERRATA): the printed lambda2 = -(3531 sqrt30/(3920 pi)) sqrt(kappa) implies
  c_2 = -7062/(3136 pi), the printed c_2 is -7061/(3136 pi) ~ -0.7167; neither survives, nor do
  -0.8485 (m = 3) and -1.0645 (m = 4), nor any variant tried (degree 0 dropped, literal volume,
  "radial" force law). (7.21), evaluated with exact projections (kappa restored), does not give
  (7.22a). Our O(eps^2) equations reproduce (7.22a)'s cos 2t term and (7.22b)'s constant, but give
  +9/56 sqrt(5/pi) for (7.22a)'s constant (printed -9/56) and 439/(378 sqrt pi) for (7.22b)'s
  cos 2t term (printed 403); the direct solve confirms ours (x_2 coefficients).
* Non-axisymmetric: |grad_S Y_{m,k}|^2 has degrees <= 2m only (the thesis's "infinitely many
  degrees" is wrong). The real obstruction is different: for 1 <= k and 3k <= m the O(eps^3)
  forcing contains Yr_{m,3k} at the oscillation frequency (degenerate degree-m eigenspace), so the
  real harmonic Yr_{m,k} is not a nonlinear normal mode and c_{m,k} is undefined. For 3k > m it is
  defined; all real quadrupoles share c_2 (one quartic invariant), c_{3,3} = -0.5815139637.

Expansion
---------
tau = lambda t, psi = lambda Phi, Lambda = lambda^2/lambda0^2 = 1 + mu1 eps + mu2 eps^2, kappa' =
kappa/lambda0^2 (then kappa drops out: c does not depend on kappa). The equations become

    R_tau = Phi_r - grad_S R . grad_S Phi / R^2                         (r = R, both sides)
    Lambda [Phi_tau + |grad Phi|^2/2]_out^in = kappa' (G(R) + 2)         (r = R)

with R = 1 + sum_p eps^p x_p, Phi = sum_p eps^p Phi_p, evaluated at r = R by the Taylor series of
r^n and r^-(n+1) about r = 1 (exact for these harmonic terms). The unknowns are expanded in the
unnormalised real basis B_{n,l} = Pt_n^l(cos theta) cos(l phi) (Pt without Condon-Shortley phase)
and in cos(j tau) (x, even in tau) / sin(j tau) (Phi, odd in tau): every structure constant
is then rational, and the arithmetic is exact (Python Fractions). Products of harmonics use the
Gaunt coefficients of sympy.physics.wigner (``gaunt``), converted to this basis; products of
tangential gradients use grad f . grad g = (Delta(fg) - f Delta g - g Delta f)/2, so that only scalar
products of harmonics occur.

At order p, per (n, l, j): with forcings rK_in, rK_out (sin j) and rS (cos j) from lower orders,

    X [kappa'(n-1)(n+2) - j^2 (2n+1)/(n(n+1))] = -rS - mu_{p-1} M - j rK_in/n - j rK_out/(n+1),

A = (rK_in - jX)/n, B = (jX - rK_out)/(n+1) (x = X cos j tau, a = A sin j tau, b = B sin j tau).
The bracket vanishes for (n, j) = (m, 1) (secular term: fixes mu_{p-1}, and X := 0 there, which
defines eps as the amplitude of cos(tau) Y at O(eps)), for (1, 0) (rigid translation: the forcing
must vanish; X := 0 fixes the centre) and for no other (n, j) used (checked). Degree 0: volume
gives x_p's degree-0 part, the interior kinematic condition must then hold identically (checked),
and the degree-0 stress fixes the interior pressure. Then c = mu2/2 (mu1 = 0 is found, not
assumed), times the square of the normalisation of Y relative to B_{m,k}.
"""

from __future__ import annotations

import argparse
import hashlib
import math
import sys
import time
from collections import defaultdict
from fractions import Fraction as Fr
from functools import lru_cache
from pathlib import Path

import mpmath as mp
import numpy as np
import sympy as sp
from sympy.physics.wigner import gaunt

HERE = Path(__file__).resolve()
sys.path.insert(0, str(HERE.parent))  # the shared check harness, also when imported by tests
from _checks import check, section, summary  # noqa: E402  (derivations/_checks.py)
REPO = HERE.parents[1]
TARGET = REPO / "spectralshell" / "models" / "nonlinear_coefficients.py"
GENERATED_RANGE = [(m, k) for m in range(2, 9) for k in range(0, m + 1)]
DIGITS = 30
ORDER = 3  # highest power of eps kept



# =============================================================================================
# 1. Structure constants of the basis B_{n,l} = Pt_n^l(cos th) cos(l ph) from Gaunt coefficients
# =============================================================================================
def _norm_sq(n: int, l: int) -> sp.Expr:
    """N_{n,l}^2 = (2n+1)/(4 pi) (n-l)!/(n+l)!, so Y_{n,l} = N (-1)^l Pt_n^l e^{i l phi} (l >= 0)."""
    return sp.Rational(_norm_sq_times_pi(n, l).numerator, _norm_sq_times_pi(n, l).denominator) / sp.pi


def _norm_sq_times_pi(n: int, l: int) -> Fr:
    return Fr((2 * n + 1) * math.factorial(n - l), 4 * math.factorial(n + l))


def _exact_sqrt(q: Fr) -> Fr:
    num, den = q.numerator, q.denominator
    rn, rd = math.isqrt(num), math.isqrt(den)
    if rn * rn != num or rd * rd != den:
        raise ArithmeticError(f"{q} is not the square of a rational")
    return Fr(rn, rd)


@lru_cache(maxsize=None)
def legendre_triple(a: int, al: int, b: int, be: int, c: int, ga: int) -> Fr:
    """I = int_{-1}^{1} Pt_a^al Pt_b^be Pt_c^ga dx, one order the sum of the other two, from gaunt.

    With Y_{l,mu} = N s(mu) Pt_l^|mu| e^{i mu phi}, s(mu) = (-1)^mu for mu > 0 and 1 otherwise, the
    Gaunt integral with the largest order taken negative is 2 pi N_a N_b N_c (-1)^{max order} I.
    I is rational (the integrand is a polynomial); it is recovered exactly from I^2 and the sign.
    """
    orders = [al, be, ga]
    big = max(orders)
    assert sum(orders) == 2 * big, (al, be, ga)
    mus = list(orders)
    mus[orders.index(big)] = -big  # the (first) largest order negated; the orders then sum to 0
    G = gaunt(a, b, c, *mus)
    if G == 0:
        return Fr(0)
    # G^2 = rational / pi (sympy evaluates the square of sqrt(rational) exactly)
    g2_pi = sp.Rational(sp.expand(G**2 * sp.pi))
    sq = (Fr(int(g2_pi.p), int(g2_pi.q))
          / (4 * _norm_sq_times_pi(a, al) * _norm_sq_times_pi(b, be) * _norm_sq_times_pi(c, ga)))
    sign = (1 if float(G) > 0 else -1) * (-1) ** big
    return sign * _exact_sqrt(sq)


def _h(c: int, g: int) -> Fr:
    """int_{-1}^1 (Pt_c^g)^2 dx = 2/(2c+1) (c+g)!/(c-g)!."""
    return Fr(2 * math.factorial(c + g), (2 * c + 1) * math.factorial(c - g))


@lru_cache(maxsize=None)
def ang_product(a: int, al: int, b: int, be: int) -> tuple:
    """B_{a,al} B_{b,be} = sum coef B_{c,ga}: tuple of ((c, ga), coef), exact.

    cos(al ph) cos(be ph) = (cos((al+be) ph) + cos((al-be) ph))/2, and Pt_a^al Pt_b^be expanded in
    Pt_c^ga for ga = al+be and ga = |al-be| (Gaunt selection: |a-b| <= c <= a+b, a+b+c even, c >= ga).
    """
    out: dict = defaultdict(Fr)
    for ga in (al + be, abs(al - be)):
        for c in range(max(abs(a - b), ga), a + b + 1):
            if (a + b + c) % 2:
                continue
            val = legendre_triple(a, al, b, be, c, ga)
            if val:
                out[(c, ga)] += val / _h(c, ga) / 2
    return tuple((key, v) for key, v in sorted(out.items()) if v)


# =============================================================================================
# 2. Fields: dict (n, l, kind, j) -> Fraction; kind 0: cos(j tau), kind 1: sin(j tau)
# =============================================================================================
def _time_product(k1: int, j1: int, k2: int, j2: int):
    """Products of cos/sin(j tau) as ((kind, j), coef) pairs."""
    h = Fr(1, 2)
    s, d = j1 + j2, abs(j1 - j2)
    if k1 == 0 and k2 == 0:
        return [((0, s), h), ((0, d), h)]
    if k1 == 1 and k2 == 1:
        return [((0, d), h), ((0, s), -h)]
    if k1 == 1:  # sin j1 cos j2
        j1, j2 = j2, j1
    # cos j1 sin j2 = (sin(j1+j2) + sin(j2-j1))/2
    out = [((1, s), h)]
    if j2 != j1:
        out.append(((1, d), h if j2 > j1 else -h))
    return out


def f_add(*terms):
    """Linear combination: f_add((c1, f1), (c2, f2), ...)."""
    out: dict = defaultdict(Fr)
    for coef, f in terms:
        if coef == 0:
            continue
        for key, v in f.items():
            out[key] += coef * v
    return {k: v for k, v in out.items() if v}


def f_mul(f, g):
    out: dict = defaultdict(Fr)
    if not f or not g:
        return {}
    for (a, al, k1, j1), v1 in f.items():
        for (b, be, k2, j2), v2 in g.items():
            v12 = v1 * v2
            tp = _time_product(k1, j1, k2, j2)
            for (c, ga), ca in ang_product(a, al, b, be):
                for (kk, jj), ct in tp:
                    out[(c, ga, kk, jj)] += v12 * ca * ct
    return {k: v for k, v in out.items() if v}


def f_lap(f):
    """Delta_S B_{n,l} = -n(n+1) B_{n,l}."""
    return {key: -key[0] * (key[0] + 1) * v for key, v in f.items()}


def f_graddot(f, g):
    """grad_S f . grad_S g = (Delta(fg) - f Delta g - g Delta f)/2 (band-limited: degrees <= deg f + deg g)."""
    return f_add((Fr(1, 2), f_lap(f_mul(f, g))), (Fr(-1, 2), f_mul(f, f_lap(g))),
                 (Fr(-1, 2), f_mul(g, f_lap(f))))


def f_dtau(f):
    out: dict = {}
    for (n, l, kind, j), v in f.items():
        if j == 0:
            continue
        out[(n, l, 1 - kind, j)] = (-j if kind == 0 else j) * v
    return out


ONE = {(0, 0, 0, 0): Fr(1)}


# ---- truncated power series in eps whose coefficients are fields ----------------------------
def s_zero():
    return [{} for _ in range(ORDER + 1)]


def s_add(*terms):
    return [f_add(*[(c, s[i]) for c, s in terms]) for i in range(ORDER + 1)]


def s_mul(s, t):
    out = s_zero()
    for i in range(ORDER + 1):
        if not s[i]:
            continue
        for j in range(ORDER + 1 - i):
            if t[j]:
                out[i + j] = f_add((1, out[i + j]), (1, f_mul(s[i], t[j])))
    return out


def s_map(fun, s):
    return [fun(f) for f in s]


def s_graddot(s, t):
    out = s_zero()
    for i in range(ORDER + 1):
        for j in range(ORDER + 1 - i):
            if s[i] and t[j]:
                out[i + j] = f_add((1, out[i + j]), (1, f_graddot(s[i], t[j])))
    return out


def s_inverse(s):
    """1/s for s = 1 + d, d = O(eps)."""
    assert s[0] == ONE
    d = [{}] + s[1:]
    out = [dict(ONE)] + [{} for _ in range(ORDER)]
    power = [dict(ONE)] + [{} for _ in range(ORDER)]
    for k in range(1, ORDER + 1):
        power = s_mul(power, d)
        out = s_add((1, out), ((-1) ** k, power))
    return out


def _gen_binom(e: int, k: int) -> Fr:
    out = Fr(1)
    for i in range(k):
        out *= Fr(e - i, i + 1)
    return out


class SurfacePowers:
    """(1 + Xs)^e as eps-series for any integer e (R = 1 + Xs, Xs = O(eps))."""

    def __init__(self, xs):
        self.pow = [[dict(ONE)] + [{} for _ in range(ORDER)]]
        for _ in range(ORDER):
            self.pow.append(s_mul(self.pow[-1], xs))
        self.cache: dict = {}

    def __call__(self, e: int):
        if e not in self.cache:
            self.cache[e] = s_add(*[(_gen_binom(e, k), self.pow[k]) for k in range(ORDER + 1)])
        return self.cache[e]


# =============================================================================================
# 3. The Lindstedt-Poincare solution
# =============================================================================================
def basis_norm_sq(m: int, k: int) -> sp.Expr:
    """Y = Nrm B_{m,k}: Nrm^2 = (2m+1)/(4 pi) (k = 0), 2 (2m+1)/(4 pi) (m-k)!/(m+k)! (k > 0)."""
    return (1 if k == 0 else 2) * _norm_sq(m, k)


def mean_square(m: int, k: int) -> Fr:
    """<B_{m,k}^2> over the unit sphere (rational) = 1/(4 pi Nrm^2)."""
    return Fr(1, 2 * m + 1) * Fr(math.factorial(m + k), math.factorial(m - k)) * (1 if k == 0 else Fr(1, 2))


def solve(m: int, k: int = 0, *, force_law: str = "normal", volume: str = "reference",
          drop_degree0: bool = False, keep: bool = False) -> dict:
    """Lindstedt-Poincare solution to O(eps^3) for the initial shape 1 + delta B_{m,k}.

    Returns mu1, mu2 (Lambda = 1 + mu1 delta + mu2 delta^2), cP = mu2/2 (in delta), the exact
    c (in eps, orthonormal Y) as sympy, the O(eps^2) fields and diagnostics.
    ``drop_degree0`` imitates the thesis (sums from n = 2): x_2, Phi_2 have no degree-0 part.
    """
    kp = Fr(2 * m + 1, m * (m + 1) * (m - 1) * (m + 2))  # kappa' = kappa / lambda0^2
    vol = {"reference": Fr(0), "literal": 3 * mean_square(m, k)}[volume]
    diag = {"degree1_forcing": [], "volume_kinematic": [], "resonances": [], "degenerate": [],
            "parity": []}
    xs = s_zero()  # R - 1
    Cin: dict = {}  # radial exponent e -> series of angular*time fields (inner, e = n >= 1)
    Cout: dict = {}  # exponent e = -n-1 (outer)
    qin = s_zero()  # d a_0 / d tau (interior degree 0)
    mus = [Fr(0)] * (ORDER + 1)  # Lambda = 1 + sum mus[p] eps^p
    M = Fr(-(2 * m + 1), m * (m + 1))  # (a_tau - b_tau) of the O(eps) solution at (m, k, j=1)
    forced2 = {}
    secular: dict = {}

    def put(store, e, p, field):
        store.setdefault(e, s_zero())
        store[e][p] = f_add((1, store[e][p]), (1, field))

    for p in range(1, ORDER + 1):
        # ---- residuals of the order-p equations with the order-p unknowns set to zero -------
        P = SurfacePowers(xs)
        R = s_add((1, [dict(ONE)] + [{}] * ORDER), (1, xs))
        lapR = s_map(f_lap, xs)
        g = s_graddot(xs, xs)
        if force_law == "normal":
            num = s_add((1, s_mul(R, lapR)), (-2, s_mul(R, R)), (-2, g))
            den = s_add((1, s_mul(s_mul(R, R), R)), (1, s_mul(R, g)))
        else:  # "radial"
            num = s_add((1, lapR), (-2, R))
            den = s_mul(R, R)
        Gp2 = s_mul(s_add((1, num), (2, den)), s_inverse(den))  # G + 2
        xs_tau = s_map(f_dtau, xs)

        def side(C, extra_tau=None):
            phi_r, phi_tau, kin_grad, gsq = s_zero(), s_zero(), s_zero(), s_zero()
            for e, ce in C.items():
                phi_r = s_add((1, phi_r), (e, s_mul(ce, P(e - 1))))
                phi_tau = s_add((1, phi_tau), (1, s_mul(s_map(f_dtau, ce), P(e))))
                kin_grad = s_add((1, kin_grad), (1, s_mul(s_graddot(xs, ce), P(e - 2))))
                for e2, ce2 in C.items():
                    gsq = s_add((1, gsq), (1, s_mul(s_graddot(ce, ce2), P(e + e2 - 2))))
            if extra_tau is not None:
                phi_tau = s_add((1, phi_tau), (1, extra_tau))
            kin = s_add((1, xs_tau), (-1, phi_r), (1, kin_grad))  # = 0
            bern = s_add((1, phi_tau), (Fr(1, 2), s_mul(phi_r, phi_r)), (Fr(1, 2), gsq))
            return kin, bern

        kin_in, bern_in = side(Cin, qin)
        kin_out, bern_out = side(Cout)
        lam = [dict(ONE)] + [{(0, 0, 0, 0): mus[i]} if mus[i] else {} for i in range(1, ORDER + 1)]
        stress = s_add((1, s_mul(lam, s_add((1, bern_in), (-1, bern_out)))), (-kp, Gp2))
        volume_s = s_mul(s_mul(R, R), R)
        rKi, rKo, rS, rV = kin_in[p], kin_out[p], stress[p], volume_s[p]

        # parity in tau: kinematic residuals are sin series, stress and volume cos series
        diag["parity"].append(all(key[2] == 1 for key in list(rKi) + list(rKo))
                              and all(key[2] == 0 for key in list(rS) + list(rV)))

        # ---- solve ---------------------------------------------------------------------------
        modes = {(key[0], key[1]) for key in list(rKi) + list(rKo) + list(rS) + list(rV)}
        if p == 1:
            modes = {(m, k)}
        js = sorted({key[3] for key in list(rKi) + list(rKo) + list(rS) + list(rV)} | {0, 1})
        xnew, anew, bnew, qnew = {}, {}, {}, {}
        # secular condition first: mu_{p-1}
        if p >= 2:
            F = (-rS.get((m, k, 0, 1), Fr(0)) - rKi.get((m, k, 1, 1), Fr(0)) / m
                 - rKo.get((m, k, 1, 1), Fr(0)) / (m + 1))
            mus[p - 1] = F / M
            # the (m, k) equation in ODE form X'' + X = sum_j F_j cos(j tau) (mu term excluded)
            secular[p] = {j: (-rS.get((m, k, 0, j), Fr(0)) - j * rKi.get((m, k, 1, j), Fr(0)) / m
                              - j * rKo.get((m, k, 1, j), Fr(0)) / (m + 1)) * Fr(m * (m + 1), 2 * m + 1)
                          for j in range(0, p + 1)}
        for (n, l) in sorted(modes):
            if drop_degree0 and n == 0 and p >= 2:
                continue
            for j in js:
                fKi = rKi.get((n, l, 1, j), Fr(0))
                fKo = rKo.get((n, l, 1, j), Fr(0))
                fS = rS.get((n, l, 0, j), Fr(0))
                if n == 0:
                    # volume: 3 x_p + rV = vol [p == 2] (degree 0 of R^3 / 1, <B_00> = 1)
                    X = (Fr(vol if (p == 2 and j == 0) else 0) - rV.get((0, 0, 0, j), Fr(0))) / 3
                    if j >= 1:
                        diag["volume_kinematic"].append(-j * X + fKi == 0)
                        B = j * X - fKo
                        Q = j * B + 2 * kp * X - fS
                        anew_b = B
                    else:
                        anew_b, Q = Fr(0), 2 * kp * X - fS
                    if X:
                        xnew[(0, 0, 0, j)] = X
                    if anew_b:
                        bnew[(0, 0, 1, j)] = anew_b
                    if Q:
                        qnew[(0, 0, 0, j)] = Q
                    continue
                rhs = -fS - j * fKi / n - j * fKo / (n + 1)
                if (n, l, j) == (m, k, 1):
                    rhs -= mus[p - 1] * M if p >= 2 else 0
                    X = Fr(1) if p == 1 else Fr(0)
                    if p >= 2:
                        assert rhs == 0
                else:
                    coef = kp * (n - 1) * (n + 2) - Fr(j * j * (2 * n + 1), n * (n + 1))
                    if coef == 0:
                        if n == 1 and j == 0:
                            diag["degree1_forcing"].append((p, l, rhs))
                        elif n == m and j == 1:
                            diag["degenerate"].append((p, l, rhs))
                        else:
                            diag["resonances"].append((p, n, l, j, rhs))
                        if rhs != 0 and p < ORDER:
                            raise ArithmeticError(f"unremovable resonance at order {p}: n={n}, l={l}, j={j}")
                        X = Fr(0)
                    else:
                        X = rhs / coef
                    if p == 2 and j in (0, 2):
                        forced2[(n, l, j)] = rhs * Fr(n * (n + 1), 2 * n + 1)
                A = (fKi - j * X) / n
                B = (j * X - fKo) / (n + 1)
                if X:
                    xnew[(n, l, 0, j)] = X
                if A:
                    anew[(n, l, 1, j)] = A
                if B:
                    bnew[(n, l, 1, j)] = B
        if p == ORDER and not keep:
            break
        xs[p] = xnew
        qin[p] = qnew
        for (n, l, kind, j), v in anew.items():
            put(Cin, n, p, {(n, l, kind, j): v})
        for (n, l, kind, j), v in bnew.items():
            put(Cout, -n - 1, p, {(n, l, kind, j): v})

    cP = mus[2] / 2
    nrm2 = basis_norm_sq(m, k)
    c_exact = sp.Rational(cP.numerator, cP.denominator) * nrm2
    return {"m": m, "k": k, "mu1": mus[1], "mu2": mus[2], "cP": cP, "c": c_exact, "x": xs,
            "forced2": forced2, "secular": secular, "diag": diag, "kappa_prime": kp}


def c_pair(c: sp.Expr) -> tuple[int, int]:
    """(num, den) with c = num / (den pi) (every c here is a rational multiple of 1/pi)."""
    q = sp.Rational(c * sp.pi)
    return int(q.p), int(q.q)


def c_to_mpf(c: sp.Expr, digits: int = DIGITS) -> mp.mpf:
    num, den = c_pair(c)
    with mp.workdps(digits + 10):
        return mp.mpf(num) / (mp.mpf(den) * mp.pi)


def c_string(c: sp.Expr, digits: int = DIGITS) -> str:
    with mp.workdps(digits + 10):
        return mp.nstr(c_to_mpf(c, digits), digits, min_fixed=-5, max_fixed=5)


def not_a_normal_mode(m: int, k: int) -> bool:
    """True if the O(eps^3) forcing has a component Yr_{m,3k} at the frequency (k >= 1, 3k <= m).

    Then the single real harmonic Yr_{m,k} does not continue to a periodic orbit of the same
    symmetry at this order (the degenerate degree-m eigenspace needs a mixed leading shape), and
    no coefficient c_{m,k} is defined. Checked against the computed forcing in :func:`main`.
    """
    return k >= 1 and 3 * k <= m


# =============================================================================================
# 4. Checks
# =============================================================================================
th, ph, eps_, kap = sp.symbols("theta phi epsilon kappa", real=True)


def _lap_S(f):
    return sp.diff(sp.sin(th) * sp.diff(f, th), th) / sp.sin(th) + sp.diff(f, ph, 2) / sp.sin(th) ** 2


def _grad_dot(f, g):
    return sp.diff(f, th) * sp.diff(g, th) + sp.diff(f, ph) * sp.diff(g, ph) / sp.sin(th) ** 2


def check_model_equations() -> None:
    """Force law (A), Delta_S X decomposition, kinematic form and the gradient identity."""
    section("A. Model equations by explicit vector calculus (sympy; exact identities checked at points)")
    rhat = sp.Matrix([sp.sin(th) * sp.cos(ph), sp.sin(th) * sp.sin(ph), sp.cos(th)])
    thhat = sp.Matrix([sp.cos(th) * sp.cos(ph), sp.cos(th) * sp.sin(ph), -sp.sin(th)])
    phhat = sp.Matrix([-sp.sin(ph), sp.cos(ph), 0])
    # a finite-amplitude, non-axisymmetric, odd+even shape (no small-eps assumption)
    f = sp.cos(th) * sp.sin(th) ** 2 * sp.cos(2 * ph) + sp.Rational(1, 3) * sp.cos(th) ** 2 + sp.sin(th) * sp.sin(ph)
    R = 1 + eps_ * f
    X = R * rhat
    Xth, Xph = X.diff(th), X.diff(ph)
    N = Xth.cross(Xph)
    F = kap * X.applyfunc(_lap_S)  # F = kappa Delta_S X, componentwise (7.1e)
    jump_717 = (N.dot(F)) * sp.sin(th) / N.dot(N)  # [[p]] from (7.17): [[p]] |N| = n.F sin
    g = _grad_dot(R, R)
    G = (R * _lap_S(R) - 2 * R**2 - 2 * g) / (R * (R**2 + g))
    G_rad = (_lap_S(R) - 2 * R) / R**2
    dec = (_lap_S(R) - 2 * R) * rhat + 2 * (sp.diff(R, th) * thhat + sp.diff(R, ph) / sp.sin(th) * phhat)
    pts = [(0.3, 0.7, 0.4), (1.1, 2.5, 0.25), (2.2, 4.0, 0.5), (1.7, 0.1, 0.1)]
    err_A = err_dec = err_N = err_rad = 0.0
    for t0, p0, e0 in pts:
        sub = {th: sp.Float(t0, 40), ph: sp.Float(p0, 40), eps_: sp.Float(e0, 40), kap: 1}
        err_A = max(err_A, abs(sp.N((jump_717 - kap * G).subs(sub), 30)))
        err_dec = max(err_dec, max(abs(sp.N(v, 30)) for v in (X.applyfunc(_lap_S) - dec).subs(sub)))
        Nexp = sp.sin(th) * R * (R * rhat - sp.diff(R, th) * thhat - sp.diff(R, ph) / sp.sin(th) * phhat)
        err_N = max(err_N, max(abs(sp.N(v, 30)) for v in (N - Nexp).subs(sub)))
        lhs = (kap * G - kap * G_rad).subs(sub)
        rhs = (-kap * g * _lap_S(R) / (R**2 * (R**2 + g))).subs(sub)
        err_rad = max(err_rad, abs(sp.N(lhs - rhs, 30)))
    check("(7.17) with F = kappa Delta_S X, X = R rhat: [[p]] = kappa (R Lap R - 2R^2 - 2g)/(R(R^2+g))",
          err_A < 1e-25, f"max error {float(err_A):.1e} at finite eps")
    check("Delta_S (R rhat) = (Delta_S R - 2R) rhat + 2 grad_S R", err_dec < 1e-25, f"{float(err_dec):.1e}")
    check("N = X_theta x X_phi = sin(theta) R (R rhat - grad_S R)", err_N < 1e-25, f"{float(err_N):.1e}")
    check("normal law - radial law = -kappa g Lap R/(R^2(R^2+g)) (an O(eps^3) difference)",
          err_rad < 1e-25, f"{float(err_rad):.1e}")
    # linear limit: G = -2 + eps (Lap + 2) x; for degree m: -(m-1)(m+2) -> lambda0^2 of (7.4)
    x = sp.Function("x")(th, ph)
    Rl = 1 + eps_ * x
    gl = _grad_dot(Rl, Rl)
    Gl = (Rl * _lap_S(Rl) - 2 * Rl**2 - 2 * gl) / (Rl * (Rl**2 + gl))
    lin = sp.simplify(sp.diff(Gl, eps_).subs(eps_, 0) - (_lap_S(x) + 2 * x))
    check("linear load: d G/d eps at 0 = (Delta_S + 2) x, i.e. -(m-1)(m+2) x for degree m (6.17)", lin == 0)
    mm = sp.Symbol("m", positive=True)
    # a r^m Y inside, b r^-(m+1) Y outside; kinematic x' = m a = -(m+1) b; stress a' - b' = -kappa (m-1)(m+2) x
    lam2 = sp.simplify(kap * (mm - 1) * (mm + 2) / (1 / mm + 1 / (mm + 1)))
    check("linear limit lambda0^2 = kappa m(m+1)(m-1)(m+2)/(2m+1) (7.4)",
          sp.simplify(lam2 - kap * mm * (mm + 1) * (mm - 1) * (mm + 2) / (2 * mm + 1)) == 0, str(lam2))
    # kinematic: N . X_t = N . grad psi  <=>  R_t = psi_r - grad_S R . grad_S psi / R^2 (at r = R)
    t, r = sp.symbols("t r", positive=True)
    Rt = sp.Function("R")(th, ph, t)
    pr, pth_, pph_ = sp.symbols("psi_r psi_th psi_ph")
    grad_psi = pr * rhat + pth_ / Rt * thhat + pph_ / (Rt * sp.sin(th)) * phhat
    Nt = sp.sin(th) * Rt * (Rt * rhat - sp.diff(Rt, th) * thhat - sp.diff(Rt, ph) / sp.sin(th) * phhat)
    lhs = sp.simplify(Nt.dot(sp.diff(Rt, t) * rhat - grad_psi) / (sp.sin(th) * Rt**2))
    rhs = sp.diff(Rt, t) - pr + (sp.diff(Rt, th) * pth_ + sp.diff(Rt, ph) * pph_ / sp.sin(th) ** 2) / Rt**2
    check("(7.18): n.(X_t - grad psi) = 0  <=>  R_t = psi_r - grad_S R . grad_S psi / R^2",
          sp.simplify(lhs - rhs) == 0)
    f1 = sp.sin(th) ** 2 * sp.cos(th) * sp.cos(2 * ph)
    f2 = sp.cos(th) ** 3 + sp.sin(th) * sp.cos(ph)
    ident = sp.simplify(_grad_dot(f1, f2) - (_lap_S(f1 * f2) - f1 * _lap_S(f2) - f2 * _lap_S(f1)) / 2)
    check("grad_S f . grad_S g = (Delta(fg) - f Delta g - g Delta f)/2", ident == 0)


def check_structure_constants() -> None:
    """Gaunt-derived products against quadrature and against exact Legendre integrals."""
    section("B. Products of harmonics from sympy.physics.wigner.gaunt")
    from scipy.special import lpmv

    x, wx = np.polynomial.legendre.leggauss(80)
    phs = np.linspace(0, 2 * np.pi, 96, endpoint=False)

    def B(n, l):
        return ((-1) ** l * lpmv(l, n, x))[:, None] * np.cos(l * phs)[None, :]  # lpmv has the CS phase

    err = 0.0
    cases = [(2, 0, 2, 0), (3, 1, 2, 1), (4, 2, 3, 1), (3, 3, 3, 2), (5, 0, 4, 3), (6, 2, 6, 4), (8, 0, 16, 0)]
    for a, al, b, be in cases:
        lhs = B(a, al) * B(b, be)
        rhs = sum(float(c) * B(n, l) for (n, l), c in ang_product(a, al, b, be))
        err = max(err, float(np.abs(lhs - rhs).max() / np.abs(lhs).max()))
    check("B_{a,al} B_{b,be} = sum coef B_{c,ga} on a 80 x 96 grid (relative)", err < 1e-12, f"{err:.1e}")
    z = sp.Symbol("z")

    def pt(n, l):
        return sp.expand((1 - z**2) ** sp.Rational(l, 2) * sp.diff(sp.legendre(n, z), z, l))

    bad = []
    for a, al, b, be, c, ga in [(2, 1, 3, 1, 3, 2), (4, 0, 4, 2, 6, 2), (5, 3, 3, 1, 4, 2), (3, 2, 5, 3, 4, 1)]:
        exact = sp.integrate(sp.expand(pt(a, al) * pt(b, be) * pt(c, ga)), (z, -1, 1))
        got = legendre_triple(a, al, b, be, c, ga)
        if sp.Rational(got.numerator, got.denominator) != sp.nsimplify(exact):
            bad.append((a, al, b, be, c, ga, got, exact))
    check("int Pt Pt Pt dx from gaunt = exact sympy integral", not bad, str(bad))
    # the engine's gradient product (identity + gaunt) against direct differentiation on the grid
    worst, top_ok = 0.0, True
    tt = np.arccos(x)[:, None]
    for m, k in [(3, 1), (4, 3), (5, 2)]:
        prod = f_graddot({(m, k, 0, 0): Fr(1)}, {(m, k, 0, 0): Fr(1)})
        top_ok &= max(key[0] for key in prod) <= 2 * m
        h = 1e-6

        def Bt(dt):
            return ((-1) ** k * lpmv(k, m, np.cos(tt[:, 0] + dt)))[:, None]

        dB = (Bt(h) - Bt(-h)) / (2 * h) * np.cos(k * phs)[None, :]
        Bph = -k * Bt(0) * np.sin(k * phs)[None, :] / np.sin(tt)
        direct = dB**2 + Bph**2
        eng = sum(float(v) * B(n, l) for (n, l, _, _), v in prod.items())
        worst = max(worst, float(np.abs(direct - eng).max() / np.abs(direct).max()))
    check("engine grad_S B . grad_S B (identity + gaunt) = direct derivatives; degrees <= 2m",
          worst < 1e-7 and top_ok, f"relative error {worst:.1e} (finite-difference limited)")


def band_limit_claim() -> None:
    """Thesis 7.3 last paragraph: <|Psi_{m,k}|^2, Y_{n,l}> nonzero for infinitely many (n, l)?"""
    section("G. Thesis claim: a non-axisymmetric mode excites infinitely many degrees")
    from scipy.special import sph_harm_y

    # complex Y_{m,k}: Psi = grad_S Y, |Psi|^2 = grad Y . grad conj(Y)
    # = (Delta |Y|^2)/2 + m(m+1)|Y|^2, and |Y|^2 = Y conj(Y) has degrees 0..2m (gaunt selection)
    ok_all = True
    for m, k in [(2, 1), (3, 2), (4, 3), (5, 5)]:
        nz = [n for n in range(0, 4 * m + 3) if gaunt(m, m, n, k, -k, 0) != 0]
        ok_all &= max(nz) <= 2 * m
        # numerical projection of |grad Y|^2 on Y_{n,0} for n up to 4m (Gauss-Legendre x uniform phi)
        x, wx = np.polynomial.legendre.leggauss(6 * m + 8)
        tt = np.arccos(x)[:, None]
        pp = np.linspace(0, 2 * np.pi, 8 * m + 8, endpoint=False)[None, :]
        Y = sph_harm_y(m, k, tt, pp)
        h = 1e-6
        dY = (sph_harm_y(m, k, tt + h, pp) - sph_harm_y(m, k, tt - h, pp)) / (2 * h)
        psi2 = np.abs(dY) ** 2 + (k**2) * np.abs(Y) ** 2 / np.sin(tt) ** 2
        w = wx[:, None] * (2 * np.pi / pp.size)
        proj = [abs(np.sum(w * psi2 * np.conj(sph_harm_y(n, 0, tt, pp)))) for n in range(0, 4 * m + 3)]
        scale = max(proj)
        beyond = max(proj[2 * m + 1:]) / scale
        ok_all &= beyond < 1e-8
        print(f"    (m, k) = ({m}, {k}): <|Psi|^2, Y_n0> != 0 for n in {nz}; "
              f"numerical |projection| beyond n = 2m: {beyond:.1e} (relative)")
    check("<|Psi_{m,k}|^2, Y_{n,l}> = 0 for n > 2m: only finitely many degrees (thesis claim refuted)", ok_all)


def table(pairs) -> dict:
    """Solve every (m, k) of ``pairs``; check the diagnostics; return {(m, k): result}."""
    section("C. Lindstedt-Poincare coefficients c_{m,k}: lambda = lambda0 (1 + c eps^2), radial-only membrane")
    out = {}
    t0 = time.time()
    failed = []
    for m, k in pairs:
        r = solve(m, k)
        d = r["diag"]
        degenerate = [x for x in d["degenerate"] if x[2] != 0]
        ok = (r["mu1"] == 0 and all(d["parity"]) and all(d["volume_kinematic"])
              and not [x for x in d["resonances"] if x[0] < ORDER and x[4] != 0]
              and all(rhs == 0 for (_, _, rhs) in d["degree1_forcing"])
              and bool(degenerate) == not_a_normal_mode(m, k))
        r["normal_mode"] = not degenerate
        out[(m, k)] = r
        if degenerate:
            print(f"  (m, k) = ({m}, {k}): NOT a nonlinear normal mode: O(eps^3) forcing of Yr_{{{m},{degenerate[0][1]}}}"
                  f" at the frequency ({float(degenerate[0][2]):.3e}); no c defined")
        else:
            print(f"  c_{{{m},{k}}} = {r['c']}  =  {c_string(r['c'])}")
        if not ok:
            failed.append(((m, k), d))
    check("every (m, k): lambda1 = 0 found (not assumed), tau-parity, volume <-> interior kinematics, "
          "no resonance, degree 1 never forced at j = 0, non-normal modes exactly when 3k <= m",
          not failed, str(failed))
    print(f"  ({len(out)} solves in {time.time() - t0:.1f} s)")
    return out


def degrees_zero_and_one(tab: dict) -> None:
    section("D. Degrees 0 and 1 (omitted by the thesis's sums)")
    worst = 0
    for m in (2, 3, 4):
        ref = tab[(m, 0)]["c"] if (m, 0) in tab else solve(m)["c"]
        lit = solve(m, volume="literal")["c"]
        drop = solve(m, drop_degree0=True)["c"]
        shift = sp.simplify(lit - ref)
        worst = max(worst, abs(float(shift + sp.Rational(3, 8) / sp.pi)))
        print(f"  m = {m}: c (volume 4 pi/3) = {float(ref):+.10f}; initial shape exactly 1 + eps Y: "
              f"{float(lit):+.10f} (shift {shift}); degree 0 dropped: {float(drop):+.10f}")
    check("degree 0 matters: the volume fixes a uniform dilation, shift literal - reference = -3/(8 pi)"
          " = -(3/2)(v/3) for V = (4 pi/3)(1 + v eps^2), v = 3/(4 pi): lambda ~ R^(-3/2) (sigma_eff = kappa)",
          worst < 1e-25)
    print("  degree 1: every O(eps^2) product Y_m Y_m has m + m + n even, so n = 1 never occurs at O(eps^2);"
          " at O(eps^3) degree 1 is forced only at odd harmonics (bounded). It does not affect c.")


def quadrupole(tab: dict) -> None:
    section("E. Consistency: every real quadrupole has the same c (Cayley-Hamilton for 3x3 traceless Q)")
    cs = [tab[(2, k)]["c"] if (2, k) in tab else solve(2, k)["c"] for k in (0, 1, 2)]
    check("c_{2,0} = c_{2,1} = c_{2,2} (quartic invariants of a quadrupole: tr Q^4 = (tr Q^2)^2/2)",
          cs[0] == cs[1] == cs[2], str(cs[0]))


def thesis_comparison(tab: dict) -> None:
    section("F. Thesis 7.3 printed results")
    m = 2
    r = tab[(2, 0)] if (2, 0) in tab else solve(2)
    n2 = basis_norm_sq(m, 0)
    ours = {}
    for (n, l, j), F in r["forced2"].items():
        if n in (2, 4):
            ours[(n, j)] = sp.simplify(sp.Rational(F.numerator, F.denominator) * n2 / sp.sqrt(basis_norm_sq(n, 0)))
    s5 = sp.sqrt(5 / sp.pi)
    print(f"  O(eps^2), m = 2, X'' + w^2 X = ...  (orthonormal Y, as (7.22)):")
    print(f"    n = 2: ours {ours[(2, 2)]} cos 2t + {ours[(2, 0)]};  (7.22a) 23/56 sqrt(5/pi) cos 2t - 9/56 sqrt(5/pi)")
    print(f"    n = 4: ours {ours[(4, 2)]} cos 2t + {ours[(4, 0)]};  (7.22b) 403/(378 sqrt(pi)) cos 2t + 425/(378 sqrt(pi))")
    check("(7.22a) cos 2t coefficient 23/56 sqrt(5/pi) reproduced", sp.simplify(ours[(2, 2)] - sp.Rational(23, 56) * s5) == 0)
    check("(7.22a) constant: ours +9/56 sqrt(5/pi), printed -9/56 (sign misprint or error in the thesis)",
          sp.simplify(ours[(2, 0)] - sp.Rational(9, 56) * s5) == 0)
    check("(7.22b) constant 425/(378 sqrt(pi)) reproduced", sp.simplify(ours[(4, 0)] - sp.Rational(425, 378) / sp.sqrt(sp.pi)) == 0)
    check("(7.22b) cos 2t: ours 439/(378 sqrt(pi)), printed 403/(378 sqrt(pi))",
          sp.simplify(ours[(4, 2)] - sp.Rational(439, 378) / sp.sqrt(sp.pi)) == 0)
    # (7.21) as printed, with exact projections (and kappa restored in the (m^2+m-1)/lambda0^2 term)
    kp = sp.Rational(2 * m + 1, m * (m + 1) * (m - 1) * (m + 2))
    from sympy.physics.wigner import wigner_3j
    agree_proj = True
    for n in (2, 4):
        P = gaunt(m, m, n, 0, 0, 0)
        psi_id = (m * (m + 1) - sp.Rational(n * (n + 1), 2)) * P
        psi_th = (-m * (m + 1) * sp.sqrt(sp.Rational((2 * m + 1) ** 2 * (2 * n + 1), 4) / sp.pi)
                  * wigner_3j(m, m, n, 1, -1, 0) * wigner_3j(m, m, n, 0, 0, 0))
        agree_proj &= sp.simplify(psi_id - psi_th) == 0
        a = sp.Rational(n * (n + 1), 2 * n + 1)
        const = (m * m + m - 1) * kp * a * P + a / (4 * (m + 1) ** 2) * psi_id
        cos2 = P + (m * m + m - 1) * kp * a * P - a / (4 * (m + 1) ** 2) * psi_id
        print(f"    (7.21) evaluated, n = {n}: {sp.simplify(cos2)} cos 2t + {sp.simplify(const)}")
    check("thesis's 3j formula for <|Psi_m0|^2, Y_n0> = (m(m+1) - n(n+1)/2) <Y_m0^2, Y_n0>", agree_proj)
    print("    -> (7.21) as printed does not give (7.22a) (n = 2: 43/140, 27/140 vs 23/56, -9/56 in sqrt(5/pi)).")
    # O(eps^3) and the final numbers
    num, den = c_pair(r["c"])
    lam2_printed = -sp.Rational(3531, 3920) * sp.sqrt(30) / sp.pi  # times sqrt(kappa)
    lam0 = sp.sqrt(sp.Rational(24, 5))
    from_lam2 = sp.simplify(lam2_printed / lam0)
    print(f"  printed lambda2 / lambda0 = {from_lam2} = -7062/(3136 pi); printed c = -7061/(3136 pi)")
    check("ERRATA item 1: printed lambda2 implies 7062 (= 2 x 3531), the printed c has 7061",
          sp.simplify(from_lam2 + sp.Rational(7062, 3136) / sp.pi) == 0)
    sec = {j: sp.Rational(v.numerator, v.denominator) * n2 for j, v in r["secular"][3].items()}
    print(f"  O(eps^3), (2,0) equation X'' + X = F1 cos t + F3 cos 3t (mu term excluded), orthonormal Y:")
    print(f"    ours F1 = {sec[1]} = {float(sec[1]):.6f}, F3 = {sec[3]} = {float(sec[3]):.6f};"
          f" printed (divided by pi kappa, the factor its lambda2 term carries): 3531/(784 pi) = "
          f"{3531 / (784 * math.pi):.6f}, 8364/(4704 pi) = {8364 / (4704 * math.pi):.6f}")
    printed = {2: (-sp.Rational(7061, 3136) / sp.pi, "0.7167"),
               3: (-sp.Rational(529881455, 198772992) / sp.pi, "0.8485"),
               4: (-sp.Rational(60326472574591, 18039224403200) / sp.pi, "1.0645")}
    for mm, (val, txt) in printed.items():
        ours_c = tab[(mm, 0)]["c"] if (mm, 0) in tab else solve(mm)["c"]
        variants = {"literal volume": solve(mm, volume="literal")["c"],
                    "degree 0 dropped": solve(mm, drop_degree0=True)["c"],
                    "radial force law": solve(mm, force_law="radial")["c"],
                    "radial law, degree 0 dropped": solve(mm, force_law="radial", drop_degree0=True)["c"]}
        vs = ", ".join(f"{k_}: {float(v):+.4f}" for k_, v in variants.items())
        print(f"  m = {mm}: thesis -{txt} (exact form {float(val):+.6f}); ours {float(ours_c):+.10f}; variants {vs}")
        check(f"thesis c_{mm} = -{txt} does not survive (ours {float(ours_c):+.6f}; no variant gives it)",
              all(abs(float(v - val)) > 1e-3 for v in [ours_c, *variants.values()]))


def generated_text(tab: dict) -> str:
    """Source of spectralshell/models/nonlinear_coefficients.py (deterministic)."""
    digest = hashlib.sha256(HERE.read_bytes()).hexdigest()
    exact, digits, missing = [], [], []
    for (m, k), r in sorted(tab.items()):
        if r["normal_mode"]:
            num, den = c_pair(r["c"])
            exact.append(f"    ({m}, {k}): ({num}, {den}),")
            digits.append(f'    ({m}, {k}): "{c_string(r["c"])}",')
        else:
            missing.append(f"    ({m}, {k}),")
    ms = sorted({m for m, _ in tab})
    return f'''"""Nonlinear frequency coefficients c_{{m,k}} of the inviscid spherical membrane (thesis 7.3).

DO NOT EDIT: generated by ``derivations/lindstedt_sphere.py --write`` (sha256 of the generator
below); ``tests/test_lindstedt.py`` checks the hash and recomputes entries.

lambda = lambda0 (1 + c_{{m,k}} eps^2 + O(eps^4)), lambda0^2 = kappa m(m+1)(m-1)(m+2)/(2m+1) (7.4),
for the free oscillation started from the shape 1 + eps Y, Y = Y_{{m,0}} (k = 0) or the orthonormal
real harmonic sqrt(2) Re Y_{{m,k}} (k > 0, any azimuthal phase), with the enclosed volume equal to
the unit sphere's (``volume="reference"``). c does not depend on kappa.

Model: RADIAL-ONLY membrane displacement X = R rhat (as in the thesis), F = kappa Delta_S X (7.1e)
with the exact normal balance (7.17), irrotational inviscid fluid of density 1 inside and outside,
exact kinematic condition (7.18). Every c = EXACT[m, k][0] / (EXACT[m, k][1] pi).

``volume="literal"``: the initial shape is exactly 1 + eps Y, whose volume exceeds 4 pi/3 by
eps^2; the equilibrium radius grows by eps^2/(4 pi) and lambda ~ R^(-3/2), so c shifts by -3/(8 pi).

Corrections to the printed thesis values (-7061/(3136 pi) ~ -0.7167, -0.8485, -1.0645 for m = 2, 3,
4): none survive; see the generator's output. Pairs in NOT_NORMAL_MODES (k >= 1, 3k <= m): the
O(eps^3) forcing excites Y_{{m,3k}} at the oscillation frequency, so the single real harmonic does
not continue to a periodic orbit of its own symmetry and c is not defined.
"""

from __future__ import annotations

from fractions import Fraction

import mpmath

from ..errors import ParameterError
from .._validate import require_choice, require_int_in_range

GENERATOR = "derivations/lindstedt_sphere.py"
GENERATOR_SHA256 = "{digest}"
M_MIN, M_MAX = {ms[0]}, {ms[-1]}

#: (m, k) -> (num, den): c_{{m,k}} = num / (den pi), exact
EXACT = {{
{chr(10).join(exact)}
}}

#: (m, k) -> c_{{m,k}} to {DIGITS} significant digits (mpmath from the exact value)
DIGITS30 = {{
{chr(10).join(digits)}
}}

#: (m, k) whose real harmonic is not a nonlinear normal mode (k >= 1, 3k <= m)
NOT_NORMAL_MODES = (
{chr(10).join(missing)}
)

#: c_literal - c_reference = LITERAL_SHIFT[0] / (LITERAL_SHIFT[1] pi)
LITERAL_SHIFT = (-3, 8)
VOLUMES = ("reference", "literal")


def _key(m: int, k: int) -> tuple[int, int]:
    m = require_int_in_range("m", m, M_MIN, M_MAX)
    k = abs(require_int_in_range("k", k, -m, m))
    if (m, k) in NOT_NORMAL_MODES:
        raise ParameterError(f"k = {{k}} is invalid for m = {{m}}: must satisfy k = 0 or 3|k| > m (for 3|k| <= m "
                             "the real harmonic Y_{{m,k}} is not a nonlinear normal mode; no c is defined)")
    return m, k


def lp_coefficient_exact(m: int, k: int = 0, *, volume: str = "reference") -> tuple[int, int]:
    """(num, den) with c_{{m,k}} = num / (den pi), exact. Raises ParameterError (see :func:`lp_coefficient`)."""
    c = Fraction(*EXACT[_key(m, k)])
    if require_choice("volume", volume, VOLUMES) == "literal":
        c += Fraction(*LITERAL_SHIFT)
    return c.numerator, c.denominator


def lp_coefficient_mpf(m: int, k: int = 0, *, volume: str = "reference", dps: int = 30) -> mpmath.mpf:
    """c_{{m,k}} as an mpmath number with ``dps`` decimal digits (evaluated from the exact value)."""
    num, den = lp_coefficient_exact(m, k, volume=volume)
    with mpmath.workdps(dps):
        return +(mpmath.mpf(num) / (mpmath.mpf(den) * mpmath.pi))


def lp_coefficient(m: int, k: int = 0, *, volume: str = "reference") -> float:
    """c_{{m,k}} in lambda = lambda0 (1 + c eps^2) (radial-only membrane; see the module docstring).

    Raises ParameterError for m outside [M_MIN, M_MAX], |k| > m, 3|k| <= m with k != 0, or an
    unknown ``volume``.
    """
    return float(lp_coefficient_mpf(m, k, volume=volume, dps=20))
'''


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="regenerate " + str(TARGET.relative_to(REPO)))
    ap.add_argument("--m", type=int, nargs="*", help="degrees to tabulate (default 2..8)")
    ap.add_argument("--k", type=int, nargs="*", help="orders to tabulate (default 0..m)")
    ap.add_argument("--quick", action="store_true", help="skip sections A, B, G")
    args = ap.parse_args(argv)
    pairs = [(m, k) for (m, k) in GENERATED_RANGE
             if (args.m is None or m in args.m) and (args.k is None or k in args.k)]
    if not args.quick:
        check_model_equations()
        check_structure_constants()
    tab = table(pairs)
    degrees_zero_and_one(tab)
    quadrupole(tab)
    thesis_comparison(tab)
    if not args.quick:
        band_limit_claim()
    section("H. Generated file")
    if sorted(tab) == sorted(GENERATED_RANGE):
        text = generated_text(tab)
        if args.write:
            TARGET.write_text(text)
            print(f"  wrote {TARGET.relative_to(REPO)}")
        check("generated file is up to date", TARGET.exists() and TARGET.read_text() == text)
    else:
        print("  subset run: generated file not compared")
    return summary()


if __name__ == "__main__":
    sys.exit(main())
