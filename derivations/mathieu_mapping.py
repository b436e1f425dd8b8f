"""Derive, with sympy, the facts the Mathieu model and the Hill assembler rely on.

1. The map of (2.2) u'' + kappa (1 + 2 tau sin t) u = 0 onto DLMF 28.2.1
   y'' + (a - 2 q cos 2x) y = 0: with t = 2x - pi/2, a = 4 kappa and q = 4 kappa tau.
2. The Fourier form (2.6) for D(d/dt) u + 2 tau sin(t) G u = 0: the coefficient of e^{(gamma+in)t}
   is D(s_n) u_n - i tau G (u_{n-1} - u_{n+1}), s_n = gamma + i n.
3. The real blocks of the reality-condition packing: for complex D = Dr + i Di acting on
   u = x + i y, real/imaginary parts of D u and of i G (u_{n-1} - u_{n+1}).

Run: python derivations/mathieu_mapping.py (exit status 0 when every identity holds).
"""

import sympy as sp


def check_mapping() -> None:
    x, kappa, tau = sp.symbols("x kappa tau", positive=True)
    y = sp.Function("y")
    t = 2 * x - sp.pi / 2
    # u(t) = y(x): d^2u/dt^2 = y''(x) / 4
    lhs = y(x).diff(x, 2) / 4 + kappa * (1 + 2 * tau * sp.sin(t)) * y(x)
    a, q = 4 * kappa, 4 * kappa * tau
    dlmf = y(x).diff(x, 2) + (a - 2 * q * sp.cos(2 * x)) * y(x)
    assert sp.simplify(4 * lhs - dlmf) == 0
    print("(2.2) -> DLMF 28.2.1 with t = 2x - pi/2: a = 4 kappa, q = 4 kappa tau   [ok]")


def check_fourier() -> None:
    t, tau, gamma, nu, kappa = sp.symbols("t tau gamma nu kappa")
    n = 3  # a generic interior index; the identity is the same for every n
    u = {k: sp.Symbol(f"u{k}") for k in range(n - 2, n + 3)}
    series = sum(u[k] * sp.exp((gamma + sp.I * k) * t) for k in u)
    ode = series.diff(t, 2) + nu * series.diff(t) + kappa * (1 + 2 * tau * sp.sin(t)) * series
    expanded = sp.expand(sp.expand(ode.rewrite(sp.exp)) * sp.exp(-(gamma + sp.I * n) * t))
    # keep the t-independent part: the coefficient of e^{(gamma + i n) t}
    coeff = sp.simplify(sum(term for term in expanded.as_ordered_terms() if not term.has(t)))
    s = gamma + sp.I * n
    expected = (s**2 + nu * s + kappa) * u[n] - sp.I * tau * kappa * (u[n - 1] - u[n + 1])
    assert sp.simplify(coeff - expected) == 0
    print("(2.9) Fourier coefficient: D(s_n) u_n = i tau G (u_{n-1} - u_{n+1}), D = s^2 + nu s + kappa, G = kappa   [ok]")


def check_real_blocks() -> None:
    dr, di, g, xr, xi, pr, pi_, mr, mi = sp.symbols("Dr Di G xr xi pr pi mr mi", real=True)
    Du = (dr + sp.I * di) * (xr + sp.I * xi)
    assert sp.expand(sp.re(Du) - (dr * xr - di * xi)) == 0
    assert sp.expand(sp.im(Du) - (di * xr + dr * xi)) == 0
    # i G (u_{n-1} - u_{n+1}) with u_{n-1} = pr + i pi, u_{n+1} = mr + i mi
    rhs = sp.I * g * ((pr + sp.I * pi_) - (mr + sp.I * mi))
    assert sp.expand(sp.re(rhs) - (-g * pi_ + g * mi)) == 0      # lower kron(J, G), upper -kron(J, G)
    assert sp.expand(sp.im(rhs) - (g * pr - g * mr)) == 0
    # harmonic n = 0: u_{-1} = conj(u_1): i G (conj u_1 - u_1) = 2 G Im u_1
    assert sp.expand(sp.I * g * ((mr - sp.I * mi) - (mr + sp.I * mi)) - 2 * g * mi) == 0
    # subharmonic n = 0: u_{-1} = conj(u_0): i G conj(u_0) = G Im u_0 + i G Re u_0
    assert sp.expand(sp.I * g * (xr - sp.I * xi) - (g * xi + sp.I * g * xr)) == 0
    print("real packing blocks [[Dr,-Di],[Di,Dr]], kron(J,G), n = 0 rows of (2.7)/(2.8)   [ok]")


if __name__ == "__main__":
    check_mapping()
    check_fourier()
    check_real_blocks()
