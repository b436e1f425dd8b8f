"""Natural modes of the unforced basilar membrane (thesis 5.4) against independent oracles.

Oracles: at alpha = 0 each cosine mode solves Z_k(s) + 1 = 0, which the substitution
r = sqrt(s + zeta k^2) turns into a quartic polynomial in r (roots by numpy.roots, physical sheet
Re r > 0); the inviscid modes are i w_j with w_j^2 the eigenvalues of diag(sqrt(k/2)) C diag(sqrt(k/2));
the argument principle (count of modes in a box) for the coupled case.
"""

import json

import numpy as np
import pytest

import spectralshell as ss
from spectralshell.cli import main
from spectralshell.errors import ParameterError
from spectralshell.models.cochlea import natural_frequencies, natural_mode_family
from spectralshell.solvers.nonlinear_eigen import count_by_winding


def quartic_modes(k, zeta):
    """Roots s of 2 s^2/k + 2 s (zeta k + sqrt(zeta) r) + 1 = 0, s = r^2 - zeta k^2, Re r > 0,
    Im s >= 0."""
    a, b = np.sqrt(zeta), zeta * k * k
    # u = r^2 - b: (2/k) u^2 + 2 zeta k u + 2 a r u + 1 as a polynomial in r (highest power first)
    u = np.poly1d([1.0, 0.0, -b])
    poly = (2.0 / k) * u * u + (2 * zeta * k) * u + np.poly1d([2 * a, 0.0]) * u + 1.0
    r = poly.roots
    s = r[r.real > 0] ** 2 - b
    return np.sort_complex(s[s.imag >= 0])


@pytest.mark.parametrize("zeta", [1e-6, 2e-5, 1e-3, 0.05])
def test_uniform_stiffness_modes_match_the_quartic(zeta):
    """alpha = 0, M = 6: every mode equals the physical root of mode k's quartic, and each quartic
    has exactly one physical root with Im s >= 0 (so none is missed)."""
    res = ss.natural_modes("cochlea", zeta=zeta, alpha=0.0, n_spatial=6)
    want = []
    for k in range(1, 7):
        roots = quartic_modes(k, zeta)
        assert roots.size == 1
        want.append(roots[0])
    got = np.sort_complex(res.gamma)
    np.testing.assert_allclose(got, np.sort_complex(np.array(want)), rtol=1e-12)
    assert np.all(res.error_estimate < 1e-12) and not res.warnings


def test_coupled_modes_small_zeta():
    """alpha = 1.56, M = 20, zeta = 2e-5 (Table 5.1, thesis Fig 5.7 left): 20 decaying
    oscillatory modes; the argument principle counts exactly 20 modes in a box around them; as zeta -> 0 they approach the inviscid i w_j with an O(sqrt(zeta)) shift."""
    res = ss.natural_modes("cochlea", zeta=2e-5, alpha=1.56, n_spatial=20)
    g = res.gamma
    assert g.size == 20 and np.all(g.real < 0) and np.all(g.imag > 0) and not res.warnings
    T, dT = natural_mode_family(alpha=1.56, n_spatial=20)(2e-5)
    left, height = 1.5 * g.real.min(), 1.2 * g.imag.max()
    box = [left + 0.05j, 0.01 + 0.05j, 0.01 + 1j * height, left + 1j * height]
    assert count_by_winding(T, box, dT=dT) == 20
    w = natural_frequencies(1.0, 1.56, np.arange(1, 21))
    shift = {z: np.max(np.abs(np.sort(ss.natural_modes("cochlea", zeta=z, alpha=1.56,
                                                           n_spatial=20).gamma.imag) - w))
             for z in (1e-8, 1e-6)}
    assert shift[1e-8] < 1e-3 and 5 < shift[1e-6] / shift[1e-8] < 20   # ~ sqrt(100) = 10


def test_large_zeta_least_damped_is_nearly_real():
    """zeta = 1e-2 (Fig 5.7 right): the least damped modes decay essentially without oscillating
    (|Im| / |Re| < 1e-3; measured 1.5e-6, 2.0e-5, 2.3e-4), as the thesis says; all modes decay."""
    res = ss.natural_modes("cochlea", zeta=1e-2, alpha=1.56, n_spatial=20, count=3)
    assert np.all(res.gamma.real < 0)
    assert np.all(np.abs(res.gamma.imag) < 1e-3 * np.abs(res.gamma.real))


def test_units_and_errors(capsys):
    """(kappa, nu) gives rates in units of the forcing frequency: gamma = sqrt(kappa) s(zeta)."""
    a = ss.natural_modes("cochlea", zeta=1e-3, alpha=0.5, n_spatial=5, count=2).gamma
    b = ss.natural_modes("cochlea", kappa=4.0, nu=2e-3, alpha=0.5, n_spatial=5, count=2).gamma
    np.testing.assert_allclose(b, 2 * a, rtol=1e-12)
    with pytest.raises(ParameterError, match="n_spatial"):
        ss.natural_modes("cochlea", zeta=1e-3, alpha=0.5)
    code = main(["modes", "cochlea", "--sigma", "6e5", "--n-spatial", "8", "--count", "2", "--json"])
    data = json.loads(capsys.readouterr().out)
    assert code == 0 and data["params"]["units"] == "s^-1" and len(data["modes"]) == 2
    assert data["params"]["zeta"] == pytest.approx(0.02 / np.sqrt(6e5 * (3.5 / np.pi)**3))


@pytest.mark.slow  # 50-70 s: make test-all
def test_modes_just_above_the_cut_are_on_the_sheet_by_an_independent_count():
    """zeta = 1e-2, alpha = 1.56, M = 20: the three least damped modes are nearly real decays
    1e-8..1e-6 above the branch cut s < -zeta (thesis Fig 5.7 right). Each is on the principal
    sheet and not on the cut, with a sheet margin millions of times its error: an
    argument-principle count of det T at 30 digits (the mpmath residual, independent of the
    double-precision continuation) on a circle around it that stays above the cut finds one
    root. (The margin's error was once scaled by Re beta, which is small there while |beta|
    is not: it came out ~1e-8, a hundredth of the margin.)"""
    import mpmath

    from spectralshell.models.cochlea import natural_mode_residual_mp, sheet_margin
    from spectralshell.params.registry import make_params
    from spectralshell.models.cochlea import mode_family
    from spectralshell.solvers.continued_modes import continued_modes, margin_error

    zeta, M = 1e-2, 20
    family = mode_family(make_params("cochlea", dict(kappa=1.0, nu=zeta, alpha=1.56,
                                                     n_spatial=M)))
    modes = continued_modes(family, count=3)
    s = modes.gamma / family.gamma_scale
    error = modes.error / family.gamma_scale
    assert np.all((s.real < -zeta) & (s.imag > 0) & (s.imag < 1e-6)) and not modes.on_cut.any()
    for root, err in zip(s, error):
        margin = sheet_margin(root, zeta, M)
        assert margin > 1e6 * margin_error(family, root, err, margin)
        radius = root.imag / 2
        with mpmath.workdps(30):
            theta = np.linspace(0.0, 2 * np.pi, 65)
            dets = [complex(natural_mode_residual_mp(complex(root + radius * np.exp(1j * t)),
                                                     zeta=zeta, alpha=1.56, n_spatial=M)[0])
                    for t in theta]
        winding = np.sum(np.angle(np.array(dets[1:]) / np.array(dets[:-1]))) / (2 * np.pi)
        assert round(winding) == 1 and abs(winding - 1) < 1e-6
