"""Floquet exponents of the sphere with a non-uniform kappa (issue 28: part 1's exponents for
the coupled system of part 2).

Oracles: the per-degree exponents of the uniform model (``ss.exponents("sphere", m=...)``) for
a uniform f, the non-uniform ``floquet`` tau_min (an exponent must sit on Re gamma = 0 there,
at Im gamma 0 or 1/2 by kind), and closed-form zeros of j_0 and j_1 for the interior fluid's
poles that the winding count marks.
"""

import json
import math

import numpy as np
import pytest

import spectralshell as ss
from spectralshell.cli import main
from spectralshell.special.spherical import spherical_jn_zeros

KAPPA = "0.02*(1 + 0.3*cos(theta)**2)"
UNIFORM = "0.02*(1 + 0*cos(theta))"


def _within(gamma, lo):
    """The exponents with Re gamma > lo, sorted by (Re, Im) rounded to 1e-8 (a conjugate
    pair's members sort alike whatever their last bits)."""
    kept = [g for g in gamma if g.real > lo + 1e-9]
    return np.array(sorted(kept, key=lambda g: (round(g.real, 8), round(g.imag, 8))))


def test_a_uniform_kappa_gives_the_per_degree_exponents():
    coupled = ss.exponents("sphere", kappa=UNIFORM, nu=0.006, tau=0.3, l_max=4)
    assert coupled.params["l_max"] == 4
    degrees = [(l, c) for l in (2, 3, 4) for c in ("poloidal", "toroidal")]
    per_degree = [ss.exponents("sphere", m=l, kappa=0.02, nu=0.006, tau=0.3, component=c)
                  for l, c in degrees]
    lo = max([coupled.complete_in[0]] + [r.complete_in[0] for r in per_degree])
    expected = [g for (l, _), r in zip(degrees, per_degree) for g in r.gamma
                for _ in range(2 * l + 1)]
    a, b = _within(coupled.gamma, lo), _within(expected, lo)
    assert a.size == b.size > 0
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-10)


def test_the_subharmonic_tau_min_puts_the_largest_exponent_on_the_axis():
    """At the non-uniform floquet's tau_min (subharmonic, the smaller kind) the largest
    Re gamma is 0 to 1e-10, with Im gamma = 1/2 (the toroidal sectors included)."""
    f = ss.floquet("sphere", kappa=KAPPA, nu=0.006, l_max=4, tol=1e-12)
    assert f.subharmonic.tau_min < f.harmonic.tau_min
    r = ss.exponents("sphere", kappa=KAPPA, nu=0.006, tau=f.subharmonic.tau_min, l_max=4,
                     tol=1e-12)
    lead = r.gamma[0]
    assert abs(lead.real) < 1e-10 and lead.imag == pytest.approx(0.5, abs=1e-12)
    # below it every exponent decays; the two copies (k = +-3) of the critical sector agree
    assert abs(r.gamma[1] - lead) < 1e-10 and r.gamma[2].real < -1e-3


@pytest.mark.slow
def test_the_harmonic_tau_min_puts_an_exponent_on_the_axis():
    """At the harmonic tau_min (above the subharmonic one: the subharmonic is unstable there)
    a harmonic exponent (Im gamma = 0) has Re gamma = 0 to 1e-10. ~100 s."""
    f = ss.floquet("sphere", kappa=KAPPA, nu=0.006, l_max=4, tol=1e-12)
    r = ss.exponents("sphere", kappa=KAPPA, nu=0.006, tau=f.harmonic.tau_min, l_max=4,
                     tol=1e-12)
    on_axis = [g for g in r.gamma if abs(g.real) < 1e-10]
    assert on_axis and all(abs(g.imag) < 1e-12 for g in on_axis)


def test_cli_exponents_of_a_nonuniform_kappa(capsys):
    code = main(["exponents", "sphere", "--kappa", UNIFORM, "--nu", "0.006", "--tau", "0.3",
                 "--l-max", "4", "--count", "3", "--json"])
    assert code == 0
    out = json.loads(capsys.readouterr().out)
    api = ss.exponents("sphere", kappa=UNIFORM, nu=0.006, tau=0.3, l_max=4, count=3)
    assert out["params"] == {"kappa": UNIFORM, "nu": 0.006, "l_max": 4}
    assert [complex(e["re"], e["im"]) for e in out["exponents"]] == list(api.gamma)
    code = main(["exponents", "sphere", "--kappa", UNIFORM, "--nu", "0.006", "--tau", "0.3",
                 "--l-max", "99"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and "l_max" in err


def test_zeros_of_spherical_bessel_functions():
    """j_0 = sin z / z vanishes at k pi; j_1 where tan z = z (4.4934..., 7.7252...)."""
    np.testing.assert_allclose(spherical_jn_zeros(0, 20.0), np.pi * np.arange(1, 7),
                               rtol=1e-15)
    z = spherical_jn_zeros(1, 10.0)
    np.testing.assert_allclose(np.tan(z), z, rtol=1e-12)
    assert z.size == 2 and z[0] == pytest.approx(4.493409457909064, abs=1e-14)
    assert spherical_jn_zeros(3, 6.0).size == 0 and math.isclose(
        spherical_jn_zeros(3, 7.0)[0], 6.987932000500519, abs_tol=1e-13)


@pytest.mark.slow
def test_auto_l_max_stops_when_the_least_damped_exponent_settles():
    """l_max 'auto' (kappa 0.02: from l_max = 6, compared with 4): a uniform f's least damped
    exponent is the per-degree one of l = 3 at every truncation, so the refinement stops at
    the first pair. ~40 s."""
    r = ss.exponents("sphere", kappa=UNIFORM, nu=0.006, tau=0.3, count=3)
    assert r.params["l_max"] == 6
    lead = ss.exponents("sphere", m=3, kappa=0.02, nu=0.006, tau=0.3).gamma[0]
    assert abs(r.gamma[0] - lead) < 1e-10 and r.error_estimate < 1e-6


ASYMMETRIC = "0.02*(1 + 0.2*sin(theta)*cos(phi) + 0.1*cos(theta))"


def test_a_costly_truncation_is_refused_before_any_work(monkeypatch, capsys):
    """Each degree truncation of the exponents is priced as floquet's (runner.nonuniform.Price)
    and refused above the limit before any sector is solved: the solver and the sectors' modes
    are patched to fail, so a refusal that ran any of them would not be a ParameterError. The
    kappa without symmetry couples every mode (priced ~27 min at l_max = 12); the CLI says so
    in one line (exit 2); max_seconds lowers the limit (also for l_max 'auto', whose first
    truncations are priced before the coarser is solved) and is refused for other models."""
    from spectralshell.errors import ParameterError
    from spectralshell.runner import nonuniform

    def no_solve(*args, **kwargs):
        raise AssertionError("a sector was solved before the price was checked")

    with monkeypatch.context() as patch:
        patch.setattr(nonuniform, "hill_exponents", no_solve)
        patch.setattr(nonuniform, "sector_modes", no_solve)
        with pytest.raises(ParameterError) as info:
            ss.exponents("sphere", kappa=ASYMMETRIC, nu=0.006, tau=0.3, l_max=12)
        text = str(info.value)
        assert "l_max = 12" in text and "blocks <= " in text and "max_seconds=" in text
        assert "SPECTRALSHELL_MAX_SECONDS" in text and "\n" not in text
        for l_max in (4, "auto"):
            with pytest.raises(ParameterError, match="above the limit of 0.001"):
                ss.exponents("sphere", kappa=KAPPA, nu=0.006, tau=0.3, l_max=l_max,
                             max_seconds=1e-3)
        assert main(["exponents", "sphere", "--kappa", ASYMMETRIC, "--nu", "0.006",
                     "--tau", "0.3", "--l-max", "12"]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "SPECTRALSHELL_MAX_SECONDS" in err
    with pytest.raises(ParameterError, match="max_seconds"):
        ss.exponents("sphere", m=3, kappa=0.02, nu=0.006, tau=0.3, max_seconds=10)
