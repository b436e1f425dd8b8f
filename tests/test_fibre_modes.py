"""Natural modes of the unforced immersed fibre (tau = 0) against independent evidence.

Oracles: det D(gamma) of derivations/fibre_linear_result.md in mpmath at 30 digits with mpmath's
own I_m, K_m (:func:`mp_det`, the unscaled 2x2 matrix, not the package's scaled Delta); mpmath
findroot; the small-nu expansions of derivations/fibre_modes.py (Rayleigh frequency with its
Stokes-layer corrections, the fast mode); the steady-Stokes double root -kappa m/(4 nu) and the
logarithmic frequency of m = 2; the damped-Mathieu threshold at a tongue tip of the Floquet solver
(a different method: Hill determinants, not the dispersion relation); argument-principle counts
with the vectorised D(s) of models/fibre.py (slow).
"""

from __future__ import annotations

import json
import math

import mpmath as mp
import numpy as np
import pytest
from scipy.optimize import brentq, minimize_scalar

import spectralshell as ss
from spectralshell.cli import main
from spectralshell.errors import ParameterError
from spectralshell.models.fibre import (_p_q, fast_limit, lambda0_squared, modal_residual,
                                        modal_system, natural_determinant, oscillatory_limit,
                                        stokes_limit, zeta_max)
from spectralshell.solvers.modes import find_modes


def mp_det(gamma, m, kappa, nu):
    """det D(gamma) at the current mpmath precision: D = s^2 [[2/m + 1/P + 1/Q, 1/P - 1/Q],
    [1/P - 1/Q, 1/P + 1/Q]] + kappa [[m^2, m], [m, m^2]] with mpmath's besseli/besselk."""
    s = mp.mpc(gamma)
    kappa, nu = mp.mpf(kappa), mp.mpf(nu)
    beta = mp.sqrt(s / nu)
    P = beta * mp.besseli(m + 1, beta) / mp.besseli(m, beta)
    Q = beta * mp.besselk(m - 1, beta) / mp.besselk(m, beta)
    rr = s**2 * (mp.mpf(2) / m + 1 / P + 1 / Q) + kappa * m * m
    rt = s**2 * (1 / P - 1 / Q) + kappa * m
    tt = s**2 * (1 / P + 1 / Q) + kappa * m * m
    return rr * tt - rt * rt


def mp_distance(gamma, m, kappa, nu):
    """|det/det'| / |gamma| at 30 digits: the relative distance to the nearest root (det' by a
    forward difference of relative step 1e-12, ample for a distance of order 1e-12 or less)."""
    with mp.workdps(30):
        g = mp.mpc(gamma)
        h = mp.mpf("1e-12") * abs(g)
        f0 = mp_det(g, m, kappa, nu)
        return float(abs(f0 * h / (mp_det(g + h, m, kappa, nu) - f0)) / abs(g))


CASES = [(2, 0.3, 1e-7), (2, 1.0, 1e-3), (2, 0.02, 2e-4), (2, 1.0, 0.5), (2, 1.0, 10.0), (3, 0.02, 2e-4),
         (3, 4.0, 0.7), (4, 0.08, 5e-5), (5, 1.0, 10.0), (10, 0.04, 5e-3), (30, 1.0, 1e-5), (60, 2.0, 0.2)]


@pytest.mark.parametrize("m,kappa,nu", CASES)
def test_modes_solve_the_mpmath_determinant(m, kappa, nu):
    """Both double-precision modes lie within 1e-12 (relative) of roots of the 30-digit det D, are
    distinct, decay, have Im gamma >= 0, come least damped first, and carry error estimates."""
    res = find_modes(modal_system(m=m, kappa=kappa, nu=nu))
    g = res.gamma
    assert g.size == 2 and np.all(np.isfinite(g)) and np.all(g.real < 0) and np.all(g.imag >= 0)
    assert g[0].real >= g[1].real and abs(g[0] - g[1]) > 1e-6 * abs(g[0])
    assert np.all(res.principal_sheet | res.on_cut)
    assert np.all(res.error_estimate <= 1e-12 * abs(g))
    for root in g:
        assert mp_distance(root, m, kappa, nu) <= 1e-12


def test_mpmath_findroot_reaches_the_same_modes():
    """mpmath's secant method on the 30-digit det D, started 1 % away, lands on each mode."""
    m, kappa, nu = 2, 1.0, 0.5
    for g in find_modes(modal_system(m=m, kappa=kappa, nu=nu)).gamma:
        with mp.workdps(30):
            root = mp.findroot(lambda s: mp_det(s, m, kappa, nu), mp.mpc(g * (1 + 0.01j)), tol=1e-22)
        assert abs(complex(root) - g) <= 1e-13 * abs(g)


def test_double_agrees_with_30_digit_polish():
    system = modal_system(m=3, kappa=4.0, nu=0.7)
    fast, ref = find_modes(system), find_modes(system, precision=30)
    assert np.all(abs(fast.gamma - ref.gamma) <= 1e-13 * abs(ref.gamma))
    assert np.all(fast.error_estimate >= ref.double_error)
    assert np.all(ref.error_estimate <= 1e-25 * abs(ref.gamma))


@pytest.mark.parametrize("m", [2, 3, 6])
def test_small_nu_rayleigh_mode_and_stokes_layer(m):
    """nu -> 0: the least damped mode tends to i lambda0, lambda0^2 = kappa m(m^2-1)/2, with Re < 0;
    its deviation is O(sqrt nu) (slope 1/2), after -(m^2+1)/(2m) sqrt(i lambda0 nu) it is O(nu)
    (slope 1), after the O(nu) term -(m^4-3)/(4m^2) nu it is O(nu^(3/2))."""
    kappa = 0.5
    lam0 = math.sqrt(lambda0_squared(m, kappa))
    nus = np.array([1e-9, 1e-8, 1e-7, 1e-6])
    osc = np.array([find_modes(modal_system(m=m, kappa=kappa, nu=nu)).gamma[0] for nu in nus])
    assert np.all(osc.real < 0)
    leading = 1j * lam0 - (m * m + 1) / (2 * m) * np.sqrt(1j * lam0 * nus)
    slopes = [np.polyfit(np.log(nus), np.log(abs(osc - ref)), 1)[0]
              for ref in (1j * lam0, leading, [oscillatory_limit(m=m, kappa=kappa, nu=nu) for nu in nus])]
    assert slopes == pytest.approx([0.5, 1.0, 1.5], abs=0.02)


def test_small_nu_fast_mode():
    """The second mode: gamma ~ (kappa^2 m^4/(4 nu))^(1/3) e^{2 pi i/3} (1 + O(nu^(2/3))); with the
    first correction of derivations/fibre_modes.py the relative error is O(nu^(4/3))."""
    m, kappa = 3, 1.0
    nus = np.array([1e-10, 1e-9, 1e-8])
    fast = np.array([find_modes(modal_system(m=m, kappa=kappa, nu=nu)).gamma[1] for nu in nus])
    lead = (kappa**2 * m**4 / (4 * nus)) ** (1 / 3) * np.exp(2j * np.pi / 3)
    two = np.array([fast_limit(m=m, kappa=kappa, nu=nu) for nu in nus])
    assert np.polyfit(np.log(nus), np.log(abs(fast / lead - 1)), 1)[0] == pytest.approx(2 / 3, abs=0.02)
    assert np.polyfit(np.log(nus), np.log(abs(fast / two - 1)), 1)[0] == pytest.approx(4 / 3, abs=0.05)


@pytest.mark.parametrize("m", [2, 3, 5])
def test_large_nu_stokes_pair(m):
    """nu -> infinity: both modes tend to the steady-Stokes double root sigma0 = -m/(4 zeta)
    (gamma0 = -kappa m/(4 nu)); the larger deviation is the first correction
    sigma0^2 |1/m + 2c|/(4(m-+1) zeta) of derivations/fibre_modes.py (c = 1/(2(m-2)), or
    -log(beta0/2) - gamma_E for m = 2, from 1/Q; 1/(2(m+2)) from 1/P), which is O(zeta^-2)
    (times log zeta for m = 2), up to the same-order coupling sigma^4/m^2 of A+ and A- (a few %);
    the quartic model of :func:`stokes_limit`, which keeps the coupling, is far closer."""
    kappa = 0.3
    errs, first = [], []
    for zeta in (10.0, 40.0):
        nu = zeta * math.sqrt(kappa)
        g = find_modes(modal_system(m=m, kappa=kappa, nu=nu)).gamma / math.sqrt(kappa)
        s0 = -m / (4 * zeta)
        c_minus = -np.log(np.sqrt(complex(s0 / zeta)) / 2) - np.euler_gamma if m == 2 else 1 / (2 * (m - 2))
        first.append(s0 * s0 * max(abs(1 / m + 1 / (m + 2)) / (4 * (m + 1)),
                                   abs(1 / m + 2 * c_minus) / (4 * (m - 1))) / zeta)
        errs.append(np.max(abs(g - s0)))
        model = stokes_limit(m=m, kappa=kappa, nu=nu) / math.sqrt(kappa)
        assert np.max([np.min(abs(model - x)) for x in g]) < 0.05 * abs(g[0] - g[1])
    assert errs[0] < 0.02 * m / 40.0  # 2 % of sigma0 at zeta = 10
    assert errs == pytest.approx(first, rel=0.2)  # the coupling term: up to ~15 % at m = 5
    assert errs[1] / errs[0] == pytest.approx(first[1] / first[0], rel=0.05)  # zeta^-3 (log for m = 2)


def test_m2_overdamped_mode_has_logarithmic_frequency():
    """m = 2, large nu: the 2D Stokes paradox (log beta in K_0/K_1) gives one overdamped mode a
    frequency Im gamma ~ pi m^2 kappa^2/(64 nu^3) (derivations/fibre_modes.py, Part 6)."""
    kappa, nu = 1.0, 30.0
    g = find_modes(modal_system(m=2, kappa=kappa, nu=nu)).gamma
    assert max(g.imag) == pytest.approx(math.pi * 4 * kappa**2 / (64 * nu**3), rel=0.02)


@pytest.mark.parametrize("m", [2, 3, 4])
def test_nu_sweep_1e_7_to_10_finite_and_continuous(m):
    """kappa = 1, nu from 1e-7 to 10 (ratio 10^(1/20)): two finite decaying modes everywhere,
    each branch continuous (nearest-neighbour matching, steps below 25 % of |gamma|)."""
    rows = [find_modes(modal_system(m=m, kappa=1.0, nu=nu)).gamma for nu in np.logspace(-7, 1, 161)]
    assert all(np.all(np.isfinite(g)) and np.all(g.real < 0) for g in rows)
    a, b = [rows[0][0]], [rows[0][1]]
    for g in rows[1:]:
        if abs(g[0] - a[-1]) + abs(g[1] - b[-1]) <= abs(g[1] - a[-1]) + abs(g[0] - b[-1]):
            a.append(g[0]), b.append(g[1])
        else:
            a.append(g[1]), b.append(g[0])
    for branch in (np.array(a), np.array(b)):
        assert np.max(abs(np.diff(branch)) / abs(branch[1:])) < 0.25


def test_kappa_and_nu_enter_through_zeta_only():
    """gamma/sqrt(kappa) is a function of zeta = nu/sqrt(kappa) (the scaling of Delta)."""
    a = find_modes(modal_system(m=3, kappa=0.04, nu=0.006)).gamma / 0.2
    b = find_modes(modal_system(m=3, kappa=4.0, nu=0.06)).gamma / 2.0
    np.testing.assert_allclose(a, b, rtol=1e-12)


def test_residual_is_the_determinant_of_the_floquet_block():
    """Delta(beta) = det D(gamma)/kappa^2 with D from models/fibre.unforced (vectorised kernels)."""
    rng = np.random.default_rng(3)
    for _ in range(30):
        m, zeta = int(rng.integers(2, 40)), 10 ** rng.uniform(-7, 1)
        kappa = 10 ** rng.uniform(-2, 1)
        beta = 10 ** rng.uniform(-1, 3) * np.exp(1j * rng.uniform(0, np.pi / 2))
        nu = zeta * math.sqrt(kappa)
        want = natural_determinant(np.array([nu * beta * beta]), m=m, kappa=kappa, nu=nu)[0] / kappa**2
        assert abs(modal_residual(beta, m=m, zeta=zeta)[0] - want) <= 1e-10 * (abs(want) + m**4)


@pytest.mark.parametrize("m,beta", [(2, -0.01 + 0.5j), (3, -1e-3 + 0.2j), (4, -2 + 5j), (5, -0.3 - 2j)])
def test_second_sheet_continuation_against_mpmath(m, beta):
    """Q on Re beta < 0 (DLMF 10.34.2 with scipy's ive/kve) equals mpmath's principal-branch
    beta K_{m-1}/K_m, so Newton iterates may cross the cut near nearly real modes."""
    with mp.workdps(30):
        b = mp.mpc(beta)
        want = complex(b * mp.besselk(m - 1, b) / mp.besselk(m, b))
    assert abs(_p_q(m, beta)[1] - want) <= 1e-13 * abs(want)


def test_near_cut_mode_is_resolved_by_precision():
    """m = 10, zeta = 10: one overdamped mode has Re beta/|beta| ~ 1e-28 (the log part of K_9
    enters at beta^18): on the cut in double precision, on the physical sheet at 45 digits."""
    system = modal_system(m=10, kappa=1.0, nu=10.0)
    fast, ref = find_modes(system), find_modes(system, precision=45)
    assert fast.on_cut.any()
    assert ref.principal_sheet.all()


def test_tongue_tip_sits_where_the_mode_frequency_is_one_half():
    """Second method (Floquet engine, Hill determinants): the principal subharmonic tongue of
    m = 3, nu = 2e-4 has its tip at the kappa where Im gamma = 1/2, and its tip tau is the
    damped-Mathieu threshold 4 delta (x'' + 2 delta x' + lambda0^2 (1 + 2 tau sin t) x, lambda0 = 1/2,
    delta = -Re gamma), both to first order in the damping."""
    m, nu = 3, 2e-4

    def osc(kappa):
        return find_modes(modal_system(m=m, kappa=kappa, nu=nu)).gamma[0]

    kappa_star = brentq(lambda k: osc(k).imag - 0.5, 0.018, 0.026, xtol=1e-12)
    delta = -osc(kappa_star).real
    tip = minimize_scalar(lambda k: ss.floquet("fibre", m=m, kappa=k, nu=nu, kind="subharmonic",
                                               tol=1e-9).subharmonic.tau_min,
                          bracket=(0.97 * kappa_star, kappa_star, 1.03 * kappa_star), tol=1e-8)
    assert tip.x == pytest.approx(kappa_star, rel=3e-3)
    assert tip.fun == pytest.approx(4 * delta, rel=0.03)


# ----------------------------------------------------------------------------- API and CLI


def test_api_inviscid_closed_form():
    res = ss.natural_modes("fibre", m=3, kappa=0.2, nu=0.0, precision=25)
    assert res.gamma[0] == pytest.approx(1j * math.sqrt(0.2 * 3 * 8 / 2), rel=1e-15)
    with mp.workdps(30):
        exact = mp.sqrt(mp.mpf(0.2) * 12)
        assert abs(mp.mpf(res.gamma_digits[0][1]) - exact) < mp.mpf(10) ** -23
    more = ss.natural_modes("fibre", m=3, kappa=0.2, nu=0.0, count=2)  # flagged, not refused
    assert more.gamma.tolist() == res.gamma.tolist() and "count = 2" in more.warnings[0]
    with pytest.raises(ParameterError, match="count"):
        ss.natural_modes("fibre", m=3, kappa=0.2, nu=0.0, count=0)


def test_api_zeta_shorthand_and_count():
    a = ss.natural_modes("fibre", m=2, zeta=0.05)
    b = ss.natural_modes("fibre", m=2, kappa=1.0, nu=0.05, count=1)
    assert a.gamma.size == 2 and b.gamma.size == 1 and a.gamma[0] == b.gamma[0]
    assert a.model == "fibre" and a.decay_rate[0] < 0


def test_cli_modes_fibre_json(capsys):
    assert main(["modes", "fibre", "--m", "2", "--kappa", "1", "--nu", "0.01", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["model"] == "fibre" and len(data["modes"]) == 2
    assert data["params"] == {"m": 2, "kappa": 1.0, "nu": 0.01}  # no pumping option at tau = 0
    g = complex(data["modes"][0]["gamma_re"], data["modes"][0]["gamma_im"])
    assert mp_distance(g, 2, 1.0, 0.01) <= 1e-12


@pytest.mark.parametrize("argv", [["--m", "1", "--kappa", "1", "--nu", "0.1"],
                                  ["--m", "2", "--kappa", "1", "--nu", "-1"],
                                  ["--m", "2", "--radius", "1", "--nu", "0.1"],
                                  ["--m", "12", "--kappa", "1", "--nu", "100"],
                                  ["--m", "2", "--zeta", "1e-12"]])
def test_cli_modes_fibre_bad_input_exit_2(capsys, argv):
    assert main(["modes", "fibre", *argv]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "error" in err


def test_invalid_parameters_name_the_range():
    with pytest.raises(ParameterError, match=r"^nu = 0 is invalid"):
        modal_system(m=2, kappa=1.0, nu=0.0)
    with pytest.raises(ParameterError, match=r"^zeta = .* is invalid: must be in \[1e-10, 72.17\]"):
        modal_system(m=10, kappa=1.0, nu=80.0)
    with pytest.raises(ParameterError, match="physical"):
        ss.natural_modes("fibre", m=2, physical={"rho": 1, "mu": 0.01, "radius": 1, "sigma": 1})
    assert zeta_max(2) == 1e3 and 70 < zeta_max(10) < 75


# ----------------------------------------------------------------------------- completeness (slow)


@pytest.mark.slow
@pytest.mark.parametrize("m,zeta", [(m, z) for m in (2, 3, 5, 10) for z in (1e-4, 0.01, 0.3, 1.0, 5.0)]
                         + [(40, 0.01), (40, 0.12), (100, 0.06), (200, 0.044)])
def test_no_mode_is_missed_argument_principle(m, zeta):
    """Completeness: the zeros of det D (vectorised models/fibre.unforced) in the box
    delta <= Re beta <= L, 0 <= Im beta <= L are exactly the modes found there; the other modes
    found have 0 <= Re beta < delta (near the cut). L is four times the largest modal scale; beyond
    it the large-beta terms S^2 (2(x+y)/m) ~ zeta^4 beta^7 dominate, so no root lies outside."""
    from test_sphere_modes import _winding

    res = find_modes(modal_system(m=m, kappa=1.0, nu=zeta))
    beta = res.x
    size = 4 * max(np.max(abs(beta)), 2 * m + 10)
    delta = 1e-3 * np.min(abs(beta))

    def f(b):
        return natural_determinant(zeta * b * b, m=m, kappa=1.0, nu=zeta)

    count = _winding(f, [complex(delta, 0), complex(size, 0), complex(size, size), complex(delta, size)])
    assert abs(count - round(count)) < 1e-6
    assert round(count) == int(np.sum(beta.real >= delta))
    assert np.all(beta.real > -1e-13 * abs(beta))


@pytest.mark.slow
def test_seeds_cover_m_2_to_200():
    """Both modes found for m = 2..200 on a grid of zeta from 1e-10 to zeta_max(m) (ten per decade,
    plus a fine grid across the crossover zeta ~ 0.6/sqrt(m), where continuation is needed)."""
    for m in (2, 3, 4, 6, 9, 15, 25, 40, 70, 110, 160, 200):
        top = 0.999 * zeta_max(m)
        grid = np.concatenate([np.logspace(-10, math.log10(top), int(10 * (math.log10(top) + 10))),
                               np.linspace(0.3, 0.9, 40) / math.sqrt(m)])
        for zeta in grid:
            g = find_modes(modal_system(m=m, kappa=1.0, nu=zeta)).gamma
            assert g.size == 2 and np.all(g.real < 0) and abs(g[0] - g[1]) > 1e-7 * abs(g[0])
