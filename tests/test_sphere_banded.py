"""Sparse ultraspherical operators of the sphere (discretise/sphere_banded.py).

Independent oracles:
* the ultraspherical helpers of discretise/chebyshev.py against numpy's Chebyshev series and
  scipy's Gegenbauer polynomials evaluated at points;
* natural modes: roots of the exact dispersion relation det D(s) = 0 (thesis (7.14)) and
  D_Phi(s) = 0, from :func:`spectralshell.natural_modes` at 30 digits (Bessel functions, no
  radial grid); the finite eigenvalues of the banded pencil near them by sparse shift-invert
  ARPACK (scipy), convergence under refinement n = 32, 64, 128;
* sparsity: non-zero counts of the matrices and of the stepper's sparse LU factor against c n;
* the rewritten rows themselves: derivations/sphere_banded.py (sympy, exact fields);
* time stepping of the DAE: observed order of the IMEX schemes under refinement.
"""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sparse
import scipy.sparse.linalg as spla
from numpy.polynomial import chebyshev as cheb
from scipy.special import eval_gegenbauer

import spectralshell as ss
from spectralshell.discretise.chebyshev import (ultraspherical_conversion,
                                                ultraspherical_derivative,
                                                ultraspherical_multiplication)
from spectralshell.discretise.sphere_banded import banded_operators
from spectralshell.discretise.sphere_radial import exterior_scale_hint
from spectralshell.discretise.sphere_stepping import degree_system
from spectralshell.errors import ParameterError
from spectralshell.solvers.stepper import _sparse_factor, integrate

NNZ_PER_N = 70      # nnz(M) + nnz(L_fluid) + nnz(L_stiffness) <= 70 n (measured 64 n, 34 n)


def series(c, lam, x):
    """Value of sum_j c_j C^(lam)_j(x) (lam = 0: Chebyshev T)."""
    if lam == 0:
        return cheb.chebval(x, c)
    return sum(cj * eval_gegenbauer(j, lam, x) for j, cj in enumerate(c))


def test_ultraspherical_helpers():
    """D_k, S_lam and multiplication by a polynomial (shifted variable) act on coefficients as
    the operations on the functions they represent (exact on the kept coefficients)."""
    n = 14
    a = np.random.default_rng(1).standard_normal(n)
    a[-4:] = 0.0                                 # room for a degree-3 multiplication
    x = np.linspace(-0.95, 0.95, 9)
    for k in (1, 2):
        d = ultraspherical_derivative(n, k) @ a
        np.testing.assert_allclose(series(d, k, x), cheb.chebval(x, cheb.chebder(a, k)),
                                   atol=1e-11)
    y = 0.5 + 0.5 * x
    for lam in (0, 1, 2):
        np.testing.assert_allclose(series(ultraspherical_conversion(n, lam) @ a, lam + 1, x),
                                   series(a, lam, x), atol=1e-12)
        product = ultraspherical_multiplication(n, lam, [0.3, -1.0, 0.0, 2.0], shift=0.5,
                                                scale=0.5) @ a
        np.testing.assert_allclose(series(product, lam, x),
                                   (0.3 - y + 2 * y**3) * series(a, lam, x), atol=1e-11)


def nearest_eigenvalue(A, B, sigma):
    """Eigenvalue of s B v = A v nearest sigma (ARPACK on (A - sigma B)^{-1} B)."""
    lu = spla.splu(sparse.csc_matrix(A - sigma * B, dtype=complex))
    op = spla.LinearOperator(A.shape, dtype=complex,
                             matvec=lambda v: lu.solve(np.asarray(B @ v, dtype=complex)))
    mu = spla.eigs(op, k=1, which="LM", return_eigenvectors=False, tol=1e-14)
    return sigma + 1.0 / mu[0]


@pytest.mark.parametrize("component", ["poloidal", "toroidal"])
@pytest.mark.parametrize("m", [2, 3, 4])
@pytest.mark.parametrize("zeta", [1e-3, 1e-2, 0.1])
def test_modes_match_dispersion_relation_and_converge(component, m, zeta):
    """The eigenvalue of the pencil nearest the exact mode is it to 1e-8 at n = 128 (inner and
    outer coefficients, exterior scale max(1, hint) as the stepper uses; measured <= 7e-12), and
    the error falls under refinement 32 -> 64 -> 128."""
    exact = complex(ss.natural_modes("sphere", m=m, kappa=1.0, nu=zeta, count=1,
                                     component=component, precision=30).gamma[0])
    scale = max(1.0, exterior_scale_hint(nu=zeta, s_scale=abs(exact)))
    errors = []
    for n in (32, 64, 128):
        ops = banded_operators(m=m, nu=zeta, component=component, n_inner=n, n_outer=n,
                               exterior_scale=scale)
        A, B = ops.pencil(1.0)
        errors.append(abs(nearest_eigenvalue(A, B, exact) - exact) / abs(exact))
    assert errors[2] <= 1e-8, errors
    assert errors[2] < errors[1] < errors[0], errors


@pytest.mark.parametrize("component", ["poloidal", "toroidal"])
def test_nonzeros_grow_linearly(component):
    """nnz of M, L_fluid, L_stiffness and of the stepper's sparse LU factor of M - h L are at
    most 70 n for n = 16 .. 1024 (the stepper's per-step cost is proportional to them)."""
    for n in (16, 64, 256, 1024):
        ops = banded_operators(m=3, nu=0.01, component=component, n_inner=n, n_outer=n,
                               exterior_scale=1.7)
        assert all(sparse.issparse(A) for A in (ops.M, ops.L_fluid, ops.L_stiffness))
        nnz = ops.M.nnz + ops.L_fluid.nnz + ops.L_stiffness.nnz
        A, B = ops.pencil(1.0)
        lu = _sparse_factor(sparse.csc_matrix(11 / 6 * B - 0.01 * A))
        assert nnz <= NNZ_PER_N * n, (n, nnz / n)
        assert lu.L.nnz + lu.U.nnz <= NNZ_PER_N * n, (n, (lu.L.nnz + lu.U.nnz) / n)


def test_no_growing_mode():
    """m = 2, zeta = 0.01, n = 48: every finite eigenvalue away from 0 (QZ, |s| > 1e-3) and the
    eigenvalues nearest 0 (shift-invert, the discretised continuum, where QZ is not accurate)
    have negative real parts; the number of finite eigenvalues is rank M."""
    ops = banded_operators(m=2, nu=0.01, n_inner=48, n_outer=48)
    A, B = ops.pencil(1.0)
    values = sla.eigvals(A.toarray(), B.toarray())
    finite = values[np.isfinite(values) & (np.abs(values) < 1e8)]
    assert finite.size == np.linalg.matrix_rank(B.toarray())
    assert np.all(finite[np.abs(finite) > 1e-3].real < 0)
    lu = spla.splu(sparse.csc_matrix(A))
    op = spla.LinearOperator(A.shape, matvec=lambda v: lu.solve(np.asarray(B @ v)), dtype=float)
    near = 1.0 / spla.eigs(op, k=8, which="LM", return_eigenvectors=False, tol=1e-13)
    assert np.all(near.real < 0), near


def test_bad_input():
    for kwargs, name in ((dict(n_inner=4), "n_inner"), (dict(m=1), "m"),
                         (dict(exterior_scale=0.0), "exterior_scale"),
                         (dict(component="axial"), "component"), (dict(nu=0.0), "nu")):
        args = dict(m=2, nu=0.01, n_inner=16, n_outer=16) | kwargs
        with pytest.raises(ParameterError, match=name):
            banded_operators(**args)


@pytest.mark.slow
def test_derivation_script_passes():
    """derivations/sphere_banded.py: the polynomial-coefficient rows are the rows of
    sphere_radial times the stated factors, and the exact fields solve them (~15 s)."""
    script = Path(__file__).resolve().parents[1] / "derivations" / "sphere_banded.py"
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                          timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr


@pytest.fixture(scope="module")
def forced_dae():
    """(system, start, displacement at t = 2 by SBDF4 with dt = 2.5e-4)."""
    system = degree_system(m=2, kappa=1.0, nu=0.05, tau=0.3, radial="banded", n_radial=32)
    y0 = system.initial_state([1.0, 0.0])
    return system, y0, system.displacement(integrate(system, y0, scheme="SBDF4", dt=2.5e-4,
                                                     t_end=2.0).final)


@pytest.mark.parametrize("name,order", [("SBDF3", 3), ("CNAB2", 2), ("MCNAB2", 2), ("RK443", 3)])
def test_forced_dae_steps_at_the_scheme_order(forced_dae, name, order):
    """The sparse DAE of degree_system(radial='banded') (m = 2, nu = 0.05, tau = 0.3: the
    explicit stiffness term acts on the algebraic stress rows) stepped from the inconsistent
    state at rest: the displacement at t = 2 converges at the scheme's order (errors against an
    SBDF4 run with dt = 2.5e-4)."""
    system, y0, want = forced_dae
    errors = [np.max(np.abs(system.displacement(integrate(system, y0, scheme=name, dt=dt,
                                                          t_end=2.0).final) - want))
              for dt in (0.02, 0.01)]
    assert abs(np.log2(errors[0] / errors[1]) - order) < 0.2, errors


@pytest.mark.parametrize("name", ["SBDF4", "CNAB2", "RK222"])
def test_sparse_stepper_path_matches_the_plain_implementation(name):
    """The stepper's sparse path (SuperLU without row interchanges, in-place CSR products) on
    the banded DAE (forced, tau = 0.3), with two columns and with a complex state, gives the
    trajectory of the schemes written out plainly with dense np.linalg.solve per step
    (tests/test_stepper_fast_path.py) to 1e-12 of the largest entry."""
    from test_stepper_fast_path import assert_same_run

    system = degree_system(m=2, kappa=1.0, nu=0.05, tau=0.3, radial="banded", n_radial=16)
    assert all(A.format == "csr" for A in (system.M, system.L, system.N))
    columns = system.initial_state([[1.0, 0.0], [0.2, 1.0]])
    assert_same_run(system, name, columns, 0.02, 30)
    assert_same_run(system, name, columns[:, 0] * (1 + 0.5j), 0.02, 30)


def test_auto_radial_is_collocation_at_automatic_resolutions_and_banded_above():
    """'auto' (the default): the automatic resolutions and n < BANDED_FROM are collocation, a
    larger n_radial is the sparse DAE; both give the leading mode of the dispersion relation
    (to 1e-9); coupled (non-uniform kappa) systems stay collocation, which they need."""
    import spectralshell as ss
    from spectralshell.discretise import sphere_stepping as st

    exact = complex(ss.natural_modes("sphere", m=2, kappa=1.0, nu=0.01, count=1).gamma[0])
    auto = st.degree_system(m=2, kappa=1.0, nu=0.01)
    assert auto.radial == "collocation" and auto.n_inner <= st.N_AUTO_MAX < st.BANDED_FROM
    big = st.degree_system(m=2, kappa=1.0, nu=0.01, n_radial=st.BANDED_FROM)
    assert big.radial == "banded" and sparse.issparse(big.L)
    below = st.degree_system(m=2, kappa=1.0, nu=0.01, n_radial=st.BANDED_FROM - st.N_STEP)
    assert below.radial == "collocation"
    for system in (auto, big, below):
        assert abs(system.leading - exact) <= 1e-9 * abs(exact)
