"""Radial Chebyshev operators of the sphere (discretise/sphere_radial.py) and the eigen-solver.

Oracle: the exact dispersion relations of derivations/sphere_linear_result.md, det D(s) = 0
(poloidal, thesis (7.14)) and D_Phi(s) = 0 (toroidal), evaluated in mpmath at 30 digits with
mpmath's own besseli/besselk of half-integer order (``mp_det_poloidal``, ``mp_toroidal``) and
solved with mpmath's secant method from a rough seed. None of this shares code with the
discretisation; the agreement is a second-method check of both.

Resolutions below are the measured minimum for 1e-8 (validation/bench_modes_chebyshev_resolution.py)
plus 8 nodes; the coarse pencil of each two-resolution check is that minimum.
"""

import subprocess
import sys
from functools import lru_cache
from pathlib import Path

import mpmath as mp
import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sparse

from spectralshell.discretise.sphere_radial import exterior_scale_hint, radial_operators
from spectralshell.errors import ConvergenceError, ParameterError
from spectralshell.solvers.eigen import (converged_modes, finite_eigenvalues, least_damped)

ANGLE = -np.pi / 3          # complex scaling used for the eigenvalue checks
TOL = 1e-8                  # required relative agreement with the dispersion relation
ZETAS = (1e-3, 1e-2, 1e-1, 1.0)


# ----------------------------------------------------------------------------- oracles
def _mp_pq(s, m, nu):
    mp.mp.dps = 30
    s = mp.mpc(s)
    beta = mp.sqrt(s / nu)
    P = beta * mp.besseli(m + 1.5, beta) / mp.besseli(m + 0.5, beta)
    Q = beta * mp.besselk(m - 0.5, beta) / mp.besselk(m + 0.5, beta)
    return s, P, Q


def mp_det_poloidal(s, m, nu, kappa=1.0):
    """det D(s) of the result file, 30 digits (D_PsiY = D_YPsi / (m(m+1)))."""
    s, P, Q = _mp_pq(s, m, nu)
    q = kappa * (m - 1) * (m + 2)
    yy = s**2 * (mp.mpf(2 * m + 1) / (m * (m + 1)) + m / ((m + 1) * Q) + (m + 1) / (m * P)) + q
    yp = s**2 * (m / Q - (m + 1) / P)
    pp = s**2 * (1 / Q + 1 / P) + q
    return yy * pp - yp**2 / (m * (m + 1))


def mp_toroidal(s, m, nu, kappa=1.0):
    """D_Phi(s) = nu s (2m + 1 + P + Q) + q of the result file, 30 digits."""
    s, P, Q = _mp_pq(s, m, nu)
    return nu * s * (2 * m + 1 + P + Q) + kappa * (m - 1) * (m + 2)


# rough locations (3 digits) of the roots; the roots themselves are computed by mpmath
SEEDS_OSC = {(2, 1e-3): -0.045 + 2.148j, (2, 1e-2): -0.156 + 2.056j, (2, 1e-1): -0.663 + 1.814j,
             (2, 1.0): -0.935 + 0.222j, (3, 1e-3): -0.085 + 4.059j, (3, 1e-2): -0.292 + 3.884j,
             (3, 1e-1): -1.19 + 3.355j, (3, 1.0): -1.325 + 0.0502j, (4, 1e-3): -0.134 + 6.196j,
             (4, 1e-2): -0.460 + 5.920j, (4, 1e-1): -1.858 + 5.032j, (4, 1.0): -1.545 + 0.00383j}
SEEDS_OVERDAMPED = {2: -0.2309 + 1e-7j, 3: -0.4822 + 1e-7j, 4: -0.7365 + 1e-8j}   # zeta = 1
SEEDS_TOR = {(2, 1e-3): -7.939 + 13.747j, (2, 1e-2): -3.704 + 6.381j, (2, 1e-1): -1.900 + 2.963j,
             (2, 1.0): -0.8816 + 0.01276j, (3, 1e-3): -14.62 + 25.32j,
             (3, 1e-2): -6.826 + 11.754j, (3, 1e-1): -3.556 + 5.441j, (3, 1.0): -1.544 + 0.00382j,
             (4, 1e-3): -21.64 + 37.47j, (4, 1e-2): -10.108 + 17.392j,
             (4, 1e-1): -5.347 + 8.041j, (4, 1.0): -2.1233 + 0.000526j}


@lru_cache(maxsize=None)
def mp_root(kind, m, nu, seed):
    """Root of det D (kind 'poloidal') or D_Phi ('toroidal') near ``seed``, to ~25 digits."""
    f = (lambda s: mp_det_poloidal(s, m, nu)) if kind == "poloidal" else \
        (lambda s: mp_toroidal(s, m, nu))
    x0 = mp.mpc(seed)
    root = mp.findroot(f, (x0, x0 * (1 + mp.mpf("1e-6"))), solver="secant",
                       tol=mp.mpf(10) ** -50, maxsteps=100, verify=False)
    assert abs(f(root)) < 1e-20 * abs(f(x0)), "oracle root did not converge"
    assert abs(root - x0) < 0.01 * abs(x0), "oracle root far from its seed"
    return complex(root)


# ----------------------------------------------------------------------------- helpers
def pencil(m, nu, n, *, component="poloidal", angle=ANGLE, s_scale):
    ops = radial_operators(m=m, nu=nu, component=component, n_inner=n[0], n_outer=n[1],
                           exterior_angle=angle,
                           exterior_scale=exterior_scale_hint(nu=nu, s_scale=s_scale))
    return ops.pencil(1.0)


def rel_error(values, exact):
    return np.min(np.abs(np.asarray(values) - exact)) / abs(exact)


# (fine, coarse) resolutions (n_inner, n_outer) by zeta, complex-scaled exterior
RES_POL = {1e-3: ((36, 36), (28, 28)), 1e-2: ((24, 36), (16, 28)), 1e-1: ((20, 32), (12, 24)),
           1.0: ((16, 52), (10, 44))}
RES_TOR = {1e-3: ((68, 48), (60, 40)), 1e-2: ((36, 32), (28, 24)), 1e-1: ((20, 32), (12, 24)),
           1.0: ((16, 52), (10, 44))}
# real operators (exterior_angle = 0, the time-stepper setting), zeta <= 0.1
RES_REAL = {1e-3: ((36, 44), (28, 36)), 1e-2: ((24, 52), (16, 44)), 1e-1: ((20, 72), (12, 64))}


# ----------------------------------------------------------------------------- agreement
@pytest.mark.parametrize("zeta", ZETAS)
@pytest.mark.parametrize("m", [2, 3, 4])
def test_poloidal_oscillatory_mode_matches_dispersion_relation(m, zeta):
    """The oscillatory natural mode (kappa = 1, nu = zeta) agrees with the root of det D to 1e-8,
    passes the two-resolution check, and is the least-damped oscillatory converged mode: all
    converged modes with larger Re s are non-oscillatory (interior viscous modes near
    -nu j_{m+1,k}^2 at small zeta, overdamped modes 1e-7 above the branch cut at zeta = 1)."""
    exact = mp_root("poloidal", m, zeta, SEEDS_OSC[m, zeta])
    fine, coarse = RES_POL[zeta]
    modes = converged_modes(pencil(m, zeta, fine, s_scale=abs(exact)),
                            pencil(m, zeta, coarse, s_scale=abs(exact)))
    k = np.argmin(np.abs(modes.values - exact))
    assert abs(modes.values[k] - exact) <= TOL * abs(exact)
    assert modes.error_estimate[k] <= 1e-6 * abs(exact)
    assert np.all(np.abs(modes.values[:k].imag) <= 1e-5 * np.abs(modes.values[:k]))


@pytest.mark.parametrize("m", [2, 3, 4])
def test_overdamped_mode_next_to_branch_cut(m):
    """zeta = 1: the slow overdamped root of det D lies 1e-7 above the negative real axis (the
    branch cut of beta); the complex-scaled exterior resolves it, and it is the least-damped
    mode."""
    exact = mp_root("poloidal", m, 1.0, SEEDS_OVERDAMPED[m])
    fine, coarse = RES_POL[1.0]
    modes = least_damped(pencil(m, 1.0, fine, s_scale=abs(exact)),
                         pencil(m, 1.0, coarse, s_scale=abs(exact)), count=1)
    assert abs(modes.values[0] - exact) <= TOL * abs(exact)


@pytest.mark.parametrize("zeta", [1e-3, 1e-2, 1e-1])
@pytest.mark.parametrize("m", [2, 3, 4])
def test_real_operators_match_dispersion_relation(m, zeta):
    """The real matrices (exterior_angle = 0, used for time stepping) reach 1e-8 too for
    zeta <= 0.1, where the mode's vortical tail decays (Re beta >= 2.5)."""
    exact = mp_root("poloidal", m, zeta, SEEDS_OSC[m, zeta])
    fine, coarse = RES_REAL[zeta]
    L, M = pencil(m, zeta, fine, angle=0.0, s_scale=abs(exact))
    assert np.isrealobj(L) and np.isrealobj(M)
    modes = converged_modes((L, M), pencil(m, zeta, coarse, angle=0.0, s_scale=abs(exact)))
    assert rel_error(modes.values, exact) <= TOL


@pytest.mark.parametrize("zeta", ZETAS)
@pytest.mark.parametrize("m", [2, 3, 4])
def test_toroidal_mode_matches_D_phi(m, zeta):
    """The toroidal mode agrees with the root of D_Phi(s) = 0 to 1e-8 and is the least-damped
    converged non-real toroidal mode."""
    exact = mp_root("toroidal", m, zeta, SEEDS_TOR[m, zeta])
    fine, coarse = RES_TOR[zeta]
    modes = converged_modes(pencil(m, zeta, fine, component="toroidal", s_scale=abs(exact)),
                            pencil(m, zeta, coarse, component="toroidal", s_scale=abs(exact)))
    k = np.argmin(np.abs(modes.values - exact))
    assert abs(modes.values[k] - exact) <= TOL * abs(exact)
    assert np.all(np.abs(modes.values[:k].imag) <= 1e-5 * np.abs(modes.values[:k]))


# ----------------------------------------------------------------------------- convergence
def test_error_falls_under_refinement():
    """m = 2, zeta = 0.01, complex-scaled exterior: the error falls by more than 3x per 4 extra
    nodes until it reaches ~1e-10 (spectral convergence), for both the poloidal and toroidal
    modes."""
    for kind, seed in (("poloidal", SEEDS_OSC[2, 1e-2]), ("toroidal", SEEDS_TOR[2, 1e-2])):
        exact = mp_root(kind, 2, 1e-2, seed)
        errors = [rel_error(finite_eigenvalues(*pencil(2, 1e-2, (n, n + 4), component=kind,
                                                        s_scale=abs(exact))), exact)
                  for n in (6, 10, 14, 18)]
        for a, b in zip(errors, errors[1:]):
            assert b < a / 3 or b < 1e-10, errors
        assert errors[-1] < 1e-7


def test_exterior_error_of_real_map():
    """Exterior error, real map xi = 1/r (exterior_scale 1, angle 0): with the inner grid fixed
    and converged, the error of the m = 3, zeta = 0.1 mode (|beta| = 6, Re beta = 3.4) falls
    with n_outer faster than any power but slower than geometrically: measured 7e-4, 1e-5,
    4e-7, 2e-8, 1e-9 at n_outer = 16, 32, 48, 64, 80, a gain per 16 nodes of 60, 30, 21, 16.
    The cause is the tail exp(-beta (r - 1)) = exp(-beta (1/xi - 1)), flat but not analytic at
    xi = 0. (With exterior_scale_hint, L = 1.34, 24 outer nodes reach 1e-8.)"""
    exact = mp_root("poloidal", 3, 0.1, SEEDS_OSC[3, 0.1])
    errors = []
    for n_outer in (16, 32, 48, 64, 80):
        ops = radial_operators(m=3, nu=0.1, n_inner=24, n_outer=n_outer)
        errors.append(rel_error(finite_eigenvalues(*ops.pencil(1.0)), exact))
    gains = [a / b for a, b in zip(errors, errors[1:])]
    assert errors[0] > 1e-4 and errors[-1] < 1e-8, errors
    assert all(g > 10 for g in gains), errors
    assert gains[-1] < gains[0] / 2, errors                 # sub-geometric


def test_real_map_fails_honestly_near_the_cut():
    """zeta = 1 with the real exterior map: the oscillatory mode -0.935 + 0.222i sits where
    Re beta = 0.11, its tail barely decays and the discretised continuous spectrum crowds the
    negative real axis. The two-resolution check must then not report it (no converged value
    within 1e-3 of it), while the complex-scaled exterior does (test above)."""
    exact = mp_root("poloidal", 2, 1.0, SEEDS_OSC[2, 1.0])
    fine = pencil(2, 1.0, (16, 60), angle=0.0, s_scale=abs(exact))
    coarse = pencil(2, 1.0, (12, 48), angle=0.0, s_scale=abs(exact))
    values = finite_eigenvalues(*fine)
    assert rel_error(values, exact) > 1e-6           # not resolved ...
    modes = converged_modes(fine, coarse)
    assert modes.values.size == 0 or rel_error(modes.values, exact) > 1e-3   # ... nor claimed
    assert modes.skipped > 10                         # the continuum cloud is rejected


# ----------------------------------------------------------------------------- fields
def _sph_i(n, z):
    return mp.sqrt(mp.pi / (2 * z)) * mp.besseli(n + mp.mpf(1) / 2, z)


def _sph_k(n, z):
    return mp.sqrt(mp.pi / (2 * z)) * mp.besselk(n + mp.mpf(1) / 2, z)


def exact_poloidal_fields(m, nu, s, X, r, inside):
    """(u^Y, u^Psi, p) of the result file, section 2: p = a r^m or b r^-(m+1),
    u^Y = -p'/s + A m(m+1) f/r, u^Psi = -p/(r s) + A (f/r + f'), f = i_m or k_m (beta r),
    amplitudes fixed by u(1) = s X; z f'(z) = m f(z) +- z f_{m+1}(z)."""
    mp.mp.dps = 30
    s, c = mp.mpc(s), m * (m + 1)
    beta = mp.sqrt(s / nu)
    if inside:
        f = lambda t: _sph_i(m, beta * t)                                      # noqa: E731
        df = lambda t: (m * _sph_i(m, beta * t) / t + beta * _sph_i(m + 1, beta * t))  # noqa
        pw, dpw = (lambda t: t**m), (lambda t: m * t ** (m - 1))
    else:
        f = lambda t: _sph_k(m, beta * t)                                      # noqa: E731
        df = lambda t: (m * _sph_k(m, beta * t) / t - beta * _sph_k(m + 1, beta * t))  # noqa
        pw, dpw = (lambda t: t ** (-m - 1)), (lambda t: -(m + 1) * t ** (-m - 2))
    amp = mp.lu_solve(mp.matrix([[-dpw(1) / s, c * f(1)], [-pw(1) / s, f(1) + df(1)]]),
                      mp.matrix([s * X[0], s * X[1]]))
    a, A = amp[0], amp[1]
    out = []
    for t in r:
        t = mp.mpf(t)
        out.append([complex(-a * dpw(t) / s + A * c * f(t) / t),
                    complex(-a * pw(t) / (t * s) + A * (f(t) / t + df(t))),
                    complex(a * pw(t))])
    return np.array(out).T


def test_poloidal_fields_match_exact_solution():
    """Velocity and pressure recovered from the eigenvector (real operators, m = 3, zeta = 0.01)
    equal the exact fields built from its own X, inside and outside (r = 1/xi), to 1e-7 of
    their maximum; the discrete residual |(L - s M) v| is at rounding level."""
    m, nu = 3, 1e-2
    exact = mp_root("poloidal", m, nu, SEEDS_OSC[m, nu])
    ops = radial_operators(m=m, nu=nu, n_inner=24, n_outer=52)
    L, M = ops.pencil(1.0)
    values, V = finite_eigenvalues(L, M, vectors=True)
    k = np.argmin(np.abs(values - exact))
    s, v = values[k], V[:, k]
    assert np.linalg.norm(L @ v - s * M @ v) < 1e-9 * np.linalg.norm(L, 1)
    X = ops.displacement(v)
    u_in, u_out = ops.velocity(v)
    p_in, p_out = ops.pressure(v, s * v)
    want_in = exact_poloidal_fields(m, nu, s, X, ops.r_inner, True)
    live = ops.xi_outer > 0
    want_out = exact_poloidal_fields(m, nu, s, X, 1 / ops.xi_outer[live], False)
    got_in = np.vstack([u_in, p_in])
    got_out = np.vstack([u_out, p_out])[:, live]
    for got, want in ((got_in, want_in), (got_out, want_out)):
        for row in range(3):
            scale = np.max(np.abs(want[row]))
            assert np.max(np.abs(got[row] - want[row])) < 1e-7 * scale, row
    np.testing.assert_allclose(np.vstack([u_out, p_out])[:, ~live], 0, atol=1e-12)


def test_toroidal_field_matches_exact_solution():
    """u^Phi of the toroidal eigenvector equals X^Phi s i_m(beta r)/i_m(beta) inside and
    X^Phi s k_m(beta r)/k_m(beta) outside (result file section 2), to 1e-7."""
    m, nu = 2, 0.1
    exact = mp_root("toroidal", m, nu, SEEDS_TOR[m, nu])
    ops = radial_operators(m=m, nu=nu, component="toroidal", n_inner=20, n_outer=64)
    values, V = finite_eigenvalues(*ops.pencil(1.0), vectors=True)
    k = np.argmin(np.abs(values - exact))
    s, v = values[k], V[:, k]
    (X,) = ops.displacement(v)
    u_in, u_out = ops.velocity(v)
    beta = mp.sqrt(mp.mpc(s) / nu)
    want_in = [complex(s * X * _sph_i(m, beta * t) / _sph_i(m, beta)) for t in ops.r_inner]
    live = ops.xi_outer > 0
    want_out = [complex(s * X * _sph_k(m, beta / t) / _sph_k(m, beta)) for t in ops.xi_outer[live]]
    scale = abs(s * X)
    assert np.max(np.abs(u_in[0] - want_in)) < 1e-7 * scale
    assert np.max(np.abs(u_out[0][live] - want_out)) < 1e-7 * scale
    assert np.all(ops.pressure(v, s * v)[0] == 0)


# ----------------------------------------------------------------------------- structure
@pytest.mark.parametrize("component", ["poloidal", "toroidal"])
def test_operator_structure_for_time_stepping(component):
    """Real matrices at angle 0; the blocks tile v; M vanishes exactly on the algebraic rows;
    L_stiffness is -(m-1)(m+2) in the stress rows against the membrane unknowns and 0 elsewhere;
    the kinematic rows are s X = u(1)."""
    m = 3
    ops = radial_operators(m=m, nu=0.05, component=component, n_inner=10, n_outer=14)
    assert np.isrealobj(ops.M) and np.isrealobj(ops.L_fluid)
    covered = np.concatenate([np.arange(ops.size)[sl] for sl in ops.blocks.values()])
    assert np.array_equal(np.sort(covered), np.arange(ops.size))
    assert not ops.M[ops.constraint_rows].any()
    assert np.all(ops.M[np.setdiff1d(np.arange(ops.size), ops.constraint_rows)].any(axis=1))
    mem = ops.blocks["membrane"]
    rows, cols = np.nonzero(ops.L_stiffness)
    assert set(cols) <= set(range(ops.size)[mem]) and set(rows) <= set(ops.constraint_rows)
    np.testing.assert_array_equal(ops.L_stiffness[rows, cols], -(m - 1) * (m + 2))
    assert len(rows) == len(ops.membrane_names)
    np.testing.assert_array_equal(ops.M[mem, mem], np.eye(len(ops.membrane_names)))
    L, M = ops.pencil(2.5)
    np.testing.assert_array_equal(L, ops.L_fluid + 2.5 * ops.L_stiffness)
    assert ops.r_inner[0] == 1.0 and ops.xi_outer[0] == 1.0 and ops.xi_outer[-1] == 0.0


@pytest.mark.parametrize("component", ["poloidal", "toroidal"])
@pytest.mark.parametrize("m,zeta,n", [(2, 1e-4, (8, 8)), (3, 1e-2, (16, 24)), (4, 1.0, (24, 32)),
                                      (10, 10.0, (12, 40))])
def test_real_operators_have_no_growing_modes(component, m, zeta, n):
    """Time-stepper safety: at tau = 0 every finite eigenvalue of the real operators has
    Re s < 0, at coarse and fine resolution, small and large zeta (the physical problem is
    dissipative; a spurious Re s >= 0 would blow up a time stepper). The discretised continuous
    spectrum approaches s = 0 from the left."""
    ops = radial_operators(m=m, nu=zeta, component=component, n_inner=n[0], n_outer=n[1])
    assert finite_eigenvalues(*ops.pencil(1.0)).real.max() < 0


@pytest.mark.parametrize("kwargs,name", [
    (dict(m=1), "m"), (dict(nu=0.0), "nu"), (dict(nu=float("nan")), "nu"),
    (dict(n_inner=3), "n_inner"), (dict(n_outer=5), "n_outer"),
    (dict(component="radial"), "component"), (dict(exterior_angle=0.3), "exterior_angle"),
    (dict(exterior_angle=-np.pi / 2), "exterior_angle"),
    (dict(exterior_scale=0.0), "exterior_scale")])
def test_bad_arguments_name_the_parameter(kwargs, name):
    args = dict(m=2, nu=0.1, n_inner=8, n_outer=10) | kwargs
    with pytest.raises(ParameterError, match=name):
        radial_operators(**args)


# ----------------------------------------------------------------------------- eigen solver
def _pencil_with(values, n_infinite, seed=0):
    """Random equivalence transform of diag(values, 1...) and diag(1..., 0...): known finite
    spectrum ``values`` and ``n_infinite`` infinite eigenvalues."""
    rng = np.random.default_rng(seed)
    n = len(values) + n_infinite
    A = np.diag(np.concatenate([values, np.ones(n_infinite)]))
    B = np.diag(np.concatenate([np.ones(len(values)), np.zeros(n_infinite)]))
    P, Q = rng.normal(size=(n, n)), rng.normal(size=(n, n))
    return P @ A @ Q, P @ B @ Q


def test_order_of_a_conjugate_pair_does_not_depend_on_rounding():
    """Real parts equal to rounding (a conjugate pair from QZ): Im s > 0 first, either way."""
    for eps in (3e-15, -3e-15, 0.0):
        got = finite_eigenvalues(np.diag([-1 - 2j, -1 + eps + 2j, -0.5, -1.001 + 5j]),
                                 np.eye(4))
        np.testing.assert_allclose(got, [-0.5, -1 + eps + 2j, -1 - 2j, -1.001 + 5j], rtol=1e-14)
    assert finite_eigenvalues(np.diag([1.0, 0.0]), np.diag([0.0, 1.0])).size == 1


def test_finite_eigenvalues_drop_infinite_and_sort():
    vals = np.array([-1 + 2j, -1 - 2j, -0.5, -3.0, 0.25])
    L, M = _pencil_with(vals, 4)
    got, V = finite_eigenvalues(L, M, vectors=True)
    want = vals[np.lexsort((-vals.imag, -vals.real))]
    np.testing.assert_allclose(got, want, atol=1e-10)
    for s, v in zip(got, V.T):
        assert np.linalg.norm(L @ v - s * M @ v) < 1e-10 * np.linalg.norm(L)
    np.testing.assert_allclose(finite_eigenvalues(sparse.csr_matrix(L), sparse.csr_matrix(M)),
                               want, atol=1e-10)


def test_finite_eigenvalues_match_dense_qz():
    """Fast path (balanced) against plain scipy.linalg.eigvals on a regular random pencil."""
    rng = np.random.default_rng(3)
    L, M = rng.normal(size=(30, 30)), rng.normal(size=(30, 30))
    ref = sla.eigvals(L, M)
    got = finite_eigenvalues(L, M)
    assert got.size == ref.size and np.all(np.diff(got.real) <= 1e-12)
    assert np.max(np.min(np.abs(got[:, None] - ref[None, :]), axis=1)) < 1e-9 * np.abs(ref).max()


def test_least_damped_rejects_unconverged_eigenvalues():
    """Genuine eigenvalues reappear (to 1e-10) at the other resolution, junk ones (a mock
    discretised continuum near 0) do not; only Im >= 0 is reported, one per conjugate pair."""
    genuine = [-1 + 2j, -1 - 2j, -0.5, -3.0]
    fine = _pencil_with(genuine + [-0.01, -0.02, -0.03 + 0.001j, -0.03 - 0.001j], 3, seed=1)
    coarse = _pencil_with([g * (1 + 1e-10) for g in genuine] + [-0.015, -0.04], 2, seed=2)
    modes = least_damped(fine, coarse, count=3)
    np.testing.assert_allclose(modes.values, [-0.5, -1 + 2j, -3.0], atol=1e-8)
    assert modes.skipped == 3 and np.all(modes.error_estimate < 1e-8)
    with pytest.raises(ConvergenceError, match="count = 4"):
        least_damped(fine, coarse, count=4)
    assert converged_modes(fine, coarse).values.size == 3


def test_eigen_solver_input_errors():
    with pytest.raises(ParameterError):
        finite_eigenvalues(np.eye(3), np.eye(4))
    with pytest.raises(ParameterError):
        finite_eigenvalues(np.full((2, 2), np.nan), np.eye(2))
    with pytest.raises(ParameterError, match="count"):
        least_damped((np.eye(2), np.eye(2)), (np.eye(2), np.eye(2)), count=0)
    with pytest.raises(ParameterError, match="zero"):
        finite_eigenvalues(np.diag([1.0, 0.0]), np.diag([1.0, 0.0]))
    singular = np.ones((2, 2))                  # det(L - s M) = 0 for every s
    with pytest.raises(ConvergenceError, match="singular"):
        finite_eigenvalues(singular, singular)


# ----------------------------------------------------------------------------- derivation
@pytest.mark.slow
def test_derivation_script_passes():
    """derivations/sphere_radial.py: every row and operator re-derived symbolically (~10 s)."""
    script = Path(__file__).resolve().parents[1] / "derivations" / "sphere_radial.py"
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0, done.stdout + done.stderr
