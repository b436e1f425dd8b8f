"""Fibre figures and thesis claims of 4.2-4.4 (Fig 4.2: the pressure jump drives the instability)."""

import json

import numpy as np
import pytest
from scipy.optimize import brentq

import spectralshell as ss
from spectralshell.cli import main
from spectralshell.models.fibre import hill_system
from spectralshell.params.physical import TABLE_4_1, fibre_forced
from spectralshell.reports import figures


def test_pressure_jump_carries_the_instability():
    """Thesis 4.2 / Fig 4.2: pumping only the pressure jump nearly reproduces the principal
    subharmonic threshold; pumping only the tangential stress gives no instability with tau <= 1/2."""
    common = dict(m=3, kappa=0.0219, nu=2e-4, kind="subharmonic")
    both = ss.floquet("fibre", forcing="both", **common).subharmonic.tau_min
    pressure = ss.floquet("fibre", forcing="pressure", **common).subharmonic.tau_min
    tangential = ss.floquet("fibre", forcing="tangential", tau_max=0.5, **common).subharmonic
    assert abs(pressure - both) < 0.02 * both
    assert tangential.tau_min is None


@pytest.mark.parametrize("case,m", [(1, 3), (2, 2)])
def test_table_4_1_resonant_mode(case, m):
    """Thesis 4.4: at tau = 0.45 the simulations of Table 4.1 grow in m = 3 (case 1) and m = 2
    (case 2) with period doubling; these are the least-threshold unstable degrees."""
    res = ss.stability("fibre", tau=0.45, m="2:6", **fibre_forced(**TABLE_4_1[case]))
    unstable = {mode["m"]: mode for mode in res.modes if mode["unstable"]}
    lowest = min(unstable, key=lambda d: min(unstable[d][f"tau_{unstable[d]['kind']}"]))
    assert lowest == m and unstable[m]["kind"] == "subharmonic"


@pytest.mark.slow
def test_fig_4_2_panels(tmp_path):
    assert main(["figure", "fig-4.2", "--out", str(tmp_path), "--workers", "1"]) == 0
    both, pressure, tangential = json.loads((tmp_path / "fig-4.2.json").read_text())
    assert all(t is None or t > 0.5 for t in tangential["subharmonic"]["tau_min"])
    tips = {p["params"]["forcing"]: sorted(t["tau"] for t in p["tips"]) for p in (both, pressure)}
    assert tips["both"][0] == pytest.approx(tips["pressure"][0], rel=0.02)


# ----------------------------------------------------------------------------- Table 4.1 at tau = 0.45


def hill_determinant(system, tau, x, subharmonic, n_temporal=20):
    """det(I + D^-1 T) of the Hill system truncated to |n| <= n_temporal, at the Floquet exponent
    gamma = x (harmonic) or x + i/2 (subharmonic): built here from D(s) and G alone (not with
    discretise/hill.py). A root x > 0 is a growing Floquet solution, e^{x t} times a 2 pi- (or
    4 pi-) periodic function. Real for real x > 0 (D(conj s) = conj D(s) and n -> -n)."""
    half = int(subharmonic)
    s = x + 1j * (np.arange(-n_temporal - half, n_temporal + 1) + 0.5 * half)
    b = system.block_size
    forcing = np.broadcast_to(system.forcing, (s.size, b, b))
    couplings = 1j * tau * np.linalg.solve(system.unforced(s), forcing)
    M = np.eye(s.size * b, dtype=complex)
    for k, coupling in enumerate(couplings):
        if k > 0:
            M[k * b:(k + 1) * b, (k - 1) * b:k * b] = -coupling
        if k < s.size - 1:
            M[k * b:(k + 1) * b, (k + 1) * b:(k + 2) * b] = coupling
    return np.linalg.det(M)


@pytest.mark.parametrize("case,expected", [(1, {3: "subharmonic", 5: "harmonic"}),
                                           (2, {2: "subharmonic", 5: "harmonic"})])
def test_table_4_1_unstable_modes_at_tau_045(case, expected):
    """Table 4.1 cases at tau = 0.45, m = 2..6: besides the principal subharmonic mode of thesis 4.4,
    m = 5 is harmonically unstable (tau_min 0.2954 and 0.3978, the n = 2 finger: 2 Im gamma = 2.1
    and 4.3 from the natural modes). Second method for each marginal tau and kind: the real growth
    rate x of the Hill determinant above (|n| <= 20, built without the package's Hill assembler)
    is zero at tau_c (quadratic extrapolation from tau_c (1 + 1e-3, 2e-3, 3e-3), to 1e-6),
    absent just below it and positive at tau = 0.45."""
    params = fibre_forced(**TABLE_4_1[case])
    res = ss.stability("fibre", tau=0.45, m="2:6", **params)
    unstable = {mode["m"]: mode for mode in res.modes if mode["unstable"]}
    assert {m: mode["kind"] for m, mode in unstable.items()} == expected
    for m, kind in expected.items():
        (tau_c,) = unstable[m][f"tau_{kind}"]
        other = "harmonic" if kind == "subharmonic" else "subharmonic"
        assert unstable[m][f"tau_{other}"] == []
        system = hill_system(m=m, **params)

        def growth(tau):
            f = lambda x: hill_determinant(system, tau, x, kind == "subharmonic").real  # noqa: E731
            return brentq(f, 0.0, 0.2, xtol=1e-15) if f(0.0) * f(0.2) < 0 else None

        assert growth(tau_c * (1 - 2e-3)) is None
        taus = tau_c * (1 + np.array([1e-3, 2e-3, 3e-3]))
        rates = np.array([growth(t) for t in taus])
        assert np.all(np.diff(rates) > 0) and rates[0] > 0
        zero = np.polynomial.Polynomial.fit(taus, rates, 2).roots()
        assert np.min(abs(zero - tau_c)) <= 1e-6 * tau_c
        assert growth(0.45) > 0.04


# ----------------------------------------------------------------------------- Figs 4.3 and 4.4


@pytest.mark.parametrize("name,cases", [("fig-4.3", [(2e-4, 0.02), (2e-4, 0.04), (2e-4, 0.08)]),
                                        ("fig-4.4", [(5e-5, 0.04), (1e-3, 0.04), (5e-3, 0.04)])])
def test_figs_4_3_4_4_parameter_sets_and_resonances(tmp_path, monkeypatch, name, cases):
    """The panels are the thesis's parameter sets (captions of Figs 4.3/4.4). Coarse run (m = 2..5):
    each m the figure marks unstable at tau = 0.45 sits on the finger n = round(2 Im gamma) of its
    natural mode (dispersion relation, not the Hill solve), subharmonic for odd n, harmonic for even."""
    monkeypatch.setattr(figures, "FIBRE_DEGREES", (2, 5))
    paths = figures.make_figure(name, tmp_path)
    assert all(p.exists() for p in paths)
    panels = json.loads((tmp_path / f"{name}.json").read_text())
    assert [(p["params"]["nu"], p["params"]["kappa"]) for p in panels] == cases
    marked = 0
    for panel in panels:
        for mode in panel["stability"]["modes"]:
            if mode["unstable"]:
                gamma = ss.natural_modes("fibre", m=mode["m"], count=1, **panel["params"]).gamma[0]
                n = round(2 * gamma.imag)
                assert abs(2 * gamma.imag - n) < 0.4  # the nearest finger is unambiguous
                assert mode["kind"] == ("subharmonic" if n % 2 else "harmonic")
                marked += 1
    assert marked >= 3


@pytest.mark.slow
@pytest.mark.parametrize("name", ["fig-4.3", "fig-4.4"])
def test_figs_4_3_4_4_full(tmp_path, name):
    """Full figures (m = 2..10) from the CLI: the principal subharmonic modes of Table 4.1 (m = 3 at
    kappa = 0.02, m = 2 at kappa = 0.08) are the lowest thresholds of their panels."""
    assert main(["figure", name, "--out", str(tmp_path), "--workers", "1"]) == 0
    panels = json.loads((tmp_path / f"{name}.json").read_text())
    assert all(len(p["floquet"]) == 9 for p in panels)
    if name == "fig-4.3":
        for panel, m in zip(panels[::2], (3, 2)):
            lowest = min((t, int(d)) for d, r in panel["floquet"].items()
                         for k in ("harmonic", "subharmonic") for t in r[k]["tau"])
            assert lowest[1] == m and lowest[0] < 0.11
