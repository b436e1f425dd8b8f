"""Radial Chebyshev operators of the fibre (discretise/fibre_radial.py), a second discretisation.

Oracle: the fibre's natural modes from its Bessel dispersion relation det D(gamma) = 0
(``ss.natural_modes("fibre", ...)``: Newton on the Bessel-ratio form, certified by an
argument-principle count), which shares no code with the collocation; and the rows' derivation,
``derivations/fibre_radial.py`` (run by tests/test_derivations.py).
"""

import numpy as np
import pytest

import spectralshell as ss
from spectralshell.discretise.fibre_radial import fibre_radial_operators
from spectralshell.errors import ParameterError
from spectralshell.solvers.eigen import converged_modes

TOL = 1e-8
#: (fine, coarse) resolutions (n_inner, n_outer); exterior scale 0.5 (the clip of
#: exterior_scale_hint), which resolves the fast Stokes-layer mode too
FINE, COARSE = (64, 80), (56, 72)


def pencil(m, nu, kappa, n):
    return fibre_radial_operators(m=m, nu=nu, n_inner=n[0], n_outer=n[1],
                                  exterior_scale=0.5).pencil(kappa)


@pytest.mark.parametrize("m, kappa, nu", [(3, 0.02, 2e-4), (2, 1.0, 0.01), (5, 0.1, 1e-3)])
def test_finite_eigenvalues_are_the_natural_modes(m, kappa, nu):
    """Both natural modes with Im gamma >= 0 (the Rayleigh oscillation and the fast Stokes-layer
    mode) are eigenvalues of the pencil at K = kappa to 1e-8, accepted by the two-resolution
    check; the Rayleigh mode is the least damped oscillatory one (the converged eigenvalues with
    larger Re s are real: the interior viscous modes near -nu j^2 of a still membrane)."""
    exact = ss.natural_modes("fibre", m=m, kappa=kappa, nu=nu).gamma
    assert exact.size == 2
    modes = converged_modes(pencil(m, nu, kappa, FINE), pencil(m, nu, kappa, COARSE))
    found = [int(np.argmin(np.abs(modes.values - g))) for g in exact]
    for k, g in zip(found, exact):
        assert abs(modes.values[k] - g) <= TOL * abs(g)
    ahead = modes.values[:found[0]]
    assert np.all(np.abs(ahead.imag) <= 1e-8 * np.abs(ahead))


def test_operator_structure():
    """Real matrices; M is the identity on the interior vorticity rows and the kinematics and
    zero elsewhere; the membrane term sits only in the two stress rows, with E = [[m^2, m],
    [m, m^2]] split by row; f and omega vanish at infinity."""
    m = 4
    ops = fibre_radial_operators(m=m, nu=0.01, n_inner=10, n_outer=12)
    assert ops.size == 2 * (10 + 12) + 2
    assert all(np.isrealobj(A) for A in (ops.M, ops.L_fluid, ops.L_stiffness))
    diff = np.flatnonzero(np.diag(ops.M))
    wi, wo, mem = (ops.blocks[k] for k in ("omega_inner", "omega_outer", "membrane"))
    expected = np.r_[np.arange(wi.start + 1, wi.stop), np.arange(wo.start + 1, wo.stop - 1),
                     np.arange(mem.start, mem.stop)]
    assert np.array_equal(diff, expected) and np.count_nonzero(ops.M) == diff.size
    rows = np.flatnonzero(ops.L_stiffness.any(axis=1))
    assert np.array_equal(rows, [wi.start, wo.start])
    assert np.array_equal(ops.L_stiffness[np.ix_(rows, np.arange(mem.start, mem.stop))],
                          [[m * m, m], [m, m * m]])
    assert np.array_equal(ops.pumped("pressure") + ops.pumped("tangential"), ops.L_stiffness)
    assert not ops.pumped("pressure")[wo.start].any() and not ops.pumped("tangential")[wi.start].any()
    v = np.arange(ops.size, dtype=float)
    assert np.array_equal(ops.displacement(v), v[-2:])


@pytest.mark.parametrize("kwargs, name", [
    ({"m": 1}, "m"), ({"nu": 0.0}, "nu"), ({"n_inner": 3}, "n_inner"), ({"n_outer": 5}, "n_outer"),
    ({"exterior_scale": 0.0}, "exterior_scale")])
def test_bad_arguments_name_the_parameter(kwargs, name):
    args = {"m": 3, "nu": 0.01, "n_inner": 8, "n_outer": 8, **kwargs}
    with pytest.raises(ParameterError, match=name):
        fibre_radial_operators(**args)
    with pytest.raises(ParameterError, match="forcing"):
        fibre_radial_operators(m=3, nu=0.01, n_inner=8, n_outer=8).pumped("normal")
