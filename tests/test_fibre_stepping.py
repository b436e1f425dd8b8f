"""The fibre's time stepper (runner/fibre_stepping.py on discretise/fibre_radial.py), issue 28 §1:
above tau_min the growth rate equals the Floquet exponents' to 1e-6, below it decays.

Oracles: tau_min from the tau-eigenproblem of the Hill pencil (``ss.floquet``) and the leading
exponent gamma (``ss.exponents``), both built on the Bessel-function load D(s); the stepper
collocates the fluid in r and shares no physics code with them.
"""

import numpy as np
import pytest

import spectralshell as ss
from spectralshell.errors import ParameterError
from spectralshell.runner.fibre_stepping import fibre_rate

DTAU = 0.02


def check_rates(m, kappa, nu, forcing):
    """Stepped at tau_min -+ DTAU: decays below and grows above, Re gamma to 1e-6 and within
    the stated error, the frequency |Im gamma| (1/2 above: the subharmonic tongue)."""
    params = {"m": m, "kappa": kappa, "nu": nu, "forcing": forcing}
    tau_min = ss.floquet("fibre", kind="subharmonic", **params).subharmonic.tau_min
    for tau, sign in ((tau_min - DTAU, -1), (tau_min + DTAU, 1)):
        gamma = complex(ss.exponents("fibre", tau=tau, count=1, **params).gamma[0])
        fit = fibre_rate(tau=tau, **params)
        assert np.sign(fit.growth_rate) == sign and abs(gamma.real) > 1e-3
        assert abs(fit.growth_rate - gamma.real) < 1e-6
        assert abs(fit.growth_rate - gamma.real) <= fit.error_estimate < 1e-5
        assert abs(fit.frequency - abs(gamma.imag)) < 1e-6
    assert gamma.imag == pytest.approx(0.5)


def test_growth_rate_equals_the_floquet_exponent():
    """m = 3, kappa = 0.02, nu = 2e-4 (Table 4.1, case 1): measured 1e-7 (SBDF3, 320 steps a
    period), error estimate 7e-7."""
    check_rates(3, 0.02, 2e-4, "both")


def test_unforced_fibre_rings_at_the_rayleigh_mode():
    """tau = 0 (no explicit term): X^r decays and oscillates at the least damped natural mode of
    the dispersion relation (ss.natural_modes), to 1e-6 and within the stated error."""
    gamma = complex(ss.natural_modes("fibre", m=3, kappa=0.02, nu=2e-4).gamma[0])
    fit = fibre_rate(m=3, kappa=0.02, nu=2e-4, tau=0.0, periods=20)
    error = max(abs(fit.growth_rate - gamma.real), abs(fit.frequency - gamma.imag))
    assert error < 1e-6 and error <= fit.error_estimate


@pytest.mark.slow
@pytest.mark.parametrize("m, kappa, forcing", [(2, 0.08, "both"), (2, 0.08, "pressure"),
                                               (3, 0.02, "pressure")])
def test_growth_rate_equals_the_floquet_exponent_more_cases(m, kappa, forcing):
    """Table 4.1 case 2 and the pressure-only pumping of Fig 4.2 (about 15 s each)."""
    check_rates(m, kappa, 2e-4, forcing)


@pytest.mark.slow
def test_tangential_pumping_decays_at_the_exponent_rate():
    """Pumping only the tangential jump has no tongue below 1/2 (Fig 4.2): at tau = 0.4 the
    stepped fibre decays at Re gamma of the leading exponent."""
    params = {"m": 3, "kappa": 0.02, "nu": 2e-4, "forcing": "tangential", "tau": 0.4}
    gamma = complex(ss.exponents("fibre", count=1, **params).gamma[0])
    fit = fibre_rate(**params)
    assert gamma.real < -1e-3 and abs(fit.growth_rate - gamma.real) < 1e-6


@pytest.mark.parametrize("kwargs, name", [({"nu": 0.0}, "nu"), ({"m": 1}, "m"),
                                          ({"forcing": "normal"}, "forcing"),
                                          ({"periods": 5}, "periods"), ({"kappa": -1}, "kappa"),
                                          ({"n_inner": 8}, "n_inner"), ({"tau": "x"}, "tau")])
def test_bad_arguments_name_the_parameter(kwargs, name):
    args = {"m": 3, "kappa": 0.02, "nu": 2e-4, "tau": 0.1, **kwargs}
    with pytest.raises(ParameterError, match=name):
        fibre_rate(**args)
