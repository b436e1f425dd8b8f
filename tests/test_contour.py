"""The argument-principle path for the smallest real tau (solvers.contour) against dense LAPACK:
log det by LU of the assembled A - tau B, zero counts and real tau by QZ of the same truncation,
and a coarse Fig 6.13 map cell by cell against the dense-eig path."""

import dataclasses

import numpy as np
import pytest

from spectralshell.models.fibre import hill_system as fibre
from spectralshell.models.sphere import hill_system as sphere
from spectralshell.params.physical import CARDIAC, PhysicalSphere, bpm_to_rad_per_s
from spectralshell.runner import solve
from spectralshell.runner.floquet import tau_map
from spectralshell.solvers import _schur, contour
from spectralshell.solvers.marginal import (Pencils, TruncationSchedule, dense_taus,
                                            marginal_tau, truncation_taus)

from test_contour_blocks import qz_squares, real_squares

KINDS = ("harmonic", "subharmonic")
TAU_MAX = 0.5


def atrium(sigma: float, bpm: float, m: int):
    """The sphere of Fig 6.13 at stiffness sigma (dyn/cm) and beat rate bpm."""
    forced = PhysicalSphere(rho=CARDIAC["rho"], mu=CARDIAC["mu"], radius=CARDIAC["radius"],
                            sigma=sigma, omega=bpm_to_rad_per_s(bpm)).forced()
    return sphere(m=m, kappa=forced["kappa"], nu=forced["nu"])


def cells(count: int, seed: int):
    """A seeded random sample of Fig 6.13 cells (sigma, bpm, m, kind)."""
    rng = np.random.default_rng(seed)
    lo, hi = CARDIAC["sigma_range"]
    return [(rng.uniform(lo, hi), rng.uniform(50, 650), int(rng.integers(2, 7)), KINDS[i % 2])
            for i in range(count)]


def two_sided(system, kind, n):
    return Pencils(system, kind).get(n, "two-sided")[0]


@pytest.mark.parametrize("kind", KINDS)
def test_log_det_matches_dense_lu(kind):
    """log det(A - tau B) - log det A and its z-derivative against LAPACK's LU (slogdet) of the
    assembled dense matrix, the derivative by central differences of that."""
    hill = two_sided(atrium(6000.0, 120.0, 3), kind, 14)
    log_g = contour.LogDet(hill)
    A = hill.dense(0.0)

    def dense(z):
        sign, logabs = np.linalg.slogdet(hill.dense(np.sqrt(z)))
        sign_a, logabs_a = np.linalg.slogdet(A)
        return logabs - logabs_a, sign / sign_a

    z = np.array([0.05 + 0.01j, 0.2 - 0.03j, 0.13 + 0.0j, -0.02 + 0.1j])
    values, slopes = log_g(z)
    for zj, value, slope in zip(z, values, slopes):
        modulus, phase = dense(zj)
        assert value.real == pytest.approx(modulus, abs=1e-9)
        assert np.exp(1j * value.imag) == pytest.approx(phase, abs=1e-9)
        h = 1e-6
        (up, p_up), (down, p_down) = dense(zj + h), dense(zj - h)
        difference = (up - down + np.log(p_up / p_down)) / (2 * h)
        assert slope == pytest.approx(difference, rel=1e-5)


def test_kernel_rejects_other_blocks():
    one = np.ones((3, 1, 1), dtype=complex)
    with pytest.raises(ValueError, match="2 x 2"):
        _schur.logdet(one, one[:2], one[:2], np.zeros(1, complex), np.zeros(1, complex),
                      np.zeros(1, complex))


def inside(z, left, right, half, margin=0.0):
    return ((z.real > left - margin) & (z.real < right + margin)
            & (np.abs(z.imag) < half + margin))


@pytest.mark.parametrize("sigma, bpm, m, kind", cells(6, seed=3))
def test_winding_counts_qz_eigenvalues(sigma, bpm, m, kind):
    """Zeros of g counted by the winding number = eigenvalues z = tau^2 of the dense QZ of the
    same truncation inside rectangles of several sizes (those passing within 1e-4 of an
    eigenvalue skipped)."""
    hill = two_sided(atrium(sigma, bpm, m), kind, 16)
    log_g = contour.LogDet(hill)
    z = qz_squares(hill)
    checked = 0
    for left, right, half in ((-0.01, 0.3, 0.005), (-0.05, 0.5, 0.1), (0.02, 1.0, 0.4),
                              (-0.2, 2.0, 1.0)):
        if np.any(inside(z, left, right, half, 1e-4) & ~inside(z, left, right, half, -1e-4)):
            continue
        count = np.count_nonzero(inside(z, left, right, half))
        assert contour.winding(log_g, contour.rectangle(left, right, half)) == count
        checked += 1
    assert checked >= 2


@pytest.mark.parametrize("sigma, bpm, m, kind", cells(24, seed=11))
def test_smallest_real_tau_is_qz_smallest(sigma, bpm, m, kind):
    """tau_min of the contour path = the smallest real tau <= 1/2 of QZ on the real form of the
    same truncation (the reference path), and QZ has no real tau below it: the certificate."""
    system = atrium(sigma, bpm, m)
    n = TruncationSchedule.of(system).first
    pencils = Pencils(system, kind)
    found = contour.smallest_real_tau(pencils.get(n, "two-sided")[0], TAU_MAX)
    assert found is not None  # every seeded cell is certified (a declined one: test below)
    tau_min, complete_to = found
    reference = dense_taus(pencils.get(n, "real")[0])
    reference = reference[(reference >= 0) & (reference <= TAU_MAX)]
    if tau_min is None:
        assert not reference.size and complete_to >= TAU_MAX
    else:
        assert reference.size and tau_min == pytest.approx(reference[0], rel=1e-10)
        assert complete_to > tau_min
        assert not np.any(reference[1:] <= complete_to)


def test_sample_is_mostly_certified():
    """The contour path answers (rather than declining to the dense path) on most of a seeded
    sample of Fig 6.13 cells, so that the test above checks it."""
    answered = 0
    for sigma, bpm, m, kind in cells(24, seed=11):
        system = atrium(sigma, bpm, m)
        n = TruncationSchedule.of(system).first
        answered += contour.smallest_real_tau(two_sided(system, kind, n), TAU_MAX) is not None
    assert answered >= 20


def test_close_pair_is_not_missed():
    """Two real tau 1 % apart (0.41368 and 0.41834, found by QZ) below tau_max: a coarse
    sampling of the contour would see their 2 pi turn as none and answer 'no tau'."""
    system = atrium(7000.0, 365.7894736842105, 3)
    hill = two_sided(system, "harmonic", 12)
    reference = dense_taus(Pencils(system, "harmonic").get(12, "real")[0])
    reference = reference[reference >= 0]
    assert reference[1] < 1.02 * reference[0] < TAU_MAX
    tau_min, _ = contour.smallest_real_tau(hill, TAU_MAX)
    assert tau_min == pytest.approx(reference[0], rel=1e-10)


def test_declined_truncation_is_solved_densely(monkeypatch):
    """Where the certificate is declined, 'smallest' answers as the dense path."""
    system = atrium(9000.0, 200.0, 4)
    monkeypatch.setattr("spectralshell.solvers.marginal.smallest_real_tau",
                        lambda *a, **k: None)
    declined = truncation_taus(system, "subharmonic", 30, tau_max=TAU_MAX, method="smallest")
    dense = truncation_taus(system, "subharmonic", 30, tau_max=TAU_MAX, method="dense")
    assert declined.method == dense.method == "structured"
    np.testing.assert_array_equal(declined.tau, dense.tau)


@pytest.mark.parametrize("sigma, bpm, kind", [(1000.0, 207.89473684210526, "harmonic"),
                                               (1000.0, 144.73684210526315, "subharmonic"),
                                               (15000.0, 300.0, "harmonic")])
def test_marginal_tau_smallest_matches_dense(sigma, bpm, kind):
    """A converged solve by 'smallest' = by 'dense' within tol, same truncation pair (two
    points with a tau <= 1/2 (0.3449, 0.3375), one without)."""
    system = atrium(sigma, bpm, 2)
    dense = marginal_tau(system, kind, tol=1e-9, tau_max=TAU_MAX, method="dense")
    fast = marginal_tau(system, kind, tol=1e-9, tau_max=TAU_MAX, method="smallest")
    assert (fast.tau_min is None) == (dense.tau_min is None)
    assert fast.n_temporal == dense.n_temporal
    assert fast.method == "contour"
    if dense.tau_min is not None:
        assert fast.tau_min == pytest.approx(dense.tau_min, abs=1e-9)
        assert fast.error_estimate == pytest.approx(dense.error_estimate, abs=1e-12)


def coarse_map():
    sigma = CARDIAC["sigma_range"]
    return tau_map("sphere", x=("sigma", f"{sigma[0]}:{sigma[1]}:8"), y=("bpm", "50:650:8"),
                   m="2:6", workers=1, physical={k: CARDIAC[k] for k in ("rho", "mu", "radius")})


def test_coarse_fig_6_13_map_matches_dense_path(monkeypatch):
    """Fig 6.13 on an 8 x 8 grid, m = 2..6, both kinds: the sweep's contour path against the
    dense-eig path (every truncation by eig of W) cell by cell, within each cell's tolerance
    (tol = 1e-8 plus the two error estimates), and with the same truncation pairs."""
    fast = coarse_map()
    monkeypatch.setattr(solve, "SWEEP_METHOD", "auto")
    dense = coarse_map()
    np.testing.assert_array_equal(fast["has_tau"].values, dense["has_tau"].values)
    has = dense["has_tau"].values
    assert 20 < has.sum() < has.size  # both answers occur
    allowed = 1e-8 + fast["error_estimate"].values + dense["error_estimate"].values
    gap = np.abs(fast["tau_min"].values - dense["tau_min"].values)
    assert np.all(gap[has] <= allowed[has])
    np.testing.assert_array_equal(fast["n_temporal"].values, dense["n_temporal"].values)


def fibre_cells(count: int, seed: int):
    """A seeded sample of the fibre's Fig 4.1 range (m, kappa, nu, kind)."""
    rng = np.random.default_rng(seed)
    return [(int(rng.integers(2, 5)), rng.uniform(0.002, 0.3), rng.choice([2e-4, 1e-3]),
             KINDS[i % 2]) for i in range(count)]


@pytest.mark.parametrize("m, kappa, nu, kind", fibre_cells(12, seed=41))
def test_fibre_smallest_real_tau_is_qz_smallest(m, kappa, nu, kind):
    """The fibre (the other 2 x 2 block model the sweeps solve this way): tau_min and its
    certificate against QZ on the real form of the same truncation (4 of the 12 sampled cells
    have a tau <= 1/2)."""
    system = fibre(m=m, kappa=kappa, nu=nu)
    n = TruncationSchedule.of(system).first
    pencils = Pencils(system, kind)
    found = contour.smallest_real_tau(pencils.get(n, "two-sided")[0], TAU_MAX)
    assert found is not None
    tau_min, complete_to = found
    reference = dense_taus(pencils.get(n, "real")[0])
    reference = reference[(reference >= 0) & (reference <= TAU_MAX)]
    if tau_min is None:
        assert not reference.size
    else:
        assert reference.size and tau_min == pytest.approx(reference[0], rel=1e-10)
        assert not np.any(reference[1:] <= complete_to)


def test_well_conditioned_agrees_with_block_inverses():
    """The contour path's closed-form 2 x 2 check = whether LAPACK's block inverses pass the
    condition limit, on sampled pencils and on pencils made ill conditioned (a block scaled
    towards singular, a singular block)."""
    from spectralshell.solvers.half_product import block_inverses, well_conditioned

    checked = {True: 0, False: 0}
    for sigma, bpm, m, kind in cells(8, seed=5):
        pencils = Pencils(atrium(sigma, bpm, m), kind)
        pencils.reserve = 16  # the truncations below are cut out of N = 16
        for n in (12, 8):
            assert pencils.well_conditioned(n, "two-sided") == (
                pencils.get(n, "two-sided")[1] is not None)
        hill = pencils.pencil(12, "two-sided")
        for squash in (1.0, 1e-7, 1e-9, 1e-12, 0.0):
            diag = hill.diag.copy()
            diag[3, 1] *= squash  # second row of one block towards a multiple of nothing
            diag[3, 1] += (1 - squash) * 1e-3 * diag[3, 0]  # ... or of the first row
            bad = dataclasses.replace(hill, diag=diag)
            expected = block_inverses(bad) is not None
            assert well_conditioned(bad) == expected
            checked[expected] += 1
    assert checked[True] and checked[False]


@pytest.mark.parametrize("sigma, bpm, m, kind", cells(6, seed=17))
def test_newton_root_is_qz_root(sigma, bpm, m, kind):
    """The kernel's safeguarded Newton step on the real axis finds QZ's real z = tau^2 to
    rounding from brackets around it, including brackets that end at (a rounding of) the root
    itself (a neighbour's tau_min as hint), and reports a bracket without a sign change."""
    system = atrium(sigma, bpm, m)
    n = TruncationSchedule.of(system).first
    pencils = Pencils(system, kind)
    blocks = contour.LogDet(pencils.pencil(n, "two-sided")).blocks
    reference = dense_taus(pencils.get(n, "real")[0])
    squares = reference[reference > 0] ** 2
    checked = 0
    for z in squares[squares <= 1]:
        if np.sum(np.abs(squares / z - 1) < 1e-2) > 1:
            continue  # another zero within the bracket below
        checked += 1
        found = _schur.root(*blocks, z * (1 - 1e-3), z * (1 + 2e-3), 1e-13)
        assert found == pytest.approx(z, rel=1e-12)
        for lo, hi in ((found * (1 - 1e-7), found * (1 + 1e-12)),
                       (found * (1 - 1e-12), found * (1 + 1e-5))):
            assert _schur.root(*blocks, lo, hi, 1e-15) == pytest.approx(z, rel=1e-12)
    assert checked
    assert np.isnan(_schur.root(*blocks, 1e-9, 2e-9, 1e-15))  # no zero there: no sign change


@pytest.mark.parametrize("kind", KINDS)
def test_scalar_coupling_form_equals_general_form(kind):
    """The kernel's short form for a coupling that is a multiple of the identity (the sphere's
    G = q I) against its general form, reached by multiplying every block row by a fixed
    non-diagonal P (the coupling is then P q: det(A - tau B) gains det(P)^K, d/dz log det
    nothing)."""
    hill = two_sided(atrium(6000.0, 120.0, 3), kind, 14)
    P = np.array([[1.0, 0.3], [-0.2, 0.9]])
    rows = dataclasses.replace(hill, diag=P @ hill.diag, lower=P @ hill.lower,
                               upper=P @ hill.upper)
    z = np.array([0.05 + 0.01j, 0.2 - 0.03j, 0.13 + 0.0j, -0.02 + 0.1j])

    def kernel(h):
        out, slope = np.empty_like(z), np.empty_like(z)
        assert _schur.logdet(*contour.LogDet(h).blocks, z, out, slope) == 0
        return out, slope

    (value, slope), (value_p, slope_p) = kernel(hill), kernel(rows)
    shift = len(hill.diag) * np.log(np.linalg.det(P))
    np.testing.assert_allclose(np.exp(1j * (value_p - value - shift).imag), 1, atol=1e-10)
    np.testing.assert_allclose((value_p - value).real, shift, rtol=1e-10)
    np.testing.assert_allclose(slope_p, slope, rtol=1e-10)


def composed_smallest(hill, tau_max, hint=None, whole=True):
    """smallest_real_tau as the Python composition it was before the kernel took its steps
    (issue 25): sign change near the hint, strip counts, real-axis scan (without a hint and
    with g of opposite signs at the first strip's ends, first the bisected sign change over
    [0, z_max]; ``whole=False``: the scan alone, as before), Newton root and its dyadic cell,
    disk count, each from the module's public pieces (LogDet, winding, rectangle, circle) and
    ``_schur.root``; the kernel's one call must answer the same, bitwise."""
    log_g = contour.LogDet(hill)
    z_max = tau_max * tau_max

    def first_change(points):  # the points in turn, up to the lowest sign change
        previous = 0.0
        for j, point in enumerate(points):
            found = log_g(points[j:j + 1])
            if found is None:
                return None
            sign = np.sign(np.cos(found[0][0].imag))
            if j and previous * sign < 0:
                return float(points[j - 1]), float(point)
            previous = sign
        return None

    def zeros_below(right, strips):
        count = None
        for strip in strips:
            side = strip * z_max
            count = contour.winding(log_g, contour.rectangle(-side, right, side))
            if count == 0:
                break
        return count

    def root(lo, hi, rtol, otherwise=None):
        z = _schur.root(*log_g.blocks, lo, hi, rtol)
        if z is None or (np.isnan(z) and otherwise is None):
            raise ZeroDivisionError
        return otherwise if np.isnan(z) else z

    def certified(bracket, strips):  # the root in its dyadic cell, the counts below and around
        try:
            z = root(*bracket, rtol=contour.ROOT_RTOL)
            step = np.ldexp(1.0, np.frexp(z)[1] - 30)
            lo = np.floor(z / step) * step
            z = root(float(lo), float(lo + step), 4 * np.finfo(float).eps, otherwise=z)
        except ZeroDivisionError:
            return None
        rho = contour.DISK * z
        if zeros_below(z - rho / 2, strips) != 0:
            return None
        if contour.winding(log_g, contour.circle(z, rho)) != 1:
            return None
        return np.sqrt(z), np.sqrt(z + rho / 2)

    def whole_interval():  # a sign change over [0, z_max] bisected to the scan's spacing
        ends = log_g(np.array([0.0, z_max]))
        if ends is None or not np.cos((ends[0][1] - ends[0][0]).imag) < 0:
            return None
        lo, hi = 0.0, z_max
        while hi - lo > z_max / contour.SCAN_POINTS:
            mid = 0.5 * (lo + hi)
            found = log_g(np.array([mid]))
            if found is None:
                return None
            if np.cos((found[0][0] - ends[0][0]).imag) > 0:
                lo = mid
            else:
                hi = mid
        return certified((lo, hi), contour.STRIPS[:1])

    bracket = None
    if hint is not None and 0.0 < hint * hint <= z_max:
        z0, offsets = hint * hint, np.array(contour.HINT_STEPS)
        bracket = first_change(np.clip(np.concatenate([z0 * (1 - offsets[::-1]), [z0],
                                                       z0 * (1 + offsets)]), 0.0, z_max))
    if bracket is None:
        right = z_max * (1 + 1e-6)
        if zeros_below(right, contour.STRIPS[:1]) == 0:
            return None, tau_max
        ends = log_g(np.array([right, -contour.STRIPS[0] * z_max]))
        if whole and ends is not None and np.cos((ends[0][0] - ends[0][1]).imag) < 0:
            found = whole_interval()
            if found is not None:
                return found
        bracket = first_change(np.linspace(0.0, z_max, contour.SCAN_POINTS + 1))
        if bracket is None:
            return (None, tau_max) if zeros_below(right, contour.STRIPS[1:]) == 0 else None
    return certified(bracket, contour.STRIPS)


def hints_around(tau):
    """Hints as a sweep passes them: none, the answer itself, a neighbour's nearby value, one
    far off, one above tau_max (ignored)."""
    out = [None, 0.3, 0.7]
    if tau is not None:
        out += [tau, tau * (1 + 3e-6), tau * (1 - 2e-3), tau * 1.04]
    return out


def solve_cases(sigma, bpm, m, kind):
    """(N, pencil, hint) at both truncations of a solve of one Fig 6.13 cell, with the hints of
    :func:`hints_around` its own answer."""
    system = atrium(sigma, bpm, m)
    first = TruncationSchedule.of(system).first
    pencils = Pencils(system, kind)
    for n in (first, first + max(6, first // 2)):
        hill = pencils.pencil(n, "two-sided")
        plain = contour.smallest_real_tau(hill, TAU_MAX)
        for hint in hints_around(None if plain is None else plain[0]):
            yield n, hill, hint


@pytest.mark.parametrize("sigma, bpm, m, kind", cells(16, seed=29) + [
    (7000.0, 365.7894736842105, 3, "harmonic"), (1000.0, 50.0, 2, "subharmonic")])
def test_kernel_steps_equal_python_composition(sigma, bpm, m, kind):
    """The kernel's smallest() (one call per truncation) answers exactly as the Python
    composition of the same steps, with and without hints, at both truncations of a solve,
    on Fig 6.13 cells (incl. the close pair above and the lowest beat rate); the answers
    themselves are checked against QZ by the tests above."""
    for n, hill, hint in solve_cases(sigma, bpm, m, kind):
        got = contour.smallest_real_tau(hill, TAU_MAX, hint)
        assert got == composed_smallest(hill, TAU_MAX, hint), (n, hint)


@pytest.mark.parametrize("m, kappa, nu, kind", fibre_cells(6, seed=43))
def test_kernel_steps_equal_python_composition_fibre(m, kappa, nu, kind):
    """The same on the fibre (a general 2 x 2 coupling, not a multiple of the identity)."""
    system = fibre(m=m, kappa=kappa, nu=nu)
    hill = Pencils(system, kind).pencil(TruncationSchedule.of(system).first, "two-sided")
    plain = contour.smallest_real_tau(hill, TAU_MAX)
    for hint in hints_around(None if plain is None else plain[0]):
        assert contour.smallest_real_tau(hill, TAU_MAX, hint) == composed_smallest(
            hill, TAU_MAX, hint)


@pytest.mark.parametrize("budget", [20, 30, 60])
def test_kernel_steps_equal_python_composition_when_counts_fail(monkeypatch, budget):
    """With a node budget so small that some counts stop (the certificate declined, or a
    strip tried after a failed other one), the kernel still answers as the
    composition, and declines (None) where it does."""
    monkeypatch.setattr(contour, "MAX_NODES", budget)
    outcomes = set()
    for sigma, bpm, m, kind in cells(10, seed=31):
        system = atrium(sigma, bpm, m)
        hill = Pencils(system, kind).pencil(TruncationSchedule.of(system).first, "two-sided")
        for hint in (None, 0.2, 0.45):
            got = contour.smallest_real_tau(hill, TAU_MAX, hint)
            assert got == composed_smallest(hill, TAU_MAX, hint)
            outcomes.add("declined" if got is None else "none" if got[0] is None else "tau")
    assert len(outcomes) >= 2 and (budget > 20 or "declined" in outcomes)


@pytest.mark.parametrize("sigma, bpm, m, kind, tau_max", [
    *((*cell, TAU_MAX) for cell in cells(24, seed=11)),
    (16295.055551162224, 534.7644738418962, 4, "harmonic", 1.2),
    (8284.008734924846, 295.0839232519992, 2, "harmonic", 2.0),
    (1926.3965038161932, 649.5056690390428, 2, "subharmonic", 2.0),
    (13395.013120171767, 190.70612100189436, 3, "harmonic", 0.8)])
def test_whole_interval_root_answers_as_the_scan(sigma, bpm, m, kind, tau_max):
    """Without a hint, where g has opposite signs at the ends of the first strip's rectangle
    (an odd number of real tau <= tau_max), the kernel first bisects the sign change over
    [0, tau_max^2] and certifies its root; the answer is the scan's (the composition without
    that step), bitwise, wherever the scan's is certified, and QZ's smallest real tau. The last
    four cells have 3-9 real tau below tau_max (QZ), where the bisection may find a higher one
    first: its certificate then fails and the scan decides."""
    system = atrium(sigma, bpm, m)
    n = TruncationSchedule.of(system).first
    pencils = Pencils(system, kind)
    hill = pencils.get(n, "two-sided")[0]
    got = contour.smallest_real_tau(hill, tau_max)
    assert got == composed_smallest(hill, tau_max)
    scan = composed_smallest(hill, tau_max, whole=False)
    if scan is not None:
        assert got == scan
    reference = dense_taus(pencils.get(n, "real")[0])
    reference = np.sort(reference[(reference >= 0) & (reference <= tau_max)])
    if got is not None and got[0] is not None:
        assert got[0] == pytest.approx(reference[0], rel=1e-10)
    elif got is not None:
        assert not reference.size


@pytest.mark.parametrize("sigma, bpm, m, kind", cells(12, seed=37) + [
    (7000.0, 365.7894736842105, 3, "harmonic"), (1000.0, 50.0, 2, "subharmonic")])
def test_fewer_starting_nodes_same_answers(sigma, bpm, m, kind):
    """The starting nodes of the counts (UPPER_RECTANGLE: 4 top segments and 1 per side;
    UNIT_HALF_CIRCLE: 4 segments) are only where the walk begins: the kernel started from the
    former denser ones (8 and 4 per side; 8 on the half circle) answers the same, bitwise, with
    and without hints, at both truncations of a solve, on Fig 6.13 cells (the answers are
    checked against QZ above)."""
    dense_rectangle, dense_circle = contour._upper_rectangle(8, 4), contour.circle(0.0, 1.0, 16)
    assert dense_rectangle.size > contour.UPPER_RECTANGLE.size
    assert dense_circle.size > contour.UNIT_HALF_CIRCLE.size
    for n, hill, hint in solve_cases(sigma, bpm, m, kind):
        got = _schur.smallest(*contour._kernel_blocks(hill), dense_rectangle, dense_circle,
                              contour.HINT_STEPS, contour.STRIPS, TAU_MAX ** 2,
                              -1.0 if hint is None else hint * hint, contour.DISK,
                              contour.SCAN_POINTS, contour.MAX_BEND, contour.MAX_TURN,
                              contour.MAX_NODES, contour.ROOT_RTOL)
        want = contour.smallest_real_tau(hill, TAU_MAX, hint)
        if got is None or want is None:
            assert got is want, (n, hint)
        elif np.isnan(got):
            assert want == (None, TAU_MAX), (n, hint)
        else:
            assert want == (np.sqrt(got), np.sqrt(got + contour.DISK * got / 2)), (n, hint)


def test_conditioning_values_equal_numpy_norms():
    """The kernel's conditioning (which measures a run of equal coupling blocks once) against
    numpy's 1-norms of each block and of its inverse, on coupling blocks all equal (the
    sphere's) and all different (random), and with a singular block (inf)."""
    rng = np.random.default_rng(23)
    for trial in range(40):
        K = int(rng.integers(2, 40))
        diag = rng.normal(size=(K, 2, 2)) + 1j * rng.normal(size=(K, 2, 2))
        varied = rng.normal(size=(K - 1, 2, 2)) + 1j * rng.normal(size=(K - 1, 2, 2))
        equal = np.ascontiguousarray(np.repeat(varied[:1], K - 1, axis=0))
        for lower, upper in ((equal, -equal), (varied, equal), (equal, varied)):
            upper = np.ascontiguousarray(upper)
            inverse = np.linalg.norm(np.linalg.inv(diag), 1, axis=(1, 2))
            cond = np.max(np.linalg.norm(diag, 1, axis=(1, 2)) * inverse)
            coupled = inverse.max() * (np.linalg.norm(lower, 1, axis=(1, 2)).max()
                                       + np.linalg.norm(upper, 1, axis=(1, 2)).max())
            got = _schur.conditioning(diag, lower, upper)
            np.testing.assert_allclose(got, (cond, coupled), rtol=1e-12)
    diag[K // 2] = [[1.0, 2.0], [2.0, 4.0]]  # singular
    assert _schur.conditioning(diag, equal, equal) == (np.inf, np.inf)
    diag[K // 2] = 0.0  # its norm times the inverse's is 0 inf: the coupled bound still says
    assert _schur.conditioning(diag, equal, equal)[1] == np.inf


@pytest.mark.parametrize("sigma, bpm, m, kind", cells(8, seed=47) + [
    (7000.0, 365.7894736842105, 3, "harmonic")])
def test_opposite_signs_at_rectangle_ends_mean_an_odd_count(sigma, bpm, m, kind):
    """The kernel does not walk a rectangle where g has opposite signs at its two real ends
    (only whether the count is zero is asked there: an odd count is not). On rectangles
    holding 0, 1 and 2 real zeros (QZ of the same truncation; complex ones come in conjugate
    pairs), the sign test says odd exactly where the walk's count is odd, and that count is
    QZ's; the kernel's answers with the test are those of the composition without it
    (test_kernel_steps_equal_python_composition)."""
    hill = two_sided(atrium(sigma, bpm, m), kind, 16)
    log_g = contour.LogDet(hill)
    z = qz_squares(hill)
    real = real_squares(z)
    real = real[real > 0][:3]
    rights = [real[0] / 2] + [(a + b) / 2 for a, b in zip(real, real[1:])]
    checked = set()
    for held, right in enumerate(rights):
        for half in (1e-6, 1e-4, 1e-2):
            left = -half
            if np.any(inside(z, left, right, half, 1e-4 * half)
                      & ~inside(z, left, right, half, -1e-4 * half)):
                continue  # an eigenvalue on the edge
            count = contour.winding(log_g, contour.rectangle(left, right, half))
            assert count == np.count_nonzero(inside(z, left, right, half))
            values, _ = log_g(np.array([right, left]))
            opposite = np.cos(values[0].imag - values[1].imag) < 0
            assert opposite == (count % 2 == 1) == (held % 2 == 1)
            checked.add(held)
    assert checked >= {0, 1} and (len(real) < 3 or 2 in checked)
