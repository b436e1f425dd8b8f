"""ss.natural_modes and `spectralshell modes` against published values and closed forms."""

import json

import mpmath
import numpy as np
import pytest

import spectralshell as ss
from spectralshell.cli import main
from spectralshell.discretise.sphere_radial import radial_operators
from spectralshell.models.sphere import lambda0_squared
from spectralshell.params.physical import BALLOONS, balloon
from spectralshell.solvers.eigen import least_damped

# Table 7.3, "Viscous Theory" column (s^-1), m = 2 balloons in water
PRINTED_VISCOUS = (45.35, 25.42, 20.74, 27.33, 18.99, 14.76, 14.53, 9.46, 6.93)


def test_table_7_3_viscous_column():
    """Frequencies of the least-damped m = 2 mode of each balloon, in s^-1 from cgs input."""
    for (kind, radius, _), printed in zip(BALLOONS, PRINTED_VISCOUS):
        b = balloon(kind, radius)
        res = ss.natural_modes("sphere", m=2, count=1, physical={
            "rho": b.rho, "mu": b.mu, "radius": b.radius, "sigma": b.sigma})
        assert res.params["units"] == "s^-1"
        assert round(float(res.gamma[0].imag), 2) == printed
        assert res.gamma[0].real < 0 and res.error_estimate[0] < 1e-9


def test_inviscid_modes_are_lamb_closed_form():
    res = ss.natural_modes("sphere", m=3, kappa=0.2, nu=0.0, precision=25)
    assert res.gamma[0] == pytest.approx(1j * np.sqrt(lambda0_squared(3, 0.2)), rel=1e-15)
    with mpmath.workdps(30):  # lambda0^2 = kappa * 3*4*2*5 / 7 with kappa the double nearest 0.2
        exact = mpmath.sqrt(mpmath.mpf(0.2) * 120 / 7)
        assert abs(mpmath.mpf(res.gamma_digits[0][1]) - exact) < mpmath.mpf(10) ** -23


def test_zeta_shorthand_equals_kappa_one():
    a = ss.natural_modes("sphere", m=2, zeta=0.05)
    b = ss.natural_modes("sphere", m=2, kappa=1.0, nu=0.05)
    np.testing.assert_array_equal(a.gamma, b.gamma)


@pytest.mark.parametrize("m,zeta", [(2, 1e-2), (3, 1e-1)])
def test_dispersion_relation_against_radial_chebyshev(m, zeta):
    """Second method: eigenvalues of the radial Chebyshev pencil (complex-scaled exterior) that
    agree between two resolutions contain the dispersion-relation modes to 1e-8."""
    fine, coarse = (radial_operators(m=m, nu=zeta, n_inner=n, n_outer=n, exterior_angle=-np.pi / 3)
                    .pencil(1.0) for n in (40, 32))
    cheb = least_damped(fine, coarse, count=2).values
    for g in ss.natural_modes("sphere", m=m, zeta=zeta).gamma:
        assert np.min(np.abs(cheb - g)) < 1e-8 * abs(g)


def test_cli_modes_json_contract(capsys):
    assert main(["modes", "sphere", "--m", "2", "--kappa", "1", "--nu", "0.01", "--count", "1",
                 "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["model"] == "sphere" and len(data["modes"]) == 1
    mode = data["modes"][0]
    assert mode["gamma_im"] >= 0 and {"gamma_re", "gamma_im"} <= set(mode)


@pytest.mark.parametrize("argv", [["--m", "2", "--zeta", "-1"], ["--m", "2.5", "--kappa", "1"],
                                  ["--m", "2", "--zeta", "0.1", "--nu", "0.1"],
                                  ["--m", "2", "--radius", "2", "--sigma", "1"],
                                  ["--m", "2", "--zeta", "0.1", "--count", "x"],
                                  ["--m", "2", "--zeta", "0.1", "--count", "0"]])
def test_cli_modes_bad_input_exit_2(capsys, argv):
    assert main(["modes", "sphere", *argv]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "error" in err
