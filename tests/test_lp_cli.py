"""`spectralshell lp` and ss.lp_coefficient: the issue's JSON contract and bad input."""

import json

import mpmath
import pytest

import spectralshell as ss
from spectralshell.cli import main


def test_lp_json_contract(capsys):
    assert main(["lp", "--m", "2", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert {"m", "k", "coefficient", "coefficient_exact", "lambda0_over_sqrt_kappa"} <= set(data)
    num, den = (int(x) for x in data["coefficient_exact"].removesuffix("*pi)").split("/("))
    assert data["coefficient"] == pytest.approx(float(mpmath.mpf(num) / (den * mpmath.pi)), rel=1e-15)
    assert data["lambda0_over_sqrt_kappa"] == pytest.approx(float(mpmath.sqrt(mpmath.mpf(24) / 5)),
                                                            rel=1e-15)  # (7.4), m = 2
    assert ss.lp_coefficient(2) == data["coefficient"]


@pytest.mark.parametrize("argv", [["--m", "1"], ["--m", "2", "--k", "3"], ["--m", "x"], []])
def test_lp_bad_input_exit_2(capsys, argv):
    assert main(["lp", *argv]) == 2
    assert capsys.readouterr().err.count("\n") == 1
