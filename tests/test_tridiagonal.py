"""The compiled complex tridiagonal eigenvalue kernel (spectralshell/solvers/tridiagonal.py).

Oracles: 40-digit mpmath eig of the same matrix; LAPACK (scipy.linalg.eigvals of the dense
matrix, and eigvalsh_tridiagonal's real symmetric ?stemr, a different algorithm); closed forms
(2 x 2, diagonal, scaling). The wiring into the Floquet solver is checked against dense QZ of
the real-form pencil and against the LAPACK path it falls back to.
"""

import mpmath as mp
import numpy as np
import pytest
import scipy.linalg as sla
from hypothesis import given, settings
from hypothesis import strategies as st

import spectralshell as ss
from spectralshell.discretise.hill import assemble
from spectralshell.models.mathieu import hill_system
from spectralshell.solvers import marginal, tridiagonal
from spectralshell.solvers.half_product import (REAL_RTOL, block_inverses, dense_half_product,
                                                tridiagonal_half_product)


def dense(d, p):
    """The complex symmetric tridiagonal with diagonal d and off-diagonal products p (entries
    sqrt(p) on both sides: balanced, unlike 1 and p, on which LAPACK loses the small ones)."""
    root = np.sqrt(np.asarray(p, dtype=complex))
    return np.diag(np.asarray(d, dtype=complex)) + np.diag(root, 1) + np.diag(root, -1)


def nearest_distance(a, b):
    """max over a of the distance to the nearest element of b (and back)."""
    gap = np.abs(a[:, None] - b[None, :])
    return max(gap.min(axis=1).max(), gap.min(axis=0).max())


def mathieu_w(kind, n, kappa=0.26, nu=0.1):
    hill = assemble(hill_system(kappa=kappa, nu=nu), kind, n, "two-sided")
    return tridiagonal_half_product(hill, block_inverses(hill))


@pytest.mark.parametrize("kind, kappa, nu", [("subharmonic", 0.26, 0.1), ("harmonic", 1.3, 0.1),
                                             ("subharmonic", 2.25, 1e-4)])
def test_mathieu_w_against_40_digit_mpmath(kind, kappa, nu):
    """Every eigenvalue of a Mathieu W to ~1e-15 of its norm; the largest real one (tau_min)
    to 1e-14 relative. At (2.25, 1e-4) two eigenvalues nearly coincide (a finger tip) and
    LAPACK's largest real one is off by 8e-12 relative, the kernel's by < 1e-15."""
    d, p = mathieu_w(kind, 16, kappa, nu)
    found = tridiagonal.eigenvalues(d, p)
    assert found is not None
    with mp.workdps(40):
        exact = np.array([complex(z) for z in mp.eig(mp.matrix(dense(d, p).tolist()),
                                                      left=False, right=False)])
    scale = np.sqrt(np.vdot(d, d).real + 2 * np.abs(p).sum())
    assert nearest_distance(found, exact) <= 2e-15 * scale
    real = lambda z: z[np.abs(z.imag) <= 1e-9 * np.abs(z)].real.max()
    assert abs(real(found) - real(exact)) <= 1e-14 * real(exact)


@pytest.mark.parametrize("kind", ["harmonic", "subharmonic"])
@pytest.mark.parametrize("n", [10, 40, 160])
def test_mathieu_w_against_lapack(kind, n):
    d, p = mathieu_w(kind, n)
    found = tridiagonal.eigenvalues(d, p)
    assert found is not None
    reference = sla.eigvals(dense(d, p))
    assert nearest_distance(found, reference) <= 1e-13 * np.abs(reference).max()


def test_answers_on_almost_every_mathieu_w():
    """The kernel gives up (LAPACK then answers) on few Mathieu W: measured 2 of 2,528 over
    kappa in (0, 12], nu in {0, 1e-9, 1e-4, 0.1, 1}, N in {10, 40, 80, 160}; here a sub-grid."""
    gave_up = total = 0
    for kind in ("harmonic", "subharmonic"):
        for kappa in np.linspace(0.05, 9.0, 25):
            for nu in (0.0, 1e-4, 0.1):
                hill = assemble(hill_system(kappa=kappa, nu=nu), kind, 40, "two-sided")
                inv = block_inverses(hill)
                if inv is None:
                    continue
                d, p = tridiagonal_half_product(hill, inv)
                found = tridiagonal.eigenvalues(d, p)
                total += 1
                if found is None:
                    gave_up += 1
                    continue
                reference = sla.eigvals(dense_half_product(hill, inv))
                assert nearest_distance(found, reference) <= 1e-11 * np.abs(reference).max()
    assert total > 100 and gave_up <= 0.02 * total


def test_real_symmetric_against_lapack_stemr():
    """Real d and positive p: a real symmetric matrix, solved by LAPACK's MRRR (?stemr)."""
    rng = np.random.default_rng(1)
    d, p = rng.standard_normal(60), rng.uniform(0.1, 2.0, 59)
    found = tridiagonal.eigenvalues(d, p)
    reference = sla.eigvalsh_tridiagonal(d, np.sqrt(p))
    assert np.abs(found.imag).max() <= 1e-13
    assert np.allclose(np.sort(found.real), reference, rtol=0, atol=1e-13)


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 50),
       exponent=st.sampled_from([-150, -8, 0, 8, 150]))
def test_random_complex_against_lapack(seed, n, exponent):
    """Random complex tridiagonal matrices at scales 1e-150..1e150: either the kernel's
    eigenvalues match LAPACK's to 1e-10 of the norm (scale-free), or it declines (None)."""
    rng = np.random.default_rng(seed)
    c = lambda k: rng.standard_normal(k) + 1j * rng.standard_normal(k)
    scale = 10.0 ** exponent
    d, p = scale * c(n), scale**2 * c(n - 1)
    found = tridiagonal.eigenvalues(d, p)
    if found is None:
        return
    reference = sla.eigvals(dense(d / scale, p / scale**2)) * scale
    assert np.all(np.isfinite(found))
    size = max(1.0, np.abs(reference).max() / scale)
    assert nearest_distance(found, reference) <= 1e-10 * scale * size


def test_closed_forms():
    a, b, p = 1.0 + 2.0j, -0.5 + 0.25j, 0.3 - 0.7j
    two = np.sort_complex(tridiagonal.eigenvalues([a, b], [p]))
    root = np.sqrt(((a - b) / 2) ** 2 + p)
    assert np.allclose(two, np.sort_complex(np.array([(a + b) / 2 + root, (a + b) / 2 - root])),
                       rtol=1e-15, atol=1e-15)
    diag = np.array([3.0, -1.0 + 1.0j, 3.0, 0.0])  # a double eigenvalue, a zero one
    assert np.array_equal(np.sort_complex(tridiagonal.eigenvalues(diag, np.zeros(3))),
                          np.sort_complex(diag))
    assert np.array_equal(tridiagonal.eigenvalues([2.5j], []), [2.5j])
    assert np.array_equal(tridiagonal.eigenvalues(np.zeros(5), np.zeros(4)), np.zeros(5))
    assert tridiagonal.eigenvalues([], []).size == 0


def test_declines_non_finite_input_and_checks_shapes():
    assert tridiagonal.eigenvalues([1.0, np.nan, 2.0], [1.0, 1.0]) is None
    assert tridiagonal.eigenvalues([1.0, 2.0], [np.inf]) is None
    with pytest.raises(ValueError, match="products"):
        tridiagonal.eigenvalues([1.0, 2.0, 3.0], [1.0])


def test_half_product_diagonals_are_the_dense_ones():
    for kind in ("harmonic", "subharmonic"):
        for n in (1, 2, 7, 8):
            hill = assemble(hill_system(kappa=0.7, nu=0.1), kind, n, "two-sided")
            inv = block_inverses(hill)
            W = dense_half_product(hill, inv)
            d, p = tridiagonal_half_product(hill, inv)
            assert np.allclose(d, np.diag(W), rtol=1e-15, atol=1e-15)
            assert np.allclose(p, np.diag(W, 1) * np.diag(W, -1), rtol=1e-15, atol=1e-30)


@pytest.mark.parametrize("kind", ["harmonic", "subharmonic"])
def test_structured_taus_match_qz_and_the_lapack_fallback(kind, monkeypatch):
    """Mathieu (a scalar model, two-sided form): the real tau of one truncation agree with QZ
    of the real-form pencil (the reference path), and with the LAPACK path the solver takes
    when the kernel declines."""
    system = hill_system(kappa=1.7, nu=0.05)
    hill = assemble(system, kind, 30, marginal.preferred_form(kind, system.block_size))
    assert hill.form == "two-sided"
    kernel = marginal.structured_taus(hill)
    qz = marginal.dense_taus(assemble(system, kind, 30, "real"))
    qz = qz[qz > 0]
    assert len(kernel) == len(qz) and np.allclose(kernel, qz, rtol=1e-10)
    monkeypatch.setattr(tridiagonal, "eigenvalues", lambda d, p: None)
    lapack = marginal.structured_taus(hill)
    # The large tau are tiny mu^2 = 1/tau^2, which LAPACK has to ~eps ||W|| only: once that
    # rounding exceeds REAL_RTOL mu^2 a real mu^2 can fail the realness test (here tau = 3879
    # of the subharmonic kind with one BLAS build, Im/Re = 2e-9). Where mu^2 is 10x above that
    # level both lists must agree; above it LAPACK may miss a tau but must not invent one.
    norm_w = np.linalg.norm(dense_half_product(hill, block_inverses(hill)))
    decided = kernel < (10 * np.finfo(float).eps * norm_w / REAL_RTOL) ** -0.5
    assert decided.sum() > 20
    assert np.allclose(lapack[: decided.sum()], kernel[decided], rtol=1e-6)
    assert all(np.isclose(kernel, t, rtol=1e-6).any() for t in lapack)
    small = kernel < 10
    assert np.allclose(lapack[: small.sum()], kernel[small], rtol=1e-12)


def test_floquet_against_qz_at_random_parameters():
    """The whole solve on the kernel path: tau_min of ss.floquet equals QZ's (real-form pencil,
    the same final N) to 1e-10 relative, and every tau it lists is one of QZ's, at seeded random
    (kappa, nu) including nu = 0 and 1e-9 (a 600-point run of this check found no exception)."""
    rng = np.random.default_rng(7)
    for _ in range(40):
        kappa = float(rng.uniform(0.001, 20.0))
        nu = float(rng.choice([0.0, 1e-9, 1e-6, 1e-3, 0.1, 1.0]))
        result = ss.floquet("mathieu", kappa=kappa, nu=nu)
        for kind in ("harmonic", "subharmonic"):
            found = getattr(result, kind)
            qz = marginal.dense_taus(assemble(hill_system(kappa=kappa, nu=nu), kind,
                                              found.n_temporal, "real"))
            qz = qz[qz >= 0]
            assert abs(found.tau_min - qz[0]) <= 1e-10 * max(1.0, qz[0]), (kind, kappa, nu)
            assert all(np.abs(qz - t).min() <= 1e-8 * max(1.0, t) for t in found.tau)
