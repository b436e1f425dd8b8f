"""Periodic cylindrical membrane (thesis 8.1) against independent evidence.

Oracles: the 2D fibre model (independent code, thesis chapter 4) at k = 0; the membrane law
F = K (X_thetatheta + X_zz) applied by finite differences to displaced surfaces (elastic load and
rigid motions); the mpmath D(s) of derivations/cylinder.py (fields built from mpmath's own Bessel
functions, residuals checked there); the inviscid closed form with scipy's Bessel functions;
scipy's ODE monodromy of the inviscid Mathieu limit.
"""

import sys
from pathlib import Path

import mpmath as mp
import numpy as np
import pytest
import scipy.special as sc

import spectralshell as ss
from spectralshell.errors import ParameterError
from spectralshell.models.cylinder import (elastic_matrix, fluid_load, hill_system, lambda0_squared,
                                           unforced)
from spectralshell.solvers.marginal import marginal_tau

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "derivations"))
import cylinder as derivation  # noqa: E402  (derivations/cylinder.py, mpmath fields)


@pytest.mark.slow
def test_derivation_script_passes():
    """derivations/cylinder.py: every symbolic and 30-digit check passes (about 1 minute)."""
    import subprocess
    done = subprocess.run([sys.executable, str(Path(derivation.__file__))], capture_output=True,
                          text=True, timeout=600, cwd=Path(derivation.__file__).parent)
    assert done.returncode == 0, done.stdout + done.stderr


@pytest.mark.parametrize("m, nu, kappa", [(2, 1e-3, 0.05), (3, 2e-4, 0.02), (5, 0.05, 0.3)])
def test_k_zero_is_the_fibre(m, nu, kappa):
    """k = 0: tau_min of both kinds equals the fibre model's (thesis 4, independent code)."""
    cyl = ss.floquet("cylinder", m=m, k=0.0, kappa=kappa, nu=nu)
    fib = ss.floquet("fibre", m=m, kappa=kappa, nu=nu)
    for kind in ("harmonic", "subharmonic"):
        a, b = getattr(cyl, kind).tau_min, getattr(fib, kind).tau_min
        assert abs(a - b) <= 1e-10 * max(1.0, abs(b)), (kind, a, b)


def test_k_zero_inviscid_is_the_fibre():
    cyl = ss.floquet("cylinder", m=3, k=0.0, kappa=0.02, nu=0.0)
    fib = ss.floquet("fibre", m=3, kappa=0.02, nu=0.0)
    assert abs(cyl.subharmonic.tau_min - fib.subharmonic.tau_min) <= 1e-10


def _membrane_load(X, kappa=1.0, h=1e-2):
    """Linear part of F + K N (F = K (X_thth + X_zz), N = X_th x X_z, [[p0]] = -K) at
    (theta, z) = (0.4, 0.3) by finite differences (4th order) of the displaced surface
    X0 + eps X1, central in eps (exact for the quadratic N)."""
    def load(eps, th, z):
        def pos(a, b):
            return np.array([np.cos(a), np.sin(a), b]) + eps * X(a, b)

        def d(f, i, a, b):  # 4th-order first derivative in direction i
            e = np.array([h, 0.0]) if i == 0 else np.array([0.0, h])
            return (-f(a + 2 * e[0], b + 2 * e[1]) + 8 * f(a + e[0], b + e[1])
                    - 8 * f(a - e[0], b - e[1]) + f(a - 2 * e[0], b - 2 * e[1])) / (12 * h)

        def d2(i, a, b):
            e = np.array([h, 0.0]) if i == 0 else np.array([0.0, h])
            return (-pos(a + 2 * e[0], b + 2 * e[1]) + 16 * pos(a + e[0], b + e[1]) - 30 * pos(a, b)
                    + 16 * pos(a - e[0], b - e[1]) - pos(a - 2 * e[0], b - 2 * e[1])) / (12 * h * h)

        F = kappa * (d2(0, th, z) + d2(1, th, z))
        N = np.cross(d(pos, 0, th, z), d(pos, 1, th, z))
        return F + kappa * N

    th, z, eps = 0.4, 0.3, 1e-2
    full = (load(eps, th, z) - load(-eps, th, z)) / (2 * eps)
    rh, tt, zh = np.array([np.cos(th), np.sin(th), 0]), np.array([-np.sin(th), np.cos(th), 0]), np.eye(3)[2]
    return np.array([full @ rh, full @ tt, full @ zh]), th, z


@pytest.mark.parametrize("m, k", [(2, 0.7), (0, 1.3), (1, 0.4), (3, 0.0)])
def test_elastic_matrix_from_the_membrane_law(m, k):
    """-K E X equals the linearised membrane force with prestress, from the surface itself."""
    x = np.array([0.7, -0.4, 0.3])
    rh = lambda a: np.array([np.cos(a), np.sin(a), 0.0])  # noqa: E731
    tt = lambda a: np.array([-np.sin(a), np.cos(a), 0.0])  # noqa: E731

    def X(a, b):
        ph = m * a + k * b
        return x[0] * np.cos(ph) * rh(a) + x[1] * np.sin(ph) * tt(a) + x[2] * np.sin(ph) * np.eye(3)[2]

    load, th, z = _membrane_load(X)
    ph = m * th + k * z
    expected = -(elastic_matrix(m, k) @ x) * np.array([np.cos(ph), np.sin(ph), np.sin(ph)])
    assert np.allclose(load, expected, atol=1e-6)


@pytest.mark.parametrize("name, X, m, k, x", [
    ("rigid translation", lambda a, b: np.array([1.0, 0.0, 0.0]), 1, 0.0, [1.0, -1.0, 0.0]),
    ("rigid axial shift", lambda a, b: np.array([0.0, 0.0, 1.0]), 0, 0.0, [0.0, 0.0, 1.0]),
])
def test_rigid_motions_carry_no_elastic_load(name, X, m, k, x):
    """m = 1, k = 0 (translation e_x = cos r - sin theta) and m = 0, k = 0 (X^z = const): the
    membrane law gives no load, and E(m, k) annihilates the mode; D(s) -> 0 on it as s -> 0."""
    load, _, _ = _membrane_load(X)
    assert np.abs(load).max() < 1e-6
    assert np.abs(elastic_matrix(m, k) @ np.array(x)).max() == 0.0
    # the fluid load vanishes with the velocity: D(s) X = O(s)
    if m == 1:
        for s in (1e-4j, 1e-6j):
            D = fluid_load(np.array([s]), m=m, k=k, nu=0.1)[0] + 0.3 * elastic_matrix(m, k)
            assert np.abs(D @ np.array(x)).max() < 50 * abs(s)


@pytest.mark.parametrize("m, k, nu", [(2, 0.7, 0.05), (0, 1.3, 0.3), (1, 2.0, 0.01), (4, 0.2, 1e-9),
                                      (3, 5.0, 1e-6)])
def test_unforced_matches_mpmath_fields(m, k, nu):
    """Float D(s) against the derivation's mpmath D(s) (besseli/besselk at 30 digits, fields whose
    Stokes residuals and interface conditions are checked there), nu down to 1e-9, |s| to 300."""
    idx = [0, 2] if m == 0 else [0, 1, 2]
    for s in (0.3 + 1.7j, -0.2 + 30.5j, 0.05 - 0.7j, 300j):
        with mp.workdps(30):
            ref = derivation.D_real(m, mp.mpf(k), mp.mpc(s), mp.mpf(nu), mp.mpf("0.3"))
            ref = np.array([[complex(ref[i, j]) for j in idx] for i in idx])
        got = unforced(np.array([s]), m=m, k=k, kappa=0.3, nu=nu)[0]
        assert np.abs(got - ref).max() <= 1e-11 * np.abs(ref).max(), s


@pytest.mark.parametrize("m, k", [(2, 0.7), (0, 1.5), (1, 0.3), (6, 3.0)])
def test_reciprocity_and_reality(m, k):
    """The fluid's velocity-to-traction map is symmetric (Lorentz reciprocity) and real in time."""
    s = np.array([0.2 + 1.3j, -0.3 + 2.2j, 0.05 - 0.7j, 4.0 + 0.1j])
    H = fluid_load(s, m=m, k=k, nu=0.02)
    assert np.abs(H - np.swapaxes(H, 1, 2)).max() <= 1e-12 * np.abs(H).max()
    Hc = fluid_load(s.conj(), m=m, k=k, nu=0.02)
    assert np.abs(Hc - H.conj()).max() <= 1e-12 * np.abs(H).max()


def _added_mass(m, k):
    """I_m/(k I_m') - K_m/(k K_m') with scipy's Bessel functions and derivatives."""
    return sc.iv(m, k) / (k * sc.ivp(m, k)) - sc.kv(m, k) / (k * sc.kvp(m, k))


@pytest.mark.parametrize("m, k", [(2, 0.5), (0, 1.6), (1, 0.8), (4, 2.5)])
def test_inviscid_limit_closed_form(m, k):
    """nu -> 0: the radial Schur complement of D(s) tends to M (s^2 + lambda0^2),
    lambda0^2 = kappa (m^2 + k^2 - 1)/M, at the Stokes-layer rate sqrt(nu)."""
    kappa = 0.3
    M = _added_mass(m, k)
    lam2 = kappa * (m * m + k * k - 1) / M
    assert abs(lambda0_squared(m, k, kappa) - lam2) <= 1e-12 * lam2
    s = 0.15 + 0.9j
    errs = []
    for nu in (1e-6, 1e-8, 1e-9):
        D = unforced(np.array([s]), m=m, k=k, kappa=kappa, nu=nu)[0]
        schur = D[0, 0] - D[0, 1:] @ np.linalg.solve(D[1:, 1:], D[1:, 0])
        errs.append(abs(schur / M - (s * s + lam2)) / abs(s * s + lam2))
    assert errs[-1] < 3e-4 and errs[0] > errs[1] > errs[2]
    assert abs(np.log(errs[0] / errs[1]) / np.log(100) - 0.5) < 0.05


def test_inviscid_tau_min_against_time_integration(monodromy):
    """nu = 0: tau_min against scipy's monodromy matrix of X'' + lambda0^2 (1 + 2 tau sin t) X = 0
    with the closed-form lambda0 (scipy Bessel functions); viscous tau_min tends to it."""
    m, k, kappa = 2, 0.6, 0.05
    lam2 = kappa * (m * m + k * k - 1) / _added_mass(m, k)
    tau = ss.floquet("cylinder", m=m, k=k, kappa=kappa, nu=0.0, kind="subharmonic").subharmonic.tau_min
    below = np.abs(np.linalg.eigvals(monodromy(lam2, 0.0, tau * (1 - 1e-3))))
    above = np.abs(np.linalg.eigvals(monodromy(lam2, 0.0, tau * (1 + 1e-3))))
    assert np.max(below) < 1 + 1e-8 and np.max(above) > 1 + 1e-4
    viscous = marginal_tau(hill_system(m=m, k=k, kappa=kappa, nu=1e-9), "subharmonic", tol=1e-10).tau_min
    assert 0 < viscous - tau < 1e-3


def test_decoupled_components():
    """m = 0: torsion is X^theta alone; k = 0: axial is X^z alone; both are pumped by kappa E_jj."""
    t = hill_system(m=0, k=1.5, kappa=0.2, nu=0.01, component="torsion")
    a = hill_system(m=3, k=0.0, kappa=0.2, nu=0.01, component="axial")
    assert t.block_size == a.block_size == 1
    assert t.forcing[0, 0] == pytest.approx(0.2 * 1.5**2) and a.forcing[0, 0] == pytest.approx(0.2 * 9)
    full = unforced(np.array([0.3 + 1j]), m=0, k=1.5, kappa=0.2, nu=0.01)  # sausage pair
    assert full.shape == (1, 2, 2)
    D3 = derivation.D_real(0, mp.mpf(1.5), mp.mpc(0.3, 1), mp.mpf("0.01"), mp.mpf("0.2"))
    got = unforced(np.array([0.3 + 1j]), m=0, k=1.5, kappa=0.2, nu=0.01, component="torsion")[0, 0, 0]
    assert abs(got - complex(D3[1, 1])) < 1e-12 * abs(got)


def test_api_and_cli_contract():
    r = ss.floquet("cylinder", m=3, k=0.5, kappa=0.02, nu=2e-4)
    assert 0 < r.subharmonic.tau_min < 1
    import json
    import subprocess
    out = subprocess.run([sys.executable, "-m", "spectralshell", "floquet", "cylinder", "--m", "3",
                          "--k", "0.5", "--kappa", "0.02", "--nu", "2e-4", "--json"],
                         capture_output=True, text=True, timeout=120,
                         cwd=Path(__file__).resolve().parents[1])
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)
    assert data["model"] == "cylinder" and data["params"]["k"] == 0.5
    assert abs(data["subharmonic"]["tau_min"] - r.subharmonic.tau_min) < 1e-12


@pytest.mark.parametrize("params, name", [
    (dict(m=3, k=-0.5, kappa=0.02, nu=2e-4), "k"),
    (dict(m=-1, k=0.5, kappa=0.02, nu=2e-4), "m"),
    (dict(m=3, k=0.5, kappa=0.02), "nu"),
    (dict(m=3, k=0.5, kappa=0.0, nu=2e-4), "kappa"),
    (dict(m=3, k=0.5, kappa=0.02, nu=-1.0), "nu"),
    (dict(m=0, k=0.5, kappa=0.02, nu=2e-4), "k"),      # Rayleigh-Plateau unstable
    (dict(m=1, k=0.0, kappa=0.02, nu=2e-4), "k"),      # rigid translation
    (dict(m=2, k=0.5, kappa=0.02, nu=2e-4, component="torsion"), "component"),
    (dict(m=0, k=2.0, kappa=0.02, nu=2e-4, component="axial"), "component"),
    (dict(m=0, k=2.0, kappa=0.02, nu=0.0, component="torsion"), "nu"),
])
def test_bad_input_names_the_parameter(params, name):
    with pytest.raises(ParameterError, match=rf"^{name} "):
        ss.floquet("cylinder", **params)


def test_physical_input_matches_the_scalings():
    """cgs input: kappa = sigma/(rho R^3 omega^2), nu = mu/(rho R^2 omega), k = 2 pi j R/L
    (computed here by hand) give the same tau_min as the dimensionless call."""
    rho, mu, R, sigma, omega, L, j = 1.0, 0.02, 0.2, 2e4, 2500.0, 2.5, 1
    phys = ss.floquet("cylinder", m=3, rho=rho, mu=mu, radius=R, sigma=sigma, omega=omega,
                      period=L, j=j, kind="harmonic")
    dimless = ss.floquet("cylinder", m=3, k=2 * np.pi * j * R / L, kappa=sigma / (rho * R**3 * omega**2),
                         nu=mu / (rho * R**2 * omega), kind="harmonic")
    assert phys.harmonic.tau_min == pytest.approx(dimless.harmonic.tau_min, abs=1e-10)
    with pytest.raises(ParameterError, match="^j "):
        ss.floquet("cylinder", m=3, rho=rho, mu=mu, radius=R, sigma=sigma, omega=omega, period=L)
    with pytest.raises(ParameterError, match="^kappa "):
        ss.floquet("cylinder", m=3, k=0.5, kappa=0.1, rho=rho, mu=mu, radius=R, sigma=sigma,
                   omega=omega)


def test_tau_map_over_k_and_kappa_matches_floquet():
    """The minimum-tau map over (k R, kappa) (a sweep) agrees with independent floquet solves."""
    ds = ss.tau_map("cylinder", x=("k", "0.2:3:4"), y=("kappa", "0.01:0.05:3"), m="1:4", nu=2e-4,
                    workers=1)
    cell = ds["tau_min"].sel(kind="subharmonic", m=3).isel(k=2, kappa=0)
    k, kappa = float(ds.k[2]), float(ds.kappa[0])
    ref = ss.floquet("cylinder", m=3, k=k, kappa=kappa, nu=2e-4, kind="subharmonic").subharmonic
    assert ref.tau_min < 0.5 and float(cell) == pytest.approx(ref.tau_min, abs=1e-7)
