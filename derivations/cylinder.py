#!/usr/bin/env python3
"""Linear oscillations of a periodic cylindrical membrane in 3D unsteady Stokes flow (thesis 8.1).

The thesis proposes the geometry (section 8.1) but derives nothing for it. This script derives the
per-(m, k) system in the form the Floquet engine needs,

    D(d/dt) X + 2 tau sin(t) G X = 0    <=>    D(s_n) X_n = i tau G (X_{n-1} - X_{n+1}),

from the membrane law of the sphere (6.1) on the reference cylinder and the unsteady Stokes
fields, with every claim checked (sympy, and mpmath at 30 digits). Run
``python3 derivations/cylinder.py``; it exits with status 0 only if every check passes.

Conventions (as the fibre, derivations/fibre_linear.py, and the sphere):
  * Unit radius R = 1, density 1, kinematic viscosity nu = mu/(rho R^2 omega), time scaled so that
    the pumping period is 2 pi, K(t) = kappa (1 + 2 tau sin t), kappa = sigma/(rho R^3 omega^2).
  * Reference cylinder X0(theta, z) = r-hat(theta) + z z-hat; membrane energy
    (K/2) int int (|X_theta|^2 + |X_z|^2), so F = K Delta_S X = K (X_thetatheta + X_zz) per unit
    reference area.
  * One Fourier mode phi = m theta + k z (k = k R >= 0, m >= 0), written with real trigonometric
    modes as the fibre: X^r cos(phi) r-hat + X^theta sin(phi) theta-hat + X^z sin(phi) z-hat. In
    complex form the amplitudes are (X^r, -i X^theta, -i X^z) e^{i phi}.
  * [[q]] = q(1+) - q(1-) (outside minus inside). beta^2 = s/nu + k^2, Re beta > 0.

Fields per mode (u = -grad p / s + curl(psi z-hat) + curl curl(chi z-hat)): the pressure is
harmonic, p = a g(r) e^{i phi} with g = I_m(k r)/I_m(k) inside and K_m(k r)/K_m(k) outside; the
vortical potentials psi = A F(r) e^{i phi}, chi = C F(r) e^{i phi} solve (Lap - s/nu) = 0, so
F = I_m(beta r)/I_m(beta) inside and K_m(beta r)/K_m(beta) outside. Only the logarithmic
derivatives Lambda = g'(1) and L = F'(1) enter the interface conditions.
"""

from __future__ import annotations

import random
import sys

import mpmath as mp
import sympy as sp

from _checks import check, section, summary  # noqa: E402  (derivations/_checks.py)

mp.mp.dps = 30

r, th, z = sp.symbols("r theta z", real=True)
m_, k_ = sp.symbols("m k", nonnegative=True)
s_, nu_, beta_, K_, eps = sp.symbols("s nu beta K epsilon")
Lam_, L_ = sp.symbols("Lambda L")


def E_matrix(m, k):
    """Elastic load matrix: membrane force (with prestress) on the fluid = -K E (X^r, X^th, X^z)."""
    q = m**2 + k**2
    return sp.Matrix([[q, m, -k], [m, q, 0], [-k, 0, q]])


# ---------------------------------------------------------------------------------------------
# Part 1. Membrane law, prestress, elastic load E(m, k), rigid motions
# ---------------------------------------------------------------------------------------------
def part1():
    section("Part 1. F = K Delta_S X on the reference cylinder: prestress and the elastic load -K E X")
    fr, ft, fz = (sp.Function(n)(th, z) for n in ("fr", "ft", "fz"))
    rh = sp.Matrix([sp.cos(th), sp.sin(th), 0])
    tt = sp.Matrix([-sp.sin(th), sp.cos(th), 0])
    zh = sp.Matrix([0, 0, 1])
    X = rh + z * zh + eps * (fr * rh + ft * tt + fz * zh)
    F = K_ * (sp.diff(X, th, 2) + sp.diff(X, z, 2))
    N = sp.diff(X, th).cross(sp.diff(X, z))            # area-weighted outward normal
    F0, N0 = F.subs(eps, 0), N.subs(eps, 0)
    check("F0 = -K r-hat and N0 = r-hat: the pressurised cylinder has [[p0]] = -K (Laplace)",
          sp.simplify(F0 + K_ * rh) == sp.zeros(3, 1) and sp.simplify(N0 - rh) == sp.zeros(3, 1))
    F1 = sp.diff(F, eps).subs(eps, 0)
    N1 = sp.diff(N, eps).subs(eps, 0)
    # O(eps) of the balance [[sigma]] N + F = 0: -[[p1]] r - [[p0]] N1 + nu[[...]] + F1 = 0
    load = F1 + K_ * N1
    comp = [sp.simplify(load.dot(e)) for e in (rh, tt, zh)]
    claim = [K_ * (sp.diff(fr, th, 2) + sp.diff(fr, z, 2) - sp.diff(ft, th) + sp.diff(fz, z)),
             K_ * (sp.diff(ft, th, 2) + sp.diff(ft, z, 2) + sp.diff(fr, th)),
             K_ * (sp.diff(fz, th, 2) + sp.diff(fz, z, 2) - sp.diff(fr, z))]
    check("F1 - [[p0]] N1 = K[(Lap X^r - X^th_th + X^z_z) r + (Lap X^th + X^r_th) th + (Lap X^z - X^r_z) z]",
          all(sp.simplify(c - d) == 0 for c, d in zip(comp, claim)))
    xr, xt, xz = sp.symbols("x_r x_theta x_z")
    ph = m_ * th + k_ * z
    mode = {fr: xr * sp.cos(ph), ft: xt * sp.sin(ph), fz: xz * sp.sin(ph)}
    rows = [sp.simplify(claim[0].subs(mode).doit() / sp.cos(ph)),
            sp.simplify(claim[1].subs(mode).doit() / sp.sin(ph)),
            sp.simplify(claim[2].subs(mode).doit() / sp.sin(ph))]
    E = E_matrix(m_, k_)
    EX = E * sp.Matrix([xr, xt, xz])
    check("mode (X^r cos phi, X^th sin phi, X^z sin phi): load = -K E X, "
          "E = [[m^2+k^2, m, -k], [m, m^2+k^2, 0], [-k, 0, m^2+k^2]] (symmetric)",
          all(sp.simplify(rows[i] + K_ * EX[i]) == 0 for i in range(3)))
    check("k = 0: the (X^r, X^th) block is the fibre's E = [[m^2, m], [m, m^2]] and X^z decouples "
          "(E_zz = m^2); m = 0: X^th decouples (torsion, E = k^2) from the sausage pair (X^r, X^z)",
          E.subs(k_, 0)[:2, :2] == sp.Matrix([[m_**2, m_], [m_, m_**2]]) and E.subs(k_, 0)[2, :2] == sp.zeros(1, 2)
          and E.subs(m_, 0)[1, 0] == 0 and E.subs(m_, 0)[1, 2] == 0)
    full = lambda d: [sp.simplify(c.subs(d).doit()) for c in claim]  # noqa: E731
    check("rigid translation (m = 1, k = 0: X = e_x, i.e. (X^r, X^th) = (1, -1)), rigid axial shift "
          "(X^z = const) and rigid rotation (X^th = const) carry no elastic load",
          full({fr: sp.cos(th), ft: -sp.sin(th), fz: 0}) == [0, 0, 0]
          and full({fr: 0, ft: 0, fz: 1}) == [0, 0, 0] and full({fr: 0, ft: 1, fz: 0}) == [0, 0, 0])
    lam = sp.Symbol("lambda")
    q = m_**2 + k_**2
    charp = sp.factor((E - lam * sp.eye(3)).det())
    check("eigenvalues of E: q and q +- sqrt(q), q = m^2 + k^2: E > 0 exactly when m^2 + k^2 > 1 "
          "(m = 0, k < 1 is the Rayleigh-Plateau instability of the pressurised cylinder)",
          sp.simplify(charp + (lam - q) * ((lam - q)**2 - q)) == 0)
    return E


# ---------------------------------------------------------------------------------------------
# Part 2. Fields of one mode, their residuals; interface matrices V, T
# ---------------------------------------------------------------------------------------------
def fields(g, F, a, A, C, s, k, m, beta2):
    """(u_r, u_theta, u_z, p) amplitudes of e^{i phi} as expressions in r (g, F: radial functions)."""
    I = sp.I
    u_r = -a * sp.diff(g, r) / s + I * m * A * F / r + I * k * C * sp.diff(F, r)
    u_t = -I * m * a * g / (r * s) - A * sp.diff(F, r) - m * k * C * F / r
    u_z = -I * k * a * g / s - beta2 * C * F
    return u_r, u_t, u_z, a * g


def lap_s(f, m, k):
    return sp.diff(f, r, 2) + sp.diff(f, r) / r - (m**2 / r**2 + k**2) * f


def part2():
    section("Part 2. Fields: harmonic pressure, vortical psi, chi with (Lap - s/nu) = 0; residuals")
    g, F = sp.Function("g")(r), sp.Function("F")(r)
    a, A, C = sp.symbols("a A C")
    m, k, s, nu = m_, k_, s_, nu_
    beta2 = s / nu + k**2
    u_r, u_t, u_z, p = fields(g, F, a, A, C, s, k, m, beta2)
    g2 = -sp.diff(g, r) / r + (k**2 + m**2 / r**2) * g          # Bessel ODE of g (argument k r)
    F2 = -sp.diff(F, r) / r + (beta2 + m**2 / r**2) * F         # of F (argument beta r)

    def reduce(e):
        for _ in range(3):
            e = e.subs(sp.Derivative(g, (r, 3)), sp.diff(g2, r)).subs(sp.Derivative(g, (r, 2)), g2)
            e = e.subs(sp.Derivative(F, (r, 3)), sp.diff(F2, r)).subs(sp.Derivative(F, (r, 2)), F2)
        return sp.simplify(sp.expand(e))

    I = sp.I
    # cylindrical operators on e^{i phi} amplitudes (d/dtheta -> i m, d/dz -> i k)
    mom_r = s * u_r + sp.diff(p, r) - nu * (lap_s(u_r, m, k) - u_r / r**2 - 2 * I * m * u_t / r**2)
    mom_t = s * u_t + I * m * p / r - nu * (lap_s(u_t, m, k) - u_t / r**2 + 2 * I * m * u_r / r**2)
    mom_z = s * u_z + I * k * p - nu * lap_s(u_z, m, k)
    cont = sp.diff(r * u_r, r) / r + I * m * u_t / r + I * k * u_z
    res = [reduce(e) for e in (mom_r, mom_t, mom_z, cont)]
    check("u = -grad p/s + curl(psi z) + curl curl(chi z) with Lap p = 0 and (Lap - s/nu) psi, chi = 0 "
          "solves s u = -grad p + nu Lap u, div u = 0 (cylindrical operators, Bessel ODEs)",
          all(e == 0 for e in res), str(res))

    # interface matrices at r = 1 with g(1) = F(1) = 1, g'(1) = Lambda, F'(1) = L
    at1 = {sp.Derivative(g, r): Lam_, sp.Derivative(F, r): L_, g: 1, F: 1}

    def at_one(e):
        e = reduce(e)
        return sp.expand(e.subs(at1).subs(r, 1))

    vel = [u_r, u_t, u_z]
    dvel = [sp.diff(v, r) for v in vel]
    trac = [-p + 2 * nu * dvel[0], nu * (dvel[1] - u_t / r + I * m * u_r / r), nu * (dvel[2] + I * k * u_r)]
    amps = [a, A, C]
    V = sp.Matrix(3, 3, lambda i, j: sp.diff(at_one(vel[i]), amps[j]))
    T = sp.Matrix(3, 3, lambda i, j: sp.diff(at_one(trac[i]), amps[j]))
    V_claim, T_claim = interface_matrices(m, k, s, nu, Lam_, L_, sp.I, beta2)
    check("interface matrices: velocity V and traction T at r = 1 per amplitude (a, A, C) as stated in "
          "interface_matrices()", sp.simplify(V - V_claim) == sp.zeros(3, 3)
          and sp.simplify(T - T_claim) == sp.zeros(3, 3))
    return V, T


def interface_matrices(m, k, s, nu, Lam, L, I, beta2):
    """V, T: velocity and traction (sigma . r-hat) at r = 1 per unit amplitude (a, A, C).

    Any number type (sympy, mpmath); I is the imaginary unit of that type."""
    b2 = beta2
    V = [[-Lam / s, I * m, I * k * L],
         [-I * m / s, -L, -m * k],
         [-I * k / s, 0, -b2]]
    du = [[-(k**2 + m**2 - Lam) / s, I * m * (L - 1), I * k * (b2 + m**2 - L)],
          [-I * m * (Lam - 1) / s, -(b2 + m**2 - L), -m * k * (L - 1)],
          [-I * k * Lam / s, 0, -b2 * L]]
    T = [[-1 + 2 * nu * du[0][0], 2 * nu * du[0][1], 2 * nu * du[0][2]],
         [nu * (du[1][j] - V[1][j] + I * m * V[0][j]) for j in range(3)],
         [nu * (du[2][j] + I * k * V[0][j]) for j in range(3)]]
    if isinstance(s, sp.Basic):
        return sp.Matrix(V), sp.Matrix(T)
    return mp.matrix(V), mp.matrix(T)


# ---------------------------------------------------------------------------------------------
# Part 3. Numerical fields (mpmath Bessel functions), Cartesian residuals, the load H(s)
# ---------------------------------------------------------------------------------------------
def bessel(bes, m, x, d=0):
    """I_m or K_m (d = 0) or its derivative (d = 1, DLMF 10.29.2: I' = (I_{m-1} + I_{m+1})/2,
    K' = -(K_{m-1} + K_{m+1})/2; mpmath's besselk has no derivative option)."""
    if d == 0:
        return bes(m, x)
    sign = 1 if bes is mp.besseli else -1
    return sign * (bes(m - 1, x) + bes(m + 1, x)) / 2


def logderivs(m, k, beta):
    """(Lambda, L) inside and outside from mpmath besseli/besselk directly (no ratio kernels)."""
    def ld(f, x):
        return x * bessel(f, m, x, 1) / f(m, x)
    lam_in = ld(mp.besseli, k) if k != 0 else mp.mpf(m)
    lam_out = ld(mp.besselk, k) if k != 0 else -mp.mpf(m)
    return (lam_in, ld(mp.besseli, beta)), (lam_out, ld(mp.besselk, beta))


def H_complex(m, k, s, nu):
    """Complex load matrix: h = [[p]] r - nu[[d_r u]] = H_c (s X_c), X_c the complex amplitudes."""
    s, k, nu = mp.mpmathify(s), mp.mpmathify(k), mp.mpmathify(nu)
    b2 = s / nu + k * k
    beta = mp.sqrt(b2)
    Z = []
    for lam, L in logderivs(m, k, beta):
        V, T = interface_matrices(m, k, s, nu, lam, L, mp.mpc(0, 1), b2)
        Z.append(T * mp.inverse(V))
    return Z[0] - Z[1]           # -( [[sigma r]] ) per unit velocity: inside minus outside


def D_real(m, k, s, nu, kappa):
    """D(s) = s S^-1 H_c S + kappa E in the real basis, S = diag(1, -i, -i)."""
    S = mp.diag([1, -1j, -1j])
    Sinv = mp.diag([1, 1j, 1j])
    H = Sinv * H_complex(m, k, s, nu) * S * mp.mpmathify(s)
    return H + kappa * E_mp(m, k)


def E_mp(m, k):
    """E(m, k) of Part 1 in mpmath."""
    m, k = mp.mpf(m), mp.mpmathify(k)
    q = m * m + k * k
    return mp.matrix([[q, m, -k], [m, q, 0], [-k, 0, q]])


def cartesian_check(m, k, s, nu, X):
    """Solve the interface conditions for the complex amplitudes X, build the Cartesian velocity and
    pressure from mpmath Bessel functions, and return (max PDE residual at random points, interface
    velocity error, |traction jump from Cartesian gradients + s H_c X| / scale)."""
    s, k, nu = mp.mpmathify(s), mp.mpmathify(k), mp.mpmathify(nu)
    b2 = s / nu + k * k
    beta = mp.sqrt(b2)
    I = mp.mpc(0, 1)
    sides = []
    for (lam, L), bes in zip(logderivs(m, k, beta), (mp.besseli, mp.besselk)):
        V, _ = interface_matrices(m, k, s, nu, lam, L, I, b2)
        amp = mp.lu_solve(V, mp.matrix([s * x for x in X]))
        pw = m if bes is mp.besseli else -m
        gk = (lambda rr, d=0, b=bes: k**d * bessel(b, m, k * rr, d) / b(m, k)) if k != 0 else \
            (lambda rr, d=0, pw=pw: rr ** pw if d == 0 else pw * rr ** (pw - 1))
        Fb = lambda rr, d=0, b=bes: beta**d * bessel(b, m, beta * rr, d) / b(m, beta)  # noqa: E731
        sides.append((amp, gk, Fb))

    def cyl_fields(side, x, y, zz):
        amp, gk, Fb = side
        a, A, C = amp
        rr, t = mp.sqrt(x * x + y * y), mp.atan2(y, x)
        e = mp.exp(I * (m * t + k * zz))
        dg, dF = gk(rr, 1), Fb(rr, 1)
        ur = -a * dg / s + I * m * A * Fb(rr) / rr + I * k * C * dF
        ut = -I * m * a * gk(rr) / (rr * s) - A * dF - m * k * C * Fb(rr) / rr
        uz = -I * k * a * gk(rr) / s - b2 * C * Fb(rr)
        c, sn = mp.cos(t), mp.sin(t)
        return [e * (ur * c - ut * sn), e * (ur * sn + ut * c), e * uz, e * a * gk(rr)]

    def pde_residual(side, pt):
        f = lambda i: (lambda x, y, zz: cyl_fields(side, x, y, zz)[i])  # noqa: E731
        res = 0
        div = 0
        for i in range(3):
            lap = sum(mp.diff(f(i), pt, tuple(2 if j == d else 0 for j in range(3))) for d in range(3))
            gradp = mp.diff(f(3), pt, tuple(1 if j == i else 0 for j in range(3)))
            res = max(res, abs(s * f(i)(*pt) + gradp - nu * lap))
            div += mp.diff(f(i), pt, tuple(1 if j == i else 0 for j in range(3)))
        return max(res, abs(div))

    rng = random.Random(1)
    res = 0
    for side, rad in zip(sides, (mp.mpf("0.55"), mp.mpf("1.6"))):
        t, zz = rng.uniform(0, 6.28), rng.uniform(-1, 1)
        pt = (rad * mp.cos(t), rad * mp.sin(t), mp.mpf(zz))
        res = max(res, pde_residual(side, pt))
    # interface: velocity at r = 1 and the traction sigma . r-hat from Cartesian gradients
    t0, z0 = mp.mpf("0.7"), mp.mpf("0.3")
    pt = (mp.cos(t0), mp.sin(t0), z0)
    nrm = [mp.cos(t0), mp.sin(t0), 0]
    e = mp.exp(I * (m * t0 + k * z0))
    Xcart = [e * (X[0] * nrm[0] - X[1] * nrm[1]), e * (X[0] * nrm[1] + X[1] * nrm[0]), e * X[2]]
    vel_err, tr = 0, []
    for side in sides:
        f = lambda i, side=side: (lambda x, y, zz: cyl_fields(side, x, y, zz)[i])  # noqa: E731
        vals = cyl_fields(side, *pt)
        vel_err = max(vel_err, max(abs(vals[i] - s * Xcart[i]) for i in range(3)))
        grad = [[mp.diff(f(i), pt, tuple(1 if j == d else 0 for j in range(3))) for d in range(3)]
                for i in range(3)]
        tr.append([-vals[3] * nrm[i] + nu * sum((grad[i][d] + grad[d][i]) * nrm[d] for d in range(3))
                   for i in range(3)])
    jump = [tr[1][i] - tr[0][i] for i in range(3)]          # [[sigma . r]]
    hc = H_complex(m, k, s, nu) * mp.matrix([s * x for x in X])
    h_cart = [e * (hc[0] * nrm[0] - hc[1] * nrm[1]), e * (hc[0] * nrm[1] + hc[1] * nrm[0]), e * hc[2]]
    scale = max(abs(x) for x in h_cart)
    err = max(abs(jump[i] + h_cart[i]) for i in range(3)) / scale
    return res, vel_err, err


def part3():
    section("Part 3. mpmath fields in Cartesian coordinates: PDE residuals, interface, load H(s)")
    ok, worst = True, []
    mp.mp.dps = 20   # numerical second derivatives in 3D are slow: two cases (about 1 minute)
    for (m, k, s, nu) in [(2, 0.7, mp.mpc("0.3", "1.7"), mp.mpf("0.05")), (0, 1.3, mp.mpc("-0.2", "0.9"), 0.3)]:
        X = [mp.mpc("0.7", "-0.2"), mp.mpc("-0.4", "1.1"), mp.mpc("0.3", "0.5")]
        res, vel, err = cartesian_check(m, k, s, nu, X)
        worst.append((m, k, mp.nstr(res, 3), mp.nstr(vel, 3), mp.nstr(err, 3)))
        ok &= res < 1e-15 and vel < 1e-15 and err < 1e-15
    mp.mp.dps = 30
    check("Cartesian fields (besseli/besselk, numerical derivatives at random points) satisfy unsteady "
          "Stokes and div u = 0 inside and outside, u = s X at r = 1, and minus the jump of the full "
          "traction sigma . r-hat equals H_c (s X)", ok, str(worst))


# ---------------------------------------------------------------------------------------------
# Part 4. Properties of D(s): reality, reciprocity, passivity, decoupling, the fibre at k = 0
# ---------------------------------------------------------------------------------------------
def fibre_D(m, s, nu, kappa):
    """The fibre's D(s) (derivations/fibre_linear.py, thesis chapter 4 corrected), independent."""
    beta = mp.sqrt(mp.mpmathify(s) / nu)
    P = beta * mp.besseli(m + 1, beta) / mp.besseli(m, beta)
    Q = beta * mp.besselk(m - 1, beta) / mp.besselk(m, beta)
    s = mp.mpmathify(s)
    return mp.matrix([[s**2 * (mp.mpf(2) / m + 1 / P + 1 / Q) + kappa * m**2, s**2 * (1 / P - 1 / Q) + kappa * m],
                      [s**2 * (1 / P - 1 / Q) + kappa * m, s**2 * (1 / P + 1 / Q) + kappa * m**2]])


def maxabs(A):
    return max(abs(A[i, j]) for i in range(A.rows) for j in range(A.cols))


def part4():
    section("Part 4. D(s) = s S^-1 H_c S + kappa E: reality, reciprocity, passivity, decoupling, k = 0")
    okR = okS = okP = True
    for (m, k) in [(0, 1.5), (1, 0.3), (2, 0.7), (3, 2.0), (5, 0.1)]:
        for s in (mp.mpc("0.2", "1.3"), mp.mpc("-0.3", "2.2"), mp.mpc("0.05", "-0.7")):
            A1, A2 = D_real(m, k, s, 0.02, 0.7), D_real(m, k, mp.conj(s), 0.02, 0.7)
            okR &= maxabs(A2 - A1.apply(mp.conj)) < 1e-25
            okS &= maxabs(A1 - A1.T) < 1e-25 * maxabs(A1)
        for w in (0.3, 1.0, 4.0):
            Hm = D_real(m, k, 1j * w, 0.01, 0)
            for X in ([1, 0, 0], [0, 1, 0], [0, 0, 1], [0.3 - 0.5j, 1.2 + 0.1j, -0.4j], [1, -1, 1]):
                f = Hm * mp.matrix(X)
                okP &= mp.re(sum(f[i] * mp.conj(1j * w * X[i]) for i in range(3))) > 0
    check("real time-domain operator: D(conj s) = conj D(s) in the basis (cos, sin, sin)", okR)
    check("reciprocity: D(s) (and so the fluid's velocity-to-traction map) is symmetric", okS)
    check("passivity: Re(h . conj u) > 0 on s = i omega for every X (viscous dissipation)", okP)
    dec = True
    for s in (mp.mpc("0.2", "1.3"), mp.mpc("-0.1", "0.4")):
        D0 = D_real(0, 1.4, s, 0.05, 0.3)
        dec &= max(abs(D0[0, 1]), abs(D0[1, 0]), abs(D0[1, 2]), abs(D0[2, 1])) < 1e-25
        Dk = D_real(3, 0, s, 0.05, 0.3)
        dec &= max(abs(Dk[0, 2]), abs(Dk[2, 0]), abs(Dk[1, 2]), abs(Dk[2, 1])) < 1e-25
    check("m = 0: torsion X^theta decouples from the sausage pair (X^r, X^z); k = 0: X^z decouples from "
          "(X^r, X^theta); for m >= 1, k > 0 all three couple", dec
          and abs(D_real(2, 0.5, mp.mpc(0.1, 1), 0.05, 0.3)[1, 2]) > 1e-3)
    okF = True
    for m in (2, 3, 6):
        for s in (mp.mpc("0.3", "1.7"), mp.mpc("0.01", "-0.6")):
            Dc = D_real(m, 0, s, mp.mpf("0.03"), mp.mpf("0.4"))
            Df = fibre_D(m, s, mp.mpf("0.03"), mp.mpf("0.4"))
            okF &= maxabs(Dc[:2, :2] - Df) < 1e-25 * maxabs(Df)
    check("k = 0: the (X^r, X^theta) block equals the 2D fibre's D(s) (thesis 4, corrected) per unit "
          "length", okF)
    okC = True
    for m in (2, 4):
        s = mp.mpc("0.2", "1.1")
        Dk = D_real(m, mp.mpf("1e-12"), s, 0.03, 0.4)
        okC &= maxabs(Dk[:2, :2] - fibre_D(m, s, 0.03, 0.4)) < 1e-8
    check("k -> 0 is continuous (k = 1e-12 matches the fibre to 1e-8)", okC)


# ---------------------------------------------------------------------------------------------
# Part 5. Limits: s -> 0 and nu -> 0 (inviscid closed form)
# ---------------------------------------------------------------------------------------------
def inviscid_mass(m, k):
    """M(m, k) = I_m(k)/(k I_m'(k)) - K_m(k)/(k K_m'(k)): added mass per unit radial displacement."""
    k = mp.mpmathify(k)
    if k == 0:
        return mp.mpf(2) / m
    return mp.besseli(m, k) / (k * bessel(mp.besseli, m, k, 1)) - \
        mp.besselk(m, k) / (k * bessel(mp.besselk, m, k, 1))


def part5():
    section("Part 5. Limits: s -> 0 (D -> kappa E) and nu -> 0 (Mathieu with the inviscid frequency)")
    ok0 = True
    for (m, k) in [(2, 0.5), (0, 1.5), (1, 1.0)]:
        D = D_real(m, k, mp.mpc("1e-12", "1e-12"), 0.05, 0.3)
        ok0 &= maxabs(D - 0.3 * E_mp(m, k)) < 1e-9
    check("D(s) -> kappa E as s -> 0 (the fluid load vanishes with the velocity)", ok0)
    # inviscid: potential flow on both sides, tangential stress -> 0
    a_in, a_out, x = sp.symbols("a_in a_out x_r")
    Ip, Kp, Iv, Kv = sp.symbols("Ip Kp Iv Kv")  # I_m'(k), K_m'(k), I_m(k), K_m(k)
    s = s_
    sol = sp.solve([-a_in * k_ * Ip / s - s * x, -a_out * k_ * Kp / s - s * x], [a_in, a_out], dict=True)[0]
    jump_p = (a_out * Kv - a_in * Iv).subs(sol)
    check("inviscid: u = -grad p / s, u^r = s X^r at r = 1 gives [[p]] = s^2 M X^r, "
          "M = I_m/(k I_m') - K_m/(k K_m')",
          sp.simplify(jump_p - s**2 * x * (Iv / (k_ * Ip) - Kv / (k_ * Kp))) == 0)
    q = m_**2 + k_**2
    E = E_matrix(m_, k_)
    xr = sp.Symbol("x")
    slaved = sp.solve([E[1, 0] * xr + E[1, 1] * sp.Symbol("y"), E[2, 0] * xr + E[2, 2] * sp.Symbol("w")],
                      [sp.Symbol("y"), sp.Symbol("w")], dict=True)[0]
    eff = sp.simplify((E[0, 0] * xr + E[0, 1] * slaved[sp.Symbol("y")] + E[0, 2] * slaved[sp.Symbol("w")]) / xr)
    check("the tangential rows without fluid stress slave X^th = -m X^r/q, X^z = k X^r/q; the radial row "
          "becomes M X'' + K (m^2 + k^2 - 1) X = 0: lambda0^2 = kappa (m^2 + k^2 - 1)/M(m, k)",
          sp.simplify(eff - (q - 1)) == 0)
    check("k -> 0: M -> 2/m and lambda0^2 -> kappa m (m^2 - 1)/2, the fibre's Rayleigh frequency",
          abs(inviscid_mass(3, mp.mpf("1e-10")) - mp.mpf(2) / 3) < 1e-15)
    # the viscous D(s) tends to the inviscid one: det D(s)/s^... at small nu
    okI = True
    for (m, k, kappa) in [(2, 0.5, 0.3), (0, 1.6, 0.5), (1, 0.8, 0.2)]:
        lam2 = kappa * (m * m + k * k - 1) / inviscid_mass(m, k)
        s = mp.mpc(0.15, 0.9)
        errs = []
        for nu in (mp.mpf("1e-8"), mp.mpf("1e-10")):
            D = D_real(m, k, s, nu, kappa)
            # Schur complement onto X^r; compare with M (s^2 + lambda0^2)
            Dr = D[0, 0] - (D[0, 1:3] * mp.inverse(D[1:3, 1:3]) * D[1:3, 0])[0]
            errs.append(abs(Dr / inviscid_mass(m, k) - (s * s + lam2)) / abs(s * s + lam2))
        okI &= errs[1] < 1e-3 and errs[1] < errs[0]
    check("nu -> 0: the Schur complement of D(s) on X^r tends to M(m, k) (s^2 + lambda0^2) "
          "(O(sqrt(nu)) Stokes-layer corrections)", okI)


def main() -> int:
    part1()
    part2()
    part3()
    part4()
    part5()
    return summary()


if __name__ == "__main__":
    sys.exit(main())
