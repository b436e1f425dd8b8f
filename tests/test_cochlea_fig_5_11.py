"""Fig 5.11: marginal tau against a continuous wavenumber k, uniform stiffness (thesis 5.6.1).

Oracles:
* inviscid (nu = 0) mode k is the Mathieu equation h'' + (kappa k/2)(1 + 2 tau sin t) h = 0,
  i.e. y'' + (a - 2q cos 2x) y = 0 with a = 2 kappa k, q = 2 kappa k tau (t = 2x + const):
  scipy.special.mathieu_a/b give the finger boundaries at real, non-integer k, and the fingers touch
  tau = 0 exactly where sqrt(kappa k/2) = j/2, i.e. k_j = j^2/(2 kappa);
* viscous principal subharmonic finger: the balance of the two harmonics e^{+-it/2} alone gives
  tau = |Z_k(i/2) + kappa|/kappa, minimised over k, with Z_k = 2 nu s beta (beta + k)/k,
  beta = sqrt(s/nu + k^2) (thesis (5.9) written out in the validation report's oracle
  ``two_harmonic_tip``, not the package's model form). The neglected
  harmonics e^{+-3it/2} change the tip's k by a relative ~tau^2/8 (they add ~(tau kappa)^2/D(3i/2)
  = -tau^2 kappa/8 to Re D) and its tau only at second order in that.
"""

import functools
import json

import numpy as np
import pytest
from scipy import special

from spectralshell.errors import ParameterError
from spectralshell.models.cochlea import wavenumber_system
from spectralshell.params.physical import TABLE_5_1, cochlea_forced
from spectralshell.reports.figures import FIGURES, make_figure
from spectralshell.reports.validation import two_harmonic_tip
from spectralshell.runner import map_points
from spectralshell.solvers.marginal import marginal_tau
from spectralshell.solvers.tongues import find_tips

KINDS = ("harmonic", "subharmonic")
BASE = {k: TABLE_5_1[k] for k in ("rho", "mu", "sigma", "length", "lambda_c")}
OMEGA_500 = cochlea_forced(**BASE, omega=500.0)
OMEGA_1000 = cochlea_forced(**BASE, omega=1000.0)

# (kind, characteristic value, order): even orders are 2 pi-periodic in t (harmonic), odd 4 pi.
ORACLES = [("harmonic", special.mathieu_a, 2), ("harmonic", special.mathieu_b, 2),
           ("subharmonic", special.mathieu_a, 1), ("subharmonic", special.mathieu_b, 1),
           ("subharmonic", special.mathieu_a, 3), ("subharmonic", special.mathieu_b, 3)]


def test_registered():
    assert "fig-5.11" in FIGURES


@pytest.mark.parametrize("kind,char_value,order", ORACLES)
def test_inviscid_real_wavenumber_is_mathieu(kind, char_value, order):
    """nu = 0 at the omega = 500 kappa: the finger boundary through q = 0.5 lies at the real
    wavenumber k = a_r(q)/(2 kappa) with tau = q/a_r(q)."""
    kappa, q = OMEGA_500["kappa"], 0.5
    a = char_value(order, q)
    k = a / (2 * kappa)
    assert abs(k - round(k)) > 0.04  # a genuinely non-integer wavenumber
    res = marginal_tau(wavenumber_system(k, kappa=kappa, nu=0.0), kind, tol=1e-12)
    assert np.min(np.abs(res.tau - q / a)) < 1e-10


def test_inviscid_tips_at_half_integer_frequencies():
    """nu = 0: the engine's finger tips over k lie at k_j = j^2/(2 kappa), tau = 0, alternating
    subharmonic (j odd) and harmonic (j even)."""
    kappa = OMEGA_500["kappa"]
    factory = functools.partial(wavenumber_system, kappa=kappa, nu=0.0)
    grid = np.linspace(0.05, 2.5, 30)
    rows = map_points(factory, list(grid), KINDS, executor="serial", tol=1e-10, tau_max=1.0)
    tips, failures = find_tips(factory, grid, rows, KINDS, tol=1e-10)
    assert not failures and len(tips) == 3
    for j, tip in enumerate(tips, start=1):
        assert tip.kind == ("subharmonic" if j % 2 else "harmonic")
        assert tip.kappa == pytest.approx(j * j / (2 * kappa), rel=1e-11)  # Tip.kappa holds k here
        assert tip.tau == 0.0


@pytest.mark.parametrize("params", [OMEGA_500, OMEGA_1000], ids=["omega500", "omega1000"])
def test_viscous_principal_tip_against_two_harmonic_balance(params):
    """Table 5.1 at omega = 500 and 1000 rad/s: the tip of the principal subharmonic finger
    matches the two-harmonic balance to within tau^2/4 (relative) in k and in tau."""
    kappa, nu = params["kappa"], params["nu"]
    factory = functools.partial(wavenumber_system, kappa=kappa, nu=nu)
    k1 = 1 / (2 * kappa)
    grid = np.linspace(0.9 * k1, 1.1 * k1, 9)
    rows = map_points(factory, list(grid), ("subharmonic",), executor="serial", tol=1e-12)
    tips, failures = find_tips(factory, grid, rows, ("subharmonic",), tol=1e-12)
    assert not failures and len(tips) == 1
    k_tip, tau_tip = two_harmonic_tip(kappa, nu)
    assert 1e-3 < tau_tip < 1e-2  # damped: lifted off zero by the Stokes layers
    assert abs(tips[0].tau / tau_tip - 1) < tau_tip**2 / 4
    assert abs(tips[0].kappa / k_tip - 1) < tau_tip**2 / 4


def test_wavenumber_must_be_positive():
    with pytest.raises(ParameterError, match="wavenumber"):
        wavenumber_system(0.0, kappa=1.0, nu=1e-5)


@pytest.mark.slow
def test_figure(tmp_path):
    """fig-5.11 writes its files; at both frequencies the tips alternate S, H, S, ... starting
    with the principal subharmonic at the two-harmonic k, each to the right of its inviscid k_j
    and higher than the one before (damping grows with k); k = 1 is unstable below tau = 1/2 at
    both (omega = 1000: subharmonic tau_min < 0.1, as Table 5.2 says)."""
    paths = make_figure("fig-5.11", tmp_path)
    assert all(p.exists() and p.stat().st_size > 0 for p in paths)
    data = json.loads((tmp_path / "fig-5.11.json").read_text())
    for omega, params in (("500.0", OMEGA_500), ("1000.0", OMEGA_1000)):
        panel = data[omega]
        tips = panel["tips"]
        assert not panel["tip_failures"] and len(tips) >= 3
        for j, tip in enumerate(tips, start=1):
            assert tip["kind"] == ("subharmonic" if j % 2 else "harmonic")
            assert tip["k"] > panel["inviscid_tips_k"][j - 1]
        assert np.all(np.diff([t["tau"] for t in tips]) > 0)
        k_tip, tau_tip = two_harmonic_tip(params["kappa"], params["nu"])
        assert tips[0]["k"] == pytest.approx(k_tip, rel=tau_tip**2 / 4)
        assert 1 in panel["unstable_integer_k"]
    assert data["1000.0"]["integer_k_tau_min"]["subharmonic"]["1"] < 0.1
