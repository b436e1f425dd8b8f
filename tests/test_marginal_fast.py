"""Arnoldi fast path for the smallest marginal tau (solvers.half_product) against dense solves and
closed-form oracles.

The block test model: M coupled damped Mathieu oscillators u'' + C u' + K (1 + 2 tau sin t) u = 0,
i.e. D(s) = s^2 I + s C + K and G = K, with K the matrix of multiplication by
kappa e^{-alpha |x|} on [-pi, pi] in the orthonormal cosine basis (the cochlea's graded stiffness,
symmetric positive definite): an independent stand-in for a block model of size b = M.
"""

import numpy as np
import pytest
import scipy.special as special
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st
from scipy.integrate import quad

from spectralshell.discretise.hill import assemble
from spectralshell.models.base import HillSystem
from spectralshell.models.mathieu import hill_system as mathieu
from spectralshell.models.sphere import hill_system as sphere
from spectralshell.solvers import marginal
from spectralshell.solvers.half_product import block_inverses, smallest_taus
from spectralshell.solvers.marginal import (dense_taus, marginal_tau, preferred_form,
                                            structured_taus, truncation_taus)

KINDS = ("harmonic", "subharmonic")


def cosine_coupling(n_spatial: int, alpha: float) -> np.ndarray:
    """<phi_j, e^{-alpha|x|} phi_k> for phi_0 = 1/sqrt(2 pi), phi_j = cos(j x)/sqrt(pi), from
    cos(jx) cos(kx) = (cos((j-k)x) + cos((j+k)x))/2 and the moments
    int_{-pi}^{pi} e^{-alpha|x|} cos(p x) dx
        = 2 alpha (1 - (-1)^p e^{-alpha pi}) / (alpha^2 + p^2)."""
    def moment(p):
        return 2 * alpha * (1 - (-1.0) ** p * np.exp(-alpha * np.pi)) / (alpha**2 + p**2)

    j = np.arange(n_spatial)
    c = 0.5 * (moment(j[:, None] - j[None, :]) + moment(j[:, None] + j[None, :])) / np.pi
    w = np.where(j == 0, np.sqrt(0.5), 1.0)
    return c * w[:, None] * w[None, :]


def oscillators(stiffness: np.ndarray, damping: np.ndarray) -> HillSystem:
    """D(s) = s^2 I + s C + K, G = K (coupled damped Mathieu oscillators)."""
    eye = np.eye(len(stiffness))

    def unforced(s):
        s = np.asarray(s, dtype=complex)[:, None, None]
        return s * s * eye + s * damping + stiffness

    return HillSystem(name="oscillators", block_size=len(stiffness), unforced=unforced,
                      forcing=stiffness, polynomial=(stiffness, damping, eye),
                      n_resonant=float(np.sqrt(np.linalg.eigvalsh(stiffness).max())))


def cochlea_like(n_spatial: int, *, kappa: float = 4.0, alpha: float = 1.56,
                 nu: float = 0.05) -> HillSystem:
    """Graded stiffness kappa e^{-alpha|x|}, damping nu (1 + j/M) on mode j: not simultaneously
    diagonalisable with K, so the blocks stay coupled."""
    damping = nu * np.diag(1 + np.arange(n_spatial) / n_spatial)
    return oscillators(kappa * cosine_coupling(n_spatial, alpha), damping)


def agree_below_radius(fast, dense: np.ndarray) -> None:
    """The fast list equals the dense one up to the completeness radius (rtol 1e-9)."""
    wanted = dense[dense <= fast.complete_to * (1 + 1e-9)]
    assert fast.tau.size == wanted.size, (fast.tau, wanted)
    np.testing.assert_allclose(fast.tau, wanted, rtol=1e-9)


def test_cosine_coupling_matches_quadrature():
    """Independent check of the test model's matrix: quadrature of the defining integral."""
    alpha, K = 1.56, cosine_coupling(6, 1.56)
    phi = [lambda x: 1 / np.sqrt(2 * np.pi)] + [lambda x, j=j: np.cos(j * x) / np.sqrt(np.pi)
                                                  for j in range(1, 6)]
    for j, k in [(0, 0), (0, 3), (2, 2), (1, 4), (5, 5)]:
        value = quad(lambda x: np.exp(-alpha * abs(x)) * phi[j](x) * phi[k](x), -np.pi, np.pi,
                     points=[0.0], epsabs=1e-14)[0]
        assert abs(K[j, k] - value) < 1e-12


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("form", ["real", "two-sided"])
def test_truncated_pencil_is_the_assembled_one(kind, form):
    """HillMatrices.truncated (the reuse of one pencil for a smaller truncation) against
    assembling that truncation directly, block for block."""
    system = cochlea_like(3)
    cut, direct = assemble(system, kind, 9, form).truncated(5), assemble(system, kind, 5, form)
    assert (cut.n_temporal, cut.bipartite) == (direct.n_temporal, direct.bipartite)
    for name in ("diag", "lower", "upper"):
        np.testing.assert_array_equal(getattr(cut, name), getattr(direct, name))
    if direct.self_coupling is not None:
        np.testing.assert_array_equal(cut.self_coupling, direct.self_coupling)
    np.testing.assert_array_equal(cut.B.toarray(), direct.B.toarray())


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("form", ["real", "two-sided"])
def test_block_inverses_with_symmetries_and_reuse_are_the_inverses(kind, form):
    """The halved inversions (conjugate-symmetric two-sided blocks, realified real-form blocks)
    and the reuse of a smaller truncation's inverses against numpy.linalg.inv block by block."""
    system = cochlea_like(36)
    small, hill = assemble(system, kind, 3, form), assemble(system, kind, 6, form)
    direct = np.linalg.inv(hill.diag)
    fresh = block_inverses(hill)
    reused = block_inverses(hill, (hill.block_range(3), block_inverses(small)))
    if form == "real":  # every block but the harmonic n = 0 one is inverted as complex b x b
        assert fresh.complex_rows.size == len(hill.diag) - (kind == "harmonic")
    atol = 1e-13 * np.abs(direct).max()
    for inverses in (fresh, reused):
        np.testing.assert_allclose(inverses.full(), direct, rtol=0, atol=atol)
    np.testing.assert_allclose(fresh.subset(hill.block_range(3)).full(), np.linalg.inv(small.diag),
                               rtol=0, atol=atol)


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("n_spatial,n_temporal", [(20, 12), (32, 12)])
def test_krylov_matches_dense_eig_on_coupled_oscillators(kind, n_spatial, n_temporal):
    """Same truncation: Arnoldi on the real form against dense eig of the half product W."""
    system = cochlea_like(n_spatial)
    fast = smallest_taus(assemble(system, kind, n_temporal, "real"))
    assert fast is not None and fast.tau.size
    form = preferred_form(kind, system.block_size)
    dense = structured_taus(assemble(system, kind, n_temporal, form))
    agree_below_radius(fast, dense)


@pytest.mark.parametrize("kind", KINDS)
def test_krylov_matches_qz_of_the_whole_pencil(kind):
    """Second method: scipy.linalg.eigvals(A, B) of the full real-form pencil (QZ)."""
    system = cochlea_like(16)
    fast = smallest_taus(assemble(system, kind, 12, "real"))
    qz = dense_taus(assemble(system, kind, 12, "real"))
    agree_below_radius(fast, qz[qz > 0])


@pytest.mark.parametrize("kind", KINDS)
def test_decoupled_oscillators_reduce_to_mathieu_equations(kind):
    """Oracle by decoupling: with C = nu I, K = Q diag(kappa_j) Q^T turns the system into M
    independent damped Mathieu equations u'' + nu u' + kappa_j (1 + 2 tau sin t) u = 0, so
    tau_min is the least of the scalar Mathieu tau_min (b = 1, dense path)."""
    n, nu = 24, 0.02
    K = 2.5 * cosine_coupling(n, 1.56)
    block = marginal_tau(oscillators(K, nu * np.eye(n)), kind, tol=1e-10, method="krylov")
    assert block.method == "krylov"
    scalar = [marginal_tau(mathieu(kappa=k, nu=nu), kind, tol=1e-10).tau_min
              for k in np.linalg.eigvalsh(K)]
    assert abs(block.tau_min - min(t for t in scalar if t is not None)) < 1e-9


# (kind, scipy characteristic-value function, order r, q): DLMF 28.2.1 with a = 4 kappa,
# q = 4 kappa tau (derivations/mathieu_mapping.py, tests/test_mathieu.py): at kappa = a_r(q)/4
# the undamped Mathieu equation has the marginal tau = q / a_r(q).
UNDAMPED = {"harmonic": [(special.mathieu_b, 2, 0.8), (special.mathieu_a, 2, 1.1),
                         (special.mathieu_b, 4, 2.5)],
            "subharmonic": [(special.mathieu_a, 1, 0.3), (special.mathieu_b, 1, 0.1),
                            (special.mathieu_b, 3, 1.7)]}


@pytest.mark.parametrize("kind", KINDS)
def test_undamped_block_model_hits_scipy_mathieu_characteristic_values(kind):
    """Oracle: scipy.special.mathieu_a/b. An undamped block model whose stiffness K has the
    eigenvalues kappa_j = a_r(q_j)/4 (with the cochlea coupling's eigenvectors, plus other
    eigenvalues) has each tau_j = q_j / a_r(q_j) among its marginal amplitudes."""
    n = 30
    values, vectors = np.linalg.eigh(cosine_coupling(n, 1.56))
    kappas = 3.0 * values
    expected = []
    for j, (char_value, order, q) in enumerate(UNDAMPED[kind]):
        a = char_value(order, q)
        kappas[-1 - 3 * j] = a / 4
        expected.append(q / a)
    system = oscillators((vectors * kappas) @ vectors.T, np.zeros((n, n)))
    fast = smallest_taus(assemble(system, kind, 40, "real"))
    assert fast is not None and fast.complete_to > max(expected)
    for tau in expected:
        assert np.min(np.abs(fast.tau - tau)) < 1e-10


@settings(max_examples=6, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n_spatial=st.integers(12, 16),
       n_temporal=st.integers(16, 20), kind=st.sampled_from(KINDS))
@example(seed=338149281, n_spatial=13, n_temporal=17, kind="harmonic")  # a real tau at the radius
def test_no_real_tau_below_the_reported_ones_is_missed(seed, n_spatial, n_temporal, kind):
    """Random block models (random SPD stiffness and damping that do not commute): every real
    tau of the dense spectrum up to the Krylov radius is found, none below tau_min is missed."""
    rng = np.random.default_rng(seed)
    a, c = rng.standard_normal((2, n_spatial, n_spatial))
    K = a @ a.T / n_spatial + 0.2 * np.eye(n_spatial)
    C = 0.05 * (c @ c.T / n_spatial + 0.1 * np.eye(n_spatial))
    system = oscillators(K, C)
    fast = smallest_taus(assemble(system, kind, n_temporal, "real"))
    assume(fast is not None)
    form = preferred_form(kind, system.block_size)
    dense = structured_taus(assemble(system, kind, n_temporal, form))
    agree_below_radius(fast, dense)
    if dense.size:
        assert fast.tau.size and fast.tau[0] == pytest.approx(dense[0], rel=1e-9)


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("name,system,n", [
    ("mathieu, 20 tongues below tau = 1/2", mathieu(kappa=100.0, nu=1e-3), 200),
    ("sphere m = 3", sphere(m=3, kappa=0.02, nu=0.006), 150)])
def test_krylov_matches_dense_on_long_scalar_and_sphere_truncations(kind, name, system, n):
    """b = 1 and 2 at N = 150-200 (order of W 200-300)."""
    fast = smallest_taus(assemble(system, kind, n, "real"))
    assert fast is not None and fast.tau.size
    form = preferred_form(kind, system.block_size)
    agree_below_radius(fast, structured_taus(assemble(system, kind, n, form)))


@pytest.mark.parametrize("kind", KINDS)
def test_auto_switch_uses_krylov_for_big_blocks_with_the_dense_answer(kind, monkeypatch):
    """marginal_tau: 'auto' picks Arnoldi when (N + 1) b >= KRYLOV_MIN_ORDER (lowered here so
    that the dense reference stays cheap) and reports the same tau_min, truncations and error
    estimate as the dense reference; below the threshold (both thresholds at 600) it stays
    dense."""
    system = cochlea_like(20)
    dense = marginal_tau(system, kind, tol=1e-10, method="dense")
    # the dense list is complete up to the first real tau of either truncation that the other
    # does not repeat to 1e-10 (the truncations' own bound, 1/sqrt(floor), lies far beyond)
    assert dense.method == "structured"
    big, small = (truncation_taus(system, kind, n, method="dense").tau
                  for n in (dense.n_temporal, dense.n_previous))
    alone = [t for a, b in ((big, small), (small, big)) for t in a
             if np.abs(b - t).min() > 1e-10 * max(1.0, t)]
    assert alone and dense.complete_to == min(alone) < dense.tau[-1]
    assert set(dense.tau) == {t for t in big if np.abs(small - t).min() <= 1e-10 * max(1.0, t)}
    monkeypatch.setattr(marginal, "BLOCK_KRYLOV_MIN_ORDER", 600)
    assert marginal_tau(system, kind, tol=1e-10).method == "structured"  # (N + 1) b < 600
    monkeypatch.setattr(marginal, "KRYLOV_MIN_ORDER", 200)
    auto = marginal_tau(system, kind, tol=1e-10)
    assert auto.method == "krylov" and np.isfinite(auto.complete_to)
    assert (auto.n_temporal, auto.n_previous) == (dense.n_temporal, dense.n_previous)
    assert abs(auto.tau_min - dense.tau_min) < 1e-12
    assert abs(auto.error_estimate - dense.error_estimate) < 1e-12
    listed = dense.tau[dense.tau <= auto.complete_to * (1 - 1e-9)]
    np.testing.assert_allclose(auto.tau[:listed.size], listed, rtol=1e-9)


#: A Fig 5.18 cell (human cochlea, 63.6 Hz, sigma = 1.85e9) where real tau crowd towards 1/2:
#: Arnoldi and the shift-invert cover give up on its small truncations and dense eig answers.
CROWDED = {"kappa": 10373.189950738564, "nu": 4.031237198723707e-05, "alpha": 1.559718442300574}


def test_block_model_falls_back_once_then_stays_dense(monkeypatch):
    """Blocks larger than 2 x 2 go to Arnoldi from half order BLOCK_KRYLOV_MIN_ORDER; once a
    truncation of the solve has fallen back from it to dense, the later ones below
    KRYLOV_MIN_ORDER go to dense directly (no Arnoldi run), and the answer -- tau_min, the
    truncation pair, the error estimate and complete_to -- is the dense path's."""
    from spectralshell.models import cochlea
    system = cochlea.hill_system(**CROWDED, n_spatial=16)
    runs = []
    real = marginal.smallest_taus
    monkeypatch.setattr(marginal, "smallest_taus",
                        lambda hill, **kw: runs.append(hill.n_temporal) or real(hill, **kw))
    auto = marginal_tau(system, "harmonic", n_temporal=34, tau_max=0.5)  # N = 34, then 26
    dense = marginal_tau(system, "harmonic", n_temporal=34, tau_max=0.5, method="dense")
    orders = [marginal.half_order(system, n) for n in runs]
    assert marginal.BLOCK_KRYLOV_MIN_ORDER <= min(orders) < marginal.KRYLOV_MIN_ORDER
    assert runs == [34]  # N = 26 (half order 432) after the fall-back: dense directly
    assert auto.method == "structured" and auto.tau_min is not None
    assert (auto.n_temporal, auto.n_previous) == (dense.n_temporal, dense.n_previous)
    assert abs(auto.tau_min - dense.tau_min) < 1e-12
    assert abs(auto.error_estimate - dense.error_estimate) < 1e-12
    assert auto.complete_to == dense.complete_to


def test_tau_max_with_no_tau_below_it(monkeypatch):
    """Nothing below tau_max: the Krylov radius passes tau_max and tau_min is None, as dense."""
    monkeypatch.setattr(marginal, "KRYLOV_MIN_ORDER", 200)
    system = cochlea_like(20, kappa=0.02)  # natural frequencies far below the first resonance
    auto = marginal_tau(system, "harmonic", tol=1e-10, tau_max=0.5)
    dense = marginal_tau(system, "harmonic", tol=1e-10, tau_max=0.5, method="dense")
    assert auto.tau_min is None and dense.tau_min is None
    assert auto.method == "krylov" and auto.complete_to >= 0.5


def test_krylov_falls_back_when_it_cannot_answer():
    """When the Krylov space would exceed a third of the operator (here a short truncation) the
    dense path answers; a singular block (undamped Mathieu at sqrt(kappa) = 3/2, tau = 0 exact)
    goes to QZ, as on the dense path."""
    system = sphere(m=3, kappa=0.02, nu=0.006)
    for kind in KINDS:
        fast = truncation_taus(system, kind, 20, method="krylov")
        dense = truncation_taus(system, kind, 20, method="dense")
        assert fast.method == "structured" and np.array_equal(fast.tau, dense.tau)
    res = marginal_tau(mathieu(kappa=2.25, nu=0.0), "subharmonic", method="krylov")
    assert res.method == "qz" and res.tau_min == 0.0


# Fig 6.13 cells (cardiac atrium, rho 1, mu 0.04, R 2 cm; params.physical.sphere_forced_params):
# sigma 5e3 dyn/cm at 300 bpm (m = 3: a harmonic tau = 0.4348 <= 1/2) and 1e4 at 150 bpm (none).
MAP_CELLS = [(3, 0.6332573977646111, 0.0003183098861837907),
             (3, 5.066059182116889, 0.0006366197723675814)]


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("m,kappa,nu", MAP_CELLS)
def test_map_cell_pair_matches_qz_of_both_truncations(m, kappa, nu, kind):
    """marginal_tau with tau_max = 1/2, as a map point runs it (the smaller truncation cut out
    of the larger, dense eig of W by direct LAPACK calls): tau_min, its error estimate and the
    listed tau equal those of QZ (scipy.linalg.eigvals(A, B)) of the two truncations' real-form
    pencils, each assembled on its own; no tau <= 1/2 in QZ at either truncation gives None."""
    system = sphere(m=m, kappa=kappa, nu=nu)
    found = marginal_tau(system, kind, tol=1e-8, tau_max=0.5)
    qz = [dense_taus(assemble(system, kind, n, "real")) for n in (found.n_temporal,
                                                                   found.n_previous)]
    last, previous = (t[(t >= 0) & (t <= 0.5)] for t in qz)
    if found.tau_min is None:
        assert last.size == 0 and previous.size == 0
        return
    np.testing.assert_allclose(found.tau, last, rtol=1e-12)
    assert found.error_estimate == pytest.approx(max(abs(last[0] - previous[0]),
                                                     8 * np.finfo(float).eps), abs=1e-13)


def test_an_unsettled_larger_tau_bounds_the_claim_and_every_settles_it():
    """Fibre m = 2, nu = 2e-4, kappa = 0.172, subharmonic: the pair of truncations that settles
    tau_min = 0.605133 moves the next tau (0.75999) by more than tol, so it is not listed and
    the list is claimed complete only below it (it was claimed to 2.3e6). every=True raises N
    until it settles too. Oracle: the dense truncations N = 60 and 80 (a pair far above the
    solver's) agree on both to 1e-12."""
    from spectralshell.models.fibre import hill_system as fibre
    system = fibre(m=2, nu=2e-4, kappa=0.172)
    far = [truncation_taus(system, "subharmonic", n, method="dense").tau for n in (60, 80)]
    oracle = far[1][far[1] < 1.0]
    np.testing.assert_allclose(far[0][:oracle.size], oracle, atol=1e-12)
    assert oracle.size == 2
    plain = marginal_tau(system, "subharmonic", tol=1e-10)
    assert plain.tau.size == 1 and abs(plain.tau_min - oracle[0]) < 1e-10
    assert plain.tau_min < plain.complete_to < oracle[1] + 1e-6
    every = marginal_tau(system, "subharmonic", tol=1e-10, tau_max=1.0, every=True)
    np.testing.assert_allclose(every.tau, oracle, atol=1e-10)
    assert every.complete_to >= 1.0
    with pytest.raises(ValueError, match="tau_max"):
        marginal_tau(system, "subharmonic", every=True)


@pytest.mark.parametrize("case", ["cochlea omega=600", "oscillators M=12"])
@pytest.mark.parametrize("n", [8, 10])
def test_subharmonic_arnoldi_on_the_complex_two_sided_w_matches_qz(case, n, monkeypatch):
    """Subharmonic kind of a block model: Arnoldi on the complex W of the two-sided form
    (krylov_form) lists the real tau of dense QZ of the real-form pencil up to its radius (to
    1e-9 relative; tau_min to 1e-12, and QZ has no real tau below it), and the truncation path
    runs it on that form (here, within its work budget or by dense after it) with the same
    tau_min."""
    from spectralshell.models import cochlea
    from spectralshell.params.physical import cochlea_params
    if case.startswith("cochlea"):
        p = cochlea_params({"omega": 600.0})
        system = cochlea.hill_system(kappa=p["kappa"], nu=p["nu"], alpha=p["alpha"],
                                     n_spatial=16)
    else:
        system = cochlea_like(12)
    assert marginal.krylov_form("subharmonic", system.block_size) == "two-sided"
    qz = dense_taus(assemble(system, "subharmonic", n, "real"))
    qz = np.sort(qz[qz >= 0])
    fast = smallest_taus(assemble(system, "subharmonic", n, "two-sided"))
    assert fast is not None and fast.tau.size
    agree_below_radius(fast, qz)
    assert abs(fast.tau[0] - qz[0]) < 1e-12
    forms = []
    real = marginal.smallest_taus
    monkeypatch.setattr(marginal, "smallest_taus",
                        lambda hill, **kw: forms.append(hill.form) or real(hill, **kw))
    found = truncation_taus(system, "subharmonic", n, tau_max=0.5, method="krylov")
    assert forms == ["two-sided"] and abs(found.tau[0] - qz[0]) < 1e-12
