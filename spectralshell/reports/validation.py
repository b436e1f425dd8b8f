"""Validation report: a registry of cases, each a number the package computes through its public
API set against independent evidence, and a runner writing ``report.md``, the same as one
self-contained ``report.html`` (figures embedded), JSON and PNGs.

A :class:`Case` is data: name, section, quantity, source (where the expected value comes from:
a thesis table/figure/claim, a closed form, a scipy oracle, a second method, mpmath, convergence
under refinement), the expected value (or a callable computing it independently of the package's
solvers), a callable computing the value through :mod:`spectralshell.api` (or the figure data it
wrote), a tolerance (absolute, or relative with ``relative=True``; 0 for exact matches of discrete
outcomes) and whether it belongs to the quick set.

``spectralshell validate --quick`` runs the quick cases (seconds); without ``--quick`` every case
runs, including the reproduction of each thesis figure of :mod:`spectralshell.reports.figures`
(PNGs under ``figures/``) and the checks of what those figures show. The report closes with "Where
the thesis is wrong" (:mod:`spectralshell.reports.thesis_errata`), each finding with the live
result of its supporting cases.

Adding cases (another model): write a function returning a list of :class:`Case`
(``section`` = its heading) and append it to :data:`SECTIONS`. ``compute`` and a callable
``expected`` receive a :class:`Context` (output directory, figure cache); ``compute`` may return a
:class:`Measured` to attach a note (truncation, error estimate) to the value.
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

import mpmath
import numpy as np
import scipy.special as special
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, minimize_scalar

from ..runner.floquet import exponents, floquet, stability, tongues
from ..runner.lp import lp_summary
from ..runner.modes import natural_modes as solve_natural_modes
from ..runner.simulate import simulate
from .._version import __version__, libraries, libraries_line
from ..discretise.sphere_radial import radial_operators
from ..params.physical import BALLOONS, CARDIAC, TABLE_4_1, TABLE_6_1, balloon, fibre_forced
from ..solvers.eigen import least_damped
from .figures import FIGURES, make_figure
from .thesis_errata import FINDINGS, Finding

SOURCE_KINDS = ("thesis", "closed form", "scipy oracle", "second method", "mpmath", "refinement")


@dataclass(frozen=True)
class Measured:
    """A computed value with a note for the report (truncation, error estimate, ...)."""

    value: Any
    note: str = ""


@dataclass(frozen=True, kw_only=True)
class Case:
    """One validation case (see the module docstring)."""

    name: str
    section: str
    quantity: str
    source: str
    source_kind: str
    expected: Any
    compute: Callable[["Context"], Any]
    tolerance: float
    relative: bool = False
    quick: bool = False

    def __post_init__(self) -> None:
        if self.source_kind not in SOURCE_KINDS:
            raise ValueError(f"case {self.name}: source_kind {self.source_kind!r} not in {SOURCE_KINDS}")


@dataclass(frozen=True, kw_only=True)
class Outcome:
    """The result of one case: values, error (inf for a mismatch or a failure), pass/fail."""

    case: Case
    expected: Any
    computed: Any
    error: float
    passed: bool
    seconds: float
    note: str = ""
    message: str = ""


class Context:
    """What a case may use besides the API: the output directory and the figures made so far."""

    def __init__(self, out: Path, workers: int | None = None):
        self.out = Path(out)
        self.workers = workers
        self.figures: dict[str, list[Path]] = {}
        self.checked_by: dict[str, list[str]] = {}
        self.current: str | None = None  # the case being evaluated
        self._data: dict[str, Any] = {}

    def figure(self, name: str) -> Any:
        """The JSON data of thesis figure ``name``, made once into ``out/figures``."""
        if self.current is not None and self.current not in self.checked_by.setdefault(name, []):
            self.checked_by[name].append(self.current)
        if name not in self._data:
            where = self.out / "figures"
            where.mkdir(parents=True, exist_ok=True)
            paths = make_figure(name, where, workers=self.workers)
            self.figures[name] = paths
            self._data[name] = json.loads(next(p for p in paths if p.suffix == ".json").read_text())
        return self._data[name]


# ------------------------------------------------------------------ independent oracles


def mathieu_monodromy(kappa: float, nu: float, tau: float) -> np.ndarray:
    """Monodromy matrix of u'' + nu u' + kappa (1 + 2 tau sin t) u = 0 over 2 pi (DOP853, rtol 1e-12)."""

    def rhs(t, y):
        return [y[1], -nu * y[1] - kappa * (1 + 2 * tau * np.sin(t)) * y[0]]

    return np.column_stack([solve_ivp(rhs, (0, 2 * np.pi), y0, method="DOP853", rtol=1e-12,
                                      atol=1e-14).y[:, -1] for y0 in ([1.0, 0.0], [0.0, 1.0])])


def _multiplier_det(kappa: float, nu: float, tau: float, kind: str) -> float:
    """det(M - rho I) with rho = +1 (harmonic) or -1 (subharmonic): zero on a marginal curve."""
    target = 1.0 if kind == "harmonic" else -1.0
    return float(np.linalg.det(mathieu_monodromy(kappa, nu, tau) - target * np.eye(2)))


def monodromy_tau_min(kappa: float, nu: float, kind: str, tau_hi: float = 2.0, steps: int = 60) -> float:
    """Smallest tau with a multiplier +-1, by time integration alone: first sign change of
    det(M(tau) -+ I) on a tau grid, then brentq (no Hill matrices involved)."""
    taus = np.linspace(0.0, tau_hi, steps + 1)
    values = [_multiplier_det(kappa, nu, t, kind) for t in taus]
    for i in range(steps):
        if values[i] * values[i + 1] < 0:
            return brentq(lambda t: _multiplier_det(kappa, nu, t, kind), taus[i], taus[i + 1],
                          xtol=1e-14, rtol=1e-14)
    raise RuntimeError(f"no {kind} multiplier crossing for tau <= {tau_hi}")


def _unit_lambda0_squared(model: str, m: int | None) -> float:
    """lambda0^2 / kappa of the inviscid limit: 1 (Mathieu), Rayleigh m(m^2-1)/2 (fibre),
    Lamb m(m+1)(m-1)(m+2)/(2m+1) (sphere, (6.23)/(7.4)); written out here, not imported."""
    if model == "mathieu":
        return 1.0
    if model == "fibre":
        return m * (m * m - 1) / 2.0
    return m * (m + 1) * (m - 1) * (m + 2) / (2.0 * m + 1.0)


def sphere_dispersion_mp(gamma, m: int, nu, component: str = "poloidal"):
    """det D(gamma) (poloidal) or D_Phi(gamma) (toroidal) at kappa = 1 in mpmath, from the formulas of
    derivations/sphere_linear_result.md with mpmath's own I and K of half-integer order."""
    s, nu = mpmath.mpc(gamma), mpmath.mpf(nu)
    beta = mpmath.sqrt(s / nu)
    P = beta * mpmath.besseli(m + 1.5, beta) / mpmath.besseli(m + 0.5, beta)
    Q = beta * mpmath.besselk(m - 0.5, beta) / mpmath.besselk(m + 0.5, beta)
    q = (m - 1) * (m + 2)
    if component == "toroidal":
        return nu * s * (2 * m + 1 + P + Q) + q
    yy = s**2 * (mpmath.mpf(2 * m + 1) / (m * (m + 1)) + m / ((m + 1) * Q) + (m + 1) / (m * P)) + q
    ypsi = s**2 * (m / Q - (m + 1) / P)
    return yy * (s**2 * (1 / Q + 1 / P) + q) - ypsi * ypsi / (m * (m + 1))


def mp_mode(m: int, zeta: float, seed: complex, component: str = "poloidal") -> complex:
    """A root of :func:`sphere_dispersion_mp` by a 30-digit secant iteration from ``seed``."""
    with mpmath.workdps(30):
        x0 = mpmath.mpc(seed)
        root = mpmath.findroot(lambda g: sphere_dispersion_mp(g, m, zeta, component),
                               (x0, x0 * (1 + mpmath.mpf("1e-7"))), solver="secant",
                               tol=mpmath.mpf(10) ** -40, verify=False)
        return complex(root)


def two_harmonic_tip(kappa: float, nu: float) -> tuple[float, float]:
    """(k, tau) of the tip of the principal subharmonic finger of the uniform cochlea over a
    continuous wavenumber k, from the balance of the two harmonics e^{+-it/2} alone:
    tau(k) = |Z_k(i/2) + kappa| / kappa, Z_k(s) = 2 nu s beta (beta + k)/k, beta = sqrt(s/nu + k^2)
    (thesis (5.9) written out here, not the package's form), minimised over k near the inviscid
    resonance k = 1/(2 kappa). The neglected harmonics e^{+-3it/2} shift k and tau by a relative
    ~tau^2/8."""

    def z(k: float, s: complex = 0.5j) -> complex:
        beta = np.sqrt(s / nu + k * k)
        return 2 * nu * s * beta * (beta + k) / k

    k1 = 1 / (2 * kappa)
    best = minimize_scalar(lambda k: abs(z(k) + kappa) / kappa, bracket=(0.95 * k1, k1, 1.05 * k1),
                           tol=1e-12)
    return float(best.x), float(best.fun)


# ------------------------------------------------------------------ helpers of the cases


def _tau_near(model: str, kind: str, target: float, **params) -> Measured:
    res = getattr(floquet(model, kind=kind, **params), kind)
    tau = float(res.tau[np.argmin(np.abs(res.tau - target))])
    return Measured(tau, f"N = {res.n_temporal}, error estimate {res.error_estimate:.1e}")


def _tau_min(model: str, kind: str, **params) -> Measured:
    res = getattr(floquet(model, kind=kind, **params), kind)
    return Measured(res.tau_min, f"N = {res.n_temporal}, error estimate {res.error_estimate:.1e}")


def _unstable(model: str, tau: float, params: dict, *, lowest_only: bool = False) -> str:
    """'m = 3 subharmonic' (the unstable degrees of m = 2..6 at ``tau``, or only the one with the
    lowest threshold)."""
    res = stability(model, tau=tau, m="2:6", **params)
    modes = [(min(d[f"tau_{d['kind']}"]), d["m"], d["kind"]) for d in res.modes if d["unstable"]]
    modes = sorted(modes)[:1] if lowest_only else sorted(modes, key=lambda x: x[1])
    return "; ".join(f"m = {m} {kind}" for _, m, kind in modes) or "none"


def _scipy_case(model: str, kind: str, fn: str, order: int, q: float, *, m: int | None = None,
                section: str, quick: bool = False) -> Case:
    """Undamped (inviscid) marginal tau against scipy's Mathieu characteristic values: with
    t = 2x - pi/2, X'' + L (1 + 2 tau sin t) X = 0 is DLMF 28.2.1 with a = 4 L, q = 4 L tau
    (derivations/mathieu_mapping.py), L = lambda0^2; at L = a_r(q)/4 the curve passes tau = q/a."""
    unit = _unit_lambda0_squared(model, m)
    degree = {} if m is None else {"m": m}
    label = f"{model}.scipy.{fn[-1]}{order}.q{q:g}" if model == "mathieu" else \
        f"{model}.inviscid.scipy.m{m}" + ("" if quick else f".{fn[-1]}{order}")

    def expected(ctx):
        return q / getattr(special, fn)(order, q)

    def compute(ctx):
        kappa = getattr(special, fn)(order, q) / (4 * unit)
        return _tau_near(model, kind, q / getattr(special, fn)(order, q), kappa=kappa, nu=0.0, **degree)

    where = "" if m is None else f" (m = {m}: lambda0^2 = {unit:g} kappa)"
    return Case(name=label, section=section, quantity=f"undamped {kind} tau at lambda0^2 = "
                f"{fn[-1]}_{order}(q)/4, q = {q:g}{where}",
                source=f"scipy.special.{fn}({order}, {q:g}) (DLMF 28.2.1: a = 4 lambda0^2, q = 4 lambda0^2 tau)",
                source_kind="scipy oracle", expected=expected, compute=compute, tolerance=1e-10,
                quick=quick)


def _slope(values: Sequence[float], nus: Sequence[float]) -> float:
    return float(np.polyfit(np.log(nus), np.log(np.abs(values)), 1)[0])


def _inviscid_rate(model: str) -> Measured:
    """Slope of log(tau_min(nu) - tau_min(0)) against log nu (subharmonic, m = 3, kappa = 0.02)
    for nu = 1e-6 .. 1e-9: the Stokes-layer damping makes it 1/2."""
    nus = [1e-6, 1e-7, 1e-8, 1e-9]
    base = floquet(model, kind="subharmonic", m=3, kappa=0.02, nu=0.0).subharmonic.tau_min
    diff = [floquet(model, kind="subharmonic", m=3, kappa=0.02, nu=nu).subharmonic.tau_min - base
            for nu in nus]
    return Measured(_slope(diff, nus), f"tau_min(1e-9) - tau_min(0) = {diff[-1]:.2e}")


def _tips(panel: dict, kind: str | None = None) -> list[dict]:
    return sorted((t for t in panel["tips"] if kind is None or t["kind"] == kind), key=lambda t: t["kappa"])


# ------------------------------------------------------------------ chapter 2: damped Mathieu

MATHIEU = "Chapter 2: damped Mathieu equation"


def mathieu_cases() -> list[Case]:
    cases = [_scipy_case("mathieu", "subharmonic", "mathieu_a", 1, 1.3, section=MATHIEU, quick=True),
             _scipy_case("mathieu", "harmonic", "mathieu_b", 2, 1.3, section=MATHIEU, quick=True)]
    cases += [_scipy_case("mathieu", kind, fn, order, q, section=MATHIEU)
              for kind, fn, order in [("harmonic", "mathieu_a", 2), ("harmonic", "mathieu_a", 4),
                                      ("harmonic", "mathieu_b", 4), ("subharmonic", "mathieu_a", 3),
                                      ("subharmonic", "mathieu_b", 3), ("subharmonic", "mathieu_b", 5)]
              for q in (0.3, 4.0)]
    for k in (1, 2, 3):
        kind = "subharmonic" if k % 2 else "harmonic"

        def tip(ctx, k=k, kind=kind):
            c = (k / 2) ** 2
            (t,) = tongues("mathieu", kappa=np.linspace(c - 0.05, c + 0.05, 11), nu=0.0, kind=kind,
                               workers=1).tips
            return Measured(t.kappa, f"tip tau = {t.tau:.1e} +- {t.tau_error:.0e}")

        cases.append(Case(name=f"mathieu.tip.k{k}", section=MATHIEU,
                          quantity=f"kappa of the undamped {kind} finger tip, k = {k}",
                          source="sqrt(kappa) = k/2 (thesis 2.2)", source_kind="closed form",
                          expected=(k / 2) ** 2, compute=tip, tolerance=1e-11, quick=k == 1))
    for kappa, nu, kind, quick in [(0.26, 0.1, "subharmonic", True), (1.1, 0.1, "harmonic", False),
                                   (2.3, 0.01, "subharmonic", False), (1.0, 0.05, "harmonic", False),
                                   (0.7, 0.5, "harmonic", False)]:
        cases.append(Case(
            name=f"mathieu.monodromy.{kind[0]}.k{kappa:g}.nu{nu:g}", section=MATHIEU,
            quantity=f"damped {kind} tau_min, kappa = {kappa:g}, nu = {nu:g}",
            source="multiplier crossing of the solve_ivp (DOP853, rtol 1e-12) monodromy "
                   "matrix, brentq", source_kind="second method",
            expected=lambda ctx, a=(kappa, nu, kind): monodromy_tau_min(*a),
            compute=lambda ctx, a=(kappa, nu, kind): _tau_min("mathieu", a[2], kappa=a[0], nu=a[1]),
            tolerance=1e-8, quick=quick))
    for kappa, nu, tau, quick in [(1.0, 0.1, 0.3, True), (0.25, 0.1, 0.4, False), (2.3, 0.05, 0.7, False)]:
        cases.append(Case(
            name=f"mathieu.exponent.k{kappa:g}.nu{nu:g}.tau{tau:g}", section=MATHIEU,
            quantity=f"largest growth rate Re gamma, kappa = {kappa:g}, nu = {nu:g}, tau = {tau:g}",
            source="log|rho|max / (2 pi) of the solve_ivp monodromy matrix",
            source_kind="second method",
            expected=lambda ctx, a=(kappa, nu, tau): float(
                np.log(np.abs(np.linalg.eigvals(mathieu_monodromy(*a))).max()) / (2 * np.pi)),
            compute=lambda ctx, a=(kappa, nu, tau): float(
                exponents("mathieu", kappa=a[0], nu=a[1], tau=a[2]).gamma.real.max()),
            tolerance=1e-9, quick=quick))
    cases.append(Case(
        name="mathieu.liouville", section=MATHIEU,
        quantity="sum of Re gamma, kappa = 1, nu = 0.1, tau = 0.3",
        source="Liouville, sum of exponents = trace = -nu", source_kind="closed form",
        expected=-0.1, compute=lambda ctx: float(exponents("mathieu", kappa=1.0, nu=0.1, tau=0.3)
                                                 .gamma.real.sum()),
        tolerance=1e-10, quick=True))
    cases.append(Case(
        name="fig-2.2.tips", section=MATHIEU,
        quantity="finger tips of Fig 2.2 (undamped, kappa in [0, 3])",
        source="sqrt(kappa) = k/2, k = 1, 2, 3", source_kind="closed form",
        expected=[0.25, 1.0, 2.25], compute=lambda ctx: [t["kappa"] for t in _tips(ctx.figure("fig-2.2")[0])],
        tolerance=1e-9))

    def fig_2_3_marginal(ctx):
        worst = 0.0
        for panel in ctx.figure("fig-2.3"):
            nu = panel["params"]["nu"]
            for t in panel["tips"]:
                worst = max(worst, abs(_multiplier_det(t["kappa"], nu, t["tau"], t["kind"])))
        return Measured(worst, "max over every tip of both panels")

    cases.append(Case(
        name="fig-2.3.tips-marginal", section=MATHIEU,
        quantity="|det(M -+ I)| at the finger tips of Fig 2.3 (nu = 0.01, 0.1)",
        source="solve_ivp monodromy matrix at each tip", source_kind="second method",
        expected=0.0, compute=fig_2_3_marginal, tolerance=1e-8))

    def lowest_finger(ctx):
        out = []
        for panel in ctx.figure("fig-2.3"):
            t = min(panel["tips"], key=lambda t: t["tau"])
            out.append(f"{t['kind']} k = {round(2 * math.sqrt(t['kappa']))}")
        return ", ".join(out)

    cases.append(Case(
        name="fig-2.3.principal", section=MATHIEU,
        quantity="lowest finger of each panel of Fig 2.3",
        source="thesis 2.2: the principal subharmonic finger reaches lowest", source_kind="thesis",
        expected="subharmonic k = 1, subharmonic k = 1", compute=lowest_finger, tolerance=0.0))
    return cases


# ------------------------------------------------------------------ chapter 4: fibre

FIBRE = "Chapter 4: immersed circular fibre (Floquet)"


def fibre_cases() -> list[Case]:
    cases = [_scipy_case("fibre", "subharmonic", "mathieu_a", 1, 1.3, m=3, section=FIBRE, quick=True),
             _scipy_case("fibre", "harmonic", "mathieu_b", 2, 4.0, m=2, section=FIBRE),
             _scipy_case("fibre", "subharmonic", "mathieu_b", 3, 0.3, m=5, section=FIBRE)]
    printed = {1: (2e-4, 0.02), 2: (2e-4, 0.08)}
    for i, name in enumerate(("nu", "kappa")):
        cases.append(Case(
            name=f"fibre.table4.1.{name}", section=FIBRE,
            quantity=f"dimensionless {name} of Table 4.1 cases 1, 2 from the physical columns",
            source="thesis Table 4.1 (printed columns)", source_kind="thesis",
            expected=[printed[c][i] for c in (1, 2)],
            compute=lambda ctx, name=name: [fibre_forced(**TABLE_4_1[c])[name] for c in (1, 2)],
            tolerance=1e-12, relative=True, quick=True))
    for case, mode in ((1, "m = 3 subharmonic"), (2, "m = 2 subharmonic")):
        cases.append(Case(
            name=f"fibre.table4.1.case{case}.mode", section=FIBRE,
            quantity=f"least-threshold unstable degree (m = 2..6) at tau = 0.45, Table 4.1 case {case}",
            source="thesis 4.4 (simulations of Table 4.1, Fig 4.5)", source_kind="thesis",
            expected=mode, compute=lambda ctx, c=case: _unstable("fibre", 0.45, fibre_forced(**TABLE_4_1[c]),
                                                                 lowest_only=True),
            tolerance=0.0, quick=True))
    common = {"m": 3, "kappa": 0.02, "nu": 2e-4}
    cases.append(Case(
        name="fibre.fig4.2.pressure", section=FIBRE,
        quantity="subharmonic tau_min with only the pressure jump pumped (m = 3, kappa = 0.02, nu = 2e-4)",
        source="thesis 4.2 / Fig 4.2: the pressure jump carries the instability (vs both jumps pumped, 1 %)",
        source_kind="thesis",
        expected=lambda ctx: floquet("fibre", kind="subharmonic", **common).subharmonic.tau_min,
        compute=lambda ctx: _tau_min("fibre", "subharmonic", forcing="pressure", **common),
        tolerance=0.01, relative=True, quick=True))

    cases.append(Case(
        name="fibre.inviscid-rate", section=FIBRE,
        quantity="slope of log(tau_min(nu) - tau_min(0)) against log nu, m = 3, kappa = 0.02",
        source="Stokes-layer damping ~ nu^(1/2)", source_kind="closed form",
        expected=0.5, compute=lambda ctx: _inviscid_rate("fibre"), tolerance=0.03))

    def fig_4_1(ctx):
        out = []
        for panel in ctx.figure("fig-4.1"):
            m, nu = panel["params"]["m"], panel["params"]["nu"]
            if nu != 2e-4:
                continue
            kc = 1.0 / (2 * m * (m * m - 1))
            t = min(_tips(panel, "subharmonic"), key=lambda t: abs(t["kappa"] - kc))
            out.append(t["kappa"] / kc)
        return out

    cases.append(Case(
        name="fig-4.1.principal-tips", section=FIBRE,
        quantity="principal subharmonic tip kappa / kappa_c, m = 2, 3, 4, nu = 2e-4 (Fig 4.1)",
        source="inviscid resonance lambda0 = 1/2, kappa_c = 1/(2 m (m^2-1)); the Stokes layer "
               "moves the tip by a few %", source_kind="closed form",
        expected=[1.0, 1.0, 1.0], compute=fig_4_1, tolerance=0.1))

    def fig_4_2_tangential(ctx):
        tangential = ctx.figure("fig-4.2")[2]
        low = [t for kind in ("harmonic", "subharmonic")
               for t in tangential[kind]["tau_min"] if t is not None and t <= 0.5]
        return "none" if not low else f"{len(low)} points, min {min(low):.3f}"

    cases.append(Case(
        name="fig-4.2.tangential", section=FIBRE,
        quantity="marginal tau <= 1/2 with only the tangential jump pumped (Fig 4.2, right)",
        source="thesis 4.2 / Fig 4.2: no physical instability", source_kind="thesis",
        expected="none", compute=fig_4_2_tangential, tolerance=0.0))

    def lowest_unstable(panel: dict) -> str:
        modes = [(min(d[f"tau_{d['kind']}"]), d["m"], d["kind"]) for d in panel["stability"]["modes"]
                 if d["unstable"]]
        return "none" if not modes else "m = {1} {2}".format(*min(modes))

    cases.append(Case(
        name="fig-4.3.resonant-modes", section=FIBRE,
        quantity="least-threshold unstable wavenumber at tau = 0.45 in the kappa = 0.02 and 0.08 panels "
                 "of Fig 4.3 (nu = 2e-4)",
        source="thesis 4.4 / Fig 4.3: the simulated cases of Table 4.1", source_kind="thesis",
        expected="kappa 0.02: m = 3 subharmonic, kappa 0.08: m = 2 subharmonic",
        compute=lambda ctx: ", ".join(f"kappa {p['params']['kappa']:g}: {lowest_unstable(p)}"
                                      for p in ctx.figure("fig-4.3") if p["params"]["kappa"] in (0.02, 0.08)),
        tolerance=0.0))

    def fig_4_4(ctx):
        low = {p["params"]["nu"]: min(t for r in p["floquet"].values() for k in ("harmonic", "subharmonic")
                                      for t in r[k]["tau"] or [math.inf])
               for p in ctx.figure("fig-4.4")}
        nus = sorted(low)
        ok = all(low[a] < low[b] for a, b in zip(nus, nus[1:]))
        return Measured("yes" if ok else "no", "; ".join(f"nu = {nu:g}: {low[nu]:.4f}" for nu in nus))

    cases.append(Case(
        name="fig-4.4.viscosity-lifts", section=FIBRE,
        quantity="lowest marginal tau over m = 2..10 rises with nu = 5e-5, 1e-3, 5e-3 (Fig 4.4, kappa = 0.04)",
        source="thesis 4.3: viscosity raises the thresholds", source_kind="thesis",
        expected="yes", compute=fig_4_4, tolerance=0.0))
    return cases


# ------------------------------------------------------------------ chapter 6: sphere, Floquet

SPHERE = "Chapter 6: immersed spherical membrane (Floquet)"
CASE_MODES = {1: "m = 3 subharmonic", 2: "m = 2 subharmonic", 3: "m = 4 subharmonic", 4: "m = 2 harmonic"}


def sphere_cases() -> list[Case]:
    cases = [_scipy_case("sphere", "subharmonic", "mathieu_a", 1, 1.3, m=3, section=SPHERE, quick=True),
             _scipy_case("sphere", "harmonic", "mathieu_b", 2, 4.0, m=2, section=SPHERE),
             _scipy_case("sphere", "subharmonic", "mathieu_b", 3, 0.3, m=4, section=SPHERE)]
    printed = {1: (0.006, 0.02), 2: (0.002, 0.06), 3: (0.001, 0.0075), 4: (0.004, 0.25)}
    for i, name in enumerate(("nu", "kappa")):
        cases.append(Case(
            name=f"sphere.table6.1.{name}", section=SPHERE,
            quantity=f"dimensionless {name} of Table 6.1 cases 1-4 from the physical columns ((6.4), (6.5))",
            source="thesis Table 6.1 (printed columns)", source_kind="thesis",
            expected=[printed[c][i] for c in range(1, 5)],
            compute=lambda ctx, name=name: [TABLE_6_1[c].forced()[name] for c in range(1, 5)],
            tolerance=1e-12, relative=True, quick=True))
    for case, mode in CASE_MODES.items():
        cases.append(Case(
            name=f"sphere.table6.1.case{case}.mode", section=SPHERE,
            quantity=f"unstable degrees (m = 2..6) at tau = 0.45, Table 6.1 case {case}",
            source="thesis 6.4.2 (simulations of Table 6.1, Fig 6.6)", source_kind="thesis",
            expected=mode, compute=lambda ctx, c=case: _unstable("sphere", 0.45, TABLE_6_1[c].forced()),
            tolerance=0.0, quick=True))

    cases.append(Case(
        name="sphere.inviscid-rate", section=SPHERE,
        quantity="slope of log|tau_min(nu) - tau_min(0)| against log nu, m = 3, kappa = 0.02",
        source="Stokes-layer damping ~ nu^(1/2)", source_kind="closed form",
        expected=0.5, compute=lambda ctx: _inviscid_rate("sphere"), tolerance=0.05))

    def fig_6_2(ctx):
        got, want = [], []
        for panel in ctx.figure("fig-6.2"):
            unit = _unit_lambda0_squared("sphere", panel["params"]["m"])
            want += [(k / 2) ** 2 / unit for k in range(1, 40) if 0.002 < (k / 2) ** 2 / unit < 0.4]
            got += [t["kappa"] for t in _tips(panel)]
        return Measured(got, f"{len(got)} tips (expected {len(want)})")

    def fig_6_2_expected(ctx):
        want = []
        for m in (2, 3, 4):
            unit = _unit_lambda0_squared("sphere", m)
            want += [(k / 2) ** 2 / unit for k in range(1, 40) if 0.002 < (k / 2) ** 2 / unit < 0.4]
        return want

    cases.append(Case(
        name="fig-6.2.tips", section=SPHERE,
        quantity="finger tips of Fig 6.2 (inviscid, m = 2, 3, 4, kappa in [0.002, 0.4])",
        source="lambda0 = k/2 with lambda0^2 of (6.23)", source_kind="closed form",
        expected=fig_6_2_expected, compute=fig_6_2, tolerance=1e-9, relative=True))

    def fig_6_3(ctx):
        low = {}
        for panel in ctx.figure("fig-6.3"):
            tips = panel["tips"]
            low.setdefault(panel["params"]["m"], {})[panel["params"]["nu"]] = min(t["tau"] for t in tips)
        ok = all(0 < v[1e-3] < v[6e-3] for v in low.values())
        note = "; ".join(f"m = {m}: {v[1e-3]:.3f} -> {v[6e-3]:.3f}" for m, v in low.items())
        return Measured("yes" if ok else "no", note)

    cases.append(Case(
        name="fig-6.3.viscosity-lifts", section=SPHERE,
        quantity="lowest finger tip rises from nu = 1e-3 to 6e-3 for m = 2, 3, 4 (Fig 6.3)",
        source="thesis 6.3: viscosity raises the fingers off the kappa axis", source_kind="thesis",
        expected="yes", compute=fig_6_3, tolerance=0.0))

    def fig_6_6(ctx):
        out = []
        for d in ctx.figure("fig-6.6"):
            modes = [f"m = {m['m']} {m['kind']}" for m in d["stability"]["modes"] if m["unstable"]]
            out.append(f"{d['case']}: {'; '.join(modes)}")
        return ", ".join(out)

    cases.append(Case(
        name="fig-6.6.modes", section=SPHERE,
        quantity="unstable degrees at tau = 0.45 marked in Fig 6.6, cases 1-4",
        source="thesis 6.4.2 (simulated modes)", source_kind="thesis",
        expected=", ".join(f"{c}: {m}" for c, m in CASE_MODES.items()), compute=fig_6_6, tolerance=0.0))

    def fig_sphere_p2(ctx):
        data = ctx.figure("fig-sphere-p2")
        rows = [r for r in data["branches"] if r["kind"] == "subharmonic" and r["l"] == 3]
        nearest = min(abs(r["eps"]) for r in rows)
        meet = [r["tau_min"] for r in rows if abs(r["eps"]) == nearest]
        uniform = floquet("sphere", m=3, kappa=data["kappa0"], nu=data["nu"],
                          kind="subharmonic").subharmonic.tau_min
        return Measured(max(abs(t - uniform) for t in meet),
                        f"{len(meet)} branches at |eps| = {nearest:.3g}, uniform {uniform:.10g}")

    cases.append(Case(
        name="fig-sphere-p2.uniform-limit", section=SPHERE,
        quantity="non-uniform kappa0 (1 + eps P_2): the degree-3 subharmonic branches meet the "
                 "per-degree tau_min as eps -> 0 (largest distance at the eps nearest 0)",
        source="the per-degree Floquet solver at uniform kappa0", source_kind="second method",
        expected=0.0, compute=fig_sphere_p2, tolerance=1e-3))

    def fig_6_12(ctx):
        panels = ctx.figure("fig-6.12")
        kappa = np.array(panels[0]["kappa"])
        best = np.full(kappa.size, np.inf)
        for panel in panels:
            for kind in ("harmonic", "subharmonic"):
                t = np.array([np.inf if v is None else v for v in panel[kind]["tau_min"]])
                best = np.minimum(best, t)
        frac = float(np.mean(best < 0.5))
        return Measured("yes" if frac > 0.5 else "no", f"{100 * frac:.0f} % of the sigma grid has tau_min < 1/2")

    cases.append(Case(
        name="fig-6.12.most-sigma", section=SPHERE,
        quantity="instability with tau < 1/2 for most of sigma in [1e3, 2e4] dyn/cm, m = 2, 3, 4 (Fig 6.12)",
        source="thesis 6.5: instabilities for most stiffness values considered", source_kind="thesis",
        expected="yes", compute=fig_6_12, tolerance=0.0))

    def fig_6_13(ctx):
        data = ctx.figure("fig-6.13")
        bpm = np.array(data["y"])
        tau = np.array([[np.inf if v is None else v for v in row] for row in data["tau_min"]])

        def fraction(lo, hi):
            return float(np.mean(tau[(bpm >= lo) & (bpm <= hi)] < 0.3))

        healthy, svt = fraction(*CARDIAC["bpm_healthy"]), fraction(*CARDIAC["bpm_svt"])
        return Measured("yes" if svt > healthy else "no",
                        f"tau_min < 0.3 on {100 * healthy:.0f} % of the healthy box, {100 * svt:.0f} % of the SVT box")

    cases.append(Case(
        name="fig-6.13.svt-wider", section=SPHERE,
        quantity="share of the map with tau_min < 0.3: SVT (300-600 bpm) box larger than healthy (60-100 bpm)",
        source="thesis 6.5 / Fig 6.13: wider unstable valleys at 300-600 bpm", source_kind="thesis",
        expected="yes", compute=fig_6_13, tolerance=0.0))
    return cases


# ------------------------------------------------------------------ chapter 7: natural modes

MODES = "Chapter 7: natural modes of the sphere"
PRINTED_7_3_VISCOUS = (45.35, 25.42, 20.74, 27.33, 18.99, 14.76, 14.53, 9.46, 6.93)
PRINTED_7_3_INVISCID = (45.45, 25.47, 20.78, 27.38, 19.03, 14.79, 14.55, 9.48, 6.94)


def _balloon_frequency(kind: str, radius: float, viscous: bool) -> float:
    b = balloon(kind, radius)
    if viscous:
        return float(solve_natural_modes("sphere", m=2, count=1, physical={
            "rho": b.rho, "mu": b.mu, "radius": b.radius, "sigma": b.sigma}).gamma[0].imag)
    return float(solve_natural_modes("sphere", m=2, kappa=1.0, nu=0.0).gamma[0].imag) / b.time_scale


def mode_cases() -> list[Case]:
    cases = []
    for m, zeta, component, quick in [(2, 0.01, "poloidal", True), (3, 0.05, "poloidal", False),
                                      (10, 0.2, "poloidal", False), (2, 3.0, "poloidal", False),
                                      (4, 0.05, "toroidal", False)]:
        def compute(ctx, a=(m, zeta, component)):
            res = solve_natural_modes("sphere", m=a[0], zeta=a[1], component=a[2], count=1)
            return Measured(complex(res.gamma[0]), f"error estimate {res.error_estimate[0]:.1e}")

        def expected(ctx, a=(m, zeta, component)):
            seed = complex(solve_natural_modes("sphere", m=a[0], zeta=a[1], component=a[2], count=1).gamma[0])
            return mp_mode(a[0], a[1], seed, a[2])

        cases.append(Case(
            name=f"modes.mpmath.{component}.m{m}.zeta{zeta:g}", section=MODES,
            quantity=f"least-damped {component} mode gamma, m = {m}, zeta = {zeta:g}",
            source="30-digit root of det D(gamma) with mpmath's I, K (derivations/sphere_linear_result.md)",
            source_kind="mpmath", expected=expected, compute=compute, tolerance=1e-12, relative=True,
            quick=quick))
    for m, zeta, quick in [(2, 0.01, True), (3, 0.1, False)]:
        def cheb(ctx, a=(m, zeta)):
            fine, coarse = (radial_operators(m=a[0], nu=a[1], n_inner=n, n_outer=n, exterior_angle=-np.pi / 3)
                            .pencil(1.0) for n in (40, 32))
            values = least_damped(fine, coarse, count=2).values
            g = complex(solve_natural_modes("sphere", m=a[0], zeta=a[1], count=1).gamma[0])
            return complex(values[np.argmin(np.abs(values - g))])

        cases.append(Case(
            name=f"modes.chebyshev.m{m}.zeta{zeta:g}", section=MODES,
            quantity=f"least-damped poloidal mode gamma, m = {m}, zeta = {zeta:g}",
            source="radial Chebyshev collocation pencil (n = 40 vs 32, complex-scaled exterior)",
            source_kind="second method", expected=cheb,
            compute=lambda ctx, a=(m, zeta): complex(solve_natural_modes("sphere", m=a[0], zeta=a[1],
                                                                       count=1).gamma[0]),
            tolerance=1e-8, relative=True, quick=quick))
    cases.append(Case(
        name="sphere.table7.3.viscous", section=MODES,
        quantity="m = 2 frequency (1/s) of the nine balloons of Table 7.2, viscous theory",
        source="thesis Table 7.3, 'Viscous Theory' column (2 decimals)", source_kind="thesis",
        expected=list(PRINTED_7_3_VISCOUS),
        compute=lambda ctx: [_balloon_frequency(k, r, True) for k, r, _ in BALLOONS],
        tolerance=0.005, quick=True))
    cases.append(Case(
        name="sphere.table7.3.inviscid", section=MODES,
        quantity="m = 2 frequency (1/s) of the nine balloons of Table 7.2, inviscid theory",
        source="thesis Table 7.3, 'Inviscid Theory' column (2 decimals)", source_kind="thesis",
        expected=list(PRINTED_7_3_INVISCID),
        compute=lambda ctx: [_balloon_frequency(k, r, False) for k, r, _ in BALLOONS],
        tolerance=0.005, quick=True))

    def small_zeta(ctx):
        data = ctx.figure("fig-7.1")
        modes = [data["modes"][str(m)][0][0] for m in (2, 3, 4)]
        return Measured([complex(g["gamma_re"], g["gamma_im"]) for g in modes], f"zeta = {data['zeta'][0]:g}")

    def stokes_layer(ctx):
        zeta = ctx.figure("fig-7.1")["zeta"][0]
        out = []
        for m in (2, 3, 4):  # i lambda0 - c_m sqrt(i lambda0 zeta), c_m = (2m^2+2m+1)/(2(2m+1))
            lam = math.sqrt(_unit_lambda0_squared("sphere", m))
            out.append(1j * lam - (2 * m * m + 2 * m + 1) / (2 * (2 * m + 1)) * np.sqrt(1j * lam * zeta))
        return out

    cases.append(Case(
        name="fig-7.1.inviscid-end", section=MODES,
        quantity="least-damped mode gamma at the smallest zeta of Fig 7.1 (1e-3), m = 2, 3, 4",
        source="Lamb frequency (7.4) with the Stokes-layer correction i lambda0 - c_m sqrt(i lambda0 zeta) "
               "(large-beta Bessel ratios; remainder O(zeta))", source_kind="closed form",
        expected=stokes_layer, compute=small_zeta, tolerance=2e-3, relative=True))

    def stokes(ctx):
        modes = ctx.figure("fig-7.1")["modes"]
        return [modes[str(m)][-1][0]["gamma_re"] for m in (2, 3, 4)]

    def stokes_expected(ctx):
        out = []
        for m in (2, 3, 4):  # det(q I + nu s R0) = 0, R0 the steady-Stokes load (result file 3)
            R0 = np.array([[m * (2 * m - 1) / (m + 1) + (m + 1) * (2 * m + 3) / m, -3 * (2 * m + 1)],
                           [-3 * (2 * m + 1) / (m * (m + 1)), 2 * (2 * m + 1)]])
            out.append(-(m - 1) * (m + 2) / (10.0 * np.linalg.eigvals(R0).real.max()))
        return out

    cases.append(Case(
        name="fig-7.1.stokes-end", section=MODES,
        quantity="decay rate of the least-damped mode at zeta = 10, m = 2, 3, 4 (Fig 7.1)",
        source="steady-Stokes relaxation -q/(nu mu_max), mu = eig R0 (relative O(zeta^-2))",
        source_kind="closed form", expected=stokes_expected, compute=stokes, tolerance=5e-3, relative=True))
    return cases


# ------------------------------------------------------------------ chapter 5: cochlea

COCHLEA = "Chapter 5: basilar membrane in the box cochlea"


def cochlea_cases() -> list[Case]:
    """Single cosine mode k of the uniform membrane (alpha = 0) is the Mathieu equation with
    lambda0^2 = kappa k / 2 in the inviscid limit (models/cochlea.py); figure claims of 5.4-5.6."""
    from ..params.physical import TABLE_5_1

    cases = []
    for fn, order, q, k, kind, quick in [("mathieu_a", 1, 1.3, 2, "subharmonic", True),
                                         ("mathieu_b", 2, 0.3, 5, "harmonic", False)]:
        def compute(ctx, a=(fn, order, q, k, kind)):
            char = getattr(special, a[0])(a[1], a[2])
            return _tau_near("cochlea", a[4], a[2] / char, kappa=char / (4 * a[3] / 2), nu=0.0, alpha=0.0,
                             spatial_mode=a[3])

        cases.append(Case(
            name=f"cochlea.inviscid.scipy.k{k}", section=COCHLEA,
            quantity=f"undamped {kind} tau of cosine mode k = {k} (alpha = 0) at lambda0^2 = kappa k/2 = "
                     f"{fn[-1]}_{order}(q)/4, q = {q:g}",
            source=f"scipy.special.{fn}({order}, {q:g}) (DLMF 28.2.1)", source_kind="scipy oracle",
            expected=lambda ctx, a=(fn, order, q): a[2] / getattr(special, a[0])(a[1], a[2]),
            compute=compute, tolerance=1e-10, quick=quick))

    def convergence_in_n(ctx):
        data = ctx.figure("fig-5.5")
        return Measured(max(data["error_in_N"][k][-1] for k in ("harmonic", "subharmonic")),
                        f"N = {data['N'][-1]} -> {2 * data['N'][-1]}, M = 64")

    cases.append(Case(
        name="fig-5.5.converged-in-N", section=COCHLEA,
        quantity="|tau_min(2N) - tau_min(N)| at the largest N of Fig 5.5 (omega = 1600 rad/s)",
        source="spectral convergence in the temporal truncation (Fig 5.5)", source_kind="refinement",
        expected=0.0, compute=convergence_in_n, tolerance=1e-12))

    def convergence_in_m(ctx):
        data = ctx.figure("fig-5.5")
        return Measured(max(data["error_in_M"][k][-1] for k in ("harmonic", "subharmonic")),
                        f"M = {data['M'][-1]} -> {2 * data['M'][-1]}, N = 20")

    cases.append(Case(
        name="fig-5.6.converged-in-M", section=COCHLEA,
        quantity="|tau_min(2M) - tau_min(M)| at the largest M of Figs 5.5-5.6 (omega = 1600 rad/s)",
        source="convergence in the number of spatial modes (Fig 5.6); tolerance = the default tol_spatial",
        source_kind="refinement", expected=0.0, compute=convergence_in_m, tolerance=1e-3))

    def modes_decay(ctx):
        data = ctx.figure("fig-5.7")
        worst = max(m["gamma_re"] for d in data.values() for m in d["modes"])
        return Measured("yes" if worst < 0 else "no", f"largest Re gamma {worst:.3g}")

    cases.append(Case(
        name="fig-5.7.modes-decay", section=COCHLEA,
        quantity="every natural mode of Fig 5.7 decays (Re gamma < 0), zeta = 2e-5 and 1e-2",
        source="thesis 5.4 / Fig 5.7: the unforced membrane is stable", source_kind="thesis",
        expected="yes", compute=modes_decay, tolerance=0.0))

    def tonotopy(ctx):
        rows = [(p["omega"], {r["kind"]: r["peak_x"] for r in p["responses"]}) for p in ctx.figure("fig-5.8")]
        ok = all(r["harmonic"] < r["subharmonic"] for _, r in rows)
        return Measured("yes" if ok else "no", "; ".join(
            f"omega {w:g}: {r['harmonic']:.2f} < {r['subharmonic']:.2f} cm" for w, r in rows))

    cases.append(Case(
        name="fig-5.8.place-order", section=COCHLEA,
        quantity="harmonic envelope (response at omega) peaks nearer the base than the subharmonic one "
                 "(omega/2), omega = 400..1600 (Fig 5.8)",
        source="thesis 5.4: the place of the peak falls with frequency (von Bekesy)", source_kind="thesis",
        expected="yes", compute=tonotopy, tolerance=0.0))

    def log_linear(ctx):
        data = ctx.figure("fig-5.9")["harmonic"]
        f, p = np.log(data["response_frequency"]), np.array(data["peak_cm"])
        r = p - np.polyval(np.polyfit(f, p, 1), f)
        r2 = 1 - float(np.sum(r * r) / np.sum((p - p.mean()) ** 2))
        return Measured("yes" if r2 >= 0.99 else "no", f"R^2 = {r2:.4f} of the fit peak ~ log(frequency)")

    cases.append(Case(
        name="fig-5.9.log-place-map", section=COCHLEA,
        quantity="harmonic peak location linear in log(frequency), R^2 >= 0.99 (Fig 5.9)",
        source="thesis 5.4: peaks on a straight line against log frequency", source_kind="thesis",
        expected="yes", compute=log_linear, tolerance=0.0))

    def principal_dip(ctx):
        data = ctx.figure("fig-5.12")
        omega = np.array(data["omega"])
        sub = np.array([r["subharmonic"]["tau_min"] or np.inf for r in data["modes"]["1"]])
        return float(omega[np.argmin(sub)])

    cases.append(Case(
        name="fig-5.12.principal-dip", section=COCHLEA,
        quantity="omega (rad/s) of the lowest subharmonic tau of mode k = 1, alpha = 0 (Fig 5.12; grid 10 rad/s)",
        source="inviscid resonance lambda0 = 1/2 of mode 1: omega = sqrt(2 sigma pi/(rho L)) (Table 5.1)",
        source_kind="closed form",
        expected=math.sqrt(2 * TABLE_5_1["sigma"] * math.pi / (TABLE_5_1["rho"] * TABLE_5_1["length"])),
        compute=principal_dip, tolerance=20.0))

    def principal_tip(ctx):
        worst, notes = 0.0, []
        for omega, panel in ctx.figure("fig-5.11").items():
            tip = panel["tips"][0]
            k, tau = two_harmonic_tip(panel["kappa"], panel["nu"])
            if tip["kind"] != "subharmonic":
                return Measured(math.inf, f"omega {float(omega):g}: first tip is {tip['kind']}")
            worst = max(worst, abs(tip["k"] / k - 1), abs(tip["tau"] / tau - 1))
            notes.append(f"omega {float(omega):g}: k {tip['k']:.7f} vs {k:.7f}, "
                         f"tau {tip['tau']:.4e} vs {tau:.4e}")
        return Measured(worst, "; ".join(notes))

    cases.append(Case(
        name="fig-5.11.principal-tip", section=COCHLEA,
        quantity="tip (k, tau) of the principal subharmonic finger of Fig 5.11 (omega = 500, 1000 "
                 "rad/s): largest relative deviation in k or tau",
        source="two-harmonic balance of (5.9), written out (two_harmonic_tip); the neglected "
               "harmonics account for ~tau^2/8 <= 2e-6", source_kind="closed form",
        expected=0.0, compute=principal_tip, tolerance=1e-5))

    def mostly_resonant(ctx):
        panels = ctx.figure("fig-5.18")["panels"]
        share = {name: float(np.mean([t is not None for row in p["tau_min"] for t in row]))
                 for name, p in panels.items()}
        return Measured("yes" if min(share.values()) >= 0.9 else "no", ", ".join(
            f"{name}: tau_min < 1/2 in {100 * v:.0f} % of the cells" for name, v in share.items()))

    cases.append(Case(
        name="fig-5.18.mostly-resonant", section=COCHLEA,
        quantity="parametric resonance (a marginal tau < 1/2 of either kind) in >= 90 % of the cells "
                 "of both Fig 5.18 panels (human, gerbil)",
        source="thesis 5.6.2: resonance possible for nearly all parameter values, human and gerbil",
        source_kind="thesis", expected="yes", compute=mostly_resonant, tolerance=0.0))

    def human_corner(ctx):
        p = ctx.figure("fig-5.18")["panels"]["human"]
        f, sigma = np.array(p["frequency_hz"]), np.array(p["sigma"])
        cells = [(f[i], sigma[j]) for i, row in enumerate(p["tau_min"])
                 for j, t in enumerate(row) if t is None]
        ok = bool(cells) and all(fi == f.max() and sj < np.median(sigma) for fi, sj in cells)
        return Measured("yes" if ok else "no", "no tau <= 1/2 at " + (", ".join(
            f"f = {fi:g} Hz, sigma = {sj:.3g}" for fi, sj in cells) or "no cell"))

    cases.append(Case(
        name="fig-5.18.human-corner", section=COCHLEA,
        quantity="the human cells of Fig 5.18 without resonance (no tau <= 1/2) exist and lie at the "
                 "highest frequency and in the lower half of sigma",
        source="thesis 5.6.2 / Fig 5.18: non-resonant only at the highest frequencies and lowest "
               "sigma (white lower-right corner)", source_kind="thesis", expected="yes",
        compute=human_corner, tolerance=0.0))

    def critical_tau(ctx):
        rows = ctx.figure("fig-5.14")["n_spatial"]
        key = max(rows, key=int)
        low = [min([t for t in (r["harmonic"]["tau_min"], r["subharmonic"]["tau_min"]) if t is not None]
                   or [math.inf]) for r in rows[key]]
        ok = all(0 < t < 0.5 for t in low)
        return Measured("yes" if ok else "no", f"M = {key}: tau_o in [{min(low):.3f}, {max(low):.3f}]")

    cases.append(Case(
        name="fig-5.14.critical-tau", section=COCHLEA,
        quantity="a critical tau_o in (0, 1/2) at every omega of Fig 5.14 (graded stiffness, largest M)",
        source="thesis 5.6: resonance for tau_o < tau < 1/2 at each forcing frequency", source_kind="thesis",
        expected="yes", compute=critical_tau, tolerance=0.0))
    return cases


# ------------------------------------------------------------------ 7.3: nonlinear coefficients

STEPPER = "Chapter 6: time stepper against Floquet (sphere)"
#: (m, kappa, nu, t_end, quick) of the cross-checks: the quick set steps the shorter time.
STEPPER_POINTS = ((2, 0.06, 0.002, 60.0, True), (2, 0.06, 0.002, 160.0, False),
                  (3, 0.02, 0.006, 160.0, False))
#: tau / tau_min of the three runs of a point: below, at and above the boundary.
STEPPER_FACTORS = {"below": 0.9, "at": 1.0, "above": 1.1}


def _stepped_rate(m: int, kappa: float, nu: float, t_end: float, factor: float):
    """Fitted growth rate of the (m, 0) mode stepped by ``simulate`` at tau = factor x the
    subharmonic tau_min of the Floquet solver, with its fit (error estimate, frequency)."""
    tau_min = floquet("sphere", m=m, kappa=kappa, nu=nu, kind="subharmonic").subharmonic.tau_min
    scene = {"params": {"kappa": kappa, "nu": nu, "tau": factor * tau_min},
             "initial": {"shape": f"{m}:0"}, "simulate": {"t_end": t_end}}
    (fit,) = simulate(scene).fits
    return tau_min, fit


def stepper_cases() -> list[Case]:
    """The time stepper (``simulate``: radial Chebyshev, IMEX) against the Floquet solver (Hill
    determinant, exact Bessel D(s)): at the Floquet tau_min the stepped mode neither grows nor
    decays (growth rate 0 within the fit's error), 10 % below it decays, 10 % above it grows,
    at the period-doubling frequency 1/2 of a subharmonic boundary."""
    cases = []
    for m, kappa, nu, t_end, quick in STEPPER_POINTS:
        label = f"stepper.m{m}.k{kappa:g}.nu{nu:g}" + (".quick" if quick else "")
        where = f"m = {m}, kappa = {kappa:g}, nu = {nu:g}, t_end = {t_end:g}"

        def at(ctx, m=m, kappa=kappa, nu=nu, t_end=t_end):
            tau_min, fit = _stepped_rate(m, kappa, nu, t_end, 1.0)
            return Measured(fit.growth_rate, f"tau_min = {tau_min:.10g}; fit error "
                                             f"{fit.error_estimate:.1e}, frequency "
                                             f"{fit.frequency:g}")

        cases.append(Case(
            name=f"{label}.at_tau_min", section=STEPPER,
            quantity=f"growth rate of the stepped (m, 0) mode at the Floquet tau_min ({where})",
            source="Floquet theory: Re gamma = 0 on the marginal curve tau_min (Hill solver)",
            source_kind="second method", expected=0.0, compute=at, tolerance=5e-6, quick=quick))
        for side, factor in STEPPER_FACTORS.items():
            if side == "at":
                continue

            def sign(ctx, m=m, kappa=kappa, nu=nu, t_end=t_end, factor=factor):
                tau_min, fit = _stepped_rate(m, kappa, nu, t_end, factor)
                grows = "grows" if fit.growth_rate > fit.error_estimate else \
                    "decays" if fit.growth_rate < -fit.error_estimate else "undecided"
                period = "period doubling" if abs(fit.frequency - 0.5) < 1e-6 else \
                    f"frequency {fit.frequency:g}"
                return Measured(f"{grows}, {period}", f"rate {fit.growth_rate:.3e} +- "
                                                      f"{fit.error_estimate:.1e}")

            cases.append(Case(
                name=f"{label}.{side}", section=STEPPER,
                quantity=f"the stepped mode at tau = {factor:g} tau_min ({where})",
                source="Floquet theory: stable below the marginal curve, unstable above it",
                source_kind="second method",
                expected=f"{'decays' if side == 'below' else 'grows'}, period doubling",
                compute=sign, tolerance=0.0, quick=quick))
    return cases


NONLINEAR = "Chapter 7.3: nonlinear frequency coefficients (inviscid, radial-only membrane)"
EXACT_C = {(2, 0): (-81161, 122304), (3, 0): (-56307454453, 38760733440),
           (4, 0): (-767309533458687, 306666814854400), (3, 3): (-226595867423, 124034347008)}


def nonlinear_cases() -> list[Case]:
    cases = []
    for (m, k), (num, den) in EXACT_C.items():
        def direct(ctx, m=m, k=k):
            check = lp_summary(m, k, check=True)["check"]
            return Measured(check["slope"], f"fit uncertainty {check['uncertainty']:.1e}")

        cases.append(Case(
            name=f"lp.c{m}{'' if k == 0 else k}.direct", section=NONLINEAR,
            quantity=f"c_{{{m},{k}}} in lambda = lambda0 (1 + c eps^2), from Newton on the periodic orbit",
            source=f"exact Lindstedt-Poincare: {num}/({den} pi) (derivations/lindstedt_sphere.py)",
            source_kind="closed form", expected=float(mpmath.mpf(num) / (den * mpmath.pi)),
            compute=direct, tolerance=1e-6, relative=True, quick=(m, k) == (2, 0)))
    return cases


#: The registry: each entry returns the cases of one section, in report order.
SECTIONS: tuple[Callable[[], list[Case]], ...] = (mathieu_cases, fibre_cases, cochlea_cases, sphere_cases,
                                                   stepper_cases, mode_cases, nonlinear_cases)


def all_cases(*, quick: bool = False) -> list[Case]:
    """Every registered case (only the quick ones with ``quick``); names are unique."""
    cases = [c for build in SECTIONS for c in build()]
    names = [c.name for c in cases]
    duplicates = sorted({n for n in names if names.count(n) > 1})
    if duplicates:
        raise ValueError(f"duplicate validation case names: {duplicates}")
    return [c for c in cases if c.quick or not quick]


# ------------------------------------------------------------------ runner


def _error(expected: Any, computed: Any, relative: bool) -> float:
    """Largest |computed - expected| (relative to |expected| with ``relative``); inf on a mismatch
    of discrete values or of lengths, or a non-finite value."""
    if isinstance(expected, str) or isinstance(computed, str):
        return 0.0 if expected == computed else math.inf
    if isinstance(expected, (list, tuple)) or isinstance(computed, (list, tuple)):
        if not (isinstance(expected, (list, tuple)) and isinstance(computed, (list, tuple))) \
                or len(expected) != len(computed):
            return math.inf
        return max((_error(e, c, relative) for e, c in zip(expected, computed)), default=0.0)
    if computed is None or expected is None:
        return 0.0 if computed is expected else math.inf
    diff = abs(complex(computed) - complex(expected))
    if relative:
        diff /= abs(complex(expected)) or 1.0
    return diff if math.isfinite(diff) else math.inf


def evaluate(case: Case, ctx: Context) -> Outcome:
    """Run one case; an exception is a failure whose message is kept."""
    t0 = time.perf_counter()
    ctx.current = case.name
    try:
        expected = case.expected(ctx) if callable(case.expected) else case.expected
        got = case.compute(ctx)
        note = ""
        if isinstance(got, Measured):
            got, note = got.value, got.note
        error = _error(expected, got, case.relative)
        return Outcome(case=case, expected=expected, computed=got, error=error,
                       passed=error <= case.tolerance, seconds=time.perf_counter() - t0, note=note)
    except Exception as exc:  # noqa: BLE001 - any failure of a case is reported, not raised
        return Outcome(case=case, expected=None, computed=None, error=math.inf, passed=False,
                       seconds=time.perf_counter() - t0, message=f"{type(exc).__name__}: {exc}")
    finally:
        ctx.current = None


@dataclass(frozen=True, kw_only=True)
class Report:
    """Outcomes of a run, the findings with their live evidence, and what was written."""

    outcomes: tuple[Outcome, ...]
    findings: tuple[tuple[Finding, str], ...]
    figures: dict[str, list[Path]]
    quick: bool
    seconds: float
    checked_by: dict[str, list[str]] = field(default_factory=dict)
    figure_errors: dict[str, str] = field(default_factory=dict)
    files: tuple[Path, ...] = field(default=())

    @property
    def passed(self) -> bool:
        return all(o.passed for o in self.outcomes) and not self.figure_errors

    @property
    def failures(self) -> list[Outcome]:
        return [o for o in self.outcomes if not o.passed]


def _live(finding: Finding) -> str:
    if finding.live is None:
        return ""
    try:
        return finding.live()
    except Exception as exc:  # noqa: BLE001 - reported in the text
        return f"recomputation failed: {type(exc).__name__}: {exc}"


def run(out: str | Path, *, quick: bool = False, cases: Sequence[Case] | None = None,
        workers: int | None = None, progress: Callable[[Outcome], None] | None = None) -> Report:
    """Run the cases (default: :func:`all_cases`), write report.md, report.json and PNGs into ``out``.

    Without ``quick`` (and with the default cases) every figure of
    :data:`spectralshell.reports.figures.FIGURES` is reproduced, also those no case checks.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    ctx = Context(out, workers)
    t0 = time.perf_counter()
    outcomes = []
    for case in all_cases(quick=quick) if cases is None else cases:
        outcome = evaluate(case, ctx)
        outcomes.append(outcome)
        if progress is not None:
            progress(outcome)
    figure_errors = {}
    if not quick and cases is None:
        for name in FIGURES:
            try:
                ctx.figure(name)
            except Exception as exc:  # noqa: BLE001 - reported as a failure of the report
                figure_errors[name] = f"{type(exc).__name__}: {exc}"
    findings = tuple((f, _live(f)) for f in FINDINGS)
    report = Report(outcomes=tuple(outcomes), findings=findings, figures=dict(ctx.figures), quick=quick,
                    seconds=time.perf_counter() - t0, checked_by=dict(ctx.checked_by),
                    figure_errors=figure_errors)
    files = write(report, out)
    return dataclasses.replace(report, files=tuple(files))


# ------------------------------------------------------------------ writing


def _fmt(value: Any) -> str:
    if value is None:
        return "-"
    if isinstance(value, str):
        return value
    if isinstance(value, (list, tuple)):
        shown = ", ".join(_fmt(v) for v in value[:6])
        return f"[{shown}{', ...' if len(value) > 6 else ''}]"
    if isinstance(value, complex):
        return f"{value.real:.12g} {'+' if value.imag >= 0 else '-'} {abs(value.imag):.12g}i"
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    return f"{float(value):.12g}"


def _fmt_error(o: Outcome) -> str:
    if o.message:
        return "failed"
    if math.isinf(o.error):
        return "mismatch"
    if o.case.tolerance == 0.0:
        return "match"
    return f"{o.error:.1e}"


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def _table(outcomes: Sequence[Outcome]) -> list[str]:
    lines = ["| case | quantity | source | expected | computed | error | tolerance | result |",
             "|---|---|---|---|---|---|---|---|"]
    for o in outcomes:
        c = o.case
        tol = "exact" if c.tolerance == 0 else f"{c.tolerance:.0e}{' rel' if c.relative else ''}"
        computed = _fmt(o.computed) + (f" ({o.note})" if o.note else "")
        if o.message:
            computed = o.message
        lines.append("| " + " | ".join(_cell(x) for x in (
            f"`{c.name}`", c.quantity, f"{c.source_kind}: {c.source}", _fmt(o.expected), computed,
            _fmt_error(o), tol, "pass" if o.passed else "**FAIL**")) + " |")
    return lines


def _findings(report: Report) -> list[str]:
    by_name = {o.case.name: o for o in report.outcomes}
    heads = {"misprint": "### Confirmed misprints",
             "claim": "### Thesis claims that do not hold at converged truncation",
             "open": "### Suspected errata not decided yet"}
    lines = ["## Where the thesis is wrong", "",
             "Each item was decided by re-derivation and independent numerical evidence (scripts and "
             "tests named), never by the thesis's own algebra. Supporting validation cases of this run "
             "are listed with their result.", ""]
    for kind, head in heads.items():
        items = [(f, live) for f, live in report.findings if f.kind == kind]
        if not items:
            continue
        lines += [head, ""]
        for f, live in items:
            lines.append(f"- **{f.where}.** Thesis: {f.thesis}. Holds: {f.holds}.")
            lines.append(f"  - Evidence: {f.evidence}.")
            if f.decided_by:
                lines.append(f"  - Decided by: {', '.join(f'`{d}`' for d in f.decided_by)}.")
            if f.cases:
                ran = [(n, by_name.get(n)) for n in f.cases]
                text = ", ".join(f"`{n}` ({'not run' if o is None else 'pass' if o.passed else 'FAIL'})"
                                 for n, o in ran)
                lines.append(f"  - Supporting cases: {text}.")
            if live:
                lines.append(f"  - Recomputed now: {live}.")
        lines.append("")
    return lines


def markdown(report: Report, chart: str | None) -> str:
    """The text of report.md."""
    n, failed = len(report.outcomes), len(report.failures)
    kinds = {k: sum(o.case.source_kind == k for o in report.outcomes) for k in SOURCE_KINDS}
    lines = [f"# spectralshell validation report ({'quick' if report.quick else 'full'})", "",
             f"spectralshell {__version__}, {libraries_line()}, "
             f"{datetime.now(timezone.utc).strftime('%Y-%m-%d %H:%M UTC')}, {report.seconds:.1f} s.", "",
             f"**{n - failed} of {n} cases pass**" + (f", **{failed} fail**." if failed else "."), "",
             "Sources: " + ", ".join(f"{k} {v}" for k, v in kinds.items() if v) + ". "
             "Errors are absolute unless the tolerance says 'rel'; 'exact' compares discrete outcomes.", ""]
    if report.quick:
        lines += ["Quick set: a few cases per model. `spectralshell validate` without `--quick` runs every "
                  "case and reproduces the thesis figures.", ""]
    if chart:
        lines += [f"![error / tolerance of every case]({chart})", ""]
    if failed or report.figure_errors:
        lines += ["## Failures", ""] + [f"- `{o.case.name}`: {o.message or _fmt_error(o)}"
                                          for o in report.failures]
        lines += [f"- figure {name}: {msg}" for name, msg in report.figure_errors.items()] + [""]
    for section in dict.fromkeys(o.case.section for o in report.outcomes):
        lines += [f"## {section}", ""] + _table([o for o in report.outcomes if o.case.section == section]) + [""]
    if report.figures:
        lines += ["## Reproduced thesis figures", "",
                  "PNG and data (JSON) in `figures/`; `spectralshell figure NAME` makes one alone.", ""]
        for name, paths in report.figures.items():
            png = next((p for p in paths if p.suffix == ".png"), None)
            checks = report.checked_by.get(name, [])
            title = FIGURES[name][0] if name in FIGURES else name
            lines += [f"### {name}: {title}", "",
                      "Checked by " + (", ".join(f"`{c}`" for c in checks) if checks else
                                       "no case (reproduced only)") + ".", ""]
            if png is not None:
                lines += [f"![{name}](figures/{png.name})", ""]
    return "\n".join(lines + _findings(report)) + "\n"


def _atomic_text(path: Path, text: str) -> None:
    tmp = path.with_name(f".partial-{path.name}")
    tmp.write_text(text)
    os.replace(tmp, path)


#: The style of report.html (self-contained: no external sheet).
HTML_STYLE = """body { font-family: sans-serif; max-width: 72em; margin: 2em auto; padding: 0 1em;
  line-height: 1.4; color: #222; }
table { border-collapse: collapse; font-size: 85%; margin: 1em 0; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.5em; vertical-align: top; }
th { background: #f0f0f0; }
img { max-width: 100%; }
code { background: #f4f4f4; padding: 0 0.2em; }"""


def html(text: str, base: Path) -> str:
    """report.md's ``text`` as one self-contained HTML page: every image (a path relative to
    ``base``) embedded as a base64 PNG data URI, the style inline."""
    import base64
    import html as escape

    from markdown_it import MarkdownIt

    md = MarkdownIt("commonmark").enable("table")
    tokens = md.parse(text)
    for token in tokens:
        for child in token.children or ():
            if child.type == "image":
                png = (base / str(child.attrs["src"])).read_bytes()
                child.attrs["src"] = "data:image/png;base64," + base64.b64encode(png).decode()
    title = text.splitlines()[0].lstrip("# ")
    return (f"<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            f"<title>{escape.escape(title)}</title>\n<style>\n{HTML_STYLE}\n</style>\n</head>\n"
            f"<body>\n{md.renderer.render(tokens, md.options, {})}</body>\n</html>\n")


def write(report: Report, out: Path) -> list[Path]:
    """report.md, report.html (the same, self-contained: figures embedded), report.json and
    errors.png (error / tolerance of every case) into ``out``."""
    from ..plots import validation_chart

    chart = validation_chart.save_errors(
        [(o.case.name, o.error, o.case.tolerance, o.passed) for o in report.outcomes], out / "errors.png")
    data = {"version": __version__, "libraries": libraries(), "quick": report.quick, "seconds": report.seconds,
            "passed": report.passed, "figure_errors": report.figure_errors,
            "figures": {name: report.checked_by.get(name, []) for name in report.figures},
            "cases": [{"name": o.case.name, "section": o.case.section, "quantity": o.case.quantity,
                       "source": o.case.source, "source_kind": o.case.source_kind,
                       "expected": _fmt(o.expected), "computed": _fmt(o.computed),
                       "error": None if math.isinf(o.error) else o.error,
                       "tolerance": o.case.tolerance, "relative": o.case.relative,
                       "passed": o.passed, "seconds": o.seconds, "note": o.note, "message": o.message}
                      for o in report.outcomes]}
    _atomic_text(out / "report.json", json.dumps(data, indent=1))
    text = markdown(report, chart.name)
    _atomic_text(out / "report.md", text)
    _atomic_text(out / "report.html", html(text, out))
    return [out / "report.md", out / "report.html", out / "report.json", chart]
