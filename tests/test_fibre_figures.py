"""Fibre figures and thesis claims of 4.2-4.4 (Fig 4.2: the pressure jump drives the instability)."""

import json

import pytest

import spectralshell as ss
from spectralshell.cli import main
from spectralshell.params.physical import TABLE_4_1, fibre_forced


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
