"""A refinement in M decides nothing on an unproved empty answer (issue 23, section 2): the
window that ends it has the empty answers of its three M proved (solvers.spatial_refinement, module
notes "Proof of empty answers"). Checked against dense eig of the same truncations, and against
the values the refinement gave before the coarser M was proved (computed with that code)."""

import dataclasses
import math

import numpy as np
import pytest

from spectralshell.discretise.hill import assemble
from spectralshell.errors import ConvergenceError
from spectralshell.models.cochlea import hill_system
from spectralshell.params.physical import cochlea_forced
from spectralshell.results.records import MarginalTau
from spectralshell.solvers import marginal
from spectralshell.solvers import spatial_refinement as sr
from spectralshell.solvers.marginal import structured_taus

#: A quick viscous cochlea (mu = 2 g/(cm s), 600 Hz, sigma = 1e9): the harmonic tau_min is
#: 0.3045, so with tau_max = 0.2 the answer is empty at every M, its truncation pair N = 10, 16.
POINT = cochlea_forced(rho=1.0, mu=2.0, sigma=1e9, length=3.5, lambda_c=1.4,
                       omega=2 * math.pi * 600.0)
OPTIONS = {"tol": 1e-4, "tau_max": 0.2, "certify_empty": "mark"}


def factory(m):
    return hill_system(n_spatial=m, **POINT)


def failing_at(monkeypatch, modes):
    """The zero count (and its disk) fails on the pencils with M in ``modes``; returns the
    list of the M it was asked about."""
    asked = []
    walk = marginal.none_up_to

    def none_up_to(hill, tau_max, solves=None):
        m = hill.diag.shape[1]  # the cochlea's block size is M
        asked.append(m)
        return m not in modes and walk(hill, tau_max, solves)

    monkeypatch.setattr(marginal, "none_up_to", none_up_to)
    return asked


def no_real_tau_below(m, answer, tau_max):
    """Dense eig of the half product W of the two-sided form (every real tau of the
    truncation, no count, no Krylov) at both truncations of ``answer``'s pair, M = m: no real
    tau <= tau_max."""
    for n in (answer.n_previous, answer.n_temporal):
        tau = structured_taus(assemble(factory(m), "harmonic", n, "two-sided"))
        assert tau is not None and not np.any(tau <= tau_max)


def test_every_m_of_the_window_is_proved(monkeypatch):
    """Nothing fails: the window (16, 24, 32) passes with change 0, complete_to = tau_max at
    N = 10, 16, the count asked at each of its M; dense eig confirms no real tau <= 0.2 at
    any of them."""
    asked = failing_at(monkeypatch, ())
    r = sr.refine_spatial(factory, ("harmonic",), options=OPTIONS)
    h = r.taus["harmonic"]
    assert (r.n_spatial_previous, r.n_spatial, r.converged) == (16, 32, True)
    assert r.change == {"harmonic": 0.0} and r.caps == {"harmonic": 0.2}
    assert h.tau_min is None and h.complete_to == 0.2 and (h.n_previous, h.n_temporal) == (10, 16)
    assert sorted(set(asked)) == [16, 24, 32]
    for m in (16, 24, 32):
        no_real_tau_below(m, h, 0.2)


def test_an_unproved_coarse_empty_answer_is_refined_past(monkeypatch):
    """The count fails at M = 16 only: the window (16, 24, 32) would pass with change 0 on that
    unproved "none"; instead the refinement goes on to (24, 32, 48), whose M are all proved
    (the proofs at M = 24 and 32 reused, not counted again; checked by dense eig in the test
    above)."""
    asked = failing_at(monkeypatch, (16,))
    r = sr.refine_spatial(factory, ("harmonic",), options=OPTIONS)
    assert (r.n_spatial_previous, r.n_spatial, r.converged) == (24, 48, True)
    assert r.change == {"harmonic": 0.0} and r.taus["harmonic"].complete_to == 0.2
    assert asked.count(24) == asked.count(32) == 2  # both truncations of each M, once


def test_unproved_at_both_m_is_not_converged(monkeypatch):
    """The count fails at M = 16 and 32: the window (16, 24, 32) has not converged (change
    unknown), and the next could not pass either (its M = 32 is unproved), so it stops there:
    flagged unconverged and marked (complete_to 0) without strict; with strict, a
    ConvergenceError says why."""
    failing_at(monkeypatch, (16, 32))
    r = sr.refine_spatial(factory, ("harmonic",), options=OPTIONS, strict=False)
    assert (r.n_spatial_previous, r.n_spatial, r.converged) == (16, 32, False)
    assert r.change == {"harmonic": None} and r.taus["harmonic"].complete_to == 0.0
    with pytest.raises(ConvergenceError, match="empty harmonic answer at n_spatial=16 is not "
                                               "proved"):
        sr.refine_spatial(factory, ("harmonic",), options=OPTIONS)
    with pytest.raises(ConvergenceError, match="zero count cannot prove"):
        sr.refine_spatial(factory, ("harmonic",), options={**OPTIONS, "certify_empty": True})


class _Modes:
    def __init__(self, m):
        self.block_size = m


def test_minimum_with_an_unproved_capped_kind(monkeypatch):
    """refine_minimum on scripted values (harmonic 0.30 at every M, the subharmonic 0.40
    capped away): the subharmonic's "none below 0.30" is unproved at M = 16 only. The window
    (16, 24, 32) is not accepted on it; (24, 32, 48) is, the proofs at M = 24 and 32 kept from
    the first window: the certificate is asked at M = 16, 24, 32, then 48 only."""
    def fake(system, kind, *, tau_max, **_):
        tau = 0.30 if kind == "harmonic" else 0.40
        found = tau if tau <= tau_max else None
        return MarginalTau(kind=kind, tau=np.array([] if found is None else [found]),
                           tau_min=found, n_temporal=6, n_previous=4,
                           error_estimate=None if found is None else 0.0, method="structured")

    asked = []

    def certify(system, kind, answer, tau_max, how):
        if answer.tau_min is not None:
            return answer
        asked.append(system.block_size)
        proved = tau_max if system.block_size != 16 else 0.0
        return dataclasses.replace(answer, complete_to=proved)

    monkeypatch.setattr(sr, "marginal_tau", fake)
    monkeypatch.setattr(sr, "reaches_resonance", lambda *_: True)
    monkeypatch.setattr(sr, "certify_empty_answer", certify)
    options = {"tau_max": 0.5, "certify_empty": "mark"}
    r = sr.refine_minimum(_Modes, ("harmonic", "subharmonic"), options=options)
    assert (r.n_spatial_previous, r.n_spatial, r.converged) == (24, 48, True)
    assert asked == [16, 24, 32, 48]
    assert sr.minimum(r.taus) == 0.30 and r.change == {"harmonic": 0.0, "subharmonic": 0.0}
    assert r.taus["subharmonic"].complete_to == 0.30


def test_fixed_m_has_no_change_from_an_unproved_coarse_answer(monkeypatch):
    """solve_fixed at M = 32 with a fixed N (the zero count marks instead of raising): the
    change from M = 16 is 0 where M = 16's empty answer is proved, unknown (None) where it is
    not; the answer at M = 32 is the same."""
    options = {"n_temporal": 16, "tau_max": 0.2, "certify_empty": True}
    proved = sr.solve_fixed(factory, 32, ("harmonic",), options)
    failing_at(monkeypatch, (16,))
    doubted = sr.solve_fixed(factory, 32, ("harmonic",), options)
    assert proved.change == {"harmonic": 0.0} and doubted.change == {"harmonic": None}
    for r in (proved, doubted):
        assert r.taus["harmonic"].tau_min is None and r.taus["harmonic"].complete_to == 0.2
