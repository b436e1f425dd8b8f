"""Cochlea cgs <-> dimensionless conversion (thesis 5.2, Table 5.1) against the printed numbers."""

import math

import pytest

from spectralshell.errors import ParameterError
from spectralshell.params.physical import (TABLE_5_1, cochlea_forced, cochlea_params,
                                           cochlea_time_scale)
from spectralshell.params.registry import physical_values


def table(omega):
    return cochlea_forced(**{k: TABLE_5_1[k] for k in ("rho", "mu", "sigma", "length", "lambda_c")},
                          omega=omega)


def test_alpha_of_table_5_1():
    assert table(400.0)["alpha"] == pytest.approx(1.56, abs=5e-3)


def test_printed_ranges_belong_to_omega_100_to_2000():
    """ERRATA: the printed nu in [8.06e-6, 1.61e-4] and kappa in [0.135, 53.9] are the values at
    omega = 2000 and 100 rad/s (to the printed 3 digits), not at the printed 400 and 1600."""
    lo, hi = table(2000.0), table(100.0)
    assert round(lo["nu"], 8) == 8.06e-6 and round(hi["nu"], 6) == 1.61e-4
    assert round(lo["kappa"], 3) == 0.135 and round(hi["kappa"], 1) == 53.9
    assert table(1600.0)["kappa"] == pytest.approx(0.2104, abs=1e-4)


def test_zeta_and_time_scale():
    """zeta = nu/sqrt(kappa) = mu/sqrt(rho sigma (L/pi)^3) = 2.2e-5 (thesis: 2e-5); the natural-mode
    time unit T = sqrt(rho L/(pi sigma)) equals 1/(omega sqrt(kappa))."""
    d = table(700.0)
    assert d["nu"] / math.sqrt(d["kappa"]) == pytest.approx(0.02 / math.sqrt(6e5 * (3.5 / math.pi)**3))
    assert cochlea_time_scale(rho=1.0, sigma=6e5, length=3.5) == pytest.approx(
        1 / (700.0 * math.sqrt(d["kappa"])), rel=1e-14)


def test_defaults_overrides_and_conflicts():
    out, phys = physical_values("cochlea", {"omega": 1000, "alpha": 0, "spatial_mode": 1})
    assert out["alpha"] == 0 and out["spatial_mode"] == 1 and phys["sigma"] == 6e5
    assert out["kappa"] == pytest.approx(6e5 * math.pi / (3.5 * 1e6), rel=1e-15)
    assert physical_values("sphere", {"m": 2})[1] is None
    with pytest.raises(ParameterError, match="omega"):
        cochlea_params({"sigma": 1e7})
    with pytest.raises(ParameterError, match="sigma"):
        cochlea_params({"omega": 400, "sigma": 1e7, "kappa": 3})
    with pytest.raises(ParameterError, match="omega"):
        cochlea_params({"omega": -1})
