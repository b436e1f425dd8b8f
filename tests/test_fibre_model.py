"""Immersed circular fibre (thesis chapter 4) against independent evidence.

Oracles: mpmath's own modified Bessel functions at 30 digits for D(s) (the formula of
derivations/fibre_linear_result.md, itself checked there against fields that satisfy the
primitive equations); closed-form limits (s -> 0 Stokes load, nu -> 0 Mathieu equation with
Rayleigh's frequency); scipy's ODE integration of the inviscid limit; dense QZ for the Hill pencil.
"""

import mpmath as mp
import numpy as np
import pytest
from scipy.optimize import fsolve

from spectralshell.discretise.hill import assemble
from spectralshell.errors import ParameterError
from spectralshell.models.fibre import (elastic_matrix, forcing_matrix, hill_system, lambda0_squared,
                                        natural_determinant, unforced)
from spectralshell.params.fibre import FibreParams
from spectralshell.solvers.marginal import dense_taus, marginal_tau, solve_truncation


def mp_unforced(s, m, kappa, nu):
    """D(s) at 30 digits with mpmath.besseli/besselk of integer order (independent of the float
    continued fractions, recurrences and Hankel expansions of special.cylindrical)."""
    with mp.workdps(30):
        s = mp.mpc(s)
        beta = mp.sqrt(s / nu)
        P = beta * mp.besseli(m + 1, beta) / mp.besseli(m, beta)
        Q = beta * mp.besselk(m - 1, beta) / mp.besselk(m, beta)
        rr = s**2 * (mp.mpf(2) / m + 1 / P + 1 / Q) + kappa * m * m
        rt = s**2 * (1 / P - 1 / Q) + kappa * m
        tt = s**2 * (1 / P + 1 / Q) + kappa * m * m
        return np.array([[complex(rr), complex(rt)], [complex(rt), complex(tt)]])


@pytest.mark.parametrize("m", [2, 3, 10, 60])
@pytest.mark.parametrize("nu", [1e-9, 1e-4, 0.01, 10.0])
@pytest.mark.parametrize("s", [0.5j, 1j, 7.5j, 400j, 0.3 + 2j, -0.2 + 30.5j])
def test_unforced_matches_mpmath(m, nu, s):
    """Float D(s) against mpmath at 30 digits: nu from 1e-9 to 10, |s| up to 400, m up to 60.
    Tolerance 1e-12 of the largest entry: the ratios are good to ~1e-15, and D_rt = s^2(1/P - 1/Q)
    cancels at large beta to an absolute error ~eps |s^2/beta|, far below that scale."""
    got = unforced(np.array([s]), m=m, kappa=0.02, nu=nu)[0]
    want = mp_unforced(s, m, 0.02, nu)
    assert np.all(np.isfinite(got))
    assert np.max(np.abs(got - want)) <= 1e-12 * np.max(np.abs(want))


def test_real_in_time_domain_and_reciprocal():
    """D(conj s) = conj D(s) (needed by the reality conditions (2.7)-(2.8)); D = D^T, because the
    velocity-to-traction map is reciprocal with equal weights (int cos^2 = int sin^2 = pi)."""
    s = np.array([0.2 + 1.5j, 3j, 0.7 + 0.1j, 0.5j, 250j])
    a = unforced(s, m=4, kappa=0.05, nu=0.01)
    np.testing.assert_allclose(unforced(s.conj(), m=4, kappa=0.05, nu=0.01), a.conj(), rtol=1e-14)
    np.testing.assert_allclose(a, np.swapaxes(a, 1, 2), rtol=0, atol=0)


@pytest.mark.parametrize("m", [2, 5])
def test_passive(m):
    """The fluid load H = D - kappa E dissipates energy on s = i omega: Re(i omega X^H H X)^* > 0,
    i.e. the Hermitian part of H(i omega)/(i omega) is positive definite."""
    for w in (0.1, 0.5, 2.0, 40.0):
        H = unforced(np.array([1j * w]), m=m, kappa=0.0, nu=0.003)[0]
        R = H / (1j * w)
        assert np.all(np.linalg.eigvalsh((R + R.conj().T) / 2) > 0)


@pytest.mark.parametrize("m", [2, 3, 7])
def test_s_to_zero_is_the_steady_stokes_load(m):
    """D(0) = kappa E exactly (the harmonic n = 0 block), and D(s) - kappa E = 4 nu s [[m, 1], [1, m]]
    + o(s), the load of the beta = 0 polynomial Stokes fields (derived independently in
    derivations/fibre_linear.py, Part 4b). Relative o(s) term ~ (s/nu) log: tolerance 1e-3."""
    nu, kappa = 0.05, 0.3
    E = elastic_matrix(m)
    assert np.array_equal(unforced(np.array([0.0]), m=m, kappa=kappa, nu=nu)[0], kappa * E)
    s = 1e-6j
    load = unforced(np.array([s]), m=m, kappa=kappa, nu=nu)[0] - kappa * E
    np.testing.assert_allclose(load, 4 * nu * s * np.array([[m, 1], [1, m]]), rtol=1e-3)


def test_inviscid_system_is_mathieu_with_rayleigh_frequency():
    """nu = 0: X'' + lambda0^2 (1 + 2 tau sin t) X = 0, lambda0^2 = kappa m (m^2 - 1)/2 (Rayleigh's
    capillary-column frequency with tension K and equal densities); no forcing when only the
    tangential jump is pumped (the slaved tangential row absorbs it)."""
    m, kappa = 3, 0.02
    lam2 = lambda0_squared(m, kappa)
    assert lam2 == pytest.approx(0.24)
    sysm = hill_system(m=m, kappa=kappa, nu=0.0)
    s = np.array([0.3j, 1.1 + 0.2j])
    np.testing.assert_allclose(sysm.unforced(s)[:, 0, 0], s * s + lam2, rtol=1e-15)
    assert sysm.forcing.tolist() == [[lam2]] and sysm.name == "fibre"
    assert sysm.polynomial is not None and sysm.n_resonant == pytest.approx(np.sqrt(lam2))
    assert not np.any(hill_system(m=m, kappa=kappa, nu=0.0, forcing="tangential").forcing)
    assert hill_system(m=m, kappa=kappa, nu=0.0, forcing="pressure").forcing.tolist() == [[lam2]]


def test_natural_mode_tends_to_rayleigh_frequency():
    """The oscillatory zero of det D(s) tends to i lambda0 with an O(sqrt nu) Stokes-layer shift
    and Re s < 0 (det D from natural_determinant; roots by scipy fsolve from the inviscid guess)."""
    m, kappa = 2, 1.0
    lam0 = np.sqrt(lambda0_squared(m, kappa))
    devs = []
    for nu in (1e-7, 1e-6, 1e-5):
        f = lambda x: [natural_determinant(complex(*x), m=m, kappa=kappa, nu=nu).real,  # noqa: E731
                       natural_determinant(complex(*x), m=m, kappa=kappa, nu=nu).imag]
        root = complex(*fsolve(f, [0.0, lam0], xtol=1e-12))
        assert abs(natural_determinant(root, m=m, kappa=kappa, nu=nu)) < 1e-9
        assert root.real < 0
        devs.append(abs(root - 1j * lam0))
    assert devs[1] / devs[0] == pytest.approx(np.sqrt(10), rel=0.03)
    assert devs[2] / devs[1] == pytest.approx(np.sqrt(10), rel=0.03)
    assert natural_determinant(1j * lam0, m=m, kappa=kappa, nu=0.0) == pytest.approx(0, abs=1e-12)


def test_natural_modes_from_nu_1e_7_to_10():
    """Continuation of the oscillatory natural mode from nu = 1e-7 to 10 (m = 2, kappa = 1): the root
    stays in Re s < 0, and at nu = 10 it approaches the negative real axis (the branch cut of beta)
    at the steady-Stokes value: 4 nu s [[m, 1], [1, m]] + kappa E = 0 with E = m [[m, 1], [1, m]]
    gives the double root s = -kappa m/(4 nu); the relative O(beta) correction is below 2 %."""
    m, kappa = 2, 1.0
    guess = 1j * np.sqrt(lambda0_squared(m, kappa))
    for nu in np.logspace(-7, 1, 17):
        f = lambda x: [natural_determinant(complex(*x), m=m, kappa=kappa, nu=nu).real,  # noqa: E731
                       natural_determinant(complex(*x), m=m, kappa=kappa, nu=nu).imag]
        root = complex(*fsolve(f, [guess.real, guess.imag], xtol=1e-13))
        assert abs(natural_determinant(root, m=m, kappa=kappa, nu=nu)) < 1e-12
        assert root.real < 0 and root.imag >= 0
        guess = root
    assert root.real == pytest.approx(-kappa * m / (4 * 10.0), rel=0.02)
    assert abs(root.imag) < 1e-3


def test_viscous_tau_min_tends_to_inviscid_with_sqrt_nu_rate():
    """Principal subharmonic tongue, m = 3, kappa = 0.02: tau_min(nu) -> tau_min(0) (Mathieu with
    lambda0^2 = 0.24) with |difference| ~ nu^(1/2), the Stokes-layer damping rate."""
    m, kappa = 3, 0.02
    inviscid = marginal_tau(hill_system(m=m, kappa=kappa, nu=0.0), "subharmonic", tol=1e-10).tau_min
    nus = np.array([1e-6, 1e-7, 1e-8, 1e-9])
    diff = [marginal_tau(hill_system(m=m, kappa=kappa, nu=nu), "subharmonic", tol=1e-10).tau_min - inviscid
            for nu in nus]
    assert min(diff) > 0  # viscosity stabilises
    slope = np.polyfit(np.log(nus), np.log(diff), 1)[0]
    assert abs(slope - 0.5) < 0.03
    assert diff[-1] < 2e-4


def test_inviscid_tau_min_against_time_integration(monodromy):
    """tau_min of the nu = 0 fibre against scipy's DOP853 monodromy matrix of the Mathieu limit:
    the Floquet multipliers have modulus 1 just below tau_min and leave the unit circle just above."""
    m, kappa = 3, 0.02
    lam2 = lambda0_squared(m, kappa)
    tau = marginal_tau(hill_system(m=m, kappa=kappa, nu=0.0), "subharmonic", tol=1e-12).tau_min
    below = np.abs(np.linalg.eigvals(monodromy(lam2, 0.0, tau * (1 - 1e-3))))
    above = np.abs(np.linalg.eigvals(monodromy(lam2, 0.0, tau * (1 + 1e-3))))
    assert np.max(below) < 1 + 1e-8
    assert np.max(above) > 1 + 1e-4
    # period doubling: the multipliers there are real and negative
    mu = np.linalg.eigvals(monodromy(lam2, 0.0, tau * (1 + 1e-3)))
    assert np.all(mu.real < 0) and np.all(abs(mu.imag) < 1e-8)


@pytest.mark.parametrize("kind", ["harmonic", "subharmonic"])
def test_structured_matches_dense(kind):
    """Fast structured eigen-solver against dense QZ of the real and two-sided pencils."""
    system = hill_system(m=3, kappa=0.02, nu=2e-4)
    fast, method, _ = solve_truncation(system, kind, 30)
    small = lambda t: np.sort(t[(t > 0) & (t < 20)])  # noqa: E731
    assert method == "structured"
    np.testing.assert_allclose(small(fast), small(dense_taus(assemble(system, kind, 30, "real"))), rtol=1e-9)
    np.testing.assert_allclose(small(fast), small(dense_taus(assemble(system, kind, 30, "two-sided"))),
                               rtol=1e-9)


def test_forcing_split_fig_4_2():
    """Fig 4.2 (m = 3, nu = 2e-4): pumping only the pressure jump keeps the physical finger (tau_min
    within 1 % of the full model); pumping only the tangential jump gives no instability with
    tau <= 1/2 (its marginal curves lie in the unphysical region)."""
    m, nu = 3, 2e-4
    assert np.array_equal(forcing_matrix(m, 0.02, "pressure") + forcing_matrix(m, 0.02, "tangential"),
                          forcing_matrix(m, 0.02, "both"))
    both = marginal_tau(hill_system(m=m, kappa=0.02, nu=nu), "subharmonic", tol=1e-10).tau_min
    pressure = marginal_tau(hill_system(m=m, kappa=0.02, nu=nu, forcing="pressure"), "subharmonic",
                            tol=1e-10).tau_min
    assert both == pytest.approx(0.1040938544, abs=1e-8)
    assert pressure == pytest.approx(both, rel=0.01)
    for kappa in (0.01, 0.02, 0.04, 0.08):
        for kind in ("harmonic", "subharmonic"):
            res = marginal_tau(hill_system(m=m, kappa=kappa, nu=nu, forcing="tangential"), kind,
                               tol=1e-10, tau_max=0.5)
            assert res.tau_min is None


@pytest.mark.parametrize("kappa, resonant, others", [(0.02, (3, "subharmonic"), [(5, "harmonic")]),
                                                     (0.08, (2, "subharmonic"), [(5, "harmonic")])])
def test_table_4_1_cases(kappa, resonant, others):
    """Table 4.1 (nu = 2e-4, tau = 0.45; section 4.4, Fig 4.5): the most unstable of m = 2..6 is the
    thesis's resonant mode, by period doubling (lambda0 = sqrt(0.24) ~ 1/2). The corrected model
    also has an m = 5 harmonic tongue (lambda0 ~ 1.1, resp. 2.2 ~ 2 x 1.1) reaching below 0.45,
    which the thesis does not mention."""
    found = {}
    for m in range(2, 7):
        system = hill_system(m=m, kappa=kappa, nu=2e-4)
        for kind in ("harmonic", "subharmonic"):
            res = marginal_tau(system, kind, tol=1e-10)
            assert res.error_estimate < 1e-10
            if res.tau_min < 0.45:
                found[(m, kind)] = res.tau_min
    assert min(found, key=found.get) == resonant
    assert sorted(found) == sorted([resonant] + others)
    assert found[resonant] < 0.11


def test_fig_4_1_fingers():
    """Fig 4.1: principal subharmonic fingers for m = 2..5 near lambda0 = 1/2, i.e.
    kappa_c = 1/(2m(m^2-1)). At nu = 2e-4 their tips sit slightly above kappa_c (the Stokes layer
    lowers the frequency) and below tau = 0.1; at nu = 1e-3 they lift and move further right."""
    for m in range(2, 6):
        kc = 1 / (2 * m * (m * m - 1))
        ks = kc * np.linspace(0.8, 1.4, 31)
        tips = {}
        for nu in (2e-4, 1e-3):
            taus = [marginal_tau(hill_system(m=m, kappa=k, nu=nu), "subharmonic", tol=1e-10).tau_min
                    for k in ks]
            i = int(np.argmin(taus))
            assert 0 < i < len(ks) - 1
            tips[nu] = (ks[i] / kc, taus[i])
        assert 1.0 < tips[2e-4][0] < 1.1 and tips[2e-4][1] < 0.1
        assert tips[1e-3][0] > tips[2e-4][0] and tips[1e-3][1] > 1.5 * tips[2e-4][1]


@pytest.mark.parametrize("bad, fragment", [({"m": 1}, "rigid translation"), ({"m": 0}, "enclosed area"),
                                           ({"m": 2.5}, "m = 2.5"), ({"m": 201}, "m = 201"),
                                           ({"kappa": 0.0}, "kappa = 0.0"), ({"nu": -1e-3}, "nu = -0.001"),
                                           ({"nu": float("nan")}, "nu = nan"),
                                           ({"forcing": "shear"}, "forcing = 'shear'")])
def test_bad_parameters(bad, fragment):
    params = {"m": 3, "kappa": 0.02, "nu": 2e-4, **bad}
    with pytest.raises(ParameterError, match=fragment):
        FibreParams(**params)
    with pytest.raises(ParameterError, match=fragment):
        hill_system(**params)


def test_params_are_frozen_and_cleaned():
    p = FibreParams(m=3.0, kappa=0.02, nu=0)
    assert (p.m, p.kappa, p.nu, p.forcing) == (3, 0.02, 0.0, "both") and isinstance(p.m, int)
    with pytest.raises(ParameterError, match="kappa = '0.02' is invalid"):
        FibreParams(m=3, kappa="0.02", nu=0.0)  # text is not a number (the CLI reads its text first)
    with pytest.raises(AttributeError):
        p.m = 4  # type: ignore[misc]
