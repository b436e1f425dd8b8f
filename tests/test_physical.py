"""Physical <-> dimensionless conversions against the thesis's printed tables (6.1, 7.2, 7.3)."""

import math

import pytest

from spectralshell.errors import ParameterError
from spectralshell.params.physical import (BALLOONS, CARDIAC, TABLE_4_1, TABLE_6_1, PhysicalSphere,
                                           balloon, fibre_forced,
                                           bpm_to_rad_per_s)

# Table 6.1, printed dimensionless columns (nu, kappa)
PRINTED_6_1 = {1: (0.006, 0.02), 2: (0.002, 0.06), 3: (0.001, 0.0075), 4: (0.004, 0.25)}
# Table 7.2, printed sigma column (dyn/cm); Table 7.3, printed inviscid-theory column (s^-1)
PRINTED_SIGMA = (92970, 98550, 155400, 113850, 130320, 153750, 148875, 149700, 156625)
PRINTED_INVISCID = (45.45, 25.47, 20.78, 27.38, 19.03, 14.79, 14.55, 9.48, 6.94)


@pytest.mark.parametrize("case", [1, 2, 3, 4])
def test_table_6_1_dimensionless_columns(case):
    got = TABLE_6_1[case].forced()
    assert got["nu"] == pytest.approx(PRINTED_6_1[case][0], rel=1e-12)
    assert got["kappa"] == pytest.approx(PRINTED_6_1[case][1], rel=1e-12)


def test_cardiac_nu_from_400_bpm():
    """Thesis 6.5: R = 2 cm, mu = 0.04, 400 bpm (as rad/s, ERRATA) gives nu = 2.39e-4."""
    omega = bpm_to_rad_per_s(CARDIAC["bpm_typical_svt"])
    assert omega == pytest.approx(2 * math.pi * 400 / 60)
    sphere = PhysicalSphere(rho=CARDIAC["rho"], mu=CARDIAC["mu"], radius=CARDIAC["radius"],
                            sigma=1e4, omega=omega)
    assert round(sphere.forced()["nu"], 6) == 2.39e-4


def test_balloons_sigma_zeta_and_inviscid_frequency():
    """Table 7.2 sigma by Young-Laplace (7.23); Table 7.3 inviscid column by (7.5), m = 2; the
    text's zeta range [5.05e-6, 1.34e-5]."""
    zetas = []
    for (kind, radius, _), sigma, freq in zip(BALLOONS, PRINTED_SIGMA, PRINTED_INVISCID):
        b = balloon(kind, radius)
        assert b.sigma == pytest.approx(sigma, rel=1e-12)
        assert round(b.lamb_frequency(2), 2) == freq
        zetas.append(b.zeta)
    assert round(min(zetas), 8) == 5.05e-6 and round(max(zetas), 7) == 1.34e-5


def test_time_scale_makes_kappa_one():
    unforced = PhysicalSphere(rho=1.0, mu=0.01, radius=3.0, sigma=500.0)
    s = PhysicalSphere(rho=1.0, mu=0.01, radius=3.0, sigma=500.0, omega=1 / unforced.time_scale)
    d = s.forced()
    assert d["kappa"] == pytest.approx(1.0, rel=1e-14)
    assert d["nu"] == pytest.approx(s.zeta, rel=1e-14)


@pytest.mark.parametrize("kwargs,name", [({"rho": 0.0}, "rho"), ({"mu": -1.0}, "mu"),
                                         ({"radius": float("nan")}, "radius"),
                                         ({"sigma": -2.0}, "sigma"), ({"omega": 0.0}, "omega")])
def test_bad_physical_input_names_the_parameter(kwargs, name):
    base = dict(rho=1.0, mu=0.01, radius=1.0, sigma=1.0, omega=1.0)
    with pytest.raises(ParameterError, match=name):
        PhysicalSphere(**{**base, **kwargs})


def test_unknown_balloon_and_unforced_conversion():
    with pytest.raises(ParameterError, match="balloon"):
        balloon("D", 6.0)
    with pytest.raises(ParameterError, match="omega"):
        PhysicalSphere(rho=1.0, mu=0.01, radius=1.0, sigma=1.0).forced()


@pytest.mark.parametrize("case,printed", [(1, (2e-4, 0.02)), (2, (2e-4, 0.08))])
def test_table_4_1_dimensionless_columns(case, printed):
    got = fibre_forced(**TABLE_4_1[case])
    assert (got["nu"], got["kappa"]) == pytest.approx(printed, rel=1e-12)


def test_kept_forced_conversion_equals_fresh_and_still_refuses():
    """sphere_forced_params keeps its (nu, kappa) per cgs input (a map converts each
    (sigma, bpm) once per degree): a kept answer equals the formulas (6.4)-(6.5), a refused input
    is refused again (not kept), and a bool equal to a kept int is still refused."""
    from spectralshell.params.physical import sphere_forced_params

    given = {"rho": 1, "mu": 0.04, "radius": 2.0, "sigma": 1234.5, "bpm": 77.0}
    omega = 2 * math.pi * 77.0 / 60
    for m in (2, 3):
        out = sphere_forced_params({**given, "m": m})
        assert out == {"m": m, "nu": pytest.approx(0.04 / (1 * 2.0**2 * omega), rel=1e-15),
                       "kappa": pytest.approx(1234.5 / (1 * 2.0**3 * omega**2), rel=1e-15)}
    for _ in range(2):
        with pytest.raises(ParameterError, match="rho = True"):
            sphere_forced_params({**given, "rho": True})
        with pytest.raises(ParameterError, match="sigma"):
            sphere_forced_params({**given, "sigma": -1.0})
        with pytest.raises(ParameterError, match="rho"):
            sphere_forced_params({**given, "rho": [1.0]})
