"""`stability`: which degrees are unstable at a given tau, against the Floquet exponents."""

import json

import numpy as np
import pytest

import spectralshell as ss
from spectralshell.cli import main
from spectralshell.models.sphere import lambda0_squared


@pytest.mark.parametrize("kappa", [0.02, 0.06, 0.0075, 0.25])
@pytest.mark.parametrize("tau", [0.2, 0.45])
def test_parity_rule_agrees_with_floquet_exponents_inviscid(kappa, tau):
    """Oracle: for nu = 0 each degree is a Mathieu equation whose Floquet exponents are computed
    directly (and checked against solve_ivp monodromy elsewhere): unstable iff max Re gamma > 0,
    harmonic iff Im gamma = 0, subharmonic iff Im gamma = 1/2."""
    res = ss.stability("sphere", tau=tau, m="2:6", kappa=kappa, nu=0.0)
    for mode in res.modes:
        gamma = ss.exponents("mathieu", kappa=lambda0_squared(mode["m"], kappa), nu=0.0,
                             tau=tau).gamma
        lead = gamma[np.argmax(gamma.real)]
        unstable = lead.real > 1e-9
        assert mode["unstable"] == unstable, (mode, gamma)
        if unstable:
            assert mode["kind"] == ("subharmonic" if abs(abs(lead.imag) - 0.5) < 1e-9 else "harmonic")


def test_cli_stability_json_shape(capsys):
    code = main(["stability", "sphere", "--kappa", "0.02", "--nu", "0.006", "--tau", "0.45",
                 "--m", "2:6", "--json"])
    data = json.loads(capsys.readouterr().out)
    assert code == 0 and data["model"] == "sphere" and data["tau"] == 0.45
    assert [m["m"] for m in data["modes"]] == [2, 3, 4, 5, 6]
    assert set(data["modes"][0]) == {"m", "unstable", "kind", "tau_harmonic", "tau_subharmonic"}
    unstable = [(m["m"], m["kind"]) for m in data["modes"] if m["unstable"]]
    assert unstable == [(3, "subharmonic")]  # thesis 6.4.2, case 1


@pytest.mark.parametrize("m", ["1:4", "6:2", "x", "2.5"])
def test_bad_degree_ranges(capsys, m):
    code = main(["stability", "sphere", "--kappa", "0.02", "--tau", "0.45", "--m", m])
    assert code == 2 and len(capsys.readouterr().err.strip().splitlines()) == 1
