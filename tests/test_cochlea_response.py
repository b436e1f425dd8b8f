"""Pure-tone response of the basilar membrane (thesis 5.5) and the marginal Floquet solution.

Oracles: the WKB place map derived in derivations/cochlea_wkb.py (slope -7/(4 lambda_c) of the
envelope peak against ln omega, LeVeque, Peskin & Lax); scipy's Mathieu functions ce_r for the
marginal solution of the (model-agnostic) null-vector solver.
"""

import json

import numpy as np
import pytest
import scipy.special as special

import spectralshell.api as api
from spectralshell.cli import main
from spectralshell.models.mathieu import hill_system as mathieu_system
from spectralshell.solvers.marginal import marginal_tau
from spectralshell.solvers.marginal_mode import marginal_mode

LAMBDA_C = 1.4


def test_tone_peaks_follow_the_wkb_place_map():
    """Table 5.1, omega = 300..1600 rad/s, 128 modes: the fitted slope of the envelope peak
    against ln omega is within 5 % of -7/(4 lambda_c) = -1.25 cm (measured -1.22), and every peak
    lies 0-0.15 cm basal of the leading-order WKB peak (derivation: the neglected viscous terms
    move it basally by up to 0.07 cm)."""
    omegas = np.array([300.0, 450.0, 700.0, 1000.0, 1600.0])
    res = [api.response("cochlea", omega=om, kind="tone", n_spatial=128) for om in omegas]
    peaks = np.array([r.to_cm(r.peak_x) for r in res])
    wkb = np.array([r.to_cm(r.wkb_peak_x) for r in res])
    slope = np.polyfit(np.log(omegas), peaks, 1)[0]
    assert abs(slope + 7 / (4 * LAMBDA_C)) < 0.05 * 7 / (4 * LAMBDA_C)
    assert np.all((wkb - peaks > 0) & (wkb - peaks < 0.15))
    assert all(r.to_cm(r.peak_error) < 0.05 for r in res)


@pytest.mark.slow
def test_parametric_peak_depends_on_the_response_frequency():
    """Thesis 5.5: the harmonic solution at tau_min (response at omega) peaks where a tone of omega
    does, the subharmonic one (response at omega/2) where a tone of omega/2 does (to 0.1 cm;
    omega = 800 rad/s, 64 modes)."""
    tone = {om: api.response("cochlea", omega=om, kind="tone", n_spatial=64) for om in (400, 800)}
    harm = api.response("cochlea", omega=800, kind="harmonic", n_spatial=64)
    sub = api.response("cochlea", omega=800, kind="subharmonic", n_spatial=64)
    assert abs(harm.to_cm(harm.peak_x) - tone[800].to_cm(tone[800].peak_x)) < 0.1
    assert abs(sub.to_cm(sub.peak_x) - tone[400].to_cm(tone[400].peak_x)) < 0.1
    assert sub.tau < 0.08 < harm.tau


@pytest.mark.parametrize("kind,char_value,order,ce", [("harmonic", special.mathieu_a, 2, True),
                                                       ("subharmonic", special.mathieu_a, 1, True),
                                                       ("subharmonic", special.mathieu_b, 3, False)])
def test_marginal_mode_is_the_mathieu_function(kind, char_value, order, ce):
    """Undamped Mathieu (2.2) at kappa = a_r(q)/4: the solution at the marginal tau = q/(4 kappa) is
    ce_r or se_r(x, q) with t = 2x - pi/2 (derivations/mathieu_mapping.py); scipy's
    mathieu_cem/sem (x in degrees) as the oracle, up to a constant factor."""
    q = 1.3
    kappa = char_value(order, q) / 4
    system = mathieu_system(kappa=kappa, nu=0.0)
    taus = marginal_tau(system, kind).tau
    tau = taus[np.argmin(np.abs(taus - q / (4 * kappa)))]
    mode = marginal_mode(system, kind, tau, 30)
    t = np.linspace(0, 4 * np.pi, 50)
    got = mode.evaluate(t)[:, 0]
    fn = special.mathieu_cem if ce else special.mathieu_sem
    want = fn(order, q, np.degrees((t + np.pi / 2) / 2))[0]
    factor = np.dot(got, want) / np.dot(want, want)
    assert mode.residual < 1e-12
    np.testing.assert_allclose(got, factor * want, atol=1e-9 * np.abs(want).max() * abs(factor))


def test_response_cli(capsys, tmp_path):
    png = tmp_path / "r.png"
    code = main(["response", "cochlea", "--omega", "800", "--n-spatial", "32", "--png", str(png), "--json"])
    data = json.loads(capsys.readouterr().out)
    assert code == 0 and data["kind"] == "tone" and len(data["x"]) == len(data["envelope"])
    assert max(data["envelope"]) == pytest.approx(1.0) and 0 < data["peak_cm"] < 3.5
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_parametric_tau_carries_its_error_in_the_spatial_modes(capsys):
    """The response's tau has an error estimate covering the truncation in M: at least
    |tau(M) - tau(M/2)| from two independent floquet solves (omega = 1000 rad/s, M = 16 and 8,
    subharmonic), and tau is floquet's at M; the JSON and the text show it."""
    res = api.response("cochlea", omega=1000.0, kind="subharmonic", n_spatial=16)
    fine, coarse = (api.floquet("cochlea", omega=1000.0, n_spatial=M, kind="subharmonic")
                    .subharmonic.tau_min for M in (16, 8))
    assert abs(res.tau - fine) < 1e-9
    assert res.tau_error >= abs(fine - coarse) > 0 and res.tau_error < 0.05
    assert api.response("cochlea", omega=1000.0, kind="tone", n_spatial=16).tau_error is None
    assert main(["response", "cochlea", "--omega", "1000", "--kind", "subharmonic",
                 "--n-spatial", "16", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["tau_error"] == pytest.approx(res.tau_error)
    assert "± " in res.summary().splitlines()[0]


@pytest.mark.parametrize("n_temporal", [None, 12])
def test_no_parametric_response_only_where_proved(monkeypatch, n_temporal):
    """'No marginal tau' (a ParameterError) is said only where the zero count proves none up
    to tau_max; with the count failing it is a ConvergenceError, also at a fixed N (whose
    complete_to is then 0), never the same "proved" sentence (issue 23)."""
    from spectralshell.errors import ConvergenceError, ParameterError
    from spectralshell.solvers import marginal

    point = dict(omega=1000.0, kind="harmonic", tau_max=0.05, n_spatial=16,
                 n_temporal=n_temporal)
    with pytest.raises(ParameterError, match="proved up to it"):
        api.response("cochlea", **point)
    monkeypatch.setattr(marginal, "none_up_to", lambda hill, tau_max, solves=None: False)
    with pytest.raises(ConvergenceError) as err:
        api.response("cochlea", **point)
    assert "proved" in str(err.value) and "proved up to it" not in str(err.value)
