"""Sphere figures and minimum-tau maps against the thesis's stated outcomes (6.2, 6.4.2, 6.5)."""

import json
import math

import numpy as np
import pytest

import spectralshell as ss

from spectralshell.api import tau_map
from spectralshell.cli import main
from spectralshell.models.sphere import lambda0_squared
from spectralshell.params.physical import CARDIAC, TABLE_6_1, sphere_forced_params
from spectralshell.plots import tau_map as tau_plot
from spectralshell.results.maps import map_dict, minimum_map, write_npz


def test_map_in_physical_units_finds_case_2_mode():
    """Table 6.1 case 2 in cgs (sigma = 3 dyn/cm, omega = 20 rad/s, R = 0.5 cm, mu = 0.01): the
    simulations of 6.4.2 see m = 2 grow subharmonically at tau = 0.45; the map point agrees."""
    case = TABLE_6_1[2]
    bpm = case.omega * 60 / (2 * math.pi)
    ds = tau_map("sphere", x=("sigma", [case.sigma]), y=("bpm", [bpm]), m="2:6", workers=1,
                 physical={"rho": case.rho, "mu": case.mu, "radius": case.radius})
    res = minimum_map(ds, "sigma", "bpm")
    assert res.has_tau[0, 0] and res.tau_min[0, 0] < 0.45
    assert (int(res.m[0, 0]), res.kind.values[0, 0], res.label.values[0, 0]) == (2, "subharmonic",
                                                                               "2S")
    assert res.error_estimate[0, 0] < 1e-8
    assert map_dict(res)["units"] == {"sigma": "dyn/cm", "bpm": "beats/min"}


def test_map_agrees_with_independent_point_solves():
    """Oracle: the map's minimum over m and kind is the smallest of independent floquet solves
    (tau_max = 1/2) at each point, within tol."""
    ds = tau_map("sphere", x=("kappa", [0.02, 0.06]), y=("nu", [0.002, 0.006]), m="2:3",
                 workers=1)
    res = minimum_map(ds, "kappa", "nu")
    for i, nu in enumerate([0.002, 0.006]):
        for j, kappa in enumerate([0.02, 0.06]):
            found = [t for m in (2, 3) for r in [ss.floquet("sphere", m=m, kappa=kappa, nu=nu,
                                                            tau_max=0.5, tol=1e-8)]
                     for t in (r.harmonic.tau_min, r.subharmonic.tau_min) if t is not None]
            assert bool(res.has_tau[i, j]) == bool(found)
            if found:
                assert abs(float(res.tau_min[i, j]) - min(found)) < 2e-8


def test_fig_6_13_map_agrees_cell_by_cell_with_independent_solves():
    """Oracle: a coarse Fig 6.13 map (cgs, 6 x 6 over the thesis's sigma and bpm ranges,
    m = 2..6) equals independent floquet solves (tau_max = 1/2, tol 1e-8) for every cell,
    degree and kind: the same has_tau, tau_min within tol."""
    physical = {k: CARDIAC[k] for k in ("rho", "mu", "radius")}
    sigma = CARDIAC["sigma_range"]
    ds = tau_map("sphere", x=("sigma", f"{sigma[0]}:{sigma[1]}:6"), y=("bpm", "50:650:6"),
                 m="2:6", physical=physical, workers=1)
    for s in ds.sigma.values:
        for b in ds.bpm.values:
            for m in range(2, 7):
                params = sphere_forced_params({**physical, "sigma": s, "bpm": b})
                res = ss.floquet("sphere", m=m, tau_max=0.5, tol=1e-8, **params)
                for kind, found in (("harmonic", res.harmonic), ("subharmonic",
                                                                  res.subharmonic)):
                    cell = ds.sel(sigma=s, bpm=b, m=m, kind=kind)
                    assert bool(cell.has_tau) == (found.tau_min is not None)
                    if found.tau_min is not None:
                        assert abs(float(cell.tau_min) - found.tau_min) <= 1e-8


def test_map_png_and_npz(tmp_path):
    ds = tau_map("sphere", x=("kappa", [0.02, 0.06]), y=("nu", [0.002, 0.006]), m="2:3", workers=1)
    assert tau_plot.save(ds, tmp_path / "map.png", min_cells=1).stat().st_size > 5_000
    res = minimum_map(ds, "kappa", "nu")
    write_npz(res, tmp_path / "map.npz")
    with np.load(tmp_path / "map.npz") as data:
        np.testing.assert_array_equal(data["tau_min"], res.tau_min.values)
        np.testing.assert_array_equal(data["label"], res.label.values)
        assert json.loads(str(data["metadata"]))["units"] == {"kappa": "1", "nu": "1"}


def test_map_is_blank_without_instability_below_tau_max():
    """Large viscosity lifts every finger above tau = 1/2 (thesis 6.3): no point of the map
    is unstable, and the map says so instead of returning a value."""
    ds = tau_map("sphere", x=("kappa", [0.02, 0.05]), y=("nu", [0.5]), m="2:3", workers=1)
    res = minimum_map(ds, "kappa", "nu")
    assert not res.has_tau.any() and np.all(np.isnan(res.tau_min))
    assert json.loads(json.dumps(map_dict(res), allow_nan=False))["tau_min"] == [[None, None]]


def test_fig_6_6_marks_the_simulated_modes(tmp_path, capsys):
    """Fig 6.6: at tau = 0.45 the unstable degrees are those the thesis's simulations showed."""
    assert main(["figure", "fig-6.6", "--out", str(tmp_path), "--workers", "1"]) == 0
    assert (tmp_path / "fig-6.6.png").stat().st_size > 10_000
    data = json.loads((tmp_path / "fig-6.6.json").read_text())
    unstable = {d["case"]: [(m["m"], m["kind"]) for m in d["stability"]["modes"] if m["unstable"]]
                for d in data}
    assert unstable == {1: [(3, "subharmonic")], 2: [(2, "subharmonic")],
                        3: [(4, "subharmonic")], 4: [(2, "harmonic")]}


@pytest.mark.slow
def test_fig_6_2_tips_at_lamb_resonances(tmp_path):
    """Fig 6.2 (inviscid): fingers touch tau = 0 where lambda0 = k/2 (6.24), lambda0^2 from (6.23)."""
    assert main(["figure", "fig-6.2", "--out", str(tmp_path), "--workers", "1"]) == 0
    data = json.loads((tmp_path / "fig-6.2.json").read_text())
    for panel in data:
        m = panel["params"]["m"]
        unit = lambda0_squared(m, 1.0)
        expected = [(k / 2) ** 2 / unit for k in range(1, 20) if 0.002 < (k / 2) ** 2 / unit < 0.4]
        got = sorted(t["kappa"] for t in panel["tips"])
        np.testing.assert_allclose(got, expected, rtol=1e-9)


def test_tau_map_rejects_physical_axis_without_physical_values():
    with pytest.raises(ValueError, match="physical"):
        tau_map("sphere", x=("sigma", [1.0]), y=("nu", [0.1]), m=2)
    with pytest.raises(ValueError, match="m"):
        tau_map("sphere", x=("kappa", [1.0]), y=("nu", [0.1]), m="1:3")


def test_fig_7_1_limits(tmp_path):
    """Fig 7.1: at small zeta the frequency approaches the inviscid lambda0 (7.4) from below;
    at zeta = 10 the least-damped mode no longer oscillates and decays slowly (Stokes limit)."""
    assert main(["figure", "fig-7.1", "--out", str(tmp_path)]) == 0
    data = json.loads((tmp_path / "fig-7.1.json").read_text())
    for m, modes in data["modes"].items():
        lam = math.sqrt(lambda0_squared(int(m), 1.0))
        first, last = modes[0][0], modes[-1][0]
        assert 0.95 * lam < first["gamma_im"] < lam and first["gamma_re"] < 0
        assert last["gamma_im"] < 1e-3 * abs(last["gamma_re"]) and -0.1 < last["gamma_re"] < 0


def test_drawing_leaves_the_users_matplotlib_backend_alone(tmp_path):
    """Plots are made without pyplot: importing them and writing a PNG neither selects a
    backend nor imports pyplot (a notebook keeps its own)."""
    code = f"""
import sys
import matplotlib
matplotlib.use("svg")
import spectralshell as ss
from spectralshell.plots import ince_strutt, sweep_plot, tau_map, trajectory, cochlea
res = ss.tongues("mathieu", kappa="0.1:1:5", nu=0.1, workers=1, tips=False)
ince_strutt.save([res], r"{tmp_path / 'tongues.png'}")
assert matplotlib.get_backend() == "svg", matplotlib.get_backend()
assert "matplotlib.pyplot" not in sys.modules
"""
    import subprocess
    import sys

    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120)
    assert run.returncode == 0, run.stderr
    assert (tmp_path / "tongues.png").stat().st_size > 5_000
