"""Cochlea natural modes (thesis 5.4): the mpmath polish (``precision``), the branch that the
zeta continuation used to lose at zeta = 1e-2, real pairs at large zeta, and the winding count.

Oracles (written out here, not the package's functions):
* T(s) = diag(Z_k(s)) + C with Z_k = 2 zeta s beta (beta + k)/k, beta = sqrt(s/zeta + k^2)
  (thesis (5.14), the printed form rather than the package's cancellation-free one) and
  C_kj = c_|k-j| + c_{k+j}, c_j = alpha (1 - (-1)^j e^{-alpha pi})/(pi (alpha^2 + j^2)), in mpmath
  at 40 digits; at alpha = 0 each mode solves Z_k(s) + 1 = 0, solved by mpmath.findroot;
* the quartic of test_cochlea_modes (alpha = 0, numpy.roots) for the real pairs;
* a matrix with known eigenvalues for the winding count.
"""

import json

import mpmath
import numpy as np
import pytest

import spectralshell as ss
from spectralshell.cli import main
from spectralshell.errors import ParameterError
from spectralshell.models.cochlea import natural_mode_family, upper_half_contour
from spectralshell.solvers.nonlinear_eigen import count_by_winding
from test_cochlea_modes import quartic_modes


def z_mp(s, k, zeta):
    beta = mpmath.sqrt(s / zeta + k * k)
    return 2 * zeta * s * beta * (beta + k) / k


def t_mp(s, zeta, alpha, M):
    def c(j):
        if alpha == 0:
            return mpmath.mpf(1 if j == 0 else 0)
        return alpha * (1 - (-1) ** j * mpmath.exp(-alpha * mpmath.pi)) / (mpmath.pi * (alpha**2 + j * j))

    T = mpmath.matrix(M, M)
    for k in range(1, M + 1):
        for j in range(1, M + 1):
            T[k - 1, j - 1] = c(abs(k - j)) + c(k + j)
        T[k - 1, k - 1] += z_mp(s, k, zeta)
    return T


def digits_of(res):
    return [mpmath.mpc(re, im) for re, im in res.gamma_digits]


def test_uniform_stiffness_30_digits_against_findroot():
    """alpha = 0, M = 5, zeta = 1e-3: each 30-digit mode agrees with mpmath.findroot on
    Z_k(s) + 1 = 0 at 40 digits to 1e-29 |s|, and its error estimate is ~1e-30 |s|."""
    zeta = 1e-3
    res = ss.natural_modes("cochlea", zeta=zeta, alpha=0.0, n_spatial=5, precision=30)
    assert res.precision == 30 and len(res.gamma_digits) == 5
    with mpmath.workdps(40):
        z = mpmath.mpf(zeta)
        for s, err in zip(digits_of(res), res.error_estimate):
            want = None
            for k in range(1, 6):  # the mode k whose scalar equation s solves
                if abs(z_mp(s, k, z) + 1) < 1e-20:
                    want = mpmath.findroot(lambda x: z_mp(x, k, z) + 1, s)
            assert want is not None
            assert abs(s - want) <= 1e-29 * abs(want)
            assert 1e-31 * abs(want) <= err <= 1e-29 * abs(want)


def test_graded_stiffness_30_digits_residual():
    """alpha = 1.56, M = 8, zeta = 1e-2: the 30-digit roots agree with the double roots to 1e-12
    and make det T, built here at 40 digits, vanish relative to ||T||^M below 1e-28."""
    alpha, zeta, M = 1.56, 1e-2, 8
    double = ss.natural_modes("cochlea", zeta=zeta, alpha=alpha, n_spatial=M)
    res = ss.natural_modes("cochlea", zeta=zeta, alpha=alpha, n_spatial=M, precision=30)
    assert not res.warnings and len(res.gamma) == M
    np.testing.assert_allclose(res.gamma, double.gamma, rtol=1e-12)
    with mpmath.workdps(40):
        for s in digits_of(res):
            T = t_mp(s, mpmath.mpf(zeta), mpmath.mpf(alpha), M)
            assert abs(mpmath.det(T)) / mpmath.mnorm(T, "F") ** M < 1e-28


def test_precision_units_and_cli(capsys):
    """(kappa, nu) = (4, 2e-3) has zeta = 1e-3 exactly in binary, so its digits are exactly twice
    those for zeta = 1e-3; the CLI prints 30-digit strings; precision < 16 is refused."""
    a = ss.natural_modes("cochlea", zeta=1e-3, alpha=0.5, n_spatial=4, count=2, precision=30)
    b = ss.natural_modes("cochlea", kappa=4.0, nu=2e-3, alpha=0.5, n_spatial=4, count=2, precision=30)
    with mpmath.workdps(40):
        for x, y in zip(digits_of(a), digits_of(b)):
            assert abs(y - 2 * x) <= 1e-29 * abs(y)
    with pytest.raises(ParameterError, match="precision"):
        ss.natural_modes("cochlea", zeta=1e-3, alpha=0.5, n_spatial=4, precision=8)
    code = main(["modes", "cochlea", "--zeta", "1e-2", "--alpha", "1.56", "--n-spatial", "6",
                 "--count", "2", "--precision", "30", "--json"])
    data = json.loads(capsys.readouterr().out)
    assert code == 0 and data["precision"] == 30
    assert all(len(m["gamma_re_digits"].lstrip("-0.")) >= 29 for m in data["modes"])


def test_branch_at_zeta_1e_2_is_found():
    """alpha = 1.56, M = 20, zeta = 1e-2 (Fig 5.7 right): all 20 branches arrive, without a
    warning. The one the old continuation lost (it jumped onto a neighbour's root where two
    branches pass close near zeta = 1e-3) ends at s = -0.026496 + 1.63e-7 i, just above the cut
    s < -zeta. Each mode is a root of T built here (smallest / largest singular value < 1e-13),
    they are distinct, and the
    winding number of det T around the upper half plane of the physical sheet is 20."""
    zeta, alpha, M = 1e-2, 1.56, 20
    res = ss.natural_modes("cochlea", zeta=zeta, alpha=alpha, n_spatial=M)
    g = res.gamma
    assert g.size == M and not res.warnings and np.all(g.imag > 0) and np.all(g.real < 0)
    assert np.min(np.abs(g - (-0.0264962221 + 1.6307e-7j))) < 1e-9
    assert np.min(np.abs(g[:, None] - g[None, :]) + np.eye(M)) > 1e-6
    k, j = np.arange(1, M + 1)[:, None], np.arange(1, M + 1)[None, :]
    c = lambda n: alpha * (1 - (-1.0) ** n * np.exp(-alpha * np.pi)) / (np.pi * (alpha**2 + n * n))  # noqa: E731
    for s in g:
        beta = np.sqrt(s / zeta + k[:, 0] ** 2)
        T = c(np.abs(k - j)) + c(k + j) + np.diag(2 * zeta * s * beta * (beta + k[:, 0]) / k[:, 0])
        sv = np.linalg.svd(T, compute_uv=False)
        assert sv[-1] / sv[0] < 1e-13
    T, dT = natural_mode_family(alpha=alpha, n_spatial=M)(zeta)
    contour = upper_half_contour(zeta=zeta, n_spatial=M, radius=2.0, depth=zeta / 4)
    assert count_by_winding(T, contour, dT=dT) == M


def test_real_pairs_at_large_zeta():
    """alpha = 0, M = 6, zeta = 0.5: where a conjugate pair has met on the negative real axis (modes
    k = 2..6 here; k = 1 stays complex), both real roots are returned (the quartic of mode k has
    two physical real roots): 11 modes from 6 branches."""
    zeta = 0.5
    want = np.sort_complex(np.concatenate([quartic_modes(k, zeta) for k in range(1, 7)]))
    assert want.size == 11
    got = np.sort_complex(ss.natural_modes("cochlea", zeta=zeta, alpha=0.0, n_spatial=6).gamma)
    np.testing.assert_allclose(got, want, rtol=1e-11, atol=0)


def test_winding_count_with_clustered_and_near_contour_roots():
    """det T = prod (s - r_j): 19 real roots crowding geometrically towards the right edge
    (r_j = -0.0005 1.4^j, as the real modes of the cochlea at zeta = 0.3 crowd towards s = 0;
    the phase along that edge turns by many pi within a sub-interval, and sampling the phase
    alone counts 17), one root 1e-9 inside the bottom edge and one 1e-9 outside it: the count is
    the number inside, and changes sign with the orientation."""
    inside = np.concatenate([-0.0005 * 1.4 ** np.arange(19), [-0.15 - 0.075j + 1e-9j]])
    roots = np.concatenate([inside, [-0.15 - 0.075j - 1e-9j, 0.5 + 0.5j, -0.5 - 0.2j]])

    def T(s):
        return np.diag(s - roots)

    def dT(s):
        return np.eye(roots.size)

    box = [-0.3 - 0.075j, -0.075j, 0.075j, -0.3 + 0.075j]
    assert count_by_winding(T, box, dT=dT) == inside.size
    assert count_by_winding(T, box[::-1], dT=dT) == -inside.size
