"""IMEX schemes (solvers/imex.py): tableau consistency, order conditions, observed order.

Oracles: the order conditions of linear multistep methods and of additive (partitioned)
Runge-Kutta methods written out from their Taylor expansions (independent of the stepper), the
closed-form solution y = exp(lambda t + mu (1 - cos t)) of y' = (lambda + mu sin t) y, scipy's
Radau at rtol 1e-12 (stiff system), and the matrix exponential of the sphere's semi-discrete
system at tau = 0.
"""

from fractions import Fraction
from itertools import product
from types import SimpleNamespace

import numpy as np
import pytest
import scipy.linalg as sla
from scipy.integrate import solve_ivp

from spectralshell.discretise.sphere_stepping import degree_system
from spectralshell.errors import ParameterError
from spectralshell.solvers.imex import SCHEMES, STARTER, Multistep, RungeKutta, scheme
from spectralshell.solvers.stepper import integrate

MULTISTEP = [n for n, s in SCHEMES.items() if isinstance(s, Multistep)]
RUNGE_KUTTA = [n for n, s in SCHEMES.items() if isinstance(s, RungeKutta)]
REQUIRED = {"SBDF2", "SBDF3", "CNAB2", "RK222", "RK443"}


def test_registry_holds_the_required_schemes():
    assert REQUIRED <= set(SCHEMES)
    assert scheme("sbdf3") is SCHEMES["SBDF3"] and scheme("RK443").order == 3
    with pytest.raises(ParameterError, match="scheme"):
        scheme("euler")
    assert isinstance(SCHEMES[STARTER], RungeKutta) and SCHEMES[STARTER].order >= 3


# ----------------------------------------------------------------------------- multistep
def lmm_conditions(alpha, beta, q):
    """Residual of the q-th order condition of sum_j alpha_j v(t - j h) = h sum_j beta_j v'(t - j h),
    exact in Fractions: sum_j alpha_j (-j)^q - q sum_j beta_j (-j)^(q-1)."""
    lhs = sum(Fraction(a) * Fraction(-j) ** q for j, a in enumerate(alpha))
    rhs = q * sum(Fraction(b) * Fraction(-j) ** (q - 1) for j, b in enumerate(beta)) if q else 0
    return lhs - rhs


@pytest.mark.parametrize("name", MULTISTEP)
def test_multistep_order_conditions(name):
    """Both the implicit method (a, b) and the explicit one (a, c) satisfy the conditions up to
    the stated order, exactly; one of them fails the next order (the order is not understated);
    c_0 = 0 (F is explicit); the arrays have equal length; a_0 > 0."""
    s = SCHEMES[name]
    assert len(s.a) == len(s.b) == len(s.c) and s.c[0] == 0 and s.a[0] > 0
    for q in range(s.order + 1):
        assert lmm_conditions(s.a, s.b, q) == 0, (name, "implicit", q)
        assert lmm_conditions(s.a, s.c, q) == 0, (name, "explicit", q)
    nxt = s.order + 1
    assert lmm_conditions(s.a, s.b, nxt) != 0 or lmm_conditions(s.a, s.c, nxt) != 0


@pytest.mark.parametrize("name", [n for n in MULTISTEP if SCHEMES[n].b[1:] == (0,) * (len(SCHEMES[n].b) - 1)])
def test_sbdf_implicit_part_is_backward_differentiation(name):
    """SBDF: b = (1, 0, ...), so a must be the BDF coefficients: the root condition holds (zero
    stability: the roots of sum a_j z^(s-j) lie in |z| <= 1, only z = 1 on the circle)."""
    a = [float(x) for x in SCHEMES[name].a]
    roots = np.roots(a)
    assert np.sum(np.isclose(roots, 1.0)) == 1
    assert np.all(np.abs(roots[~np.isclose(roots, 1.0)]) < 1)


# ----------------------------------------------------------------------------- Runge-Kutta
def rk_conditions(AE, AI, order):
    """Residuals of the additive Runge-Kutta order conditions up to ``order`` (<= 3) for
    v_{n+1} = last stage: weights b = last rows, nodes c = row sums, every colouring of the
    trees of order <= 3 (sum b = 1; b.c = 1/2; b.(c c) = 1/3; b.(A c) = 1/6)."""
    tabs = {"E": np.asarray(AE, dtype=object), "I": np.asarray(AI, dtype=object)}
    b = {k: T[-1] for k, T in tabs.items()}
    c = {k: T.sum(axis=1) for k, T in tabs.items()}
    out = []
    for x in "EI":
        out.append(("sum b", x, sum(b[x]) - 1))
    if order >= 2:
        for x, y in product("EI", repeat=2):
            out.append(("b.c", x + y, b[x].dot(c[y]) - Fraction(1, 2)))
    if order >= 3:
        for x, y, z in product("EI", repeat=3):
            out.append(("b.(cc)", x + y + z, b[x].dot(c[y] * c[z]) - Fraction(1, 3)))
            out.append(("b.(Ac)", x + y + z, b[x].dot(tabs[y].dot(c[z])) - Fraction(1, 6)))
    return out


def exact(x):
    return x if isinstance(x, Fraction) or isinstance(x, int) else Fraction(x)


@pytest.mark.parametrize("name", RUNGE_KUTTA)
def test_runge_kutta_tableau_structure_and_order(name):
    """Explicit tableau strictly lower triangular, implicit lower triangular with row 0 zero and
    a non-zero diagonal after it (every stage implicit), equal nodes c_E = c_I, and all additive
    order conditions up to the stated order (to 1e-14: RK222 has irrational entries)."""
    s = SCHEMES[name]
    AE = np.array([[exact(x) for x in row] for row in s.explicit], dtype=object)
    AI = np.array([[exact(x) for x in row] for row in s.implicit], dtype=object)
    n = AE.shape[0]
    assert AE.shape == AI.shape == (n, n)
    assert all(AE[i, j] == 0 for i in range(n) for j in range(i, n))
    assert all(AI[i, j] == 0 for i in range(n) for j in range(i + 1, n))
    assert all(AI[0, j] == 0 for j in range(n)) and all(AI[i, i] != 0 for i in range(1, n))
    assert all(abs(float(a - b)) < 1e-15 for a, b in zip(AE.sum(axis=1), AI.sum(axis=1)))
    for label, colours, residual in rk_conditions(AE, AI, s.order):
        assert abs(float(residual)) < 1e-14, (name, label, colours, float(residual))


# ----------------------------------------------------------------------------- observed order
def observed_orders(system, v0, reference, names, dts, t_end, pick=lambda v: v):
    out = {}
    for name in names:
        errors = [np.max(np.abs(pick(integrate(system, v0, scheme=name, dt=dt, t_end=t_end).final)
                                - pick(reference))) for dt in dts]
        out[name] = (np.log2(np.array(errors[:-1]) / np.array(errors[1:])), errors)
    return out


def test_observed_order_scalar_closed_form():
    """y' = (lambda + mu sin t) y, lambda = -1, mu = 0.8 (implicit lambda, explicit mu sin t):
    y(3) = exp(3 lambda + mu (1 - cos 3)). Halving the step divides the error by 2^p."""
    lam, mu, T = -1.0, 0.8, 3.0
    system = SimpleNamespace(M=np.eye(1), L=np.array([[lam]]), N=np.array([[mu]]), forcing=np.sin)
    ref = np.array([np.exp(lam * T + mu * (1 - np.cos(T)))])
    dts = {1: (0.002, 0.001), 2: (0.02, 0.01), 3: (0.04, 0.02), 4: (0.02, 0.01)}
    for name, s in SCHEMES.items():
        (rate,), errors = observed_orders(system, np.ones(1), ref, [name], dts[s.order], T)[name]
        assert abs(rate - s.order) < 0.15, (name, rate, errors)


def test_observed_order_stiff_system():
    """A stiff 3x3 system (implicit eigenvalues -1 +- 2i and -1e4, the stiff mode driven by the
    explicit term 0.5 sin t N): no order reduction on a linear problem. Reference: scipy's Radau
    at rtol 1e-12."""
    L = np.array([[-1.0, 2.0, 0.0], [-2.0, -1.0, 0.0], [1e4, 0.0, -1e4]])
    N = np.array([[0.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    system = SimpleNamespace(M=np.eye(3), L=L, N=N, forcing=lambda t: 0.5 * np.sin(t))
    T = 2.0
    v0 = np.array([1.0, 0.0, 1.0])
    ref = solve_ivp(lambda t, y: (L + 0.5 * np.sin(t) * N) @ y, (0, T), v0, method="Radau",
                    jac=lambda t, y: L + 0.5 * np.sin(t) * N, rtol=1e-12, atol=1e-15).y[:, -1]
    dts = {1: (0.002, 0.001), 2: (0.01, 0.005), 3: (0.04, 0.02), 4: (0.04, 0.02)}
    for name, s in SCHEMES.items():
        (rate,), errors = observed_orders(system, v0, ref, [name], dts[s.order], T)[name]
        assert abs(rate - s.order) < 0.25, (name, rate, errors)


def test_observed_order_on_the_sphere():
    """The sphere's semi-discrete system (m = 2, kappa = 1, nu = 0.05, 16 + 16 radial nodes) at
    tau = 0: exact solution expm(L T) y0; the membrane displacement at T = 2 converges at each
    scheme's order, stiff fluid modes (|s| up to ~1e4) notwithstanding."""
    sys0 = degree_system(m=2, kappa=1.0, nu=0.05, n_radial=16)
    y0 = sys0.initial_state([1.0, 0.0])
    T = 2.0
    ref = sla.expm(sys0.L * T) @ y0
    dts = {1: (0.002, 0.001), 2: (0.02, 0.01), 3: (0.04, 0.02), 4: (0.04, 0.02)}
    for name, s in SCHEMES.items():
        (rate,), errors = observed_orders(sys0, y0, ref, [name], dts[s.order], T,
                                          pick=sys0.displacement)[name]
        assert abs(rate - s.order) < 0.3, (name, rate, errors)
