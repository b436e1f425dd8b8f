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
