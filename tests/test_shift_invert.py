"""Shift-invert cover of [0, tau_max] (solvers.shift_invert) against closed forms and dense QZ.

Oracles: a synthetic block-tridiagonal pencil whose eigenvalues are known in closed form
(decoupled Toeplitz chains, mixed by a fixed random similarity); scipy.linalg.eigvals(A, B) (QZ)
of the same truncation for the cochlea (low forcing frequency: hundreds of complex tau with
|tau| below the smallest real one, where the smallest-|tau| Arnoldi gives up) and the sphere;
scipy.sparse.linalg.spsolve for the block factorisation of A - sigma B.
"""

import numpy as np
import pytest
import scipy.sparse.linalg as spla

from spectralshell.discretise.hill import HillMatrices, assemble
from spectralshell.models import cochlea
from spectralshell.models.sphere import hill_system as sphere
from spectralshell.params.physical import cochlea_params
from spectralshell.solvers import _schur, marginal, shift_invert
from spectralshell.solvers.half_product import smallest_taus
from spectralshell.solvers.marginal import dense_taus, marginal_tau, truncation_taus
from spectralshell.solvers.shift_invert import interval_taus, shifted_solver

KINDS = ("harmonic", "subharmonic")
LOW_OMEGA = cochlea_params({"sigma": 1e7, "omega": 314.0})  # kappa ~ 91, nu ~ 5e-5


def low_omega_cochlea(n_spatial: int):
    return cochlea.hill_system(kappa=LOW_OMEGA["kappa"], nu=LOW_OMEGA["nu"],
                               alpha=LOW_OMEGA["alpha"], n_spatial=n_spatial)


def toeplitz_pencil(n_blocks: int, real: np.ndarray, pairs: np.ndarray, seed: int = 1):
    """(pencil, its eigenvalues). Component j of every block: A = a_j, B couples neighbouring
    blocks by 1, so a_j v_k = tau (v_{k-1} + v_{k+1}) and tau = a_j / (2 cos(l pi / (K + 1))),
    l = 1..K (the tridiagonal Toeplitz eigenvalues); a complex pair p +- iq enters as the 2 x 2
    block [[p, -q], [q, p]]. Every block is then mixed as Q A_k R, Q B R with one random real
    Q, R (the spectrum is unchanged, the blocks are dense and not realified)."""
    s = len(real) + 2 * len(pairs)
    a = np.zeros((s, s))
    a[np.arange(len(real)), np.arange(len(real))] = real
    for i, z in enumerate(pairs):
        j = len(real) + 2 * i
        a[j:j + 2, j:j + 2] = [[z.real, -z.imag], [z.imag, z.real]]
    rng = np.random.default_rng(seed)
    q, r = rng.standard_normal((2, s, s)) + 3 * np.eye(s)
    block, coupling = q @ a @ r, q @ r
    hill = HillMatrices(kind="harmonic", form="real", n_temporal=n_blocks - 1,
                        diag=np.broadcast_to(block, (n_blocks, s, s)).copy(),
                        lower=np.broadcast_to(coupling, (n_blocks - 1, s, s)),
                        upper=np.broadcast_to(coupling, (n_blocks - 1, s, s)).copy(),
                        self_coupling=None)
    cosines = 2 * np.cos(np.arange(1, n_blocks + 1) * np.pi / (n_blocks + 1))
    values = np.concatenate([real, pairs, pairs.conj()])
    return hill, (values[:, None] / cosines[None, :]).ravel()


def real_in(values: np.ndarray, upper: float) -> np.ndarray:
    values = np.asarray(values)
    keep = (np.abs(values.imag) == 0) & (values.real >= 0) & (values.real <= upper)
    return np.sort(values.real[keep])


def qz_real(hill: HillMatrices, upper: float) -> np.ndarray:
    taus = dense_taus(hill)
    return np.sort(taus[(taus >= 0) & (taus <= upper)])


def assert_same_list(found: np.ndarray, expected: np.ndarray, rtol: float = 1e-9) -> None:
    assert found.size == expected.size, (found, expected)
    np.testing.assert_allclose(found, expected, rtol=rtol, atol=0)


# 6 real components with tau >= 0.3 and 10 complex pairs with |tau| >= 0.06 hugging the real
# axis (|Im/Re| = 0.01..0.1): K = 12 blocks give 180 complex tau with |tau| below the smallest
# real one, and 9 real ones in [0, TOP].
REAL = np.array([0.6, 0.75, 0.9, 1.3, 2.0, 3.1])
PAIRS = 0.12 * np.exp(1j * np.linspace(0.01, 0.1, 10)) * np.linspace(1.0, 2.5, 10)
K_BLOCKS, TOP = 12, 0.6


def test_synthetic_pencil_gives_the_closed_form_real_taus():
    """Every real tau in [0, TOP] of the Toeplitz pencil (closed form), each once, complete to
    TOP; the smallest-|tau| Arnoldi gives up on this pencil (the failure mode the cover is for).
    Each disk's certificate holds: its radius is (1 - margin) times the distance of the k-th
    nearest closed-form eigenvalue (a missed nearer one would make it the (k+1)-th's)."""
    hill, values = toeplitz_pencil(K_BLOCKS, REAL, PAIRS)
    expected = real_in(values, TOP)
    assert expected.size == 9 and np.sum(np.abs(values) < expected[0]) == 180
    assert smallest_taus(hill, tau_max=TOP) is None
    found = interval_taus(hill, TOP, work_limit=np.inf)
    assert found.complete_to == TOP
    assert_same_list(found.tau, expected, rtol=1e-10)
    for shift in found.shifts:
        distance = np.sort(np.abs(values - shift.sigma))[shift.n_eigenvalues - 1]
        assert shift.radius == pytest.approx((1 - shift_invert.RADIUS_MARGIN) * distance,
                                             rel=1e-10)


@pytest.mark.parametrize("hint", ["tau_min", 0.01, 0.59, 5.0])
def test_hint_near_or_far_gives_the_same_set(hint):
    """The first shift at the hint (exactly at the smallest real tau, an eigenvalue; far from
    it; or outside the interval, where it is ignored) changes the cover, not the answer."""
    hill, values = toeplitz_pencil(K_BLOCKS, REAL, PAIRS)
    expected = real_in(values, TOP)
    hint = expected[0] if hint == "tau_min" else hint
    found = interval_taus(hill, TOP, hint=hint, work_limit=np.inf)
    assert found.complete_to == TOP
    assert_same_list(found.tau, expected, rtol=1e-10)
    if hint < TOP:
        assert found.shifts[0].sigma == pytest.approx(hint, rel=2e-3)


def test_smallest_only_covers_up_to_tau_min():
    """``smallest_only``: the cover stops past the smallest real tau; the list is every real
    tau up to complete_to (closed form)."""
    hill, values = toeplitz_pencil(K_BLOCKS, REAL, PAIRS)
    expected = real_in(values, TOP)
    found = interval_taus(hill, TOP, smallest_only=True, work_limit=np.inf)
    assert expected[0] <= found.complete_to < TOP
    assert_same_list(found.tau, expected[expected <= found.complete_to], rtol=1e-10)


def test_tau_max_below_every_real_tau_gives_an_empty_list():
    """tau_max below the smallest real tau of the closed form: nothing listed, and the cover
    certifies the whole interval (complete_to = tau_max)."""
    hill, values = toeplitz_pencil(K_BLOCKS, REAL, PAIRS)
    tau_max = 0.9 * real_in(values, np.inf)[0]
    for smallest_only in (False, True):
        found = interval_taus(hill, tau_max, smallest_only=smallest_only, work_limit=np.inf)
        assert found.tau.size == 0 and found.complete_to == tau_max


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("n_spatial,n_temporal", [(16, 10), (32, 5)])
def test_low_frequency_cochlea_matches_qz(kind, n_spatial, n_temporal):
    """The regime the cover is for (cochlea at omega = 314 rad/s): every real tau in [0, 1/2] of
    the real-form pencil against QZ of the same pencil, and the smallest one with
    ``smallest_only``; the smallest-|tau| Arnoldi gives up here."""
    hill = assemble(low_omega_cochlea(n_spatial), kind, n_temporal, "real")
    reference = qz_real(hill, 0.5)
    assert reference.size and smallest_taus(hill, tau_max=0.5) is None
    found = interval_taus(hill, 0.5, work_limit=np.inf)
    assert found.complete_to == 0.5
    assert_same_list(found.tau, reference)
    first = interval_taus(hill, 0.5, smallest_only=True, work_limit=np.inf)
    assert first.complete_to >= reference[0]
    assert_same_list(first.tau, reference[reference <= first.complete_to])


@pytest.mark.parametrize("kind", KINDS)
def test_partial_smallest_modulus_run_is_the_start_of_the_cover(kind):
    """smallest_taus with max_rounds = 1 where it cannot reach tau_min: a radius below the
    smallest real tau of QZ and no real tau listed; the cover started there finds QZ's tau."""
    hill = assemble(low_omega_cochlea(16), kind, 10, "real")
    reference = qz_real(hill, 0.5)
    partial = smallest_taus(hill, tau_max=0.5, max_rounds=1)
    assert partial.tau.size == 0 and 0 < partial.complete_to < reference[0]
    found = interval_taus(hill, 0.5, none_below=partial.complete_to, work_limit=np.inf)
    assert found.shifts[0].sigma > partial.complete_to
    assert_same_list(found.tau, reference)


@pytest.mark.parametrize("kind", KINDS)
def test_sphere_matches_qz(kind):
    """Sphere (block size 2, long truncation) over [0, 5]: real tau against QZ."""
    hill = assemble(sphere(m=3, kappa=0.02, nu=0.006), kind, 60, "real")
    reference = qz_real(hill, 5.0)
    assert reference.size
    found = interval_taus(hill, 5.0, work_limit=np.inf)
    assert found.complete_to == 5.0
    assert_same_list(found.tau, reference)


@pytest.mark.parametrize("case", ["cochlea harmonic", "cochlea subharmonic", "toeplitz"])
def test_block_factorisation_solves_the_shifted_system(case):
    """The block elimination (complex b x b blocks on the realified rows of the cochlea's real
    form; real blocks for the mixed Toeplitz pencil) against a sparse direct solve."""
    if case == "toeplitz":
        hill = toeplitz_pencil(8, REAL, PAIRS[:3])[0]
    else:
        hill = assemble(low_omega_cochlea(12), case.split()[1], 8, "real")
    r = np.random.default_rng(3).standard_normal(hill.A.shape[0])
    for sigma in (0.0, 0.37):
        direct = spla.spsolve((hill.A - sigma * hill.B).tocsc(), r)
        x = shifted_solver(hill, sigma)(r)
        assert np.linalg.norm(x - direct) <= 1e-10 * np.linalg.norm(direct)


@pytest.mark.parametrize("repeated", [False, True])
def test_compiled_sweeps_match_the_block_recursion(repeated):
    """_schur.sweep (the solve's two passes, one zgemv per block product) against the same
    recursion in numpy, with one coupling block per position and with one repeated block."""
    rng = np.random.default_rng(5)
    m, b = 7, 5

    def blocks(count):
        return rng.standard_normal((count, b, b)) + 1j * rng.standard_normal((count, b, b))

    inv, coupling = blocks(m), blocks(1 if repeated else m)
    c = np.broadcast_to(coupling, (m, b, b))
    g0 = rng.standard_normal((m, b)) + 1j * rng.standard_normal((m, b))
    start = rng.standard_normal(b) + 1j * rng.standard_normal(b)
    back = g0.copy()
    back[m - 1] = inv[m - 1] @ back[m - 1]
    for j in range(m - 2, -1, -1):
        back[j] = inv[j] @ (back[j] - c[j] @ back[j + 1])
    forward, previous = g0.copy(), start
    for j in range(m):
        forward[j] -= inv[j] @ (c[j] @ previous)
        previous = forward[j]
    g = g0.copy()
    _schur.sweep(inv, coupling, g, None)
    np.testing.assert_allclose(g, back, rtol=1e-13, atol=1e-13 * np.abs(back).max())
    g = g0.copy()
    _schur.sweep(inv, coupling, g, start)
    np.testing.assert_allclose(g, forward, rtol=1e-13, atol=1e-13 * np.abs(forward).max())
    with pytest.raises(ValueError, match="inconsistent shapes"):
        _schur.sweep(inv, blocks(3), g, start)


def test_budget_exhausted_returns_none_and_truncation_answers_dense(monkeypatch):
    """No work allowed: interval_taus gives up; truncation_taus then answers by the dense
    path, with the dense result."""
    system = low_omega_cochlea(16)
    hill = assemble(system, "harmonic", 10, "real")
    assert interval_taus(hill, 0.5, work_limit=np.inf) is not None
    for limit in (1.0, 100.0):  # below one disk; below the cover's need (about 300)
        assert interval_taus(hill, 0.5, work_limit=limit) is None
    monkeypatch.setattr(marginal, "KRYLOV_MIN_ORDER", 100)
    monkeypatch.setattr(shift_invert, "WORK_FRACTION", 1e-6)
    fast = truncation_taus(system, "harmonic", 10, tau_max=0.5)
    dense = truncation_taus(system, "harmonic", 10, tau_max=0.5, method="dense")
    assert fast.method == "structured" and np.array_equal(fast.tau, dense.tau)


@pytest.mark.parametrize("kind", KINDS)
def test_marginal_tau_through_the_cover_matches_dense(kind, monkeypatch):
    """marginal_tau with a finite tau_max on a block model above KRYLOV_MIN_ORDER (lowered, and
    the work limit lifted, so that the reference stays cheap): the truncations go through the
    cover (shift-invert, continued from one truncation to the next) and give the dense path's
    tau_min, truncations and error estimate; a hint changes none of them."""
    system = low_omega_cochlea(16)
    dense = marginal_tau(system, kind, tol=1e-8, tau_max=0.5, method="dense")
    monkeypatch.setattr(marginal, "KRYLOV_MIN_ORDER", 100)
    monkeypatch.setattr(shift_invert, "WORK_FRACTION", np.inf)
    for hint in (None, 0.2):
        fast = marginal_tau(system, kind, tol=1e-8, tau_max=0.5, hint=hint)
        assert fast.method == "shift-invert" and fast.complete_to >= fast.tau_min
        assert (fast.n_temporal, fast.n_previous) == (dense.n_temporal, dense.n_previous)
        assert abs(fast.tau_min - dense.tau_min) < 1e-11
        assert abs(fast.error_estimate - dense.error_estimate) < 1e-11
        listed = dense.tau[dense.tau <= fast.complete_to]
        assert_same_list(fast.tau, listed)


def _counting(module, name: str, monkeypatch) -> list:
    """Patch ``module.name`` (a factory of operators) so that every product is recorded."""
    calls: list = []
    real = getattr(module, name)

    def factory(*args):
        made = real(*args)
        op, rest = (made[0], made[1:]) if isinstance(made, tuple) else (made, None)

        def product(x):
            calls.append(1)
            return op.matvec(x) if hasattr(op, "matvec") else op(x)

        counted = (spla.LinearOperator(op.shape, matvec=product, dtype=op.dtype)
                   if hasattr(op, "matvec") else product)
        return counted if rest is None else (counted, *rest)

    monkeypatch.setattr(module, name, factory)
    return calls


def test_arnoldi_runs_stop_at_their_product_budget(monkeypatch):
    """ARPACK's restarts are capped from the budget (half_product.arpack_restarts): the
    smallest-|tau| run (max_products) and each shift-invert disk (the cover's work_limit) give
    up (None) within their budget where, uncapped, they apply the operator more often (a disk
    ran to its end before the work was checked: 131 products against a limit of 120); a
    disk's products count with Arnoldi's own work (shift_invert.cover_costs)."""
    from spectralshell.solvers import half_product

    hill = assemble(low_omega_cochlea(16), "subharmonic", 10, "real")
    products = _counting(half_product, "krylov_operator", monkeypatch)
    assert smallest_taus(hill) is None  # uncapped: gives up only when the space is too big
    uncapped = len(products)
    budget = uncapped // 4
    products.clear()
    assert smallest_taus(hill, max_products=budget) is None
    assert budget // 2 < len(products) <= budget
    assert half_product.arpack_restarts(np.inf, 8, 32) is None
    assert half_product.arpack_restarts(31, 8, 32) == 0
    assert half_product.arpack_restarts(32 + 24 * 5, 8, 32) == 5

    b_products = _counting(shift_invert, "_b_product", monkeypatch)
    assert interval_taus(hill, 0.5, work_limit=np.inf).work > 500  # three disks, the first ~170
    b_products.clear()
    limit = 300.0  # the first disk's Arnoldi space (64 products) and part of a restart
    assert interval_taus(hill, 0.5, work_limit=limit) is None  # stopped inside the first disk
    orthogonalisation, factorisation = shift_invert.cover_costs(hill, 64)
    # each product weighted by Arnoldi's own work; one more for the backward error's solve
    assert 64 <= len(b_products) <= 1 + (limit - factorisation) / (1 + orthogonalisation)
