"""Floquet exponents of the viscous models (solvers/hill_exponents.py): roots of the truncated
Hill determinant continued from the natural modes, counted complete by the argument principle.

Oracles: the natural modes from the dispersion relations (tau = 0; solvers/modes.py, an
independent root finder on a scalar function of beta), the marginal solver's tau_min (an
eigenproblem in tau at fixed gamma = 0 or i/2: there the largest Re gamma must vanish), the
stepped monodromy matrix of the sphere (tests/test_stepper_sphere.py), and smoothness in tau.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import spectralshell as ss
from spectralshell.cli import main
from spectralshell.errors import ParameterError
from spectralshell.models.registry import hill_system
from spectralshell.params.registry import make_params
from spectralshell.solvers.exponents import distance
from spectralshell.solvers.hill_exponents import _contour, count_by_winding, pencil_family, slit_width

SPHERE = dict(m=3, kappa=0.02, nu=0.006)          # thesis Table 6.1 case 1 (subharmonic)
SPHERE_HARMONIC = dict(m=2, kappa=0.21, nu=0.002)  # the first harmonic tongue, tau_min ~ 0.54
FIBRE = dict(m=3, kappa=0.02, nu=2e-4)
COCHLEA = dict(kappa=0.5, nu=1e-3, alpha=1.0, n_spatial=4)


def pairs(gamma):
    """Both members of each natural-mode pair, folded into Im in (-1/2, 1/2]."""
    g = np.concatenate([gamma, np.conj(gamma)])
    return g.real + 1j * (g.imag - np.ceil(g.imag - 0.5))


@pytest.mark.parametrize("model,params", [("sphere", SPHERE), ("fibre", FIBRE),
                                          ("cochlea", COCHLEA)])
def test_tau_zero_gives_the_natural_modes(model, params):
    """At tau = 0 the exponents are the natural modes (and their conjugates), to 1e-10."""
    res = ss.exponents(model, tau=0.0, **params)
    modes = pairs(ss.natural_modes(model, **params).gamma)
    assert len(res.gamma) == len(modes)
    assert distance(res.gamma, modes) < 1e-10 and distance(modes, res.gamma) < 1e-10


@pytest.mark.parametrize("model,params,kind", [("sphere", SPHERE, "subharmonic"),
                                               ("fibre", FIBRE, "subharmonic"),
                                               ("sphere", SPHERE_HARMONIC, "harmonic"),
                                               ("cochlea", COCHLEA, "subharmonic")])
def test_largest_growth_rate_vanishes_at_tau_min(model, params, kind):
    """At the marginal solver's tau_min the least damped exponent has Re gamma = 0 (1e-10) and
    Im gamma = 0 (harmonic) or 1/2 (subharmonic); just below it all decay, just above one grows
    with that Im gamma."""
    tau_min = getattr(ss.floquet(model, kind=kind, tol=1e-13, **params), kind).tau_min
    lock = 0.5 if kind == "subharmonic" else 0.0
    at = ss.exponents(model, tau=tau_min, **params)
    assert abs(at.gamma[0].real) < 1e-10 and abs(at.gamma[0].imag - lock) < 1e-10
    below = ss.exponents(model, tau=0.98 * tau_min, **params)
    above = ss.exponents(model, tau=1.02 * tau_min, **params)
    assert below.gamma[0].real < -1e-6
    assert above.gamma[0].real > 1e-6 and abs(above.gamma[0].imag - lock) < 1e-10


def _nearest(z: complex, gamma: np.ndarray) -> complex:
    """The member of ``gamma`` nearest to ``z`` modulo i, shifted by the multiple of i that
    makes it so."""
    diff = gamma - z
    diff = diff.real + 1j * (diff.imag - np.round(diff.imag))
    return z + diff[np.argmin(np.abs(diff))]


@pytest.mark.parametrize("model,params", [("sphere", SPHERE), ("fibre", FIBRE),
                                          ("cochlea", COCHLEA)])
def test_exponents_are_continuous_in_tau(model, params):
    """Smooth in tau: over three nearby amplitudes each exponent moves O(h) and its second
    difference (each matched to its nearest neighbour at tau -+ h) is O(h^2)."""
    h, tau = 1e-3, 0.2
    g = [ss.exponents(model, tau=t, **params).gamma for t in (tau - h, tau, tau + h)]
    assert all(len(x) == len(g[0]) for x in g)
    assert distance(g[1], g[0]) < 10 * h and distance(g[2], g[1]) < 10 * h
    second = max(abs(_nearest(z, g[0]) - 2 * z + _nearest(z, g[2])) for z in g[1])
    assert second < 100 * h ** 2


def test_list_is_complete_in_the_stated_region():
    """The argument principle over the stated region (at the result's truncation) counts exactly
    the exponents listed there."""
    res = ss.exponents("sphere", tau=0.3, **SPHERE)
    lo, hi = res.complete_in
    system = hill_system(make_params("sphere", SPHERE))
    T, _ = pencil_family(system, "harmonic", res.n_temporal)(0.3)
    branch = system.branch_point
    assert count_by_winding(T, _contour(lo, hi, slit_width(res.gamma, branch), branch)) == len(res.gamma)
    assert np.all((res.gamma.real > lo) & (res.gamma.real <= hi))


def test_count_keeps_the_least_damped_and_narrows_the_claim():
    """count = 2: the two largest Re gamma; complete_in then starts at the first dropped one."""
    every = ss.exponents("sphere", tau=0.3, **SPHERE)
    two = ss.exponents("sphere", tau=0.3, count=2, **SPHERE)
    np.testing.assert_array_equal(two.gamma, every.gamma[:2])
    assert two.complete_in == (every.gamma[2].real, every.complete_in[1])
    with pytest.raises(ParameterError, match="count"):
        ss.exponents("sphere", tau=0.3, count=0, **SPHERE)


def test_cli_exponents_sphere_json(capsys):
    """The command of the issue: JSON with the exponents, the error estimate and complete_in."""
    rc = main(["exponents", "sphere", "--m", "3", "--kappa", "0.02", "--nu", "0.006",
               "--tau", "0.3", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert rc == 0 and out["n_temporal"] >= 1 and out["error_estimate"] < 1e-10
    assert len(out["exponents"]) == 4 and len(out["complete_in"]) == 2
    lead = out["exponents"][0]
    assert lead["re"] < 0 and abs(lead["im"] - 0.5) < 1e-12   # stable: tau_min = 0.355
    assert main(["exponents", "sphere", "--m", "3", "--kappa", "0.02", "--nu", "0.006",
                 "--tau", "0.3", "--count", "2", "--json"]) == 0
    assert len(json.loads(capsys.readouterr().out)["exponents"]) == 2


@pytest.mark.parametrize("model,params,n", [("sphere", SPHERE, 12), ("fibre", FIBRE, 12),
                                            ("cochlea", dict(COCHLEA, n_spatial=8), 9)])
def test_block_lu_matches_dense_lapack(model, params, n):
    """The block LU's phase of det T and tr(T^{-1} T') equal dense LAPACK's (numpy slogdet and
    solve of the assembled matrix) at points off the real axis, near a root and in both windows."""
    system = hill_system(make_params(model, params))
    g = np.array([0.1 + 0.05j, -0.3 + 0.2j, -0.7 - 0.21j, 0.02 + 1e-5j])
    for kind in ("harmonic", "subharmonic"):
        T, dT = pencil_family(system, kind, n)(0.3)
        phases, logd = T.phases(g), T.log_derivatives(g)
        for x, p, d in zip(g, phases, logd):
            sign, _ = np.linalg.slogdet(T(x))
            assert abs(p - sign) < 1e-10
            ref = np.trace(np.linalg.solve(T(x), dT(x)))
            assert abs(d - ref) < 1e-10 * max(1.0, abs(ref))


@pytest.mark.parametrize("argv,tau", [
    (["fibre", "--m", "3", "--kappa", "0.02", "--nu", "2e-4"], "0.3"),
    (["cochlea", "--kappa", "0.5", "--nu", "1e-3", "--alpha", "1", "--n-spatial", "4"], "0.45")])
def test_cli_exponents_fibre_and_cochlea(capsys, argv, tau):
    """The command for the other viscous models, with --count, above the marginal solver's
    subharmonic tau_min: the least damped exponent grows, locked to Im gamma = 1/2."""
    assert main(["exponents", *argv, "--tau", tau, "--count", "1", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    (gamma,) = out["exponents"]
    assert abs(gamma["im"] - 0.5) < 1e-12 and gamma["re"] > 0
    if argv[0] == "fibre":  # no spatial modes: the temporal estimate alone
        assert out["spatial_change"] is None and out["error_estimate"] < 1e-10
    else:  # M = 4 against M = 2 (test_exponents_error_covers_the_spatial_truncation)
        assert out["n_spatial_previous"] == 2
        assert out["error_estimate"] == out["spatial_change"] > 1e-3
    params = {k: float(v) for k, v in out["params"].items() if isinstance(v, (int, float))}
    params = {k: int(v) if k in ("m", "n_spatial") else v for k, v in params.items()}
    assert ss.floquet(argv[0], kind="subharmonic", **params).subharmonic.tau_min < float(tau)


def test_exponents_error_covers_the_spatial_truncation():
    """The cochlea's exponents at n_spatial = M carry their change from M // 2 (as floquet's
    epsilon_M, thesis 5.3): the least damped exponent at M = 8 lies within its error estimate
    of the one at M = 16 (a finer, separate solve; they differ by 2.4e-3, far above the
    temporal estimate ~1e-15), and the estimate shrinks as M grows; M = 1 says it has none."""
    params = dict(COCHLEA, tau=0.3, count=1)
    at_8 = ss.exponents("cochlea", **{**params, "n_spatial": 8})
    at_16 = ss.exponents("cochlea", **{**params, "n_spatial": 16})
    assert at_8.n_spatial_previous == 4 and at_16.n_spatial_previous == 8
    assert abs(at_8.gamma[0] - at_16.gamma[0]) <= at_8.error_estimate
    assert 1e-3 < at_16.error_estimate < at_8.error_estimate
    assert any("n_spatial = 8 and 16" in w for w in at_16.warnings)
    at_1 = ss.exponents("cochlea", **{**params, "n_spatial": 1})
    assert at_1.spatial_change is None and any("temporal truncation only" in w
                                               for w in at_1.warnings)


@pytest.mark.parametrize("argv", [
    ["--count", "0"], ["--count", "2.5"], ["--tau", "x"], ["--nu", "-1"]])
def test_cli_exponents_bad_input_exits_2_with_one_line(capsys, argv):
    """Bad input: exit status 2 and a one-line message naming the parameter."""
    base = {"--m": "3", "--kappa": "0.02", "--nu": "0.006", "--tau": "0.3"}
    base.update(dict(zip(argv[::2], argv[1::2])))
    rc = main(["exponents", "sphere", *[x for kv in base.items() for x in kv]])
    err = capsys.readouterr().err.strip()
    assert rc == 2 and len(err.splitlines()) == 1 and argv[0].lstrip("-") in err


def test_count_falls_back_to_the_default_slit_when_an_exponent_lies_on_the_contour():
    """_slit_count: det T = s - z0 with z0 on the first contour (the slit's edge, Im z0 = the
    slit) is counted on the contour of the default SLIT, which leaves z0 in the band (not
    counted); z0 on both contours (the right edge) is refused with what to change."""
    from spectralshell.errors import ConvergenceError
    from spectralshell.solvers.hill_exponents import SLIT, _slit_count

    z0 = complex(-1.0, 1e-9)
    assert _slit_count(lambda s: np.array([[s - z0]]), -2.0, 1.0, 1e-9, 0.0) == (SLIT, 0)
    assert _slit_count(lambda s: np.array([[s - z0]]), -2.0, 1.0, 1e-10, 0.0) == (1e-10, 1)
    edge = complex(1.0, 0.3)
    with pytest.raises(ConvergenceError, match="cannot be counted: give a nearby tau or n_temporal="):
        _slit_count(lambda s: np.array([[s - edge]]), -2.0, 1.0, 1e-9, 0.0)


@pytest.mark.slow  # 50-70 s: make test-all
def test_exponents_next_to_the_cut_are_counted():
    """The fibre at m = 12, kappa = nu = 1, tau = -1.138 (found by test_stress): an exponent a
    few 1e-11 off the cut made the slit as narrow and the count failed with 'an eigenvalue lies
    on the contour'; now it answers as its neighbours in tau do: the two exponents at
    Re gamma ~ -3.1 lie on the cut to within their error (not listed), and the counted region
    reaches past them (it is placed around them, so it moves with them in tau)."""
    near = [ss.exponents("fibre", m=12, kappa=1.0, nu=1.0, tau=tau) for tau in (-1.1, -1.138)]
    assert len(near[0].gamma) == len(near[1].gamma) == 0
    assert all(res.complete_in[0] < -3.5 and res.complete_in[1] == 1.0 for res in near)


@pytest.mark.parametrize("m,kappa,nu", [(8, 1.0, 1.0), (8, 0.01, 0.1), (12, 0.01, 0.1)])
def test_strongly_damped_fibre_at_tau_zero_gives_its_natural_modes(m, kappa, nu):
    """zeta = nu/sqrt(kappa) = 1, tau = 0 (each raised 'the argument principle counts ...'):
    the exponents are the natural modes of the dispersion relation (solvers/modes.py) on the
    principal sheet and their conjugates, none on the cut, to 1e-10. At m = 8 the modes lie
    3e-10 ... 1e-8 above the cut: a conjugate pair 6e-10 apart was taken for one exponent, and
    two exponents 1e-9 from the slit's edges turned the phase by 2 pi between two samples of the
    count (counted 2 of 4). At m = 12 both modes lie on the cut (none listed), where the same
    aliasing counted 2."""
    modes = ss.natural_modes("fibre", m=m, kappa=kappa, nu=nu)
    off_cut = modes.gamma[modes.principal_sheet & ~modes.on_cut]
    assert len(off_cut) == (2 if m == 8 else 0)
    res = ss.exponents("fibre", m=m, kappa=kappa, nu=nu, tau=0.0)
    expected = pairs(off_cut)
    assert len(res.gamma) == len(expected)
    assert distance(res.gamma, expected) < 1e-10 and distance(expected, res.gamma) < 1e-10
    lo, hi = res.complete_in
    assert lo < np.min(modes.gamma.real) and hi == 1.0


def test_contour_has_a_vertex_next_to_each_nearby_exponent():
    """_through: a vertex at the foot of the perpendicular from each exponent within NEAR_EDGE of
    an edge's length (also a period i away), none for a far one; det T = (s - z1)(s - z2) with
    z1, z2 1e-9 above the slit's upper edge and 0.05 apart is counted 2 with them (a plain
    sampling of the edge sees their 2 pi as 0). T has the fluid's cut: (sqrt s - sqrt z1)
    (sqrt s - sqrt z2), principal roots, zero at z1, z2 only (seen from above the cut)."""
    from spectralshell.solvers.hill_exponents import _through

    box = [0j, 1 + 0j, 1 + 0.5j, 0.5j]
    out = _through(box, [0.25 + 1e-3j, 0.5 + 0.25j, 0.7 + 0.499j - 1j])
    np.testing.assert_allclose(out, [0j, 0.25, 1, 1 + 0.5j, 0.7 + 0.5j, 0.5j], atol=1e-15)
    z = np.array([-2.0 + 2e-9j, -1.95 + 2e-9j])
    T = lambda s: np.array([[np.prod(np.sqrt(s) - np.sqrt(z))]])  # noqa: E731
    plain = _contour(-3.6, 1.0, 1e-9, 0.0)
    assert count_by_winding(T, plain) == 1
    assert count_by_winding(T, _contour(-3.6, 1.0, 1e-9, 0.0, near=z)) == 2


def test_batched_shifts_give_the_same_phases_and_log_derivatives(monkeypatch):
    """HillPencil evaluates a batch of shifts in runs of at most BATCH_BYTES of blocks (the
    cochlea at M = 32, N = 40 held 4.9 GB in one batch, 0.3 GB so): the same values bitwise as
    one run."""
    from spectralshell.solvers import hill_exponents

    system = hill_system(make_params("cochlea", {"kappa": 0.5, "nu": 1e-3, "alpha": 1.0,
                                                 "n_spatial": 8}))
    T, _ = pencil_family(system, "harmonic", 6)(0.3)
    g = np.linspace(-0.5, 0.5, 37) + 0.1j
    whole = T.phases(g), T.log_derivatives(g)
    monkeypatch.setattr(hill_exponents, "BATCH_BYTES", 1)  # one shift per run
    assert len(T._batches(g, 3)) == g.size
    np.testing.assert_array_equal(T.phases(g), whole[0])
    np.testing.assert_array_equal(T.log_derivatives(g), whole[1])


def test_winding_count_evaluates_each_point_once():
    """count_by_winding repeats the count with twice the sub-intervals (whose grid holds the
    previous one) and edges share their ends: each distinct point is now evaluated once (the
    cochlea's count at M = 16, N = 20 took 29 s); the count is still the number of zeros inside
    (three of det T = (s - z1)(s - z2)(s - z3)(s - z4), one outside, two 1e-9 from the edges),
    and an edge along a cut (Im s = +0) is still the limit from above (sqrt s - sqrt z, z above
    the cut: one zero)."""
    inside = [0.3 + 0.2j, -0.4 + 1e-9j, 0.1 + 0.5j - 1e-9j]
    zeros = np.array(inside + [0.2 - 0.7j])
    asked = []

    def T(s):
        asked.append(complex(s).__repr__())
        return np.array([[np.prod(s - zeros)]])

    box = [-1 + 0j, 1 + 0j, 1 + 0.5j, -1 + 0.5j]
    assert count_by_winding(T, box) == len(inside)
    assert len(asked) == len(set(asked))
    above = [complex(-1, 0.0), 1 + 0j, 1 + 0.5j, -1 + 0.5j]
    assert count_by_winding(lambda s: np.array([[np.sqrt(s) - np.sqrt(-0.5 + 0.1j)]]), above) == 1


def test_strongly_damped_fibre_forced_keeps_both_members_of_each_pair():
    """m = 8, kappa = 0.01, nu = 0.1, tau = -0.3 (raised 'counts 4 ... but 2 were found': each
    conjugate pair, 7e-10 apart, was taken for one exponent): four exponents, each next to a
    natural mode of the dispersion relation or its conjugate (they move by 1.1e-3 from tau = 0,
    a third of the modes' spacing), and each a singular point of the dense truncated Hill matrix
    (smallest singular value, LAPACK)."""
    from spectralshell.solvers.hill_exponents import window
    from spectralshell.solvers.nonlinear_eigen import singular_ratio

    params = dict(m=8, kappa=0.01, nu=0.1)
    res = ss.exponents("fibre", tau=-0.3, **params)
    modes = pairs(ss.natural_modes("fibre", **params).gamma)
    assert len(res.gamma) == 4 and len(np.unique(res.gamma)) == 4
    assert distance(res.gamma, modes) < 1.5e-3 and distance(modes, res.gamma) < 1.5e-3
    system = hill_system(make_params("fibre", params))
    for gamma in res.gamma:
        kind, g = window(complex(gamma))
        T, _ = pencil_family(system, kind, res.n_temporal, dense=True)(-0.3)
        assert singular_ratio(T, g) < 1e-10


class _Product:
    """det T(s) = prod_k (s - z_k), 1 x 1, as a StructuredMatrix (phases and log-derivatives
    of many points at once, both from the closed form)."""

    def __init__(self, zeros):
        self.zeros = np.asarray(zeros, dtype=complex)

    def __call__(self, s):
        return np.array([[np.prod(s - self.zeros)]])

    def phases(self, s):
        v = np.prod(np.asarray(s)[:, None] - self.zeros, axis=1)
        return v / np.abs(v)

    def log_derivatives(self, s):
        return np.sum(1.0 / (np.asarray(s)[:, None] - self.zeros), axis=1)

    def phases_and_log_derivatives(self, s):
        return np.stack([self.phases(s), self.log_derivatives(s)])


def test_guarded_count_sees_a_2_pi_turn_between_samples():
    """Three zeros inside the unit box and a row of 64 just below its bottom edge, 1/64 apart:
    every sub-interval of 16 or 32 per edge holds an even number of them, whose turn of the phase
    (~pi each) the samples read modulo 2 pi as nearly none, so the phase alone counts 33 at both
    (as the cochlea's Hill determinant at M = 32, N = 40 counted 32 of 64); guarded by
    tr(T^{-1} T') at the nodes (the trapezoid rule fixes the multiple of 2 pi, and a
    log-derivative that bends fast refines), the count is 3 from 4 or 16 sub-intervals."""
    from spectralshell.solvers.nonlinear_eigen import StructuredMatrix

    inside = [0.3 + 0.85j, 0.7 + 0.9j, 0.5 + 0.8j]
    T = _Product(inside + list((np.arange(64) + 0.5) / 64 - 1e-4j))
    assert isinstance(T, StructuredMatrix)
    box = [0j, 1 + 0j, 1 + 1j, 1j]

    def dT(s):
        return T(s) * T.log_derivatives(np.array([s]))[0]

    assert count_by_winding(T, box) == 33   # the aliasing the guard is for
    assert count_by_winding(T, box, dT=dT) == count_by_winding(T, box, dT=dT, n_start=4) == 3


def test_exponents_on_a_locking_line_are_found_from_sign_changes():
    """_on_lines: det T is real on each window's locking line, so a sign change brackets an
    exponent there. The cochlea (M = 4) above its subharmonic tau_min has a locked pair on
    Im gamma = 1/2; with either member taken out of the list, it is found again (to 1e-10 of the
    continued value), and nothing else is added."""
    from spectralshell.runner.floquet import _exponents, solver_options
    from spectralshell.solvers.hill_exponents import _in_strip, _on_lines

    _, res = _exponents("cochlea", 0.45, solver_options(1e-10, None), COCHLEA)  # at M alone
    system = hill_system(make_params("cochlea", COCHLEA))
    locked = [g for g in res.gamma if abs(g.imag - 0.5) < 1e-12]
    assert len(locked) >= 2
    for g in locked:
        found = [z for z in _in_strip(res.gamma) if abs(z - g) > 1e-12]
        _on_lines(system, 0.45, res.complete_in, system.branch_point + 1e-6, res.n_temporal,
                  1e-10, False, found, res.error_estimate)
        assert len(found) == len(res.gamma)
        assert distance(np.array([g]), np.array(found[-1:])) < 1e-10
