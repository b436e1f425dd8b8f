"""Non-uniform stiffness kappa(theta, phi): the SHTns adapter and the coupled stepper.

Oracles: scipy.special.sph_harm_y (independent harmonics), finite differences of them for the
tangential fields, a finer grid for the dealiased products, the closed form of a rotated degree-1
field, the decoupled stepper (uniform kappa), and rotation equivariance of the whole problem.
"""

import numpy as np
import pytest
from scipy.special import sph_harm_y

import spectralshell as ss
from spectralshell.discretise.shtns_adapter import Grid, grid
from spectralshell.discretise.sphere_coupled import coupled_system
from spectralshell.params.simulation import parse_expression
from spectralshell.solvers.stepper import integrate


def real_harmonic(m, k, th, ph):
    """Yr_{m,k}: Y_{m,0}, sqrt 2 Re Y_{m,k} (k > 0), sqrt 2 Im Y_{m,|k|} (k < 0)."""
    Y = sph_harm_y(m, abs(k), th, ph)
    return Y.real if k == 0 else np.sqrt(2) * (Y.real if k > 0 else Y.imag)


# ----------------------------------------------------------------------------- adapter
def test_adapter_real_harmonics_match_scipy():
    g = Grid(7)
    TH, PH = np.meshgrid(g.theta, g.phi, indexing="ij")
    coeffs = {(2, 0): 0.3, (3, 2): -1.0, (5, -4): 0.7, (7, 7): 0.2}
    want = sum(c * real_harmonic(m, k, TH, PH) for (m, k), c in coeffs.items())
    assert np.max(np.abs(g.synthesise(coeffs) - want)) < 1e-13
    back = g.analyse(want)
    assert all(abs(back[mk] - coeffs.get(mk, 0.0)) < 1e-13 for mk in back)


def test_adapter_tangential_fields_are_psi_and_phi():
    """Spheroidal coefficient 1 -> Psi = grad_S Yr; toroidal 1 -> Phi = rhat x grad_S Yr
    (central differences of scipy's harmonic, 1e-7)."""
    g = Grid(5)
    TH, PH = np.meshgrid(g.theta, g.phi, indexing="ij")
    h = 1e-5
    d_th = (real_harmonic(3, -2, TH + h, PH) - real_harmonic(3, -2, TH - h, PH)) / (2 * h)
    d_ph = (real_harmonic(3, -2, TH, PH + h) - real_harmonic(3, -2, TH, PH - h)) / (2 * h) \
        / np.sin(TH)
    vt, vp = g.synthesise_tangential({(3, -2): 1.0}, {})
    assert np.max(np.abs(vt - d_th)) < 1e-7 and np.max(np.abs(vp - d_ph)) < 1e-7
    vt, vp = g.synthesise_tangential({}, {(3, -2): 1.0})          # rhat x (th, ph) = (-ph, th)
    assert np.max(np.abs(vt + d_ph)) < 1e-7 and np.max(np.abs(vp - d_th)) < 1e-7
    S, T = g.analyse_tangential(-d_ph, d_th)
    assert abs(T[3, -2] - 1.0) < 1e-7 and max(abs(v) for v in S.values()) < 1e-7


def test_products_are_dealiased():
    """The product of two fields of degree <= l_max on the 3/2-rule grid has the same
    coefficients up to l_max as on a grid twice as fine."""
    a, b = {(4, 3): 1.0, (6, -1): 0.5}, {(5, 2): 1.0, (3, 0): -0.4}
    coarse, fine = grid(6), Grid(6, n_theta=64, n_phi=128)
    c = coarse.analyse(coarse.synthesise(a) * coarse.synthesise(b))
    f = fine.analyse(fine.synthesise(a) * fine.synthesise(b))
    assert max(abs(c[mk] - f[mk]) for mk in c) < 1e-13
    assert max(abs(v) for v in c.values()) > 0.05


def test_rotation_of_a_degree_one_field():
    """Yr_{1,0} = sqrt(3/4 pi) z rotated by beta about y (ZYZ angles (0, beta, 0)) is
    sqrt(3/4 pi) (z cos beta - x sin beta) or (z cos beta + x sin beta) -- fixes the direction
    used below; the norm is kept for any rotation."""
    g = Grid(4)
    beta = 0.7
    r = g.rotate({(1, 0): 1.0}, alpha=0.0, beta=beta, gamma=0.0)
    # x = -sqrt(4 pi / 3) Yr_{1,1} (Condon-Shortley phase), z = sqrt(4 pi / 3) Yr_{1,0}
    assert abs(r[1, 0] - np.cos(beta)) < 1e-14 and abs(abs(r[1, 1]) - np.sin(beta)) < 1e-14
    c = {(2, 1): 0.3, (3, -2): 1.0, (4, 0): -0.5}
    r = g.rotate(c, alpha=0.4, beta=1.1, gamma=-0.3)
    assert abs(sum(v * v for v in r.values()) - 1.34) < 1e-13
    assert all(abs(v) < 1e-14 for (m, _), v in r.items() if m not in (2, 3, 4))


# ----------------------------------------------------------------------------- coupled runs
def test_uniform_kappa_on_the_grid_reproduces_the_decoupled_run():
    """kappa given as the expression '0.5' goes through the coupled, grid-product stepper and
    reproduces the decoupled per-degree trajectory (1e-10 of the amplitude)."""
    base = {"params": {"nu": 0.05, "tau": 0.3}, "initial": {"shape": "2:0, 3:1:0.02"},
            "simulate": {"t_end": 8.0, "n_radial": 20, "dt": 0.02, "l_max": 6}}
    grid_run = ss.simulate({**base, "params": {**base["params"], "kappa": "0.5 + 0*cos(theta)"}})
    plain = ss.simulate({**base, "params": {**base["params"], "kappa": 0.5}})
    assert grid_run.modes == plain.modes == ((2, 0), (3, 1))     # nothing else is coupled
    assert np.max(np.abs(grid_run.radial - plain.radial)) < 1e-10 * np.max(np.abs(plain.radial))
    assert grid_run.provenance["kappa_mean"] == pytest.approx(0.5, abs=1e-14)
    assert grid_run.provenance["libraries"]["numpy"] == np.__version__


def test_rotated_axisymmetric_pattern_gives_the_rotated_trajectory():
    """kappa = 0.5 (1 + 0.4 P_2(n.rhat)) with the shape Yr_{2,0}, for n = zhat (axisymmetric:
    only k = 0 modes of degrees 2, 4, 6 are coupled) and for n rotated by Euler angles R (all
    orders couple): the rotated run's coefficients are R applied to the axisymmetric run's, at
    every saved time, for X^Y and X^Psi (1e-9 of the amplitude)."""
    l_max, angles = 6, dict(alpha=0.3, beta=0.9, gamma=-0.5)
    g = Grid(l_max)
    # the rotated axis: R applied to z (degree-1 coefficients, Condon-Shortley phase)
    r1 = g.rotate({(1, 0): 1.0}, **angles)
    n = np.array([-r1[1, 1], -r1[1, -1], r1[1, 0]])
    pattern = "0.5*(1 + 0.4*(3*({0})**2 - 1)/2)"
    dot = "{:.17g}*sin(theta)*cos(phi) + {:.17g}*sin(theta)*sin(phi) + {:.17g}*cos(theta)"
    shape0 = {(2, 0): 1.0}
    shape1 = {mk: c for mk, c in g.rotate(shape0, **angles).items() if abs(c) > 1e-15}
    runs = []
    for axis, shape in ((np.array([0.0, 0.0, 1.0]), shape0), (n, shape1)):
        kappa = parse_expression("kappa", pattern.format(dot.format(*axis))).function
        system = coupled_system(kappa=kappa, shape=shape, nu=0.05, tau=0.3, l_max=l_max,
                                n_radial=16)
        run = integrate(system, system.initial_state(shape), scheme="SBDF3", dt=0.02,
                        t_end=3.0, every=30, observe=system.displacement)
        runs.append((system, run))
    (s0, r0), (s1, r1_) = runs
    assert {m for m, _ in s0.modes} == {2, 4, 6} and all(k == 0 for _, k in s0.modes)
    assert len(s1.modes) == 5 + 9 + 13
    P0, P1 = len(s0.modes), len(s1.modes)
    scale = np.max(np.abs(r0.values))
    for i in range(r0.times.size):
        for part in (slice(0, P0), slice(P0, 2 * P0)):                 # X^Y, X^Psi
            coeffs = dict(zip(s0.modes, r0.values[i, part]))
            want = g.rotate(coeffs, **angles)
            got = dict(zip(s1.modes, r1_.values[i, slice(part.start // P0 * P1,
                                                          part.start // P0 * P1 + P1)]))
            err = max(abs(want[mk] - got.get(mk, 0.0)) for mk in want if mk[0] >= 2)
            assert err < 1e-9 * scale, (r0.times[i], err)
    assert np.max(np.abs(r0.values[-1, :P0] - r0.values[0, :P0])) > 0.1 * scale   # it moved


def test_only_the_adapter_imports_shtns():
    """Every SHTns call sits in discretise/shtns_adapter.py."""
    import ast
    from pathlib import Path

    import spectralshell

    users = []
    for path in Path(spectralshell.__file__).parent.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            names = ([a.name for a in node.names] if isinstance(node, ast.Import) else
                     [node.module or ""] if isinstance(node, ast.ImportFrom) else [])
            if any(n.split(".")[0] == "shtns" for n in names):
                users.append(path.name)
    assert users == ["shtns_adapter.py"]
