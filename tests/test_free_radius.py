"""The eigenvalue-free disk of a bipartite Hill pencil from block norms of W
(half_product.free_radius) and the count it stands in for (contour.none_up_to, issue 25):
checked against dense QZ of the same truncations and against the count itself."""

import numpy as np
import pytest

from spectralshell.errors import ConvergenceError
from spectralshell.solvers import contour, marginal
from spectralshell.solvers.half_product import (block_inverses, coupled_solves, cut_solves,
                                                 dense_half_product, free_radius,
                                                 mirrored_solves)
from spectralshell.solvers.marginal import (Pencils, TruncationSchedule, certify_empty_answer,
                                             finer, marginal_tau)

from test_contour_blocks import cochlea, qz_squares, random_pencil, real_squares


def real_taus(hill) -> np.ndarray:
    """The real tau > 0 of QZ, ascending."""
    z = real_squares(qz_squares(hill))
    return np.sqrt(z[z > 0])


def smallest_modulus(hill) -> float:
    """min |tau| over the finite eigenvalues (dense QZ)."""
    return float(np.sqrt(np.abs(qz_squares(hill)).min()))


@pytest.mark.parametrize("kind", ["harmonic", "subharmonic"])
@pytest.mark.parametrize("n_spatial, n_temporal, frequency", [(8, 12, 116.9), (16, 6, 3000.0)])
def test_free_radius_below_every_eigenvalue_cochlea(kind, n_spatial, n_temporal, frequency):
    """Gerbil cochlea truncations (two-sided form): no QZ eigenvalue has |tau| below the
    radius, and the bound is not trivially small: within a factor 10 of the nearest one (4.3 at
    116.9 Hz, the subharmonic kind)."""
    hill = Pencils(cochlea(n_spatial, frequency), kind).pencil(n_temporal, "two-sided")
    radius, nearest = free_radius(hill), smallest_modulus(hill)
    assert nearest / 10 < radius <= nearest


def test_free_radius_real_form_and_random():
    """The harmonic real form (real blocks, the n = 0 row's own coupling) and random complex
    pencils: the radius never exceeds the smallest |tau| of QZ."""
    hill = Pencils(cochlea(8), "harmonic").pencil(12, "real")
    assert hill.bipartite
    assert 0 < free_radius(hill) <= smallest_modulus(hill)
    for seed in range(6):
        hill = random_pencil(7, 4, seed)
        assert 0 < free_radius(hill) <= smallest_modulus(hill)


@pytest.mark.parametrize("kind", ["harmonic", "subharmonic"])
def test_radius_of_a_cut_from_the_larger_truncations_solves(kind):
    """The disk bound of the pair (N, N') from the block solves kept for N'
    (Pencils.coupled_solves; N's cut out of them by half_product.cut_solves) equals each
    truncation's own bound bitwise, and each of the first half of the blocks of A is solved
    once for both (the two-sided form is mirrored: the other half are their conjugates)."""
    system = cochlea(16, 3000.0)
    first = TruncationSchedule.of(system).first
    pencils = Pencils(system, kind)
    pencils.reserve = finer(first)
    for n in (first, finer(first)):
        hill = pencils.pencil(n, "two-sided")
        assert free_radius(hill, pencils.coupled_solves(n, "two-sided")) == free_radius(hill)
    solve, negated = pencils.coupled_solves(finer(first), "two-sided")
    assert negated  # the cochlea's coupling i G, -i G
    assert solve.cache_info().misses == -(-len(pencils.pencil(finer(first), "two-sided").diag) // 2)


def dense_radius(hill) -> float:
    """The bound of free_radius from the blocks of the dense W (dense_half_product, block
    inverses instead of LU solves): rho of the tridiagonal matrix of block norms, the larger
    radius of the 1- and inf-norms."""
    K, s, _ = hill.diag.shape
    W = dense_half_product(hill, block_inverses(hill))
    m = (K + 1) // 2
    radius = 0.0
    for axis in (0, 1):  # column sums: 1-norm; row sums: inf-norm
        N = np.array([[np.abs(W[i * s:(i + 1) * s, j * s:(j + 1) * s]).sum(axis=axis).max()
                       for j in range(m)] for i in range(m)])
        radius = max(radius, np.abs(np.linalg.eigvals(N)).max() ** -0.5)
    return radius


@pytest.mark.parametrize("kind", ["harmonic", "subharmonic"])
@pytest.mark.parametrize("n_temporal", [6, 7, 12])
def test_mirrored_radius_equals_dense_block_norms(kind, n_temporal):
    """The two-sided cochlea pencil is mirrored (A_{K-1-k} = conj(A_k)); its radius, whose
    blocks past the middle come from their reflections (K odd, harmonic: the norms of W's
    blocks too), equals the bound formed from every block of the dense W; each mirrored block
    solve equals the direct one."""
    hill = Pencils(cochlea(8, 3000.0), kind).pencil(n_temporal, "two-sided")
    assert hill.mirrored and hill.reflected and hill.negated
    assert free_radius(hill) == pytest.approx(dense_radius(hill), rel=1e-10)
    solve, _ = coupled_solves(hill)
    reflected = mirrored_solves(solve, len(hill.diag))
    for k in range(len(hill.diag)):
        for own, mirror in zip(solve(k), reflected(k)):
            assert (own is None) == (mirror is None)
            if own is not None:
                np.testing.assert_allclose(mirror, own, rtol=0, atol=1e-13 * np.abs(own).max())


def test_radius_of_a_cut_random_coupling():
    """A random pencil whose couplings are not negatives of each other: the cut's bound from
    the larger pencil's solves equals its own (to rounding: at the cut's ends the larger
    pencil solves both couplings in one call)."""
    for seed in range(4):
        big = random_pencil(9, 4, seed)
        solve, negated = coupled_solves(big)
        assert not negated
        for n in (2, 3):
            cut = big.truncated(n)
            own = free_radius(cut)
            kept = free_radius(cut, (cut_solves(solve, big.block_range(n)), cut.negated))
            assert own > 0 and kept == pytest.approx(own, rel=1e-12)


def test_free_radius_declines_on_a_singular_block():
    """A singular or ill-conditioned block of A gives no bound (0)."""
    hill = random_pencil(5, 4, 1)
    diag = hill.diag.copy()
    diag[2, :, 0] = diag[2, :, 1] * (1 + 1e-12)
    bad = type(hill)(kind=hill.kind, form=hill.form, n_temporal=hill.n_temporal, diag=diag,
                     lower=hill.lower, upper=hill.upper, self_coupling=None)
    assert free_radius(bad) == 0.0


@pytest.mark.parametrize("kind", ["harmonic", "subharmonic"])
def test_disk_proof_agrees_with_count(kind):
    """Where the disk proves a truncation empty up to tau_max, the count (the former path)
    proves it too and QZ has no eigenvalue of |tau| <= tau_max; above the smallest real tau
    neither claims it."""
    hill = Pencils(cochlea(8), kind).pencil(12, "two-sided")
    radius = free_radius(hill)
    tau_max = 0.8 * radius
    z_max = tau_max * tau_max
    assert contour._free_disk(hill, np.hypot(z_max * (1 + 1e-6), 1e-4 * z_max))
    assert contour._zeros_below(contour.LogDet(hill), z_max * (1 + 1e-6), z_max) == 0
    assert contour.none_up_to(hill, tau_max)
    assert smallest_modulus(hill) > tau_max
    real = np.sqrt(real_squares(qz_squares(hill)).min())
    assert not contour.none_up_to(hill, 1.01 * real)


@pytest.mark.parametrize("kind", ["harmonic", "subharmonic"])
def test_certified_empty_equals_count_only(kind, monkeypatch):
    """A certified empty answer of the viscous cochlea (M = 16, tau_max well below the first
    eigenvalue): the same MarginalTau with the disk as with the count alone (the former
    path, the disk disabled), and the disk was used."""
    system = cochlea(16, 3000.0)
    first = TruncationSchedule.of(system).first  # an empty pair stops at (first, finer(first))
    pencils = Pencils(system, kind)
    tau_max = 0.5 * min(free_radius(pencils.pencil(n, "two-sided")) for n in (first, finer(first)))
    used = []
    disk = contour._free_disk
    monkeypatch.setattr(contour, "_free_disk", lambda *a: used.append(disk(*a)) or used[-1])
    fast = marginal_tau(system, kind, tol=1e-4, tau_max=tau_max, certify_empty=True)
    assert used and all(used)
    monkeypatch.setattr(contour, "_free_disk", lambda *a: False)
    counted = marginal_tau(system, kind, tol=1e-4, tau_max=tau_max, certify_empty=True)
    assert fast.tau_min is None and counted.tau_min is None
    assert fast.complete_to == counted.complete_to == tau_max
    assert (fast.n_temporal, fast.n_previous) == (counted.n_temporal, counted.n_previous)
    assert (fast.n_previous, fast.n_temporal) == (first, finer(first))


@pytest.mark.parametrize("kind", ["harmonic", "subharmonic"])
def test_expected_empty_answer_proved_by_the_disk(kind, monkeypatch):
    """expect_empty (a kind with nothing below its cap at the coarser M, issue 25): where the
    disk bound proves both truncations empty, the answer is the plain solve's (the same
    truncation pair, nothing below tau_max, which QZ confirms at both truncations), proved
    (empty_proved, method 'contour'), and its certification walks no count; where the bound
    fails (tau_max above the smallest real tau), the same tau_min as the plain solve."""
    system = cochlea(16, 3000.0)
    first = TruncationSchedule.of(system).first
    pencils = Pencils(system, kind)
    pair = (first, finer(first))
    tau_max = 0.5 * min(free_radius(pencils.pencil(n, "two-sided")) for n in pair)
    plain = marginal_tau(system, kind, tol=1e-4, tau_max=tau_max)
    expected = marginal_tau(system, kind, tol=1e-4, tau_max=tau_max, expect_empty=True)
    assert plain.tau_min is None and not plain.empty_proved and plain.method != "contour"
    assert expected.tau_min is None and expected.empty_proved and expected.method == "contour"
    assert (expected.n_previous, expected.n_temporal) == (plain.n_previous, plain.n_temporal)
    assert expected.complete_to == tau_max
    for n in pair:  # no eigenvalue at all with |tau| <= tau_max
        assert np.abs(qz_squares(pencils.pencil(n, "two-sided"))).min() > tau_max**2

    def walked(*args, **kwargs):
        raise AssertionError("a proved answer was counted again")

    monkeypatch.setattr(marginal, "none_up_to", walked)
    proved = certify_empty_answer(system, kind, expected, tau_max, True)
    assert proved.complete_to == tau_max and proved.empty_proved
    monkeypatch.undo()
    real = float(real_taus(pencils.pencil(finer(first), "two-sided"))[0])
    above = 1.01 * real
    found = marginal_tau(system, kind, tol=1e-4, tau_max=above, expect_empty=True)
    assert found.tau_min == marginal_tau(system, kind, tol=1e-4, tau_max=above).tau_min
    assert found.tau_min == pytest.approx(real, rel=1e-4) and not found.empty_proved


@pytest.mark.parametrize("kind", ["harmonic", "subharmonic"])
def test_expected_empty_answer_proved_by_the_count(kind, monkeypatch):
    """expect_empty where the disk bound cannot prove the truncations empty (tau_max above its
    radius at both) but QZ finds no eigenvalue with |tau| <= tau_max: the zero count proves
    both, so the answer is the plain solve's (the same pair, nothing below tau_max) with
    empty_proved, and its certification walks no count again."""
    system = cochlea(16, 3000.0)
    first = TruncationSchedule.of(system).first
    pencils = Pencils(system, kind)
    pair = [pencils.pencil(n, "two-sided") for n in (first, finer(first))]
    radius = max(free_radius(hill) for hill in pair)
    nearest = min(smallest_modulus(hill) for hill in pair)
    tau_max = float(np.sqrt(radius * nearest))
    assert radius < 0.9 * tau_max and tau_max < 0.9 * nearest  # the disk fails, QZ: none
    plain = marginal_tau(system, kind, tol=1e-4, tau_max=tau_max)
    expected = marginal_tau(system, kind, tol=1e-4, tau_max=tau_max, expect_empty=True)
    assert plain.tau_min is None and expected.tau_min is None
    assert expected.empty_proved and expected.method == "contour" and not expected.count_failed
    assert (expected.n_previous, expected.n_temporal) == (plain.n_previous, plain.n_temporal)

    def walked(*args, **kwargs):
        raise AssertionError("a proved answer was counted again")

    monkeypatch.setattr(marginal, "none_up_to", walked)
    assert certify_empty_answer(system, kind, expected, tau_max, True).complete_to == tau_max


def test_expected_empty_counts_after_an_empty_truncation(monkeypatch):
    """expect_empty where the first truncation has a real tau below tau_max and the later ones
    none (gerbil, 200 Hz, sigma = 1.9e9, M = 8, harmonic, tau_max = 0.48; QZ: 0.4774 at
    N = 16, 0.4859 from N = 24 on): the count is tried first at N = 16 (fails: the tau), not
    at N = 24 (its predecessor had a tau), and again at N = 36, after N = 24 was found empty
    by its solve: it proves N = 36 empty there, so that the answer's certification walks
    N = 24's count only (issue 25). The answer is the plain solve's."""
    system = cochlea(8, 200.0, 1.9e9)
    kind, tau_max = "harmonic", 0.48
    pencils = Pencils(system, kind)
    first = TruncationSchedule.of(system).first
    pair = (finer(first), finer(finer(first)))
    assert real_taus(pencils.pencil(first, "two-sided"))[0] < tau_max
    assert all(real_taus(pencils.pencil(n, "two-sided"))[0] > tau_max for n in pair)
    walks = []
    count = marginal.none_up_to

    def recorded(hill, cap, solves=None):
        walks.append(hill.n_temporal)
        return count(hill, cap, solves)

    monkeypatch.setattr(marginal, "none_up_to", recorded)
    plain = marginal_tau(system, kind, tol=1e-4, tau_max=tau_max)
    assert walks == []
    expected = marginal_tau(system, kind, tol=1e-4, tau_max=tau_max, expect_empty=True)
    assert walks == [first, pair[1]]
    assert plain.tau_min is None and expected.tau_min is None
    assert (expected.n_previous, expected.n_temporal) == (plain.n_previous, plain.n_temporal) \
        == pair
    assert expected.method == "contour" and not expected.count_failed
    assert not expected.empty_proved  # N = 24 was solved, not counted
    walks.clear()
    assert certify_empty_answer(system, kind, expected, tau_max, True).complete_to == tau_max
    assert walks == [pair[0]]


def test_failed_count_is_not_walked_again(monkeypatch):
    """A count the solve walked that fails (here made to fail: none_up_to answers False) is
    recorded on the truncation and the answer (count_failed), the next truncation is solved
    without one, and a later proof at the same tau_max fails at once without walking it
    again: the answer marked (complete_to 0) with 'mark', a ConvergenceError otherwise."""
    system = cochlea(16, 3000.0)
    kind = "harmonic"
    first = TruncationSchedule.of(system).first
    tau_max = 0.5 * free_radius(Pencils(system, kind).pencil(first, "two-sided"))
    walks = []

    def failing(hill, cap, solves=None):
        walks.append((hill.n_temporal, cap))
        return False

    monkeypatch.setattr(marginal, "none_up_to", failing)
    answer = marginal_tau(system, kind, tol=1e-4, tau_max=tau_max, expect_empty=True)
    assert answer.tau_min is None and answer.count_failed and not answer.empty_proved
    assert walks == [(first, tau_max)]

    def walked(*args, **kwargs):
        raise AssertionError("a failed count was walked again")

    monkeypatch.setattr(marginal, "none_up_to", walked)
    assert certify_empty_answer(system, kind, answer, tau_max, "mark").complete_to == 0.0
    with pytest.raises(ConvergenceError, match="cannot prove"):
        certify_empty_answer(system, kind, answer, tau_max, True)


def test_cut_inherits_checked_structure_and_replace_does_not():
    """A central cut of a mirrored two-sided pencil is mirrored, reflected and negated without
    its own check (its parent's holds); a copy with other blocks (dataclasses.replace) checks
    its own data: a changed block breaks the reflection."""
    import dataclasses

    big = Pencils(cochlea(8, 3000.0), "harmonic").pencil(12, "two-sided")
    cut = big.truncated(7)
    assert cut.parent is big and cut.mirrored and cut.reflected and cut.negated
    diag = cut.diag.copy()
    diag[0] *= 1 + 1e-12
    changed = dataclasses.replace(cut, diag=diag)
    assert changed.parent is None
    assert not changed.reflected and not changed.mirrored and changed.negated
    real = Pencils(cochlea(8, 3000.0), "harmonic").pencil(12, "real")
    assert not real.truncated(7).reflected  # a leading cut of the real form: checked, real
