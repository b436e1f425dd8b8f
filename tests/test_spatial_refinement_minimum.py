"""Refinement in M of the smallest tau over both kinds (solvers.spatial_refinement.refine_minimum):
the kind not attaining the minimum is solved only below it. Checked against dense QZ of the full
Hill pencils (every real tau of the truncation, no capping, no Krylov) and against the
independent per-kind refinement. Cheap points: a viscous fluid (mu = 2 g/(cm s)) and a fixed
temporal truncation N = 6."""

import math

import numpy as np
import pytest

from spectralshell.discretise.hill import assemble
from spectralshell.errors import ConvergenceError
from spectralshell.models.cochlea import hill_system
from spectralshell.params.physical import cochlea_forced
from spectralshell.results.records import MarginalTau
from spectralshell.solvers import spatial_refinement as sr
from spectralshell.solvers.marginal import dense_taus, structured_taus

OPTIONS = {"n_temporal": 6, "tau_max": 0.5}
KINDS = ("harmonic", "subharmonic")


def _factory(frequency: float, sigma: float):
    d = cochlea_forced(rho=1.0, mu=2.0, sigma=sigma, length=3.5, lambda_c=1.4,
                       omega=2 * math.pi * frequency)
    return lambda m: hill_system(n_spatial=m, **d)


def _qz_taus(system, kind: str, n_temporal: int) -> np.ndarray:
    """Real tau in [0, 1/2] of one truncation by dense QZ of the real-form pencil."""
    tau = dense_taus(assemble(system, kind, n_temporal, "real"))
    return np.sort(tau[(tau >= 0) & (tau <= 0.5)])


@pytest.mark.parametrize("frequency, sigma, leader", [
    (600.0, 1e9, "harmonic"),     # harmonic 0.30, subharmonic 0.49 (per-kind refinement)
    (100.0, 1e7, "subharmonic"),  # subharmonic 0.40, harmonic 0.47
])
def test_minimum_agrees_with_dense_qz_and_with_per_kind_refinement(frequency, sigma, leader):
    factory = _factory(frequency, sigma)
    # the other kind first: it is solved in full at the start M, then capped once the leader
    # is known
    other = next(k for k in KINDS if k != leader)
    joint = sr.refine_minimum(factory, (other, leader), options=OPTIONS)
    assert joint.converged and list(joint.taus) == [other, leader]
    low = sr.minimum(joint.taus)
    assert low == joint.taus[leader].tau_min
    assert joint.caps == {leader: 0.5, other: low}
    assert joint.taus[other].tau_min is None  # nothing of the other kind below the minimum

    # oracle 1: dense QZ of both kinds at the final M and N: the smallest tau over both kinds
    # is the reported minimum, and the other kind has nothing below it
    system = factory(joint.n_spatial)
    qz = {k: _qz_taus(system, k, OPTIONS["n_temporal"]) for k in KINDS}
    assert qz[leader][0] == pytest.approx(low, rel=1e-9)
    assert qz[other].size == 0 or qz[other][0] > low

    # oracle 2: the independent refinement of each kind in full (to tau_max = 1/2)
    alone = {k: sr.refine_spatial(factory, (k,), options=OPTIONS).taus[k].tau_min for k in KINDS}
    assert alone[other] is not None and alone[other] > alone[leader]
    assert abs(low - alone[leader]) <= 1e-3  # tol_spatial: both passed the same test in M


def _scripted(monkeypatch, table):
    """refine_minimum on scripted values: ``table[M][kind]`` is the kind's tau_min at M, reported
    when <= the tau_max it is solved with (the reach test always passes)."""
    calls = []

    def fake(system, kind, *, tau_max, **_):
        tau = table[system.block_size][kind]
        calls.append((system.block_size, kind, tau_max))
        found = tau if tau <= tau_max else None
        return MarginalTau(kind=kind, tau=np.array([] if found is None else [found]),
                           tau_min=found, n_temporal=6, n_previous=4,
                           error_estimate=None if found is None else 0.0, method="structured")

    monkeypatch.setattr(sr, "marginal_tau", fake)
    monkeypatch.setattr(sr, "reaches_resonance", lambda *_: True)
    return calls


class _Modes:
    def __init__(self, m):
        self.block_size = m


def test_leader_first_caps_and_a_switch_of_leader(monkeypatch):
    """By hand: M = 16: harmonic 0.32 leads, the subharmonic (0.40) is capped at 0.32 and not
    seen. M = 24: the harmonic (first) moves to 0.45, and the subharmonic, capped at 0.45, leads
    with 0.2995. M = 32: the subharmonic first (0.2999), the harmonic capped at it: the window
    (16, 24, 32) fails, as the minimum moved by 0.02 from M = 16. M = 48: the subharmonic first
    (0.2997), the harmonic capped at it: over the window (24, 32, 48) the changes are 2e-4
    (subharmonic, its smallest cap 0.45) and 0 (harmonic, capped at 0.2997, where 0.45 and
    'none' both count as the cap): converged, reported as (24, 48)."""
    table = {16: {"harmonic": 0.32, "subharmonic": 0.40},
             24: {"harmonic": 0.45, "subharmonic": 0.2995},
             32: {"harmonic": 0.45, "subharmonic": 0.2999},
             48: {"harmonic": 0.45, "subharmonic": 0.2997}}
    calls = _scripted(monkeypatch, table)
    r = sr.refine_minimum(_Modes, KINDS, options={"tau_max": 0.5}, start=16, limit=512)
    assert calls == [(16, "harmonic", 0.5), (16, "subharmonic", 0.32),
                     (24, "harmonic", 0.5), (24, "subharmonic", 0.45),
                     (32, "subharmonic", 0.5), (32, "harmonic", 0.2999),
                     (48, "subharmonic", 0.5), (48, "harmonic", 0.2997)]
    assert (r.n_spatial_previous, r.n_spatial, r.converged) == (24, 48, True)
    assert r.caps == {"harmonic": 0.2997, "subharmonic": 0.5} and list(r.taus) == list(KINDS)
    assert r.taus["harmonic"].tau_min is None and sr.minimum(r.taus) == 0.2997
    assert r.change["subharmonic"] == pytest.approx(2e-4, abs=1e-15)
    assert r.change["harmonic"] == 0.0


def test_the_minimum_itself_must_settle(monkeypatch):
    """Per-kind changes within tol can add up in the minimum: at M = 16 the subharmonic leads
    (0.3028) and the harmonic is capped out; at M = 24 the subharmonic gives 0.3014 and the
    harmonic, capped there, 0.3000; at M = 32 the harmonic leads (0.3000) and caps the
    subharmonic out. Over the window (16, 24, 32) the harmonic changes by 1.4e-3 (its
    smallest cap 0.3014) and the subharmonic by 0 (capped at 0.3000), while the minimum moved by
    2.8e-3 > tol = 1.5e-3: refined on to M = 48, passing at (24, 48)."""
    table = {16: {"harmonic": 0.31, "subharmonic": 0.3028},
             **{m: {"harmonic": 0.3000, "subharmonic": 0.3014} for m in (24, 32, 48)}}
    _scripted(monkeypatch, table)
    r = sr.refine_minimum(_Modes, ("subharmonic", "harmonic"), options={"tau_max": 0.5},
                          tol_spatial=1.5e-3, start=16, limit=512)
    assert (r.n_spatial_previous, r.n_spatial, r.converged) == (24, 48, True)
    assert sr.minimum(r.taus) == 0.3000
    short = sr.refine_minimum(_Modes, ("subharmonic", "harmonic"), options={"tau_max": 0.5},
                              tol_spatial=1.5e-3, start=16, limit=32, strict=False)
    assert not short.converged and max(short.change.values()) <= 1.5e-3
    assert short.change["harmonic"] == pytest.approx(1.4e-3, abs=1e-15)


def test_capped_change_and_minimum():
    """A tau_min above the cap counts as the cap (a kind solved with a higher cap at one M)."""
    def m(kind, tau):
        return MarginalTau(kind=kind, tau=np.array([] if tau is None else [tau]), tau_min=tau,
                           n_temporal=6, n_previous=4, error_estimate=None if tau is None else 0.0,
                           method="structured")

    assert sr.spatial_change(m("harmonic", 0.3), m("harmonic", None), 0.2) == 0.0
    assert sr.spatial_change(m("harmonic", 0.3), m("harmonic", 0.25), 0.2) == 0.0
    assert sr.spatial_change(m("harmonic", 0.19), m("harmonic", 0.25), 0.2) == pytest.approx(0.01)
    taus = {"harmonic": m("harmonic", 0.3), "subharmonic": m("subharmonic", 0.2)}
    assert sr.minimum(taus) == 0.2 and sr.minimum({"harmonic": m("harmonic", None)}) is None


def test_a_hopeless_last_step_is_skipped(monkeypatch):
    """No tau at all, and the resonance reached from M = 300 on (scripted): with limit 512 the
    last window (256, 384, 512) could not pass (256 does not reach), so the refinement stops
    unconverged at M = 384 without solving M = 512; with limit 1024 it goes on and passes at
    the window (384, 512, 768). A tau still moving is refined to the limit regardless."""
    table = {m: {"harmonic": 1.0, "subharmonic": 1.0} for m in sr.spatial_ladder(16, 1024)}
    calls = _scripted(monkeypatch, table)
    monkeypatch.setattr(sr, "reaches_resonance", lambda system, *_: system.block_size >= 300)
    stop = sr.refine_spatial(_Modes, ("harmonic",), options={"tau_max": 0.5}, start=64,
                             limit=512, strict=False)
    assert (stop.n_spatial, stop.converged) == (384, False)
    assert max(m for m, *_ in calls) == 384
    with pytest.raises(ConvergenceError, match="n_spatial=192.*reach the harmonic resonance"):
        sr.refine_spatial(_Modes, ("harmonic",), options={"tau_max": 0.5}, start=64, limit=512)
    on = sr.refine_minimum(_Modes, KINDS, options={"tau_max": 0.5}, start=64, limit=1024)
    assert (on.n_spatial_previous, on.n_spatial, on.converged) == (384, 768, True)
    assert sr.minimum(on.taus) is None
    # a value still moving up to M = 384: the last window is solved (0.2 -> 0.15), unconverged
    for m, tau in ((128, 0.40), (192, 0.35), (256, 0.30), (384, 0.20), (512, 0.15)):
        table[m]["subharmonic"] = tau
    moving = sr.refine_minimum(_Modes, KINDS, options={"tau_max": 0.5}, start=64, limit=512,
                               strict=False)
    assert (moving.n_spatial, moving.converged, sr.minimum(moving.taus)) == (512, False, 0.15)


@pytest.mark.slow
def test_low_frequency_stiff_human_cochlea_needs_only_the_harmonic_kind():
    """Table 5.1 at f = 50 Hz, sigma = 2e9 (Fig 5.18's costliest cell): the harmonic kind attains
    the minimum (0.4827, as its own refinement finds), and the subharmonic kind, capped there,
    has no tau below it -- checked by dense eig of the half product at the truncations its
    capped solve stopped at (every real tau of the truncation, no cover)."""
    d = cochlea_forced(rho=1.0, mu=0.02, sigma=2e9, length=3.5, lambda_c=1.4,
                       omega=2 * math.pi * 50.0)

    def factory(m):
        return hill_system(n_spatial=m, **d)

    options = {"tol": 1e-4, "tau_max": 0.5}
    joint = sr.refine_minimum(factory, KINDS, options=options)
    alone = sr.refine_spatial(factory, ("harmonic",), options=options)
    assert joint.converged and sr.minimum(joint.taus) == joint.taus["harmonic"].tau_min
    assert abs(joint.taus["harmonic"].tau_min - alone.taus["harmonic"].tau_min) <= 1e-3
    assert 0.48 < joint.taus["harmonic"].tau_min < 0.49
    sub, cap = joint.taus["subharmonic"], joint.caps["subharmonic"]
    assert sub.tau_min is None and cap == joint.taus["harmonic"].tau_min
    system = factory(joint.n_spatial)
    for n in (sub.n_previous, sub.n_temporal):
        tau = structured_taus(assemble(system, "subharmonic", n, "two-sided"))
        assert not np.any(tau <= cap)



def test_coarser_m_tau_min_is_the_next_m_hint_and_changes_nothing_but_speed(monkeypatch):
    """At each M a kind's solver hint is its tau_min at the M before it where it has one
    (else the caller's, here none): checked on the calls; and the refinement (its truncations
    at M >= 64 go through Arnoldi or the shift-invert cover) gives the same minimum, pair of M
    and error estimates with these hints as with none, the minimum agreeing with dense QZ."""
    seen = []
    real = sr.marginal_tau

    def spy(system, kind, **kw):
        found = real(system, kind, **kw)
        seen.append((system.block_size, kind, kw.get("hint"), found.tau_min))
        return found

    monkeypatch.setattr(sr, "marginal_tau", spy)
    factory = _factory(600.0, 1e9)
    hinted = sr.refine_minimum(factory, KINDS, options=OPTIONS)
    found = {(m, k): t for m, k, _, t in seen}
    solved = sorted({m for m, *_ in seen})
    assert solved == list(sr.spatial_ladder(16, hinted.n_spatial))
    for m, kind, hint, _ in seen:
        coarse = found.get((solved[solved.index(m) - 1], kind))
        if m > 16 and coarse is not None and coarse <= 0.5:
            assert hint == coarse
    assert any(h is not None for *_, h, _ in seen)
    monkeypatch.setattr(sr, "coarser_hints", lambda coarse, hints, default: hints)
    seen.clear()
    plain = sr.refine_minimum(factory, KINDS, options=OPTIONS)
    assert all(h is None for _, _, h, _ in seen)
    assert hinted.converged and plain.converged
    assert (hinted.n_spatial, hinted.n_spatial_previous) == (plain.n_spatial,
                                                             plain.n_spatial_previous)
    low = sr.minimum(hinted.taus)
    assert low is not None and abs(low - sr.minimum(plain.taus)) < 1e-11
    for k in KINDS:
        a, b = hinted.taus[k], plain.taus[k]
        assert (a.tau_min is None) == (b.tau_min is None)
        if a.tau_min is not None:
            assert abs(a.error_estimate - b.error_estimate) < 1e-11
    leader = next(k for k in KINDS if hinted.taus[k].tau_min == low)
    qz = _qz_taus(factory(hinted.n_spatial), leader, OPTIONS["n_temporal"])
    assert qz[0] == pytest.approx(low, rel=1e-9)


def test_empty_answers_proved_at_the_returned_window_only(monkeypatch):
    """certify_empty with a converging N: the other kind's empty answer is proved by the zero
    count (or its disk) at the three M of the returned window only (the finest M's is returned,
    the coarser M's changes rest on theirs), with the answer marginal_tau gives there with
    certify_empty itself (the former path: complete_to = its cap, the same truncation pair);
    where the proof fails the window has not converged (change unknown) and the answer is
    marked (complete_to 0), or refused with certify_empty=True."""
    from spectralshell.solvers import marginal

    factory = _factory(600.0, 1e9)
    options = {"tol": 1e-4, "tau_max": 0.5, "certify_empty": "mark"}
    proved = []
    walk = marginal.none_up_to
    monkeypatch.setattr(marginal, "none_up_to",
                        lambda hill, tau_max, solves=None:
                        proved.append(hill.diag.shape[1]) or walk(hill, tau_max, solves))
    joint = sr.refine_minimum(factory, KINDS, options=options, tol_spatial=0.05)
    other = joint.taus["subharmonic"]
    cap = joint.caps["subharmonic"]
    assert joint.converged and other.tau_min is None and cap < 0.5
    assert joint.n_spatial > sr.SPATIAL_START  # a coarser M was solved, and not proved
    window = (joint.n_spatial_previous, sr.finer_spatial(joint.n_spatial_previous), joint.n_spatial)
    assert window == (16, 24, 32) and set(proved) == set(window)
    # the minimum: the harmonic tau_min of dense eig of W (every real tau of the truncation)
    # at the returned M and N; its change the larger distance to the harmonic tau_min of
    # marginal_tau at the two coarser M of the window (uncapped: the leader's cap is tau_max)
    lead = joint.taus["harmonic"]
    assert joint.caps["harmonic"] == 0.5 and lead.complete_to >= lead.tau_min
    dense = structured_taus(assemble(factory(32), "harmonic", lead.n_temporal, "real"))
    assert dense[0] == pytest.approx(lead.tau_min, rel=1e-9)
    coarser = [marginal.marginal_tau(factory(m), "harmonic", tol=1e-4, tau_max=0.5).tau_min
               for m in window[:2]]
    assert joint.change["harmonic"] == pytest.approx(
        max(abs(lead.tau_min - t) for t in coarser), abs=1e-12)
    assert 0.0 < joint.change["harmonic"] <= 0.05 and joint.change["subharmonic"] == 0.0
    former = marginal.marginal_tau(factory(joint.n_spatial), "subharmonic", tol=1e-4,
                                   tau_max=cap, certify_empty="mark")
    assert other.complete_to == former.complete_to == cap
    assert (other.n_temporal, other.n_previous) == (former.n_temporal, former.n_previous)
    monkeypatch.setattr(marginal, "none_up_to", lambda hill, tau_max, solves=None: False)
    marked = sr.refine_minimum(factory, KINDS, options=options, tol_spatial=0.05, strict=False)
    assert marked.taus["subharmonic"].complete_to == 0.0
    assert not marked.converged and marked.change["subharmonic"] is None
    assert marked.n_spatial == joint.n_spatial  # the next window's coarser M are unproved too
    assert marked.taus["harmonic"].tau_min == joint.taus["harmonic"].tau_min
    with pytest.raises(ConvergenceError, match="zero count cannot prove"):
        sr.refine_minimum(factory, KINDS, options={**options, "certify_empty": True},
                          tol_spatial=0.05)
