"""Natural modes of the spherical membrane (thesis 7.1-7.2): dispersion-relation roots in beta.

Oracles: det D(gamma) of derivations/sphere_linear_result.md evaluated in mpmath at 30 digits with
mpmath's own I and K of half-integer order (:func:`mp_det`); the Lamb/Rayleigh frequency (7.4)
with its Stokes-layer correction; the steady-Stokes relaxations -q/(nu mu_i); an independent
argument-principle count with the vectorised D(s) of models/sphere.py (special/spherical.py
kernels); a toy model with a closed-form spectrum for the model-agnostic solver.
"""

from __future__ import annotations

import cmath
import json
import math

import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import spectralshell as ss
from spectralshell.errors import ConvergenceError, ParameterError
from spectralshell.models.base import ModalSystem
from spectralshell.models.sphere import lambda0_squared, poloidal_unforced, toroidal_unforced
from spectralshell.models.sphere_modes import (_p_q, inviscid_limit, modal_system,
                                               poloidal_residual, poloidal_residual_mp,
                                               psi_relaxation_limit, stokes_limit, stokes_matrix,
                                               toroidal_limits, toroidal_residual_mp)
from spectralshell.results.modes import NaturalModesResult
from spectralshell.solvers.modes import find_modes
from spectralshell.special.spherical_scalar import ratio_i_scalar


def mp_d(gamma, m, kappa, nu):
    """D(gamma) (poloidal 2x2 and toroidal scalar) in mpmath at the current precision, from
    mpmath's besseli/besselk: P = beta I_{m+3/2}/I_{m+1/2}, Q = beta K_{m-1/2}/K_{m+1/2}."""
    s = mp.mpc(gamma)
    nu, kappa = mp.mpf(nu), mp.mpf(kappa)
    beta = mp.sqrt(s / nu)
    P = beta * mp.besseli(m + 1.5, beta) / mp.besseli(m + 0.5, beta)
    Q = beta * mp.besselk(m - 0.5, beta) / mp.besselk(m + 0.5, beta)
    q = kappa * (m - 1) * (m + 2)
    yy = s**2 * (mp.mpf(2 * m + 1) / (m * (m + 1)) + m / ((m + 1) * Q) + (m + 1) / (m * P)) + q
    ypsi = s**2 * (m / Q - (m + 1) / P)
    psipsi = s**2 * (1 / Q + 1 / P) + q
    return yy * psipsi - ypsi * ypsi / (m * (m + 1)), nu * s * (2 * m + 1 + P + Q) + q


def mp_newton_correction(gamma, m, kappa, nu, component):
    """|det/det'| at gamma in 30-digit arithmetic: the distance to the nearest root (relative)."""
    with mp.workdps(30):
        k = 0 if component == "poloidal" else 1
        f = lambda g: mp_d(g, m, kappa, nu)[k]  # noqa: E731
        g = mp.mpc(gamma)
        return float(abs(f(g) / mp.diff(f, g)) / abs(g))


CASES = [(2, 1e-7), (2, 1e-3), (2, 0.3), (2, 10.0), (3, 0.05), (4, 1.0), (10, 0.2), (60, 1e-5),
         (60, 0.115), (60, 3.0)]


@pytest.mark.parametrize("m,zeta", CASES)
def test_roots_solve_mpmath_determinant(m, zeta):
    """Each double-precision mode is within 1e-12 (relative) of a root of the 30-digit det D(gamma)
    (7.14), and the conjugate-free, least-damped-first conventions hold."""
    kappa = 0.37
    nu = zeta * math.sqrt(kappa)
    res = find_modes(modal_system(m=m, kappa=kappa, nu=nu))
    assert res.gamma.size == 2 and np.all(np.isfinite(res.gamma))
    assert np.all(res.gamma.imag >= 0) and res.gamma[0].real >= res.gamma[1].real
    assert np.all(res.gamma.real < 0)
    assert np.all(res.principal_sheet | res.on_cut)
    for g in res.gamma:
        assert mp_newton_correction(g, m, kappa, nu, "poloidal") <= 1e-12


@pytest.mark.parametrize("m,zeta", [(2, 1e-6), (3, 0.05), (5, 1.0), (20, 0.3), (60, 10.0)])
def test_toroidal_root_solves_mpmath_determinant(m, zeta):
    """The single toroidal mode ((6.29) at tau = 0) solves the 30-digit D_Phi(gamma) = 0."""
    kappa = 2.0
    nu = zeta * math.sqrt(kappa)
    res = find_modes(modal_system(m=m, kappa=kappa, nu=nu, component="toroidal"))
    assert res.gamma.size == 1 and res.gamma[0].real < 0 and res.gamma[0].imag >= 0
    assert mp_newton_correction(res.gamma[0], m, kappa, nu, "toroidal") <= 1e-12


@pytest.mark.parametrize("m", [2, 3, 10])
def test_inviscid_limit_lamb_frequency_and_sqrt_nu_rate(m):
    """zeta -> 0: the oscillatory mode tends to i lambda0 (Lamb/Rayleigh, (7.4)/(7.5)) with an
    O(sqrt nu) deviation (slope 1/2 in log-log), Re gamma < 0, and the Stokes-layer formula
    i lambda0 - c_m sqrt(i lambda0 nu) is right to O(nu)."""
    kappa = 0.5
    lam0 = math.sqrt(lambda0_squared(m, kappa))
    nus = np.array([1e-9, 1e-8, 1e-7, 1e-6])
    osc = []
    for nu in nus:
        g = find_modes(modal_system(m=m, kappa=kappa, nu=nu)).gamma
        osc.append(g[np.argmin(abs(g - 1j * lam0))])
    osc = np.array(osc)
    assert np.all(osc.real < 0)
    slope = np.polyfit(np.log(nus), np.log(abs(osc - 1j * lam0)), 1)[0]
    assert abs(slope - 0.5) < 0.01
    remainder = np.array([abs(g - inviscid_limit(m=m, kappa=kappa, nu=nu)) for g, nu in zip(osc, nus)])
    assert np.polyfit(np.log(nus), np.log(remainder), 1)[0] == pytest.approx(1.0, abs=0.02)


def test_psi_relaxation_branch_at_small_viscosity():
    """The fast tangential branch: |gamma| ~ (q^2/(4 nu))^(1/3) at arg 2 pi/3, relative error
    O(1/beta) ~ nu^(2/3) (derivations/sphere_linear_result.md, 4(a))."""
    m, kappa = 3, 1.0
    nus = np.array([1e-9, 1e-8, 1e-7])
    errs = []
    for nu in nus:
        g = find_modes(modal_system(m=m, kappa=kappa, nu=nu)).gamma[1]
        want = psi_relaxation_limit(m=m, kappa=kappa, nu=nu)
        errs.append(abs(g - want) / abs(want))
    assert errs[0] < 2e-6
    assert np.polyfit(np.log(nus), np.log(errs), 1)[0] == pytest.approx(2 / 3, abs=0.03)


@pytest.mark.parametrize("m", [2, 3, 4, 10])
def test_stokes_limit_overdamped_pair(m):
    """zeta -> infinity: two nearly real modes at -q/(nu mu_i), mu_i = eig R0, with relative error
    O(zeta^-2) (the next term of H(s) is O(s^2))."""
    kappa = 0.02
    errs = []
    for zeta in (10.0, 100.0):
        nu = zeta * math.sqrt(kappa)
        res = find_modes(modal_system(m=m, kappa=kappa, nu=nu))
        want = stokes_limit(m=m, kappa=kappa, nu=nu)
        errs.append(np.max(abs(res.gamma - want) / abs(want)))
        assert np.all(abs(res.gamma.imag) <= 1e-3 * abs(res.gamma.real))
    assert errs[0] < 5e-3 and errs[1] < 1.01e-2 * errs[0]


def test_stokes_matrix_is_the_small_beta_load():
    """R0 against H(s)/(nu s) from the vectorised D(s) at tiny |s|/nu (models/sphere.py)."""
    m, kappa, nu = 3, 1.0, 5.0
    s = 1e-7 * (1 + 1j)
    H = poloidal_unforced(np.array([s]), m=m, kappa=kappa, nu=nu)[0] - kappa * (m - 1) * (m + 2) * np.eye(2)
    np.testing.assert_allclose(H / (nu * s), stokes_matrix(m), rtol=1e-6)


def test_toroidal_limits():
    """Toroidal mode: (q/2)^(2/3) nu^(-1/3) e^(2 pi i/3) at small zeta, -q/((2m+1) nu) at large."""
    m, kappa = 4, 1.0
    small = find_modes(modal_system(m=m, kappa=kappa, nu=1e-9, component="toroidal")).gamma[0]
    large = find_modes(modal_system(m=m, kappa=kappa, nu=100.0, component="toroidal")).gamma[0]
    s0, _ = toroidal_limits(m=m, kappa=kappa, nu=1e-9)
    _, l0 = toroidal_limits(m=m, kappa=kappa, nu=100.0)
    assert abs(small - s0) <= 1e-10 * abs(s0)
    assert abs(large - l0) <= 1e-5 * abs(l0)


@pytest.mark.parametrize("m,zeta,component", [(2, 1e-3, "poloidal"), (3, 0.3, "poloidal"),
                                              (2, 10.0, "poloidal"), (60, 0.12, "poloidal"),
                                              (4, 0.05, "toroidal")])
def test_double_agrees_with_30_digits(m, zeta, component):
    """precision=30 (mpmath Newton with mpmath's Bessel functions) agrees with double precision to
    1e-12 relative; the polished error estimate is below 1e-25 relative and the digits parse back."""
    system = modal_system(m=m, kappa=1.3, nu=zeta * math.sqrt(1.3), component=component)
    fast = find_modes(system)
    ref = find_modes(system, precision=30)
    assert np.all(abs(fast.gamma - ref.gamma) <= 1e-12 * abs(ref.gamma))
    assert np.all(ref.double_error <= 1e-12 * abs(ref.gamma))
    assert np.all(fast.error_estimate >= ref.double_error)  # the double estimate is a bound
    assert np.all(ref.error_estimate <= 1e-25 * abs(ref.gamma))
    for g, (re, im) in zip(ref.gamma, ref.gamma_digits):
        assert complex(float(re), float(im)) == pytest.approx(g, rel=1e-15)


def test_precision_resolves_the_sheet_of_a_near_cut_mode():
    """m = 2, zeta = 1000: the least damped mode has Re beta / |beta| ~ 1e-29 (the Basset-type
    odd part of Q), below double resolution (on the cut) but resolved as principal at 40 digits."""
    system = modal_system(m=2, kappa=1.0, nu=1000.0)
    fast = find_modes(system)
    ref = find_modes(system, precision=40)
    assert fast.on_cut[0] and not fast.principal_sheet[0]
    assert ref.principal_sheet[0] and not ref.on_cut[0]
    assert float(ref.gamma_digits[0][1]) > 0


def test_cavity_resonances_are_on_the_second_sheet():
    """The interior vortical roots near beta = i j_{m+1,1} are resonances: at m = 2, zeta = 1e-3
    the 40-digit root has Re beta = -1.76e-15 (< 0), so it is no mode (module docstring)."""
    with mp.workdps(40):
        root = mp.mpc(0, 6.988)
        for _ in range(30):  # Newton on the pole-free F (the root sits next to a pole of (M1))
            f, fp = poloidal_residual_mp(root, m=2, zeta=1e-3)
            root -= f / fp
        assert abs(poloidal_residual_mp(root, m=2, zeta=1e-3)[0]) < mp.mpf(10) ** -25
        assert -2e-15 < root.real < -1.5e-15 and abs(root.imag - 6.98815) < 1e-5


@pytest.mark.parametrize("m,zeta,component,k", [(10, 1e-4, "poloidal", 2), (60, 1e-2, "poloidal", 1),
                                                (5, 1e-4, "toroidal", 1), (30, 1e-2, "toroidal", 3)])
def test_more_cavity_resonances_on_the_second_sheet(m, zeta, component, k):
    """Resonances near the k-th zero of j_{m+1} (poloidal) or j_m (toroidal), where the interior
    alone has decaying vortical modes: 50-digit Newton gives Re beta < 0 (values 1e-25..1e-5)."""
    residual = poloidal_residual_mp if component == "poloidal" else toroidal_residual_mp
    with mp.workdps(50):
        root = mp.mpc(0, mp.besseljzero(m + (1.5 if component == "poloidal" else 0.5), k))
        for _ in range(40):
            f, fp = residual(root, m=m, zeta=zeta)
            step = f / fp
            root -= step
            if abs(step) < mp.mpf(10) ** -45 * abs(root):
                break
        assert abs(step) < mp.mpf(10) ** -40 * abs(root)
        assert root.real < -mp.mpf(10) ** -30


@pytest.mark.parametrize("m", [2, 3, 4])
def test_zeta_sweep_is_finite_and_continuous(m):
    """zeta from 1e-7 to 10 on a grid of ratio 10^(1/80): both branches exist everywhere, finite,
    Re < 0, and each moves continuously (nearest-neighbour matching, steps < 15 % of |gamma|; the
    fastest change is the tangential branch reaching the cut near zeta = 0.2)."""
    zetas = np.logspace(-7, 1, 641)
    rows = []
    for zeta in zetas:
        res = find_modes(modal_system(m=m, kappa=1.0, nu=zeta))
        assert np.all(np.isfinite(res.gamma)) and np.all(np.isfinite(res.error_estimate))
        assert np.all(res.gamma.real < 0)
        rows.append(res.gamma)
    a, b = [rows[0][0]], [rows[0][1]]
    for g in rows[1:]:
        if abs(g[0] - a[-1]) + abs(g[1] - b[-1]) <= abs(g[1] - a[-1]) + abs(g[0] - b[-1]):
            a.append(g[0]), b.append(g[1])
        else:
            a.append(g[1]), b.append(g[0])
    for branch in (np.array(a), np.array(b)):
        assert np.max(abs(np.diff(branch)) / abs(branch[1:])) < 0.15
    lam0 = math.sqrt(lambda0_squared(m, 1.0))
    assert abs(a[0] - 1j * lam0) < 1e-3 * lam0 or abs(b[0] - 1j * lam0) < 1e-3 * lam0


def test_kappa_nu_enter_only_through_zeta():
    """gamma(kappa, nu)/sqrt(kappa) depends on zeta = nu/sqrt(kappa) only (the scaling after (7.12))."""
    a = find_modes(modal_system(m=3, kappa=0.04, nu=0.006)).gamma / 0.2
    b = find_modes(modal_system(m=3, kappa=4.0, nu=0.06)).gamma / 2.0
    np.testing.assert_allclose(a, b, rtol=1e-13)


def test_residual_matches_determinant_of_the_floquet_block():
    """(M1) = det D / kappa^2 and (M2) = D_Phi / kappa against models/sphere.py (ratio kernels of
    special/spherical.py), on the physical sheet."""
    rng = np.random.default_rng(1)
    for _ in range(40):
        m = int(rng.integers(2, 61))
        zeta = 10 ** rng.uniform(-7, 1)
        kappa = 10 ** rng.uniform(-3, 1)
        nu = zeta * math.sqrt(kappa)
        beta = 10 ** rng.uniform(-1.5, 3.5) * cmath.exp(1j * rng.uniform(0, math.pi / 2))
        s = np.array([nu * beta * beta])
        want = np.linalg.det(poloidal_unforced(s, m=m, kappa=kappa, nu=nu)[0]) / kappa**2
        got = poloidal_residual(beta, m=m, zeta=zeta)[0]
        scale = abs(want) + (m * m) ** 2
        assert abs(got - want) <= 1e-9 * scale
        want_t = toroidal_unforced(s, m=m, kappa=kappa, nu=nu)[0, 0, 0] / kappa
        got_t = modal_system(m=m, kappa=kappa, nu=nu, component="toroidal").residual(beta)[0]
        assert abs(got_t - want_t) <= 1e-12 * (abs(want_t) + m * m)


@pytest.mark.parametrize("m,z", [(2, 3 + 3j), (60, 500 + 500j), (60, 380 + 694j), (20, 0.01 + 40j),
                                 (200, 1e5 + 1e5j), (5, 1e-8 + 1e-8j), (60, 40 + 0.001j),
                                 (30, 2 + 700j), (2, 1e6j + 1)])
def test_scalar_ratio_kernel_against_mpmath(m, z):
    """i_{m+1}/i_m (terminating expansion DLMF 10.49.8 or continued fraction 10.33.1) against
    mpmath's I_{m+3/2}/I_{m+1/2} at 30 digits, within 1e-14 times the condition number."""
    with mp.workdps(30):
        zz = mp.mpc(z)
        want = mp.besseli(m + 1.5, zz) / mp.besseli(m + 0.5, zz)
        P = zz * want
        cond = max(1.0, abs(complex((zz**2 - (2 * m + 1) * P - P * P) / P - 1)))
    assert abs(ratio_i_scalar(m, z) - complex(want)) <= 2e-14 * cond * abs(complex(want))


def test_riccati_derivatives():
    """beta P' = beta^2 - (2m+1) P - P^2 and beta Q' = Q^2 + (2m+1) Q - beta^2 (from DLMF 10.47.2)
    against central differences, on both sheets."""
    for m, beta in [(2, 0.7 + 1.1j), (7, -0.4 + 3.0j), (30, 12 - 5j), (3, 1e-4 + 2e-4j)]:
        h = 1e-6 * abs(beta)
        P, Q, dP, dQ = _p_q(m, beta)
        fd = [(a - b) / (2 * h) for a, b in zip(_p_q(m, beta + h), _p_q(m, beta - h))]
        assert abs(dP - fd[0]) <= 1e-7 * (abs(dP) + abs(P) / abs(beta))
        assert abs(dQ - fd[1]) <= 1e-7 * (abs(dQ) + abs(Q) / abs(beta))


def test_result_to_dict_contract():
    """NaturalModesResult: frozen, JSON-serialisable, modes with gamma_re/gamma_im/error_estimate."""
    system = modal_system(m=2, kappa=0.05, nu=0.01)
    roots = find_modes(system, count=1, precision=20)
    res = NaturalModesResult.build(model="sphere", params={"m": 2, "kappa": 0.05, "nu": 0.01},
                                   roots=roots, options={"count": 1, "precision": 20})
    d = json.loads(json.dumps(res.to_dict()))
    assert d["model"] == "sphere" and d["params"]["m"] == 2 and d["precision"] == 20
    assert len(d["modes"]) == 1
    mode = d["modes"][0]
    assert {"gamma_re", "gamma_im", "error_estimate"} <= set(mode)
    assert complex(mode["gamma_re"], mode["gamma_im"]) == res.gamma[0]
    assert mode["principal_sheet"] is True and mode["gamma_re_digits"].startswith("-")
    assert d["provenance"]["options"]["count"] == 1 and d["provenance"]["version"]
    assert res.decay_rate[0] < 0 and res.frequency[0] > 0
    with pytest.raises(AttributeError):
        res.model = "x"


def test_on_cut_modes_carry_a_warning():
    res = NaturalModesResult.build(model="sphere", params={}, options={},
                                   roots=find_modes(modal_system(m=10, kappa=1.0, nu=5.0)))
    assert res.on_cut.any() and res.warnings and "branch cut" in res.warnings[0]


def test_cost_in_residual_evaluations():
    """Speed proxy independent of the machine: both poloidal modes from two seeds with at most
    16 residual evaluations, over m = 2..60 and zeta = 1e-7..10."""
    worst = 0
    for m in (2, 3, 5, 13, 29, 60):
        for zeta in np.logspace(-7, 1, 17):
            res = find_modes(modal_system(m=m, kappa=1.0, nu=zeta))
            assert res.seeds_tried <= 3
            worst = max(worst, res.evaluations)
    assert worst <= 16


@settings(max_examples=25, deadline=None)
@given(m=st.integers(2, 60), log_zeta=st.floats(-7, 1), log_kappa=st.floats(-3, 2))
def test_random_parameters_give_two_decaying_modes(m, log_zeta, log_kappa):
    kappa = 10.0**log_kappa
    res = find_modes(modal_system(m=m, kappa=kappa, nu=10.0**log_zeta * math.sqrt(kappa)))
    assert res.gamma.size == 2 and np.all(np.isfinite(res.gamma)) and np.all(res.gamma.real < 0)
    assert np.all(res.error_estimate <= 1e-12 * abs(res.gamma))


# ----------------------------------------------------------------------------- the solver alone


def _oscillator_system(kappa: float, nu: float, seeds) -> ModalSystem:
    """u'' + nu u' + kappa u = 0 as a ModalSystem in x = gamma: roots (-nu +- sqrt(nu^2 - 4 kappa))/2."""
    return ModalSystem(name="oscillator", residual=lambda x: (x * x + nu * x + kappa, 2 * x + nu),
                       residual_mp=lambda x: (x * x + nu * x + kappa, 2 * x + nu),
                       seeds=lambda: iter(seeds), to_gamma=lambda x: x,
                       sheet_margin=lambda x: 1.0, n_modes=2)


def test_solver_is_model_agnostic():
    """A closed-form spectrum: an underdamped pair is one mode (Im >= 0) -> n_modes = 2 needs two
    distinct roots; overdamped: both real roots, least damped first."""
    over = find_modes(_oscillator_system(1.0, 3.0, [-0.1 + 0.1j, -3.0]), precision=25)
    np.testing.assert_allclose(over.gamma, [(-3 + math.sqrt(5)) / 2, (-3 - math.sqrt(5)) / 2], rtol=1e-15)
    assert over.principal_sheet.all() and not over.on_cut.any()


def test_solver_raises_when_seeds_miss_modes():
    with pytest.raises(ConvergenceError, match="found 1 of the 2"):
        find_modes(_oscillator_system(1.0, 0.1, [0.3 + 1j, 0.2 - 1j]))


# ----------------------------------------------------------------------------- invalid input


@pytest.mark.parametrize("kwargs,name", [
    ({"m": 1, "kappa": 1.0, "nu": 0.1}, "m"), ({"m": 201, "kappa": 1.0, "nu": 0.1}, "m"),
    ({"m": 2.5, "kappa": 1.0, "nu": 0.1}, "m"), ({"m": 2, "kappa": 0.0, "nu": 0.1}, "kappa"),
    ({"m": 2, "kappa": float("nan"), "nu": 0.1}, "kappa"), ({"m": 2, "kappa": 1.0, "nu": 0.0}, "nu"),
    ({"m": 2, "kappa": 1.0, "nu": -1.0}, "nu"), ({"m": 2, "kappa": 1.0, "nu": 1e-12}, "zeta"),
    ({"m": 2, "kappa": 1e-6, "nu": 10.0}, "zeta"),
    ({"m": 2, "kappa": 1.0, "nu": 0.1, "component": "spin"}, "component")])
def test_invalid_model_parameters(kwargs, name):
    with pytest.raises(ParameterError, match=rf"^{name}\b.*invalid: must be"):
        modal_system(**kwargs)


@pytest.mark.parametrize("kwargs,name", [({"count": 0}, "count"), ({"count": -2}, "count"),
                                         ({"count": True}, "count"), ({"precision": 8}, "precision"),
                                         ({"precision": 2.5}, "precision")])
def test_invalid_solver_options(kwargs, name):
    with pytest.raises(ParameterError, match=rf"^{name} = .* is invalid: must be"):
        find_modes(modal_system(m=2, kappa=1.0, nu=0.01), **kwargs)


# ----------------------------------------------------------------------------- completeness (slow)


def _winding(f, vertices, n0=2000, rounds=60):
    """Winding number of f (vectorised) around a polygon.

    Samples are added at the midpoint of every step h with max(|f'/f|) h > 0.5 at its ends
    (f'/f by a forward difference of relative step 1e-7) or a phase change above 0.5 rad.
    Near a zero at distance r from the contour |f'/f| ~ 1/r, so steps shrink geometrically as
    they approach it and cannot jump over it (a phase test alone aliases two nearby zeros,
    whose joint 2 pi turn looks like no turn at all).
    """
    total = 0.0
    for a, b in zip(vertices, vertices[1:] + vertices[:1]):
        eps = 1e-7 * max(abs(a), abs(b))

        def sample(t):
            z = a + (b - a) * t
            v = f(z)
            return v, np.abs((f(z + eps) - v) / (eps * v))

        t = np.linspace(0.0, 1.0, n0)
        v, ld = sample(t)
        for _ in range(rounds):
            d = np.angle(v[1:] / v[:-1])
            h = np.diff(t) * abs(b - a)
            big = (np.abs(d) > 0.5) | (np.maximum(ld[1:], ld[:-1]) * h > 0.5)
            if not big.any():
                break
            tm = 0.5 * (t[:-1] + t[1:])[big]
            vm, ldm = sample(tm)
            t, v, ld = np.concatenate([t, tm]), np.concatenate([v, vm]), np.concatenate([ld, ldm])
            order = np.argsort(t)
            t, v, ld = t[order], v[order], ld[order]
        else:
            raise AssertionError("phase not resolved along the contour")
        total += np.sum(d)
    return total / (2 * math.pi)


@pytest.mark.slow
@pytest.mark.parametrize("m,zeta", [(m, z) for m in (2, 3, 4, 10) for z in (1e-3, 0.03, 0.2, 1.0, 10.0)]
                         + [(m, z) for m in (30, 60) for z in (0.03, 0.1, 0.2, 1.0, 10.0)]
                         + [(100, 0.03), (200, 0.05), (200, 1.0)])
@pytest.mark.parametrize("component", ["poloidal", "toroidal"])
def test_no_mode_is_missed_argument_principle(m, zeta, component):
    """Completeness: the zeros of det D (models/sphere.py, vectorised, special/spherical.py kernels)
    in the box delta <= Re beta <= L, 0 <= Im beta <= L are exactly the modes found there (det D is
    analytic in Re beta > 0: its poles lie on the imaginary axis and in Re beta < 0); every other
    mode found has 0 <= Re beta < delta (near the cut). L is four times the largest scale of the
    modes; beyond it |det D| grows like |beta|^7 (poloidal) or |beta|^3 (toroidal), the
    large-beta terms of (M1)/(M2), so no root lies outside."""
    kappa, nu = 1.0, zeta
    res = find_modes(modal_system(m=m, kappa=kappa, nu=nu, component=component))
    beta = res.x
    size = 4 * max(np.max(abs(beta)), 2 * m + 10)
    delta = 1e-3 * np.min(abs(beta))

    if component == "poloidal":
        def f(b):
            return np.linalg.det(poloidal_unforced(nu * b * b, m=m, kappa=kappa, nu=nu))
    else:
        def f(b):
            return toroidal_unforced(nu * b * b, m=m, kappa=kappa, nu=nu)[:, 0, 0]
    count = _winding(f, [complex(delta, 0), complex(size, 0), complex(size, size), complex(delta, size)])
    assert abs(count - round(count)) < 1e-6
    assert round(count) == int(np.sum(beta.real >= delta))
    assert np.all(beta.real > -1e-13 * abs(beta))


def test_count_beyond_the_modes_returns_all_with_a_warning(capsys):
    """The issue's own example, ``modes sphere --m 2 --kappa 1 --nu 0.01 --count 3``: the physical
    sheet holds two poloidal modes (the argument-principle test above), so all two come back,
    least damped first, with a warning saying why, and exit status 0."""
    from spectralshell.cli import main

    every = ss.natural_modes("sphere", m=2, kappa=1.0, nu=0.01)
    more = ss.natural_modes("sphere", m=2, kappa=1.0, nu=0.01, count=3)
    assert more.gamma.tolist() == every.gamma.tolist() and len(more.gamma) == 2
    assert not every.warnings and "count = 3" in more.warnings[0] and "all 2" in more.warnings[0]
    assert main(["modes", "sphere", "--m", "2", "--kappa", "1", "--nu", "0.01", "--count", "3",
                 "--json"]) == 0
    out, err = capsys.readouterr()
    modes = json.loads(out)["modes"]
    assert len(modes) == 2 and modes[0]["gamma_re"] > modes[1]["gamma_re"]
    assert "count = 3" in err
