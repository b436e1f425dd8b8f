"""The stepper's fast paths (solvers/stepper.py) against a plain implementation of the schemes.

Oracles: the inverse of an implicit matrix at 40 digits (mpmath); and the scheme formulas of
solvers/imex.py stepped the straightforward way, written out here independently of the stepper:
a fresh list of past values, the right-hand side summed term by term, L v and F evaluated by
products, and every step solved by np.linalg.solve. The stepper (precomputed inverse or LU factor,
sliding history with combined weights, L v of a Runge-Kutta stage from its implicit equation,
in-place products) must give the same trajectory to the rounding bound of one implicit solve,
cond(A) eps relative to the largest entry, A being the scheme's worst-conditioned implicit matrix
(cond ~ 1e4 here: a few 1e-12). The two round differently (inverse or LU against a fresh
np.linalg.solve), by up to that bound per step; the stable schemes do not amplify what earlier
steps left, and the observed gap stays below one bound.
The observed orders of all schemes are tested in tests/test_imex.py.
"""

from types import SimpleNamespace

import mpmath as mp
import numpy as np
import pytest
import scipy.sparse as sparse

from spectralshell.discretise.sphere_stepping import degree_system
from spectralshell.solvers import stepper
from spectralshell.solvers.imex import SCHEMES, STARTER, Multistep
from spectralshell.solvers.stepper import integrate

EPS = np.finfo(float).eps


def _explicit(system, t, v):
    terms = getattr(system, "explicit_terms", None)
    if terms is None:
        terms = () if system.N is None else ((system.forcing, system.N),)
    return sum((f(t) * (N @ v) for f, N in terms), np.zeros_like(v))


def _dense(A):
    return A.toarray() if sparse.issparse(A) else np.asarray(A)


def plain_rk_step(system, name, h, t, v):
    """v_{n+1} of an IMEX Runge-Kutta scheme: stage i solves
    (M - h AI_ii L) v_i = M v_n + h sum_{j<i} (AI_ij L v_j + AE_ij F(t + c_j h, v_j))."""
    AE, AI, c = SCHEMES[name].arrays()
    M, L = _dense(system.M), _dense(system.L)
    stages = [v]
    for i in range(1, AE.shape[0]):
        rhs = M @ v + h * sum(AI[i, j] * (L @ stages[j])
                              + AE[i, j] * _explicit(system, t + c[j] * h, stages[j])
                              for j in range(i))
        stages.append(np.linalg.solve(M - h * AI[i, i] * L, rhs))
    return stages[-1]


def plain_run(system, name, v0, h, steps):
    """All states v_0..v_steps of the scheme (multistep: first s - 1 steps by STARTER)."""
    M, L = _dense(system.M), _dense(system.L)
    sch = SCHEMES[name]
    states = [np.asarray(v0)]
    for n in range(steps):
        t = n * h
        if not isinstance(sch, Multistep) or n < sch.steps - 1:
            states.append(plain_rk_step(system, name if not isinstance(sch, Multistep)
                                        else STARTER, h, t, states[-1]))
            continue
        a, b, c = sch.arrays()
        rhs = sum(-a[j] * (M @ states[-j]) + h * b[j] * (L @ states[-j])
                  + h * c[j] * _explicit(system, t + (1 - j) * h, states[-j])
                  for j in range(1, len(a)))
        states.append(np.linalg.solve(a[0] * M - h * b[0] * L, rhs))
    return np.array(states)


def implicit_matrices(system, name, h):
    """Every matrix the scheme solves with: a_0 M - h b_0 L, or M - h AI_ii L per stage."""
    M, L = _dense(system.M), _dense(system.L)
    sch = SCHEMES[name]
    if isinstance(sch, Multistep):
        a, b, _ = sch.arrays()
        return [a[0] * M - h * b[0] * L] + implicit_matrices(system, STARTER, h)
    AI = sch.arrays()[1]
    return [M - h * AI[i, i] * L for i in range(1, AI.shape[0])]


def assert_same_run(system, name, v0, h, steps):
    run = integrate(system, v0, scheme=name, dt=h, t_end=steps * h)
    want = plain_run(system, name, v0, h, steps)
    scale = np.max(np.abs(want))
    bound = max(np.linalg.cond(A) for A in implicit_matrices(system, name, h)) * EPS
    gap = np.max(np.abs(run.values - want)) / scale
    assert gap <= bound, (name, gap, bound)
    np.testing.assert_array_equal(run.final, run.values[-1])


@pytest.fixture(scope="module")
def sphere():
    """Sphere degree m = 2 (nu = 0.05, 16 + 16 radial nodes, size 31), forced at tau = 0.3."""
    return degree_system(m=2, kappa=1.0, nu=0.05, tau=0.3, n_radial=16)


@pytest.mark.parametrize("name", list(SCHEMES))
def test_every_scheme_matches_the_plain_implementation(sphere, name, monkeypatch):
    """Forced and unforced (N dropped); the multistep history wraps around every 5 steps."""
    monkeypatch.setattr(stepper, "HISTORY_ROWS", 5)
    y0 = sphere.initial_state([1.0, 0.3])
    assert_same_run(sphere, name, y0, 0.01, 80)
    unforced = SimpleNamespace(M=sphere.M, L=sphere.L, N=None, forcing=None)
    assert_same_run(unforced, name, y0, 0.01, 60)


@pytest.mark.parametrize("name", ["SBDF3", "CNAB2", "RK222"])
def test_solver_kinds_and_state_kinds(sphere, name, monkeypatch):
    """LU factor instead of the inverse (INVERSE_MAX = 0), sparse matrices (SuperLU) with two
    explicit terms, a singular M (the full radial DAE), columns and complex states: one
    trajectory each, equal to the plain one. A small HISTORY_BYTES makes the multistep history
    wrap around every 3 to 6 steps."""
    monkeypatch.setattr(stepper, "HISTORY_BYTES", 3 * 16 * sphere.size)
    y0 = sphere.initial_state([1.0, 0.3])
    columns = sphere.initial_state([[1.0, 0.0], [0.2, 1.0]])
    assert_same_run(sphere, name, columns, 0.02, 30)
    assert_same_run(sphere, name, y0 * (1 + 0.5j), 0.02, 30)
    two = SimpleNamespace(M=sparse.identity(sphere.size, format="csc"),
                          L=sparse.csc_matrix(sphere.L),
                          explicit_terms=((sphere.forcing, sparse.csr_matrix(sphere.N)),
                                          (np.cos, 0.1 * sphere.N)))
    assert_same_run(two, name, y0, 0.02, 30)
    ops = sphere.operators
    dae = SimpleNamespace(M=ops.M, L=ops.L_fluid + sphere.kappa * ops.L_stiffness, N=None,
                          forcing=None)
    assert_same_run(dae, name, sphere.full_state(y0, 0.0), 0.02, 30)
    monkeypatch.setattr(stepper, "INVERSE_MAX", 0)
    monkeypatch.setattr(stepper, "_CACHE", stepper._Factorisations(4))
    assert_same_run(sphere, name, y0, 0.02, 30)
    assert stepper._CACHE.store and all(s.lu is not None for s in stepper._CACHE.store.values())


def test_precomputed_inverse_is_accurate_to_working_precision(sphere):
    """The explicit inverse of an implicit matrix (a = 11/6, h = 0.01: SBDF3's) against mpmath at
    40 digits: every entry above 1e-8 of the largest within a few units of the last place (a
    plain getri inverse is off by up to 5e-12 relative in some entries)."""
    A = 11 / 6 * np.eye(sphere.size) - 0.01 * sphere.L
    X = stepper._Solver(A, 11 / 6, 0.01).inverse
    with mp.workdps(40):
        exact = np.array(mp.inverse(mp.matrix(A.tolist())).tolist(), dtype=float)
    big = np.abs(exact) > 1e-8 * np.abs(exact).max()
    assert np.max(np.abs(X - exact)[big] / np.abs(exact)[big]) < 1e-15
