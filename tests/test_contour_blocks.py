"""The argument-principle count for pencils with M x M blocks (solvers.contour, cochlea) against
dense LAPACK: log det by LU of the assembled A - tau B, zero counts by QZ of the same pencil."""

import numpy as np
import pytest
import scipy.linalg as sla

from spectralshell.discretise.hill import HillMatrices
from spectralshell.models.sphere import hill_system as sphere
from spectralshell.params.sweep_grid import sweep_spec
from spectralshell.reports.figures import fig_5_18_scene
from spectralshell.runner.solve import spatial_system
from spectralshell.solvers import _schur, contour
from spectralshell.solvers.marginal import Pencils, structured_spectrum


def random_pencil(blocks: int, size: int, seed: int, symmetric: bool = False) -> HillMatrices:
    """A bipartite block-tridiagonal pencil with random complex blocks. ``symmetric``: g(z) =
    det(A - sqrt(z) B) / det A takes conjugate values at conjugate points, as the package's
    pencils do (the count reads half contours): real blocks P_k (real) Q_k transformed by
    random complex P_k, Q_k, which leave g unchanged and make the blocks complex."""
    rng = np.random.default_rng(seed)

    def draw(count):
        return rng.standard_normal((count, size, size)) + 1j * rng.standard_normal(
            (count, size, size))

    if not symmetric:
        return HillMatrices(kind="harmonic", form="two-sided", n_temporal=(blocks - 1) // 2,
                            diag=draw(blocks) + 3 * np.eye(size), lower=draw(blocks - 1),
                            upper=draw(blocks - 1), self_coupling=None)
    real = [rng.standard_normal((count, size, size)) for count in (blocks, blocks - 1, blocks - 1)]
    P, Q = draw(blocks) + 3 * np.eye(size), draw(blocks) + 3 * np.eye(size)
    return HillMatrices(kind="harmonic", form="two-sided", n_temporal=(blocks - 1) // 2,
                        diag=P @ (real[0] + 3 * np.eye(size)) @ Q,
                        lower=P[1:] @ real[1] @ Q[:-1], upper=P[:-1] @ real[2] @ Q[1:],
                        self_coupling=None)


def cochlea(n_spatial: int, frequency: float = 116.9, sigma: float = 1.16e9):
    """The gerbil cochlea of Fig 5.18 at one cell, with M = ``n_spatial`` modes."""
    spec = sweep_spec(fig_5_18_scene("gerbil"))
    return spatial_system(spec.model, spec.params_at({"frequency": frequency, "sigma": sigma}),
                          n_spatial)


def qz_squares(hill):
    """z = tau^2 of every finite eigenvalue of the pencil (dense QZ), each +-tau pair once (an
    imaginary pair, z < 0, by its upper member)."""
    alpha, beta = sla.eigvals(hill.A.toarray(), hill.B.toarray(), homogeneous_eigvals=True)
    finite = np.abs(beta) > 1e-12 * np.abs(alpha)
    tau = alpha[finite] / beta[finite]
    axis = np.abs(tau.real) <= 1e-9 * np.abs(tau)
    return tau[(tau.real > 0) & ~axis | axis & (tau.imag > 0)] ** 2


def real_squares(z: np.ndarray) -> np.ndarray:
    """The real ones of :func:`qz_squares`' ``z`` (|Im z| <= 1e-9 |z|), ascending: real tau
    for z > 0, imaginary tau for z < 0."""
    return np.sort(z[np.abs(z.imag) <= 1e-9 * np.abs(z)].real)


def dense_log_g(hill, z):
    """(log|g|, phase factor of g) at z by LAPACK's LU of the assembled matrices."""
    sign, modulus = np.linalg.slogdet(hill.dense(np.sqrt(z)))
    sign_a, modulus_a = np.linalg.slogdet(hill.dense(0.0))
    return modulus - modulus_a, sign / sign_a


def chained_pencil(blocks: int, size: int, seed: int) -> HillMatrices:
    """A random pencil (:func:`random_pencil`) with upper[k] = -lower[k - 1] for k >= 1, as the
    cochlea's (one coupling matrix C: lower C, upper -C)."""
    hill = random_pencil(blocks, size, seed)
    upper = np.concatenate([hill.upper[:1], -hill.lower[:-1]])
    return HillMatrices(kind="harmonic", form="two-sided", n_temporal=hill.n_temporal,
                        diag=hill.diag, lower=hill.lower, upper=upper, self_coupling=None)


def uniform_pencil(blocks: int, size: int, seed: int, real: bool) -> HillMatrices:
    """A random pencil (:func:`random_pencil`) whose every coupling block is one skew-Hermitian
    L: lower L, upper -L, as the cochlea's two-sided pencils (L = i kappa C, C real symmetric:
    ``real``), else L = i H with H complex Hermitian."""
    hill = random_pencil(blocks, size, seed)
    rng = np.random.default_rng(seed + 100)
    H = rng.standard_normal((size, size))
    if not real:
        H = H + 1j * rng.standard_normal((size, size))
    L = 1j * (H + H.conj().T) / 2
    lower = np.broadcast_to(L, hill.lower.shape).copy()
    return HillMatrices(kind="harmonic", form="two-sided", n_temporal=hill.n_temporal,
                        diag=hill.diag, lower=lower, upper=-lower, self_coupling=None)


@pytest.mark.parametrize("coupling", ["any", "chained", "uniform real", "uniform complex"])
@pytest.mark.parametrize("inverse_below", [contour.INVERSE_BELOW, 0])
@pytest.mark.parametrize("size, seed", [(3, 1), (5, 2), (8, 3)])
def test_block_log_det_matches_dense_lu(size, seed, inverse_below, coupling, monkeypatch):
    """log g and d log g / dz of M x M block pencils against slogdet of the assembled matrix,
    the derivative against central differences of it; by each of block_log_det's ways to
    S^{-1} U and S^{-1} S' (inverse and products, or LU solves: INVERSE_BELOW 0; chained
    couplings, upper[k] = -lower[k - 1], with one solve fewer), and by diagonal_log_det where
    every coupling block is one skew-Hermitian L (rotated_coupling)."""
    monkeypatch.setattr(contour, "INVERSE_BELOW", inverse_below)
    hill = {"any": lambda: random_pencil(7, size, seed),
            "chained": lambda: chained_pencil(7, size, seed),
            "uniform real": lambda: uniform_pencil(7, size, seed, real=True),
            "uniform complex": lambda: uniform_pencil(7, size, seed, real=False)}[coupling]()
    log_g = contour.LogDet(hill)
    assert not log_g.compiled
    assert log_g.chained == (coupling != "any")
    assert (log_g.rotated is not None) == coupling.startswith("uniform")
    for z in (0.05 + 0.01j, 0.3 - 0.2j, 0.13 + 0.0j, -0.4 + 0.1j):
        value, slope = log_g.point(z)
        modulus, phase = dense_log_g(hill, z)
        assert value.real == pytest.approx(modulus, abs=1e-9)
        assert np.exp(1j * value.imag) == pytest.approx(phase, abs=1e-9)
        h = 1e-6
        (up, p_up), (down, p_down) = dense_log_g(hill, z + h), dense_log_g(hill, z - h)
        assert slope == pytest.approx((up - down + np.log(p_up / p_down)) / (2 * h), rel=1e-5)


@pytest.mark.parametrize("kind", ["harmonic", "subharmonic"])
def test_rotated_coupling_cochlea(kind):
    """The cochlea's two-sided pencils have one coupling L = i kappa C (C real symmetric): the
    rotation to diagonal coupling applies, and diagonal_log_det gives block_log_det's log g and
    slope on the unrotated blocks (M = 16, N = 10) to rounding."""
    hill = Pencils(cochlea(16), kind).get(10, "two-sided")[0]
    log_g = contour.LogDet(hill)
    assert log_g.rotated is not None and not np.any(log_g.rotated[1].real)
    base = contour.block_log_det(*log_g.blocks, 0.0, log_g.chained)[0]
    for z in (0.05 + 0.01j, 0.3 - 0.2j, 0.13 + 0.0j):
        value, slope = contour.block_log_det(*log_g.blocks, z, log_g.chained)
        rotated, rotated_slope = log_g.point(z)
        assert np.exp(rotated - (value - base)) == pytest.approx(1.0, abs=1e-10)
        assert rotated_slope == pytest.approx(slope, rel=1e-10)


def test_block_path_matches_compiled_kernel():
    """On a 2 x 2 block pencil (the sphere) the LAPACK block elimination and the compiled
    adjugate kernel give the same log det and slope."""
    hill = Pencils(sphere(m=3, kappa=0.05, nu=2e-3), "subharmonic").get(14, "two-sided")[0]
    log_g = contour.LogDet(hill)
    z = np.array([0.05 + 0.01j, 0.2 - 0.03j, 0.13 + 0.0j])
    values, slopes = log_g(z)
    for zj, value, slope in zip(z, values, slopes):
        block_value, block_slope = contour.block_log_det(*log_g.blocks, zj)
        log_det_a = contour.block_log_det(*log_g.blocks, 0.0)[0]
        assert np.exp(block_value - log_det_a - value) == pytest.approx(1.0, abs=1e-10)
        assert block_slope == pytest.approx(slope, rel=1e-10)


def inside(z, left, right, half, margin=0.0):
    return ((z.real > left - margin) & (z.real < right + margin)
            & (np.abs(z.imag) < half + margin))


def check_counts(hill, rectangles):
    """Winding counts = QZ eigenvalue counts in each rectangle not passing within 1e-6 of an
    eigenvalue; returns how many were checked."""
    log_g = contour.LogDet(hill)
    z = qz_squares(hill)
    checked = 0
    for left, right, half in rectangles:
        if np.any(inside(z, left, right, half, 1e-6) & ~inside(z, left, right, half, -1e-6)):
            continue
        count = np.count_nonzero(inside(z, left, right, half))
        assert contour.winding(log_g, contour.rectangle(left, right, half)) == count
        checked += 1
    return checked


@pytest.mark.parametrize("size, seed", [(3, 4), (4, 5), (6, 6)])
def test_block_winding_counts_qz_eigenvalues_random(size, seed):
    """Random 7-block pencils (g with conjugate symmetry, complex blocks): counts in nested
    rectangles of the z plane = QZ counts."""
    hill = random_pencil(7, size, seed, symmetric=True)
    z = qz_squares(hill)
    scale = float(np.median(np.abs(z)))
    rectangles = [(-0.1 * scale, f * scale, h * scale)
                  for f, h in ((0.5, 0.2), (1.0, 0.5), (2.0, 1.0), (4.0, 3.0))]
    assert check_counts(hill, rectangles) >= 3


@pytest.mark.parametrize("inverse_below", [contour.INVERSE_BELOW, 0])
@pytest.mark.parametrize("kind", ["harmonic", "subharmonic"])
def test_block_winding_counts_qz_eigenvalues_cochlea(kind, inverse_below, monkeypatch):
    """The viscous gerbil cochlea (M = 8, N = 12, two-sided form): counts in thin strips along
    the real axis and in larger rectangles = QZ counts of the same truncation, including the
    real tau <= 1/2 that truncation has; by either of block_log_det's ways (INVERSE_BELOW)."""
    monkeypatch.setattr(contour, "INVERSE_BELOW", inverse_below)
    hill = Pencils(cochlea(8), kind).get(12, "two-sided")[0]
    z = qz_squares(hill)
    real = real_squares(z)
    assert real.size and real.min() < 0.25  # some z = tau^2 to count in the strips
    rectangles = [(-2.5e-5, 0.25, 2.5e-5), (-2.5e-3, 0.25, 2.5e-3), (-0.01, 0.5, 0.05),
                  (0.1, 1.0, 0.3)]
    assert check_counts(hill, rectangles) >= 3


@pytest.mark.parametrize("kind, form", [("harmonic", "two-sided"), ("harmonic", "real"),
                                        ("subharmonic", "two-sided")])
def test_block_log_g_conjugate_symmetric_cochlea(kind, form):
    """What the half-contour count rests on, for the cochlea's M x M blocks in each bipartite
    form: g(conj z) = conj g(z), so g is real on the real axis."""
    hill = Pencils(cochlea(8), kind).pencil(12, form)
    assert hill.bipartite
    log_g = contour.LogDet(hill)
    assert log_g.chained  # one coupling C in both forms: lower C, upper -C
    for z in (0.03 + 0.01j, 0.2 - 0.05j, 0.4 + 1e-3j, -0.1 + 0.02j):
        (value, slope), (mirror, mirror_slope) = log_g.point(z), log_g.point(z.conjugate())
        assert np.exp(value - mirror.conjugate()) == pytest.approx(1.0, abs=1e-10)
        assert mirror_slope.conjugate() == pytest.approx(slope, rel=1e-10)
    for x in (0.01, 0.1, 0.3, -0.05):
        assert abs(np.sin(log_g.point(x)[0].imag)) < 1e-10


def test_winding_of_declines_and_raises():
    """The callback walk: None where the evaluation declines, the evaluation's exception
    propagated, and a plain polynomial's zero counted."""
    nodes = contour.circle(0.0, 1.0)
    assert _schur.winding_of(lambda z: None, nodes, 1.0, 0.7, 100) is None

    def broken(z):
        raise RuntimeError("no")

    with pytest.raises(RuntimeError, match="no"):
        _schur.winding_of(broken, nodes, 1.0, 0.7, 100)
    turns = _schur.winding_of(lambda z: (np.log(z - 0.3), 1 / (z - 0.3)), nodes, 1.0, 0.7, 1000)
    assert turns == pytest.approx(1.0, abs=1e-12)  # the upper half circle's phase change, doubled
    pair = (0.2 + 0.4j, 0.2 - 0.4j)  # a conjugate pair inside, counted from the upper half
    turns = _schur.winding_of(lambda z: (np.log((z - pair[0]) * (z - pair[1])),
                                         1 / (z - pair[0]) + 1 / (z - pair[1])),
                              nodes, 1.0, 0.7, 1000)
    assert turns == pytest.approx(2.0, abs=1e-12)


@pytest.mark.parametrize("kind", ["harmonic", "subharmonic"])
def test_odd_count_shortcut_cochlea(kind, monkeypatch):
    """The sign of g at the counting rectangle's right corner (contour._odd_below) finds an odd
    number of real zeros below it exactly where dense QZ does, for caps holding 0, 1, 2 and 3
    real z = tau^2 of the viscous gerbil cochlea (M = 8, N = 12); none_up_to decides as QZ
    does, and as the count alone (the shortcut turned off) does, except where the count misses
    a close pair (test_count_misses_close_real_pair)."""
    hill = Pencils(cochlea(8), kind).get(12, "two-sided")[0]
    z = qz_squares(hill)
    real = real_squares(z)
    complex_z = z[np.abs(z.imag) > 1e-9 * np.abs(z)]
    assert real.size >= 4
    caps = [0.9 * real[0]] + [(a + b) / 2 for a, b in zip(real[:3], real[1:4])]
    for below, z_max in enumerate(caps):  # 0, 1, 2, 3 real zeros up to z_max
        right = z_max * (1 + 1e-6)
        assert np.count_nonzero(real < right) == below
        thin = min(contour.BLOCK_STRIPS) * z_max  # no complex zero in the thinnest strip
        assert not np.any(inside(complex_z, -thin, right, thin, 1e-6))
        tau_max = float(np.sqrt(z_max))
        assert contour._odd_below(contour.LogDet(hill), right, z_max) == (below % 2 == 1)
        if kind == "subharmonic" and below == 2:
            continue  # the count's known miss, below
        assert contour.none_up_to(hill, tau_max) == (below == 0)
        with monkeypatch.context() as patch:
            patch.setattr(contour, "_odd_below", lambda *args: False)
            assert contour.none_up_to(hill, tau_max) == (below == 0)


def test_count_sees_close_real_pair():
    """The viscous gerbil cochlea (M = 8, N = 12, subharmonic) has real z = tau^2 at 0.23628
    and 0.23843 (QZ; g changes sign at both): the count must not prove the strip up to
    0.23933 empty. Both lie under one top segment of the 1e-4 and 1e-6 strips, whose g'/g
    takes nearly the same value at its two ends (-1204 and -1190): the phase turns by 2 pi,
    invisible modulo 2 pi, and only log |g|, 3 off the trapezoid's prediction, shows them
    (the walk's third check, ``segment`` in _schur.c); without it both strips counted 0.
    Each strip's count is QZ's."""
    hill = Pencils(cochlea(8), "subharmonic").get(12, "two-sided")[0]
    z = qz_squares(hill)
    real = real_squares(z)
    z_max = (real[1] + real[2]) / 2
    assert np.count_nonzero(real < z_max) == 2
    assert not contour.none_up_to(hill, float(np.sqrt(z_max)))
    log_g = contour.LogDet(hill)
    for strip in contour.BLOCK_STRIPS:
        side = strip * z_max
        inside = np.count_nonzero((np.abs(z.imag) < side) & (z.real > -side) & (z.real < z_max))
        assert contour.winding(log_g, contour.rectangle(-side, z_max, side)) == inside


def test_odd_count_shortcut_random_pencils():
    """On random pencils with g conjugate-symmetric, the shortcut's parity = QZ's parity of the
    real zeros in (0, right] wherever g's sign there is clear, over many rights."""
    checked = 0
    for seed in range(4):
        hill = random_pencil(7, 4, seed, symmetric=True)
        z = qz_squares(hill)
        real = real_squares(z)
        real = real[real > 0]
        log_g = contour.LogDet(hill)
        for right in np.concatenate([real[:4] * 0.97, real[:4] * 1.03]):
            expected = np.count_nonzero(real < right) % 2 == 1
            assert contour._odd_below(log_g, right, right) == expected
            checked += 1
    assert checked >= 8


def test_crowded_cell_count_within_budget():
    """The crowded Fig 5.18 cell (human, 63.62 Hz, sigma = 1.85e9, M = 32, subharmonic, N = 51)
    has no eigenvalue in the 1e-4 strip up to the harmonic tau_min 0.49439^2 (dense eig of the
    half-size W), but complex ones 5.6e-4..1e-3 tau_max^2 from the axis near its right end (6)
    and tens more within 1e-2: the walk needs 270 nodes there since it checks log |g| too (276
    from the earlier starting nodes, 242 before the check), and the count must still prove the
    strip empty within MAX_BLOCK_NODES (at 250 it gave up, the pair (32, 64) went unproved and
    the cell refined on to M = 128, 3.7x its time; issue 25)."""
    spec = sweep_spec(fig_5_18_scene("human"))
    system = spatial_system(spec.model, spec.params_at({"frequency": 63.62, "sigma": 1.85e9}), 32)
    hill = Pencils(system, "subharmonic").pencil(51, "two-sided")
    tau_max = 0.4943905090478546
    z_max = tau_max ** 2
    lam, floor, _ = structured_spectrum(hill)
    z = 1.0 / lam[np.abs(lam) > floor]
    side = contour.BLOCK_STRIPS[0] * z_max
    assert not np.any(inside(z, -side, z_max * (1 + 1e-6), side, side))
    crowd = inside(z, -side, z_max, 1e-3 * z_max)
    assert np.count_nonzero(crowd) >= 5  # what makes the walk long
    log_g = contour.LogDet(hill)
    assert contour.winding(log_g, contour.rectangle(-side, z_max * (1 + 1e-6), side)) == 0
