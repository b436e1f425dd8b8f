"""Floquet analysis of the sphere with non-uniform stiffness kappa(theta, phi) (issue 28, part 2).

Oracles: exact Gaunt coefficients (sympy.physics.wigner) for the radial and the spheroidal and
toroidal self-couplings of the coupling matrix, exact sympy integrals for its poloidal-toroidal
entries, the per-degree Floquet solver (uniform kappa), finite differences of tau_min (the
eigenvector derivative), and the convergence of tau_min in the degree truncation.
"""

import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from scipy.special import sph_harm_y

import spectralshell as ss
from spectralshell.cli import main
from spectralshell.discretise.shtns_adapter import grid
from spectralshell.discretise.sphere_coupled import stiffness_field
from spectralshell.discretise.sphere_nonuniform import coupling_matrix, nonuniform_sphere
from spectralshell.params.expression import parse_expression
from spectralshell.reports.figures import FIGURES, _sphere_p2
from spectralshell.runner.nonuniform import (critical_exponent, solve_truncation,
                                             tau_min_sensitivity)

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "derivations"))
import _harmonics as harmonics  # noqa: E402  (derivations/_harmonics.py: Gaunt coefficients)

KAPPA0 = 0.02
#: a positive stiffness with axisymmetric and non-axisymmetric parts of degrees 1 and 2
FIELD = {(0, 0): KAPPA0 * math.sqrt(4 * math.pi), (1, 1): 0.002, (2, 0): 0.003,
         (2, 2): -0.0025, (2, -1): 0.0015}


def real_harmonic(m, k, th, ph):
    """Yr_{m,k}: Y_{m,0}, sqrt 2 Re Y_{m,k} (k > 0), sqrt 2 Im Y_{m,|k|} (k < 0)."""
    Y = sph_harm_y(m, abs(k), th, ph)
    return Y.real if k == 0 else np.sqrt(2) * (Y.real if k > 0 else Y.imag)


def kappa_function(th, ph):
    return sum(c * real_harmonic(l, k, th, ph) for (l, k), c in FIELD.items())


def real_gaunt(c, a, b) -> float:
    """int Yr_c Yr_a Yr_b over the sphere (exact, derivations/_harmonics.py), as a float."""
    value = complex(sp.N(harmonics.real_gaunt(c, a, b), 30))
    assert abs(value.imag) < 1e-25
    return value.real


L_MAX = 5


@pytest.fixture(scope="module")
def coupling():
    field = stiffness_field(grid(L_MAX), kappa_function)
    C, every = coupling_matrix(field.weight, L_MAX)
    return C, {s: i for i, s in enumerate(every)}


def test_radial_and_tangential_self_couplings_are_gaunt_integrals(coupling):
    """C_{(b,Y),(a,Y)} = q1(a) int kappa Yr_a Yr_b and C_{(b,Psi),(a,Psi)} = C_{(b,Phi),(a,Phi)}
    = q1(a) int kappa grad Yr_a . grad Yr_b / (l_b (l_b + 1)), the gradient integral being
    (1/2) sum_c kappa_c (L_a + L_b - L_c) G(c, a, b) with L = l (l + 1)."""
    C, at = coupling
    modes = [(l, k) for l in range(2, L_MAX + 1) for k in range(-l, l + 1)]
    worst = 0.0
    for a in modes:
        q1, La = (a[0] - 1) * (a[0] + 2), a[0] * (a[0] + 1)
        for b in modes:
            Lb = b[0] * (b[0] + 1)
            g = {c: real_gaunt(c, a, b) for c in FIELD}
            radial = q1 * sum(FIELD[c] * g[c] for c in FIELD)
            grad = 0.5 * sum(FIELD[c] * (La + Lb - c[0] * (c[0] + 1)) * g[c] for c in FIELD)
            for name, want in (("Y", radial), ("Psi", q1 * grad / Lb), ("Phi", q1 * grad / Lb)):
                got = C[at[(*b, name)], at[(*a, name)]]
                worst = max(worst, abs(got - want))
    assert worst < 1e-15   # entries are O(kappa0 q1) ~ 0.1 .. 0.6


def test_poloidal_toroidal_entries_are_exact_integrals():
    """C_{(b,Phi),(a,Psi)} = q1(a) int kappa Psi_a . Phi_b / L_b and C_{(b,Psi),(a,Phi)} =
    q1(a) int kappa Phi_a . Psi_b / L_b, integrated exactly by sympy for kappa =
    kappa0 (1 + 0.3 cos^2 theta) (Phi = rhat x Psi: Psi_a . Phi_b sin theta =
    d_phi Y_a d_theta Y_b - d_theta Y_a d_phi Y_b)."""
    th, ph = sp.symbols("theta phi", real=True)

    def yr(l, k):
        Y = sp.expand_complex(sp.expand_func(sp.Ynm(l, abs(k), th, ph)))
        return sp.re(Y) if k == 0 else sp.sqrt(2) * (sp.re(Y) if k > 0 else sp.im(Y))

    assert abs(float(yr(3, -2).subs({th: 0.7, ph: 0.3})) - real_harmonic(3, -2, 0.7, 0.3)) < 1e-14
    kappa = KAPPA0 * (1 + sp.Rational(3, 10) * sp.cos(th) ** 2)
    field = stiffness_field(grid(4), lambda t, p: KAPPA0 * (1 + 0.3 * np.cos(t) ** 2))
    C, every = coupling_matrix(field.weight, 4)
    at = {s: i for i, s in enumerate(every)}

    def cross(a, b):  # int kappa Psi_a . Phi_b dOmega
        Ya, Yb = yr(*a), yr(*b)
        integrand = kappa * (sp.diff(Ya, ph) * sp.diff(Yb, th) - sp.diff(Ya, th) * sp.diff(Yb, ph))
        return float(sp.integrate(sp.integrate(sp.expand(integrand), (ph, 0, 2 * sp.pi)),
                                  (th, 0, sp.pi)))

    for a, b in (((3, 1), (2, -1)), ((2, 2), (3, -2)), ((4, -1), (3, 1))):
        q1, Lb = (a[0] - 1) * (a[0] + 2), b[0] * (b[0] + 1)
        psi_to_phi = q1 * cross(a, b) / Lb
        phi_to_psi = q1 * cross(b, a) / Lb             # Phi_a . Psi_b = Psi_b . Phi_a
        assert abs(psi_to_phi) > 1e-3
        assert abs(C[at[(*b, "Phi")], at[(*a, "Psi")]] - psi_to_phi) < 1e-15
        assert abs(C[at[(*b, "Psi")], at[(*a, "Phi")]] - phi_to_psi) < 1e-15


def test_symmetries_decouple_orders_and_parity():
    """Axisymmetric kappa: each sector holds one order |k|; equatorially symmetric too: the
    poloidal slots have one parity of l + k and the toroidal ones the other."""
    sphere = nonuniform_sphere(kappa=lambda t, p: KAPPA0 * (1 + 0.3 * np.cos(t) ** 2), nu=0.006,
                               l_max=8)
    for sector in sphere.sectors:
        assert len({abs(k) for _, k, _ in sector.slots}) == 1
        parity = {(l + k + (n == "Phi")) % 2 for l, k, n in sector.slots}
        assert len(parity) == 1
    # a non-axisymmetric, equatorially asymmetric field couples everything into a few sectors
    general = nonuniform_sphere(kappa=kappa_function, nu=0.006, l_max=5)
    assert len(general.sectors) <= 2 and sum(len(s.slots) for s in general.sectors) >= 60


@pytest.mark.parametrize("kappa0, nu", [(0.02, 0.006), (0.5, 0.03)])
def test_uniform_kappa_reproduces_the_per_degree_results(kappa0, nu):
    """kappa0 (1 + 0 cos theta): tau_min per kind equals the smallest per-degree tau_min
    (degrees 2..l_max, poloidal and toroidal) to 1e-10. At kappa0 = 0.5, nu = 0.03 the
    subharmonic minimum is toroidal (l = 6: 0.7315, poloidal 0.7565), which the non-uniform
    solve missed while it left the toroidal sectors out."""
    res = ss.floquet("sphere", kappa=f"{kappa0}*(1+0*cos(theta))", nu=nu, l_max=6)
    for kind in ("harmonic", "subharmonic"):
        found = {(m, "poloidal"): getattr(ss.floquet("sphere", m=m, kappa=kappa0, nu=nu,
                                                     kind=kind), kind).tau_min
                 for m in range(2, 7)}
        cap = min(found.values())
        found.update({(m, "toroidal"): getattr(ss.floquet(
            "sphere", m=m, kappa=kappa0, nu=nu, kind=kind, component="toroidal", tau_max=cap),
            kind).tau_min for m in range(2, 7)})   # capped: uncapped ones reach ~1e5
        (l, component), expected = min(((k, t) for k, t in found.items() if t is not None),
                                       key=lambda kt: kt[1])
        assert abs(getattr(res, kind).tau_min - expected) < 1e-10
        lead = res.content[kind][0]
        assert (lead["l"], lead["component"]) == (l, component) and lead["share"] > 1 - 1e-12
        assert res.multiplicity[kind] == 2 * l + 1
    if (kappa0, nu) == (0.5, 0.03):
        assert res.content["subharmonic"][0]["component"] == "toroidal"


def test_cli_floquet_sphere_with_a_kappa_expression(capsys):
    code = main(["floquet", "sphere", "--kappa", "0.02*(1 + 0.3*cos(theta)**2)", "--nu", "0.006",
                 "--l-max", "6", "--kind", "subharmonic", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0
    assert out["params"] == {"kappa": "0.02*(1 + 0.3*cos(theta)**2)", "nu": 0.006, "l_max": 6}
    assert out["l_max"] == 6 and out["l_max_previous"] == 4
    lead = out["content"]["subharmonic"][0]
    assert (lead["l"], abs(lead["k"]), lead["component"]) == (3, 3, "poloidal")
    assert 0.35 < out["subharmonic"]["tau_min"] < 0.36


@pytest.mark.parametrize("argv, words", [
    (["--kappa", "0.02*(1+0.3*cos(theta))", "--nu", "0.006", "--m", "3"], "m = 3 is invalid"),
    (["--kappa", "0.02*(1+0.3*cos(theta))", "--nu", "0.006", "--l-max", "3"], "l_max = 3"),
    (["--kappa", "0.02", "--nu", "0.006", "--m", "3", "--l-max", "6"], "l_max = 6 is invalid"),
    (["--kappa", "0.02*(1-2*cos(theta))", "--nu", "0.006"], "> 0"),
    (["--kappa", "0.02*(1+0.3*cos(theta))", "--nu", "0"], "nu = 0"),
    (["--kappa", "0.02*(1+0.3*cos(theta))", "--nu", "0.006", "--l-max", "6",
      "--tol-spatial", "1e-3"], "tol_spatial"),
])
def test_cli_refuses_bad_non_uniform_input(capsys, argv, words):
    assert main(["floquet", "sphere", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and words.replace("_", "-") in err.replace("_", "-")


P2 = "(1.5*cos(theta)**2 - 0.5)"


@pytest.mark.parametrize("kind", ["harmonic", "subharmonic"])
def test_tau_min_derivative_from_the_eigenvectors_equals_finite_differences(kind):
    """f = 1 + eps P_2(cos theta) at eps = 0.2: w^H (A' - tau B') v / (w^H B v) against the
    central difference of tau_min with h = 1e-5 (truncation error ~h^2, rounding ~1e-13/h)."""
    def at(eps):
        return tau_min_sensitivity(kappa=f"0.02*(1 + {eps!r}*{P2})", direction=f"0.02*{P2}",
                                   nu=0.006, kind=kind, l_max=8)

    h = 1e-5
    tau, slope = at(0.2)
    difference = (at(0.2 + h)[0] - at(0.2 - h)[0]) / (2 * h)
    assert abs(slope) > 1e-3
    assert abs(slope - difference) < 1e-7


def test_tau_min_converges_geometrically_in_the_degree_truncation():
    """kappa = 0.02 (1 + 0.3 cos^2 theta), subharmonic: each step l_max -> l_max + 2 shrinks the
    change of tau_min by more than 10 (measured: ~150 per step), and 'auto' stops where the
    change is <= tol_spatial, within tol_spatial of the l_max = 12 value."""
    kappa = "0.02*(1 + 0.3*cos(theta)**2)"
    function = parse_expression("kappa", kappa).function
    values = [solve_truncation(nonuniform_sphere(kappa=function, nu=0.006, l_max=L),
                               ("subharmonic",),
                               {"tol": 1e-12, "n_temporal": None})["subharmonic"][0].tau_min
              for L in (6, 8, 10, 12)]
    changes = np.abs(np.diff(values))
    assert np.all(changes[1:] < changes[:-1] / 10) and changes[-1] < 1e-10
    auto = ss.floquet("sphere", kappa=kappa, nu=0.006, kind="subharmonic", tol_spatial=1e-6)
    assert auto.l_change["subharmonic"] <= 1e-6 and auto.l_max < 12
    assert abs(auto.subharmonic.tau_min - values[-1]) <= 1e-6
    assert auto.subharmonic.error_estimate >= auto.l_change["subharmonic"]


def test_p2_figure_is_listed_and_its_branches_hold_the_minimum(tmp_path):
    """fig-sphere-p2 (two eps): the subharmonic branches below 1/2 are the orders |k| = 0..3 of
    degree 3, and their smallest tau is the floquet tau_min at the same truncation."""
    assert "fig-sphere-p2" in FIGURES
    eps = np.array([-0.2, 0.3])
    paths = _sphere_p2(tmp_path, progress=False, workers=None, eps=eps)
    assert [p.name for p in paths] == ["fig-sphere-p2.png", "fig-sphere-p2.json"]
    rows = json.loads(paths[1].read_text())["branches"]
    for e in eps:
        sub = [r for r in rows if r["eps"] == e and r["kind"] == "subharmonic"]
        assert sorted((r["l"], r["k"]) for r in sub) == [(3, 0), (3, 1), (3, 2), (3, 3)]
        res = ss.floquet("sphere", kappa=f"0.02*(1 + {float(e)!r}*{P2})", nu=0.006, l_max=8,
                         kind="subharmonic", tol=1e-8)
        assert abs(min(r["tau_min"] for r in sub) - res.subharmonic.tau_min) < 1e-8


def test_the_critical_exponent_is_marginal_at_tau_min():
    """Newton's method on the Hill determinant (the exponents' machinery) at the tau_min of the
    marginal solver: Re gamma = 0 to 1e-10, Im gamma = 1/2 (subharmonic)."""
    kappa = "0.02*(1 + 0.3*cos(theta)**2)"
    res = ss.floquet("sphere", kappa=kappa, nu=0.006, l_max=8, kind="subharmonic")
    gamma, error = critical_exponent(kappa=kappa, nu=0.006, kind="subharmonic",
                                     tau=res.subharmonic.tau_min, l_max=8)
    assert abs(gamma.real) < 1e-10 and abs(gamma.imag - 0.5) < 1e-12 and error < 1e-10


@pytest.mark.slow
def test_the_time_stepper_decays_below_and_grows_above_tau_min():
    """The coupled time stepper (collocation in r, the same kappa field and degrees <= 8, started
    in the critical (3, 3) mode) at tau_min -+ 0.02: it decays below and grows above, at the
    rates Re gamma of the Floquet exponents to 1e-6 (measured 8e-10; about 2 minutes)."""
    kappa = "0.02*(1 + 0.3*cos(theta)**2)"
    tau_min = ss.floquet("sphere", kappa=kappa, nu=0.006, l_max=8,
                         kind="subharmonic").subharmonic.tau_min
    for tau, sign in ((tau_min - 0.02, -1), (tau_min + 0.02, 1)):
        traj = ss.simulate({"params": {"kappa": kappa, "nu": 0.006, "tau": tau},
                            "initial": {"shape": "3:3"},
                            "simulate": {"t_end": 120.0, "l_max": 8}})
        fit = next(f for f in traj.fits if (f.m, f.k) == (3, 3))
        gamma, _ = critical_exponent(kappa=kappa, nu=0.006, kind="subharmonic", tau=tau, l_max=8)
        assert np.sign(fit.growth_rate) == sign and abs(gamma.real) > 1e-3
        assert abs(fit.growth_rate - gamma.real) < 1e-6


def test_a_scene_with_a_kappa_expression_runs_floquet_only():
    scene = {"model": "sphere", "ask": ["floquet"], "floquet": {"kind": "subharmonic"},
             "params": {"kappa": "0.02*(1 + 0.3*cos(theta)**2)", "nu": 0.006, "l_max": 6}}
    res = ss.run_scene(scene)["floquet"]
    direct = ss.floquet("sphere", kappa="0.02*(1 + 0.3*cos(theta)**2)", nu=0.006, l_max=6,
                        kind="subharmonic")
    assert res.to_dict()["subharmonic"] == direct.to_dict()["subharmonic"]
    with pytest.raises(ss.errors.ParameterError, match="only 'floquet'"):
        ss.run_scene({**scene, "ask": ["tongues"]})
