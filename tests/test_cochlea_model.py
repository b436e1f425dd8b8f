"""Cochlea box model (thesis chapter 5) against independent evidence.

Oracles: mpmath at 30 digits for the transfer function Z_k(s) (the formula of
derivations/cochlea_linear_result.md, itself checked there against fields satisfying the unsteady
Stokes equations); scipy quad (QAWO) for the coupling matrix; scipy.special.mathieu_a/b for the
inviscid single modes (Mathieu equations); scipy's ODE integration of the inviscid coupled system
(monodromy); single-mode runs for the decoupled alpha = 0 block; refinement in N and M.
"""

import json

import mpmath as mp
import numpy as np
import pytest
import scipy.special as special
from scipy.integrate import quad, solve_ivp

import spectralshell as ss
from spectralshell.cli import main
from spectralshell.errors import ParameterError
from spectralshell.models.cochlea import (coupling_matrix, hill_system, natural_frequencies,
                                          stiffness_fourier, transfer, unforced)
from spectralshell.params.cochlea import CochleaParams
from spectralshell.solvers.marginal import marginal_tau, solve_truncation


def mp_transfer(s, k, nu):
    """2 s^2 beta / (k (beta - k)), beta = sqrt(s/nu + k^2), at 30 digits: the printed-family form,
    evaluated where its cancellation does not matter."""
    with mp.workdps(30):
        s, nu = mp.mpc(s), mp.mpf(nu)
        beta = mp.sqrt(s / nu + k * k)
        return complex(2 * s**2 * beta / (k * (beta - k)))


@pytest.mark.parametrize("nu", [1e-9, 1e-6, 1e-3, 0.1, 10.0])
def test_transfer_matches_mpmath(nu):
    """Z_k(s) in double against 30-digit mpmath for nu = 1e-9..10, k = 1..250, |s| <= 40: relative
    error 1e-14 (the cancellation-free form; the printed product loses up to 1e-10)."""
    k = np.array([1, 2, 7, 40, 250])
    s = np.array([0.5j, 1j, 2.5j, 20j, 40.5j, 0.2 + 3j, -0.01 + 0.7j])
    got = transfer(s[:, None], k[None, :], nu)
    want = np.array([[mp_transfer(si, ki, nu) for ki in k] for si in s])
    assert np.all(np.abs(got - want) <= 1e-14 * np.abs(want))


def test_transfer_limits():
    """nu = 0: Z = 2 s^2/k (inviscid added mass); s = 0: Z = 0 (D(0) = kappa C, (5.10))."""
    s = np.array([0.5j, 3j, 0.2 + 1j])
    np.testing.assert_allclose(transfer(s, 3, 0.0), 2 * s * s / 3, rtol=1e-15)
    assert transfer(np.array([0.0]), 5, 1e-3)[0] == 0


def test_passive_and_real_in_time():
    """Re(Z(i w)/(i w)) > 0: the fluid dissipates (viscous); Z(conj s) = conj Z(s); D = D^T."""
    w = np.array([0.05, 0.5, 1.0, 7.5, 40.0])
    for nu in (1e-8, 1e-4, 1.0):
        z = transfer(1j * w[:, None], np.arange(1, 60)[None, :], nu)
        assert np.all((z / (1j * w[:, None])).real > 0)
    s = np.array([0.3 + 2j, 1.5j])
    d = unforced(s, kappa=0.7, nu=1e-3, modes=np.arange(1, 9), coupling=coupling_matrix(np.arange(1, 9), 1.56))
    np.testing.assert_allclose(unforced(s.conj(), kappa=0.7, nu=1e-3, modes=np.arange(1, 9),
                                        coupling=coupling_matrix(np.arange(1, 9), 1.56)), d.conj())
    np.testing.assert_array_equal(d, np.swapaxes(d, 1, 2))


@pytest.mark.filterwarnings("ignore::scipy.integrate.IntegrationWarning")
@pytest.mark.parametrize("alpha", [1e-9, 0.3, 1.56, 4.3, 20.0])
def test_coupling_matrix_matches_quadrature(alpha):
    """C_kj = (2/pi) int_0^pi e^{-alpha x} cos kx cos jx dx by scipy QAWO, k, j up to 41."""
    modes = np.array([1, 2, 3, 9, 40, 41])
    C = coupling_matrix(modes, alpha)
    for a, k in enumerate(modes):
        for b, j in enumerate(modes):
            num = sum(quad(lambda t: np.exp(-alpha * t), 0, np.pi, weight="cos", wvar=w,
                           epsabs=1e-14, epsrel=1e-12)[0] for w in (k - j, k + j)) / np.pi
            assert abs(C[a, b] - num) < 1e-12


def test_coupling_alpha_to_zero_and_definite():
    """alpha -> 0 is continuous (C -> I) with no cancellation; C is positive definite with
    eigenvalues between min and max of e^{-alpha x} (a Gram matrix with that weight)."""
    M = np.arange(1, 41)
    np.testing.assert_allclose(coupling_matrix(M, 1e-13), np.eye(40), atol=1e-12)
    assert np.array_equal(coupling_matrix(M, 0.0), np.eye(40))
    assert stiffness_fourier(np.array([0]), 1e-12)[0] == pytest.approx(1 - np.pi * 1e-12 / 2, abs=1e-16)
    ev = np.linalg.eigvalsh(coupling_matrix(M, 1.56))
    assert ev.min() > np.exp(-1.56 * np.pi) and ev.max() < 1


# (kind, characteristic value, order): Mathieu y'' + (a - 2q cos 2x) y = 0 with a = 4 k', q = 4 k' tau
# for h'' + k'(1 + 2 tau sin t) h = 0 (derivations/mathieu_mapping.py); here k' = kappa K / 2.
ORACLES = [("harmonic", special.mathieu_a, 2), ("harmonic", special.mathieu_b, 2),
           ("subharmonic", special.mathieu_a, 1), ("subharmonic", special.mathieu_b, 3)]


@pytest.mark.parametrize("kind,char_value,order", ORACLES)
@pytest.mark.parametrize("mode", [1, 4])
def test_inviscid_single_mode_is_mathieu(kind, char_value, order, mode):
    """nu = 0, alpha = 0, mode K: (2/K) h'' + kappa (1 + 2 tau sin t) h = 0, a Mathieu equation
    with stiffness kappa K/2; the marginal tau q/(4 k') at k' = a_r(q)/4 must be computed."""
    q = 0.8
    k_eff = char_value(order, q) / 4
    res = ss.floquet("cochlea", kind=kind, kappa=2 * k_eff / mode, nu=0.0, alpha=0.0, spatial_mode=mode)
    assert np.min(np.abs(getattr(res, kind).tau - q / (4 * k_eff))) < 1e-10


def test_alpha_zero_block_decouples_into_single_modes():
    """alpha = 0: the M = 6 block run has exactly the union of the marginal tau of the six single
    modes (viscous, Table 5.1 at omega = 1600, where k = 1..6 resonate at low order)."""
    kappa, nu = 0.2103745080528879, 1.0071024899070775e-05
    block = hill_system(kappa=kappa, nu=nu, alpha=0.0, n_spatial=6)
    for kind in ("harmonic", "subharmonic"):
        whole = solve_truncation(block, kind, 16)[0]
        single = np.sort(np.concatenate([solve_truncation(
            hill_system(kappa=kappa, nu=nu, alpha=0.0, spatial_mode=k), kind, 16)[0] for k in range(1, 7)]))
        small = lambda t: t[t < 5.0]  # noqa: E731
        np.testing.assert_allclose(small(whole), small(single), rtol=1e-10)


def _monodromy(kappa, C, modes, tau):
    inv_mass = np.diag(modes / 2.0)
    M = len(modes)

    def rhs(t, z):
        return np.concatenate([z[M:], -kappa * (1 + 2 * tau * np.sin(t)) * inv_mass @ C @ z[:M]])

    return np.column_stack([solve_ivp(rhs, (0, 2 * np.pi), e, method="DOP853", rtol=1e-12,
                                      atol=1e-14).y[:, -1] for e in np.eye(2 * M)])


@pytest.mark.parametrize("kind,kappa", [("harmonic", 1.0), ("subharmonic", 0.8)])
def test_inviscid_coupled_tau_min_gives_multiplier_plus_minus_one(kind, kappa):
    """Oracle for the coupled block (alpha = 1.56, M = 5, nu = 0): the ODE system
    (2/k) h_k'' + kappa (1 + 2 tau sin t) (C h)_k = 0 integrated over one period by DOP853. At each
    kind's tau_min a Floquet multiplier is +1 (harmonic) or -1 (subharmonic)."""
    M = 5
    modes = np.arange(1, M + 1)
    m = getattr(ss.floquet("cochlea", kind=kind, kappa=kappa, nu=0.0, alpha=1.56, n_spatial=M), kind)
    target = 1.0 if kind == "harmonic" else -1.0
    q = np.linalg.eigvals(_monodromy(kappa, coupling_matrix(modes, 1.56), modes, m.tau_min))
    assert m.tau_min < 1 and np.min(np.abs(q - target)) < 1e-6


def test_natural_frequencies():
    """alpha = 0: w_k = sqrt(kappa k/2); the block's n_resonant is the lowest one."""
    np.testing.assert_allclose(natural_frequencies(0.3, 0.0, np.arange(1, 6)),
                               np.sqrt(0.3 * np.arange(1, 6) / 2), rtol=1e-14)
    assert hill_system(kappa=0.3, nu=1e-4, alpha=1.56, n_spatial=8).n_resonant == pytest.approx(
        natural_frequencies(0.3, 1.56, np.arange(1, 9))[0])


def test_temporal_convergence_is_fast():
    """Thesis 5.3 (Fig 5.5): convergence in N is much faster than in M. At omega = 400 rad/s,
    M = 12, tau_min at N = 8 already agrees with N = 16 to 1e-12."""
    sys_ = hill_system(kappa=3.365992128846207, nu=4.02840995962831e-05, alpha=1.56, n_spatial=12)
    for kind in ("harmonic", "subharmonic"):
        a, b = (solve_truncation(sys_, kind, n)[0][0] for n in (8, 16))
        assert abs(a - b) < 1e-12


@pytest.mark.slow
def test_spatial_convergence_omega_400():
    """Thesis 5.3 (Fig 5.6): epsilon_M = |tau(2M) - tau(M)| shrinks under refinement (omega = 400,
    alpha = 1.56, N = 16): the subharmonic tau_min changes by > 1e-3 from 16 to 32 modes and by
    < 1e-4 from 48 to 64 (measured: 1.6e-2, 3.9e-4, 2.3e-5 for 16->32->48->64)."""
    kappa, nu = 3.365992128846207, 4.02840995962831e-05
    tau = {M: solve_truncation(hill_system(kappa=kappa, nu=nu, alpha=1.56, n_spatial=M),
                               "subharmonic", 16)[0][0] for M in (16, 32, 48, 64)}
    assert abs(tau[32] - tau[16]) > 1e-3
    assert abs(tau[48] - tau[32]) > abs(tau[64] - tau[48])
    assert abs(tau[64] - tau[48]) < 1e-4


# Table 5.2 (k = 1, alpha = 0, Table 5.1 otherwise): unstable kinds at each (omega, tau).
TABLE_5_2 = {(900, 0.1): False, (1000, 0.1): True, (1100, 0.1): False,
             (900, 0.2): False, (1000, 0.2): True, (1100, 0.2): True}


@pytest.mark.parametrize("omega", [900, 1000, 1100])
def test_table_5_2(omega):
    """Table 5.2 reproduced: k = 1 mode, uniform stiffness. Unstable at tau when an odd number of
    a kind's marginal amplitudes lie below tau (one oscillator: entering and leaving a finger).
    All six cases agree with the thesis; the unstable ones are the principal subharmonic finger
    (tau_min = 0.0686 at 1000 rad/s, 0.1260 at 1100 rad/s; 0.256 at 900 rad/s)."""
    res = ss.floquet("cochlea", omega=omega, alpha=0.0, spatial_mode=1)
    for tau in (0.1, 0.2):
        unstable = any(len([t for t in getattr(res, k).tau if t < tau]) % 2 == 1
                       for k in ("harmonic", "subharmonic"))
        assert unstable == TABLE_5_2[(omega, tau)]


def test_params_validation():
    with pytest.raises(ParameterError, match="spatial_mode"):
        CochleaParams(kappa=1, nu=0, alpha=1.56, spatial_mode=1)
    with pytest.raises(ParameterError, match="n_spatial"):
        CochleaParams(kappa=1, nu=0, alpha=0, spatial_mode=1, n_spatial=4)
    with pytest.raises(ParameterError, match="kappa"):
        CochleaParams(kappa=0, nu=0, alpha=0)
    with pytest.raises(ParameterError, match="n_spatial"):
        CochleaParams(kappa=1, nu=0, alpha=0, n_spatial=0)
    with pytest.raises(ParameterError, match="omega"):
        ss.floquet("cochlea", sigma=1e6, alpha=0, spatial_mode=1)
    with pytest.raises(ParameterError, match="mu"):
        ss.floquet("cochlea", omega=400, mu=0.02, nu=1e-4, alpha=0, spatial_mode=1)


def test_cli_json_shape(capsys):
    code = main(["floquet", "cochlea", "--omega", "1000", "--alpha", "0", "--n-spatial", "4", "--json"])
    data = json.loads(capsys.readouterr().out)
    assert code == 0 and data["model"] == "cochlea" and data["n_spatial"] == 4
    assert data["n_spatial_previous"] == 2
    assert data["params"]["kappa"] == pytest.approx(6e5 * np.pi / (3.5 * 1000**2), rel=1e-14)
    for kind in ("harmonic", "subharmonic"):
        assert {"tau", "tau_min", "n_temporal", "error_estimate"} <= set(data[kind])
    # alpha = 0, modes 1..4: the subharmonic minimum is the k = 1 principal finger of Table 5.2
    assert data["subharmonic"]["tau_min"] == pytest.approx(0.0686107756923, abs=1e-11)
    code = main(["floquet", "cochlea", "--omega", "1000", "--spatial-mode", "1"])
    assert code == 2 and "alpha = 0" in capsys.readouterr().err
