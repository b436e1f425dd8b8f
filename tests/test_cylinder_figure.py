"""The periodic cylinder's figure (issue 30): the minimum-tau map over (k R, kappa) and the unstable
(m, k R) at tau = 0.45. Oracle: independent single-point floquet solves at the panel's kappa."""

import json

import spectralshell as ss
from spectralshell.reports.figures import FIGURES, _cylinder_map, CYLINDER


def test_listed():
    assert "fig-cylinder" in FIGURES and "cylinder" in FIGURES["fig-cylinder"][0]


def test_unstable_pairs_match_single_point_solves(tmp_path):
    paths = _cylinder_map(tmp_path, progress=False, workers=1, size=5)
    assert all(p.exists() and p.stat().st_size > 0 for p in paths)
    data = json.loads((tmp_path / "fig-cylinder.json").read_text())
    at = data["unstable_at"]
    assert at["tau"] == CYLINDER["tau"] and at["m"] == [1, 2, 3, 4, 5, 6]
    checked = 0
    for i, m in enumerate(at["m"]):
        for j, k in enumerate(at["k"][::2]):
            res = ss.floquet("cylinder", m=m, k=k, kappa=at["kappa"], nu=CYLINDER["nu"],
                             tau_max=0.5)
            for kind in ("harmonic", "subharmonic"):
                tau = getattr(res, kind).tau_min
                assert at[kind][i][2 * j] == (tau is not None and tau <= at["tau"])
                checked += 1
    assert checked == 36
    # the map's smallest tau over m and kinds at two cells, against the same solves
    row = data["y"].index(at["kappa"])
    for k, got in zip(data["x"][:2], data["tau_min"][row][:2]):
        solves = [ss.floquet("cylinder", m=m, k=k, kappa=at["kappa"], nu=CYLINDER["nu"],
                             tau_max=0.5) for m in at["m"]]
        taus = [t for r in solves for t in (r.harmonic.tau_min, r.subharmonic.tau_min)
                if t is not None]
        assert (not taus and got is None) or abs(min(taus) - got) < 1e-8


def test_a_map_in_physical_units_matches_single_point_solves():
    """The cylinder sweeps its cgs quantities through its own physical input, with no sweep rule
    of its own: a map over sigma (dyn/cm) and omega (rad/s) at rho = 1, mu = 0.04, R = 1 and
    period 2 pi with j = 1 (k R = 1) has every cell equal to a single floquet solve given the
    same cgs inputs."""
    import math

    phys = {"rho": 1.0, "mu": 0.04, "radius": 1.0, "period": 2 * math.pi, "j": 1}
    ds = ss.tau_map("cylinder", x=("sigma", "2e2:2e3:3"), y=("omega", "20:40:3"), m="2:3",
                    physical=phys, workers=1)
    assert ds["sigma"].attrs["units"] == "dyn/cm" and ds["omega"].attrs["units"] == "rad/s"
    found = 0
    for sigma in ds["sigma"].values:
        for omega in ds["omega"].values:
            for m in (2, 3):
                res = ss.floquet("cylinder", m=m, sigma=float(sigma), omega=float(omega),
                                 tau_max=0.5, tol=1e-8, **phys)
                for kind in ("harmonic", "subharmonic"):
                    cell = ds.sel(sigma=sigma, omega=omega, m=m, kind=kind)
                    tau = getattr(res, kind).tau_min
                    assert bool(cell["has_tau"]) == (tau is not None)
                    if tau is not None:
                        assert abs(float(cell["tau_min"]) - tau) < 1e-7
                        found += 1
    assert found >= 1
