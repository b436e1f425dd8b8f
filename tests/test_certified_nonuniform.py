"""The sphere with a non-uniform kappa proves its empty answers (issue 23, section 2): every
sector solved below a bound is proved empty there by the zero count at both truncations of its
pair, or the answer is refused (floquet; CLI exit 1) or marked (complete_to 0: a fixed
n_temporal, the sweeps); the kind's complete_to is what its sectors prove together. Checked
against dense QZ of both truncations of every sector, at both degree truncations."""

import json
import math
from types import SimpleNamespace

import numpy as np
import pytest

import spectralshell as ss
from spectralshell.discretise.sphere_nonuniform import nonuniform_sphere
from spectralshell.errors import UncertifiedWarning
from spectralshell.params.expression import parse_expression
from spectralshell.results.maps import uncertified
from spectralshell.results.records import MarginalTau
from spectralshell.runner import nonuniform
from spectralshell.runner.nonuniform import RAISE, sector_minimum, sector_taus
from spectralshell.runner.sweep import run_sweep
from spectralshell.solvers import marginal

from test_certified_empty import qz_in_strip, qz_real_below, run

KAPPA = "0.02*(1 + 0.3*cos(theta)**2)"
#: The subharmonic tau_min at l_max = 4 (nu = 0.006), in the sector of degrees 3 and 4 (l, k)
#: = (3, +-3); QZ of its truncations below.
SUBHARMONIC_MIN = 0.35616697062
OPTIONS = {"tol": 1e-9, "n_temporal": None, "certify_empty": True}


def sphere(l_max):
    return nonuniform_sphere(kappa=parse_expression("kappa", KAPPA, positive=True).function,
                             nu=0.006, l_max=l_max)


def no_count(monkeypatch):
    """The zero count made to fail: no empty answer can be proved."""
    monkeypatch.setattr(marginal, "none_up_to", lambda hill, tau_max, solves=None: False)


def test_empty_kind_is_proved_in_every_sector_by_qz():
    """No subharmonic tau <= 0.35 (0.35616697 lies just above): floquet says complete_to =
    0.35, and in every sector of both degree truncations (l_max = 4 and 2) QZ of both
    truncations of the sector's pair has no real tau, nor any eigenvalue in the thinnest
    strip, below it."""
    res = ss.floquet("sphere", kappa=KAPPA, nu=0.006, l_max=4, kind="subharmonic", tol=1e-9,
                     tau_max=0.35)
    assert res.subharmonic.tau_min is None and res.subharmonic.complete_to == 0.35
    assert res.to_dict()["subharmonic"]["complete_to"] == 0.35
    assert "no marginal tau <= 0.35 (complete to 0.35)" in res.summary()
    assert not any("complete_to" in w for w in res.warnings)
    checked = 0
    for truncation in (sphere(4), sphere(2)):
        for i, system in enumerate(truncation.systems):
            found, bound = sector_taus(truncation, i, "subharmonic",
                                       {**OPTIONS, "tau_max": 0.35}, 0.35)
            assert found.tau_min is None and found.complete_to == bound == 0.35
            for n in (found.n_temporal, found.n_previous):
                assert not qz_real_below(system, "subharmonic", n, 0.35).size
                assert not qz_in_strip(system, "subharmonic", n, 0.35).size
                checked += 1
    assert checked == 2 * (12 + 6)


def test_a_tau_just_above_the_bound_is_found_when_it_is_raised():
    """With tau_max = 0.36 the subharmonic tau_min = 0.35616697 is found, QZ's of the critical
    sector's truncation; every other sector is proved empty below it, so complete_to is
    tau_min itself (the critical sector's further tau are not the kind's list)."""
    res = ss.floquet("sphere", kappa=KAPPA, nu=0.006, l_max=4, kind="subharmonic", tol=1e-9,
                     tau_max=0.36)
    m = res.subharmonic
    assert m.tau_min == pytest.approx(SUBHARMONIC_MIN, abs=1e-9)
    assert m.complete_to == m.tau_min and not any("certified" in w for w in res.warnings)
    found, where = sector_minimum(sphere(4), "subharmonic", {**OPTIONS, "tau_max": 0.36})
    critical = sphere(4).systems[where]
    reference = qz_real_below(critical, "subharmonic", found.n_temporal, 0.36)
    assert found.tau_min == pytest.approx(np.sort(reference)[0], rel=1e-9)
    for i, system in enumerate(sphere(4).systems):       # nothing smaller in any sector
        if i != where:
            n = sector_taus(sphere(4), i, "subharmonic", {**OPTIONS, "tau_max": 0.36},
                            found.tau_min)[0].n_temporal
            assert not qz_real_below(system, "subharmonic", n, found.tau_min * (1 - 1e-9)).size


def test_a_sector_with_a_tau_at_its_bound_is_solved_again_above_it(monkeypatch):
    """A sector solved just below its own tau_min (as below an equal tau_min of another
    sector): the count cannot prove the strip empty (a real tau at its edge), so it is solved
    again 1 % higher and returns that tau. Where the count fails and nothing lies below the
    raised bound either, the sector is refused, its message naming it and both bounds."""
    truncation = sphere(4)
    _, where = sector_minimum(truncation, "subharmonic", {**OPTIONS, "tau_max": 0.5})
    cap = SUBHARMONIC_MIN * (1 - 1e-11)
    found, bound = sector_taus(truncation, where, "subharmonic", {**OPTIONS, "tau_max": 0.5},
                               cap)
    assert bound == pytest.approx(cap * (1 + RAISE), rel=1e-15)
    assert found.tau_min == pytest.approx(SUBHARMONIC_MIN, abs=1e-9)
    no_count(monkeypatch)          # nothing below 0.303 either: refused
    with pytest.raises(ss.ConvergenceError, match=rf"subharmonic, sector {where + 1} of 12 at "
                       r"l_max = 4 \(degrees 3, 4\): .*<= tau_max=0.303 .*zero count cannot "
                       r"prove.* \(0.303 lies 1% above 0.3, the smallest tau_min of the sectors "
                       r"before it\)$"):
        sector_taus(truncation, where, "subharmonic", {**OPTIONS, "tau_max": 0.5}, 0.3)


def answer(tau_min, complete_to):
    """A harmonic MarginalTau with this tau_min (None: empty) and complete_to."""
    tau = np.empty(0) if tau_min is None else np.array([tau_min])
    return MarginalTau(kind="harmonic", tau=tau, tau_min=tau_min, n_temporal=20, n_previous=14,
                       error_estimate=None if tau_min is None else 1e-12, method="structured",
                       complete_to=complete_to)


def _scripted(monkeypatch, answers):
    """sector_taus replaced by ``answers`` (tau_min, complete_to) in sector order, each
    solved below the bound it was given."""
    def fake(sphere, i, kind, options, cap):
        return answer(*answers[i]), cap
    monkeypatch.setattr(nonuniform, "sector_taus", fake)
    return SimpleNamespace(systems=[None] * len(answers))


@pytest.mark.parametrize("answers, tau_min, complete_to, where", [
    ([(None, 0.5), (None, 0.5)], None, 0.5, None),              # empty, proved
    ([(None, 0.5), (None, 0.0)], None, 0.0, None),              # one sector unproved
    ([(0.4, math.inf), (0.3, math.inf), (None, 0.3)], 0.3, 0.3, 1),   # undercut, then empty
    ([(0.3, math.inf), (0.3, 0.9)], 0.3, 0.3, 0),              # an equal tau_min
    ([(None, 0.5), (0.3, 0.45)], 0.3, 0.45, 1),                # critical last
    ([(0.3, math.inf), (None, 0.0)], 0.3, 0.0, 0),             # tau_min not proved smallest
])
def test_kind_proves_what_its_sectors_prove(monkeypatch, answers, tau_min, complete_to, where):
    """The kind's complete_to: the critical sector's (at most its bound), min(bound,
    complete_to) of an empty sector, the tau_min of a sector not critical."""
    fake = _scripted(monkeypatch, answers)
    found, at = sector_minimum(fake, "harmonic", {"tau_max": 0.5})
    assert (found.tau_min, found.complete_to, at) == (tau_min, complete_to, where)


def test_unproved_empty_sectors_are_refused_or_marked(monkeypatch):
    """With the count failing: floquet raises, naming the sector and what to change; the CLI
    prints that one line and exits 1; a fixed n_temporal keeps the answer with complete_to 0
    and a warning for each kind (the empty one, and the tau_min not proved the smallest)."""
    no_count(monkeypatch)
    with pytest.raises(ss.ConvergenceError, match=r"harmonic, sector 1 of 6 at l_max = 2 "
                       r"\(degrees 2\): harmonic: no marginal tau <= tau_max=0.5 .*zero count "
                       r"cannot prove"):
        ss.floquet("sphere", kappa=KAPPA, nu=0.006, l_max=4, tau_max=0.5, tol=1e-9)
    rc, out, err = run(["floquet", "sphere", "--kappa", KAPPA, "--nu", "0.006", "--l-max", "4",
                        "--tau-max", "0.5", "--json"])
    assert rc == 1 and out == "" and len(err.strip().splitlines()) == 1
    assert "sector 1 of" in err and "zero count cannot prove" in err
    res = ss.floquet("sphere", kappa=KAPPA, nu=0.006, l_max=4, tau_max=0.5, n_temporal=20)
    assert res.harmonic.tau_min is None and res.harmonic.complete_to == 0.0
    assert res.subharmonic.tau_min is not None and res.subharmonic.complete_to == 0.0
    data = res.to_dict()
    assert data["harmonic"]["complete_to"] == data["subharmonic"]["complete_to"] == 0.0
    assert any(w.startswith("harmonic: no marginal tau <= 0.5 was found, but none is proved "
                            "only below complete_to = 0") for w in res.warnings)
    assert any(w.startswith("subharmonic tau_min") and "not certified" in w
               for w in res.warnings)


SCENE = {"model": "sphere", "params": {"kappa": KAPPA, "l_max": 4}, "grid": {"nu": [0.006]},
         "tau_min": {"tol": 1e-8}}


def test_a_sweep_marks_unproved_points(monkeypatch, tmp_path):
    """A sweep of the non-uniform sphere with the count failing keeps its points, with
    complete_to 0: the empty harmonic one and the subharmonic tau_min (not proved the
    smallest) are uncertified (the plots mark them by it), the API warns (sweep and tau_map),
    the CLI's sweep writes them and exits 1."""
    no_count(monkeypatch)
    done = run_sweep(SCENE, executor="serial")
    ds = done.dataset
    np.testing.assert_array_equal(ds["complete_to"].values, 0.0)
    np.testing.assert_array_equal(ds["has_tau"].values, [[False, True]])
    assert done.uncertified == 2 and uncertified(ds).values.all()
    with pytest.warns(UncertifiedWarning, match=r"2 of 2 points .*tau_max"):
        ss.sweep(SCENE, executor="serial")
    with pytest.warns(UncertifiedWarning, match=r"1 of 1 points .*tau_max"):
        mapped = ss.tau_map("sphere", kappa=KAPPA, x=("nu", [0.006]), y=("l_max", [4]),
                            kind="harmonic", workers=1)
    assert uncertified(mapped).values.all() and float(mapped["complete_to"].max()) == 0.0
    scene = tmp_path / "s.toml"
    scene.write_text(f'model = "sphere"\nask = ["tau_min"]\n[params]\nkappa = "{KAPPA}"\n'
                     'l_max = 4\n[grid]\nnu = [0.006]\n[tau_min]\ntol = 1e-8\n')
    rc, out, err = run(["sweep", str(scene), "--out", str(tmp_path / "s.zarr"),
                        "--executor", "serial", "--json"])
    assert rc == 1 and json.loads(out)["uncertified"] == 2
    assert len(err.strip().splitlines()) == 1 and "2 of 2 points" in err


ASYMMETRIC = "0.02*(1 + 0.2*sin(theta)*cos(phi) + 0.1*cos(theta))"


@pytest.mark.slow
def test_two_sectors_with_one_tau_min_are_proved():
    """The asymmetric kappa at l_max = 4 has two sectors (30 and 33 slots) that no symmetry
    identifies, with the same subharmonic tau_min 0.3563731 (QZ of each): the second, solved
    below the first's, cannot be proved empty there, is solved again 1 % higher, and the kind
    is proved up to tau_min (without the second solve, the failed count refused the answer)."""
    res = ss.floquet("sphere", kappa=ASYMMETRIC, nu=0.006, l_max=4, kind="subharmonic",
                     tau_max=0.5, tol=1e-10)
    m = res.subharmonic
    assert m.tau_min == pytest.approx(0.35637312578, abs=1e-10)
    assert m.tau_min <= m.complete_to <= m.tau_min * (1 + 1e-12)   # the other sector's value
    truncation = nonuniform_sphere(
        kappa=parse_expression("kappa", ASYMMETRIC, positive=True).function, nu=0.006, l_max=4)
    assert len(truncation.systems) == 2
    for system in truncation.systems:
        tau = np.sort(qz_real_below(system, "subharmonic", m.n_temporal, 0.5))
        assert tau[0] == pytest.approx(m.tau_min, rel=1e-9)


def test_the_price_includes_the_count():
    """A truncation's price (before any solve) holds the zero count of every sector of more
    than 2 slots at the last pair of each kind, as if each were empty, beside its dense
    truncations."""
    from spectralshell.runner.nonuniform import Price
    from spectralshell.solvers.cost import certify_seconds, temporal_schedule, truncation_seconds

    truncation = sphere(6)
    dense = sum(truncation_seconds(s.block_size, n) for s in truncation.systems
                for n in temporal_schedule(s))
    count = sum(certify_seconds(s, temporal_schedule(s)[-2:]) for s in truncation.systems)
    assert count > 0.1 * dense
    assert Price.of(truncation, 2, None).seconds == pytest.approx(2 * (dense + count), rel=1e-12)


@pytest.mark.parametrize("fine, coarse, expected", [
    ((None, 0.5), (None, 0.0), 0.0),      # empty at both l_max: proved as far as both are
    ((None, 0.5), (None, 0.5), 0.5),
    ((None, 0.5), (0.49, 0.49), 0.5),     # the coarse has a tau: the fine answer's own
    ((0.3, 0.3), (None, 0.0), 0.3),
])
def test_an_empty_kind_at_both_degree_truncations_is_proved_as_far_as_both(fine, coarse,
                                                                         expected):
    assert nonuniform.both_proved(answer(*fine), answer(*coarse)).complete_to == expected


@pytest.mark.parametrize("fine, coarse, expected", [
    ((0.3, 0.3), (None, 0.0), None),     # a tau at l_max, an unproved "none" at l_max - 2
    ((0.3, 0.3), (None, 0.5), 0.2),      # ... a proved one: the capped change
    ((None, 0.5), (None, 0.0), 0.0),     # empty at both: both_proved marks the answer
    ((0.3, 0.3), (0.29, 0.29), 0.01),
])
def test_the_degree_change_rests_on_no_unproved_empty_answer(fine, coarse, expected):
    found = nonuniform.degree_change(answer(*fine), answer(*coarse), 0.5)
    assert found == (None if expected is None else pytest.approx(expected, abs=1e-15))
