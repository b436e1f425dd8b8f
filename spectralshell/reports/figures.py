"""Figure registry: each thesis figure the package reproduces, by name (``spectralshell figure``).

Every figure writes a PNG (labelled axes, units) and the data behind it as JSON (maps also NPZ).
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

import numpy as np

from ..runner.floquet import floquet, stability, tau_map as solve_tau_map, tongues
from ..runner.modes import natural_modes as solve_natural_modes
from ..runner.response import response
from ..runner.nonuniform import p2_branches
from ..runner.progress import tracked
from ..params.physical import CARDIAC, TABLE_6_1, PhysicalSphere, bpm_to_rad_per_s
from ..models.sphere import lambda0_squared
from ..plots import degree_stability, ince_strutt, natural_modes, nonuniform, tau_map
from ..results.maps import map_dict, minimum_map, unstable_at, write_npz


def _write_json(path: Path, data) -> Path:
    path.write_text(json.dumps(data, allow_nan=False))
    return path


def _diagrams(name: str, out: Path, cases: list[dict], *, kappa: str, columns: int,
              model: str = "mathieu", progress: bool, workers: int | None, **draw) -> list[Path]:
    results = [tongues(model, kappa=kappa, progress=progress, workers=workers, tau_max=1.0,
                           **case) for case in cases]  # the panels show tau <= 1
    png = ince_strutt.save(results, out / f"{name}.png", columns=columns, **draw)
    return [png, _write_json(out / f"{name}.json", [r.to_dict() for r in results])]


def _sphere_grid(name: str, nus: tuple[float, ...], out: Path, **kw) -> list[Path]:
    """Figs 6.2/6.3: rows m = 2, 3, 4, one column per nu (nu = 0: the inviscid Mathieu limit)."""
    cases = [{"m": m, "nu": nu} for m in (2, 3, 4) for nu in nus]
    return _diagrams(name, out, cases, kappa="0.002:0.4:300", columns=len(nus), model="sphere", **kw)


def _table_6_1_degrees(out: Path, *, progress: bool, workers: int | None) -> list[Path]:
    """Fig 6.6: marginal tau at each integer degree m = 2..8 for the cases of Table 6.1, with the
    degrees unstable at tau = 0.45 (the simulations' amplitude) highlighted."""
    panels, data = [], []
    for case, phys in TABLE_6_1.items():
        dimless = phys.forced()
        by_degree = {m: floquet("sphere", m=m, **dimless)
                     for m in tracked(range(2, 9), f"fig-6.6 case {case}", "m", progress)}
        stab = stability("sphere", tau=0.45, m="2:8", **dimless)
        title = f"case {case}: ν = {dimless['nu']:g}, κ = {dimless['kappa']:g}"
        panels.append((title, by_degree, stab))
        data.append({"case": case, "params": dimless, "stability": stab.to_dict(),
                     "floquet": {m: r.to_dict() for m, r in by_degree.items()}})
    png = degree_stability.save(panels, out / "fig-6.6.png")
    return [png, _write_json(out / "fig-6.6.json", data)]


def _cardiac_atrium(bpm: float, sigma: float = 1.0) -> PhysicalSphere:
    return PhysicalSphere(rho=CARDIAC["rho"], mu=CARDIAC["mu"], radius=CARDIAC["radius"],
                          sigma=sigma, omega=bpm_to_rad_per_s(bpm))


def _cardiac_fingers(out: Path, **kw) -> list[Path]:
    """Fig 6.12: fingers against sigma (dyn/cm) for an atrium at 400 bpm (nu = 2.39e-4)."""
    unit = _cardiac_atrium(CARDIAC["bpm_typical_svt"]).forced()  # kappa per dyn/cm
    lo, hi = (s * unit["kappa"] for s in CARDIAC["sigma_range"])
    cases = [{"m": m, "nu": unit["nu"]} for m in (2, 3, 4)]
    return _diagrams("fig-6.12", out, cases, kappa=f"{lo!r}:{hi!r}:300", columns=1,
                     model="sphere", x_scale=1.0 / unit["kappa"],
                     x_label="σ, membrane stiffness (dyn/cm)", **kw)


def _cardiac_map(out: Path, *, progress: bool, workers: int | None, size: int = 48) -> list[Path]:
    """Fig 6.13: minimum tau over m = 2..6 against stiffness and beat rate, an atrium."""
    sigma = CARDIAC["sigma_range"]
    res = solve_tau_map("sphere", x=("sigma", f"{sigma[0]}:{sigma[1]}:{size}"),
                      y=("bpm", f"50:650:{size}"), m="2:6", progress=progress, workers=workers,
                      physical={k: CARDIAC[k] for k in ("rho", "mu", "radius")})
    boxes = [(sigma, CARDIAC["bpm_healthy"], "healthy heart", "tab:blue"),
             (sigma, CARDIAC["bpm_svt"], "SVT", "tab:red")]
    png = tau_map.save(res, out / "fig-6.13.png", boxes=boxes)
    smallest = minimum_map(res, "sigma", "bpm")
    return [png, _write_json(out / "fig-6.13.json", map_dict(smallest)),
            write_npz(smallest, out / "fig-6.13.npz")]


#: The cylinder figure: nu, the kappa of its unstable-pairs panel and the amplitude there.
CYLINDER = {"nu": 2e-4, "kappa": 0.02, "tau": 0.45}


def _cylinder_map(out: Path, *, progress: bool, workers: int | None, size: int = 40) -> list[Path]:
    """The periodic cylinder (issue 30, thesis 8.1): minimum tau <= 1/2 over m = 1..6 and both
    kinds against the axial wavenumber k R and kappa at nu = 2e-4, the critical (m, kind)
    labelled; beside it, which (m, k R) are unstable at tau = 0.45 on the map's kappa nearest
    0.02 (``CYLINDER``)."""
    res = solve_tau_map("cylinder", x=("k", f"0.05:3:{size}"), y=("kappa", f"0.005:0.3:{size}"),
                        m="1:6", nu=CYLINDER["nu"], tau_max=0.5, progress=progress,
                        workers=workers)
    kappa = float(res["kappa"].values[np.argmin(np.abs(res["kappa"].values - CYLINDER["kappa"]))])
    png = tau_map.save_with_pairs(res, out / "fig-cylinder.png", x="k", at={"kappa": kappa},
                                  tau=CYLINDER["tau"])
    smallest = minimum_map(res, "k", "kappa")
    pairs = unstable_at(res, "k", {"kappa": kappa}, CYLINDER["tau"])
    unstable = {kind: pairs.sel(kind=kind).values.tolist() for kind in KINDS}
    data = {**map_dict(smallest), "unstable_at": {"kappa": kappa, "tau": CYLINDER["tau"],
                                                  "m": res["m"].values.tolist(),
                                                  "k": res["k"].values.tolist(), **unstable}}
    return [png, _write_json(out / "fig-cylinder.json", data),
            write_npz(smallest, out / "fig-cylinder.npz")]


def _natural_modes_against_zeta(out: Path, *, progress: bool, workers: int | None) -> list[Path]:
    """Fig 7.1: least-damped mode (decay rate, frequency) of m = 2, 3, 4 for zeta in [1e-3, 10]."""
    zeta = np.logspace(-3, 1, 161)
    by_degree = {m: [solve_natural_modes("sphere", m=m, zeta=z)
                     for z in tracked(zeta, f"fig-7.1 m = {m}", "ζ", progress)]
                 for m in (2, 3, 4)}
    inviscid = {m: float(np.sqrt(lambda0_squared(m, 1.0))) for m in by_degree}
    png = natural_modes.save(zeta, by_degree, inviscid, out / "fig-7.1.png")
    data = {"zeta": zeta.tolist(), "modes": {m: [r.to_dict()["modes"] for r in rs]
                                             for m, rs in by_degree.items()}}
    return [png, _write_json(out / "fig-7.1.json", data)]


def _fibre_grid(out: Path, **kw) -> list[Path]:
    """Fig 4.1: fibre diagrams, rows m = 2, 3, 4, columns nu = 2e-4 and 1e-3."""
    cases = [{"m": m, "nu": nu} for m in (2, 3, 4) for nu in (2e-4, 1e-3)]
    return _diagrams("fig-4.1", out, cases, kappa="0.002:0.3:150", columns=2, model="fibre", **kw)


def _fibre_forcing_split(out: Path, **kw) -> list[Path]:
    """Fig 4.2: m = 3, nu = 2e-4, pumping both jumps, only the pressure jump, only the tangential."""
    cases = [{"m": 3, "nu": 2e-4, "forcing": f} for f in ("both", "pressure", "tangential")]
    return _diagrams("fig-4.2", out, cases, kappa="0.005:0.1:150", columns=3, model="fibre", **kw)


#: Figs 4.3/4.4: integer wavenumbers shown, and the amplitude at which unstable m are highlighted
#: (tau = 0.45, the forcing of the Table 4.1 simulations).
FIBRE_DEGREES = (2, 10)
FIBRE_TAU = 0.45


def _fibre_against_m(name: str, cases: list[dict], out: Path, *, progress: bool,
                     workers: int | None) -> list[Path]:
    """Figs 4.3/4.4: marginal tau (tau <= 1) at each integer wavenumber m = 2..10 for the
    (nu, kappa) sets compared with Cortez et al. 2004, m unstable at tau = 0.45 highlighted.

    The thesis draws these diagrams against a continuous m; only integer m are fibre modes, and
    the package evaluates those (see derivations/fibre_linear_result.md, Differences)."""
    lo, hi = FIBRE_DEGREES
    panels, data = [], []
    for case in cases:
        by_degree = {m: floquet("fibre", m=m, tau_max=1.0, **case)
                     for m in tracked(range(lo, hi + 1), name, "m", progress)}
        stab = stability("fibre", tau=FIBRE_TAU, m=f"{lo}:{hi}", **case)
        title = f"fibre: ν = {case['nu']:g}, κ = {case['kappa']:g} (abscissa: wavenumber m)"
        panels.append((title, by_degree, stab))
        data.append({"params": case, "stability": stab.to_dict(),
                     "floquet": {m: r.to_dict() for m, r in by_degree.items()}})
    png = degree_stability.save(panels, out / f"{name}.png", x_label="m, Fourier mode number")
    return [png, _write_json(out / f"{name}.json", data)]


# ---------------------------------------------------------------------------------------------
# Cochlea (thesis chapter 5); Table 5.1 physical parameters, omega in rad/s
# ---------------------------------------------------------------------------------------------

def _cochlea_det_contours(out: Path, **_) -> list[Path]:
    """Fig 5.7: zero contours of Re/Im det T(s), s = gamma/sqrt(kappa), alpha = 1.56, M = 20,
    zeta = 2e-5 and 1e-2, with the modes of solve_natural_modes marked."""
    from ..models.cochlea import coupling_matrix, transfer
    from ..plots import cochlea as cochlea_plots

    M, modes = 20, np.arange(1, 21)
    C = coupling_matrix(modes, 1.56)
    panels, data = [], {}
    for zeta, (re_lim, im_lim) in ((2e-5, ((-0.08, 0.01), (0.0, 1.2))), (1e-2, ((-1.0, 0.05), (0.0, 1.2)))):
        re, im = np.meshgrid(np.linspace(*re_lim, 400), np.linspace(*im_lim, 400))
        s = (re + 1j * im).ravel()
        T = np.broadcast_to(C, (s.size, M, M)).astype(complex)
        T[:, modes - 1, modes - 1] += transfer(s[:, None], modes[None, :], zeta)
        det = (np.linalg.det(T) / np.linalg.det(C)).reshape(re.shape)
        res = solve_natural_modes("cochlea", zeta=zeta, alpha=1.56, n_spatial=M)
        panels.append((f"ζ = {zeta:g}, α = 1.56, M = {M}", re, im, det, res.gamma))
        data[str(zeta)] = res.to_dict()
    png = cochlea_plots.save_det_contours(panels, out / "fig-5.7.png")
    return [png, _write_json(out / "fig-5.7.json", data)]


COCHLEA_RESPONSE_MODES = 64


def _cochlea_profiles(out: Path, *, progress: bool, **_) -> list[Path]:
    """Fig 5.8: normalised BM envelope and profile of the harmonic (solid) and subharmonic
    (dashed) solutions at tau_min, omega = 400, 800, 1200, 1600 rad/s (M = 64)."""
    from ..plots import cochlea as cochlea_plots

    panels, data = [], []
    for omega in tracked((400.0, 800.0, 1200.0, 1600.0), "fig-5.8", "ω", progress):
        res = [response("cochlea", omega=omega, kind=k, n_spatial=COCHLEA_RESPONSE_MODES)
               for k in ("harmonic", "subharmonic")]
        panels.append((f"ω = {omega:g} rad/s", res))
        data.append({"omega": omega, "responses": [r.to_dict() for r in res]})
    png = cochlea_plots.save_responses(panels, out / "fig-5.8.png")
    return [png, _write_json(out / "fig-5.8.json", data)]


def _cochlea_peaks(out: Path, *, progress: bool, **_) -> list[Path]:
    """Fig 5.9: envelope peak against response frequency for the harmonic (+, at omega) and
    subharmonic (o, at omega/2) solutions at tau_min and the passive tone, with the WKB line."""
    from ..models.cochlea import wkb_peak
    from ..params.physical import TABLE_5_1, cochlea_forced
    from ..plots import cochlea as cochlea_plots

    omegas = np.array([400.0, 600.0, 800.0, 1000.0, 1200.0, 1400.0, 1600.0])
    series, data = [], {}
    for kind, marker, factor in (("harmonic", "+", 1.0), ("subharmonic", "o", 0.5), ("tone", "x", 1.0)):
        res = [response("cochlea", omega=om, kind=kind, n_spatial=COCHLEA_RESPONSE_MODES)
               for om in tracked(omegas, f"fig-5.9 {kind}", "ω", progress)]
        peak = np.array([r.to_cm(r.peak_x) for r in res])
        err = np.array([r.to_cm(r.peak_error) for r in res])
        series.append((kind, marker, factor * omegas, peak, err))
        data[kind] = {"response_frequency": (factor * omegas).tolist(), "peak_cm": peak.tolist(),
                      "error_cm": err.tolist(), "tau": [r.tau for r in res]}
    f = np.geomspace(150.0, 2000.0, 50)
    base = {k: TABLE_5_1[k] for k in ("rho", "mu", "sigma", "length", "lambda_c")}
    line = np.array([wkb_peak(**cochlea_forced(**base, omega=w)) for w in f]) * base["length"] / np.pi
    data["wkb"] = {"response_frequency": f.tolist(), "peak_cm": line.tolist()}
    png = cochlea_plots.save_peaks(series, (f, line), out / "fig-5.9.png")
    return [png, _write_json(out / "fig-5.9.json", data)]


KINDS = ("harmonic", "subharmonic")
#: The cochlea's Ince-Strutt figures: every tau <= 1 to 1e-8 (drawing accuracy).
COCHLEA_DIAGRAM = {"tol": 1e-8, "tau_max": 1.0}


def _traced(factory, grid: np.ndarray, options: dict, name: str, desc: str, *, progress: bool,
            workers: int | None, trace: bool = True) -> tuple[list, tuple, dict]:
    """The Ince-Strutt diagram of the family ``factory`` over ``grid`` (the parameter ``name``)
    through :func:`spectralshell.runner.floquet.ince_strutt`: (its rows, (boundaries, tips as
    (kind, x, tau)) for :func:`spectralshell.plots.cochlea.save_traced`, and its JSON record
    (grid, every tau per kind, tips with errors, boundaries, tips not located)); with
    ``trace`` False only the grid is solved (no tips, no boundaries)."""
    from ..runner.floquet import ince_strutt

    rows, tips, failures, boundaries = ince_strutt(factory, grid, KINDS, options, tips=trace,
                                                   boundaries=trace, workers=workers,
                                                   progress=progress, desc=desc)
    record = {name: grid.tolist(),
              "tau": {kind: [r[kind].tau.tolist() for r in rows] for kind in KINDS},
              "tips": [{"kind": t.kind, name: t.kappa, "tau": t.tau, f"{name}_error": t.kappa_error,
                        "tau_error": t.tau_error} for t in tips],
              "boundaries": [{"kind": b.kind, name: b.kappa.tolist(), "tau": b.tau.tolist()}
                             for b in boundaries],
              "tip_failures": failures}
    return rows, (boundaries, [(t.kind, t.kappa, t.tau) for t in tips]), record


def _cochlea_uniform(out: Path, *, progress: bool, workers: int | None = None,
                     **_) -> list[Path]:
    """Fig 5.12: the boundaries of marginal tau <= 1 against omega in [200, 2000] rad/s for the
    single modes k = 1..6, alpha = 0 (Table 5.1), traced (runner.floquet.ince_strutt over the
    family omega -> system, the cgs omega converted as floquet does)."""
    import functools

    from ..plots import cochlea as cochlea_plots
    from ..runner.floquet import family_system

    omegas = np.linspace(200.0, 2000.0, 181)
    panels, data = [], {}
    for k in range(1, 7):
        factory = functools.partial(family_system, "cochlea", {"alpha": 0.0, "spatial_mode": k},
                                    "omega")
        _, (boundaries, tips), data[k] = _traced(factory, omegas, COCHLEA_DIAGRAM, "omega",
                                                 f"fig-5.12 k = {k}", progress=progress,
                                                 workers=workers)
        panels.append((f"k = {k}, α = 0", boundaries, KINDS, tips, {}))
    png = cochlea_plots.save_traced(panels, out / "fig-5.12.png", columns=2,
                                    xlabel="forcing frequency ω (rad/s)",
                                    x_range=(omegas[0], omegas[-1]))
    return [png, _write_json(out / "fig-5.12.json", {"omega": omegas.tolist(), "modes": data})]


def _cochlea_wavenumber(out: Path, *, progress: bool, workers: int | None = None,
                        **_) -> list[Path]:
    """Fig 5.11: every real marginal tau <= 1 against a continuous wavenumber k in (0, 12],
    alpha = 0, omega = 500 and 1000 rad/s (Table 5.1), with the finger tips and the integer
    wavenumbers unstable for tau <= 1/2. The grid, the tips and the traced boundaries come from
    the Ince-Strutt engine (runner.floquet.ince_strutt) run over the 1-parameter family
    models.cochlea.wavenumber_system (k in place of kappa)."""
    import functools

    from ..models.cochlea import wavenumber_system
    from ..params.physical import TABLE_5_1, cochlea_forced
    from ..plots import cochlea as cochlea_plots
    from ..runner import map_points

    k_grid, integers = np.linspace(0.02, 12.0, 600), np.arange(1.0, 13.0)
    base = {k: TABLE_5_1[k] for k in ("rho", "mu", "sigma", "length", "lambda_c")}
    panels, data = [], {}
    for omega in (500.0, 1000.0):
        d = cochlea_forced(**base, omega=omega)
        factory = functools.partial(wavenumber_system, kappa=d["kappa"], nu=d["nu"])
        _, (boundaries, tips), record = _traced(factory, k_grid, COCHLEA_DIAGRAM, "k",
                                                f"fig-5.11, ω = {omega:g}", progress=progress,
                                                workers=workers)
        at_integers = map_points(factory, list(integers), KINDS, executor="serial",
                                 **COCHLEA_DIAGRAM)
        tau_min = {int(k): min((r[kind].tau_min for kind in KINDS if r[kind].tau_min is not None),
                               default=None) for k, r in zip(integers, at_integers)}
        unstable = {k: t for k, t in tau_min.items() if t is not None and t <= 0.5}
        panels.append((f"ω = {omega:g} rad/s, α = 0 (κ = {d['kappa']:.4g}, ν = {d['nu']:.3g})",
                       boundaries, KINDS, tips, unstable))
        data[str(omega)] = {
            "kappa": d["kappa"], "nu": d["nu"], **record,
            "inviscid_tips_k": [j * j / (2 * d["kappa"]) for j in range(1, 12)
                                if j * j / (2 * d["kappa"]) <= k_grid[-1]],
            "integer_k_tau_min": {kind: {int(k): r[kind].tau_min for k, r in zip(integers, at_integers)}
                                  for kind in KINDS},
            "unstable_integer_k": sorted(unstable)}
    png = cochlea_plots.save_traced(panels, out / "fig-5.11.png", x_range=(0.0, k_grid[-1]),
                                    xlabel="spatial wavenumber k (cosine mode cos kx; physical "
                                    "modes: integers)")
    return [png, _write_json(out / "fig-5.11.json", data)]


def _cochlea_graded(out: Path, *, progress: bool, workers: int | None = None,
                    **_) -> list[Path]:
    """Fig 5.14: the boundaries of marginal tau <= 1 against omega in [400, 1600] rad/s,
    alpha = 1.56, at M = 5, 10 and 64 spatial modes (the thesis: 250), N converged to 1e-8
    (:data:`COCHLEA_DIAGRAM`): the three panels show the convergence in M. M = 5 and 10 are
    traced (:func:`_traced`); at M = 64 the pairs of truncations prove the list of tau complete
    only up to 0.27-0.4 (the title states the lowest over the grid; a forest of fingers whose eigenvalues near the real axis do not settle
    up to N = 400), so a curve cannot be followed through, and the panel shows the tau of the
    grid as points."""
    import functools

    from ..plots import cochlea as cochlea_plots
    from ..runner.floquet import family_system

    omegas = np.linspace(400.0, 1600.0, 61)
    panels, data = [], {}
    for M in (5, 10, 64):
        factory = functools.partial(family_system, "cochlea", {"n_spatial": M}, "omega")
        title = f"α = 1.56, M = {M}"
        rows, (boundaries, tips), data[M] = _traced(factory, omegas, COCHLEA_DIAGRAM, "omega",
                                                    f"fig-5.14 M = {M}", progress=progress,
                                                    workers=workers, trace=M < 64)
        if M < 64:
            panels.append((title, boundaries, KINDS, tips, {}))
            continue
        complete = {kind: [r[kind].complete_to for r in rows] for kind in KINDS}
        data[M]["complete_to"] = complete
        lowest = min(min(c) for c in complete.values())
        panels.append((f"{title} (points: the list is complete only up to {lowest:.2g})",
                       {kind: (np.concatenate([np.full(r[kind].tau.size, w)
                                               for r, w in zip(rows, omegas)]),
                               np.concatenate([r[kind].tau for r in rows])) for kind in KINDS}))
    png = cochlea_plots.save_traced(panels, out / "fig-5.14.png",
                                    xlabel="forcing frequency ω (rad/s)",
                                    x_range=(omegas[0], omegas[-1]), columns=1)
    return [png, _write_json(out / "fig-5.14.json", {"omega": omegas.tolist(), "n_spatial": data})]


def _cochlea_convergence(out: Path, **_) -> list[Path]:
    """Figs 5.5-5.6: |tau_min(2n) - tau_min(n)| at omega = 1600 rad/s (Table 5.1), in N = 4 2^j
    at M = 64 and in M = 16 2^j at N = 20 (the thesis: M = 100, and M up to 256)."""
    from ..models.cochlea import hill_system
    from ..params.physical import TABLE_5_1, cochlea_forced
    from ..plots import cochlea as cochlea_plots
    from ..solvers.marginal import marginal_tau

    d = cochlea_forced(**{k: TABLE_5_1[k] for k in ("rho", "mu", "sigma", "length", "lambda_c")},
                       omega=1600.0)

    def tau(M: int, N: int, kind: str) -> float:
        system = hill_system(kappa=d["kappa"], nu=d["nu"], alpha=d["alpha"], n_spatial=M)
        return marginal_tau(system, kind, n_temporal=N).tau_min

    Ns, Ms = np.array([4, 8, 16, 32]), np.array([16, 32, 64])
    kinds = ("harmonic", "subharmonic")
    in_n = {k: np.array([abs(tau(64, 2 * n, k) - tau(64, n, k)) for n in Ns]) for k in kinds}
    in_m = {k: np.array([abs(tau(2 * m, 20, k) - tau(m, 20, k)) for m in Ms]) for k in kinds}
    png = cochlea_plots.save_convergence([("N (temporal modes), M = 64", Ns, in_n),
                                          ("M (spatial modes), N = 20", Ms, in_m)],
                                         out / "fig-5.5.png")
    data = {"N": Ns.tolist(), "error_in_N": {k: v.tolist() for k, v in in_n.items()},
            "M": Ms.tolist(), "error_in_M": {k: v.tolist() for k, v in in_m.items()}}
    return [png, _write_json(out / "fig-5.5.json", data)]


# ---------------------------------------------------------------------------------------------
# Fig 5.18: minimum-tau maps of the human and gerbil cochlea through the sweep runner
# ---------------------------------------------------------------------------------------------

#: Panels of Fig 5.18: name of the packaged scene spectralshell/scenes/fig-5.18-NAME.toml, title.
FIG_5_18_PANELS = (
    ("human", "human: Table 5.1 (ρ = 1 g/cm³, μ = 0.02 g/(cm s), L = 3.5 cm, λ_c = 1.4 /cm)"),
    ("gerbil", "gerbil: L = 1.3 cm, λ_c = 3.7 /cm (ρ, μ of Table 5.1)"),
)
#: Points per axis of `spectralshell figure fig-5.18` (the packaged scenes: 200, as the thesis).
#: Measured on the shared 2-core machine (processes executor, 2 workers, loaded): 6 x 6 per
#: panel took about 8 min with the joint minimum over kinds (scene option over_kinds =
#: "minimum"), against 17-33 min converging each kind: at f <= 166 Hz, sigma = 2e9 the
#: subharmonic (not the minimum there) alone took 370-500 s per point (its tau creep towards 1/2,
#: N up to 303); capped below the harmonic minimum it takes seconds.
FIG_5_18_SIZE = 6
#: How the thesis's frequency axis ("omega in [50, 20000] Hz") is read here.
FIG_5_18_FREQUENCY = {
    "axis": "f in Hz (cycles per second); omega = 2 pi f rad/s enters kappa = sigma pi/(rho L "
            "omega^2) and nu = mu pi^2/(rho L^2 omega)",
    "why": "the audible range (20 Hz - 20 kHz; gerbil up to ~50 kHz) is a range of f in Hz; the "
           "thesis labels the axis 'omega in [50, 20000] Hz' but uses omega in s^-1 everywhere else",
    "other_reading": "had the thesis put omega = 50..20000 s^-1 ('Hz' mislabelled), every feature "
                     "of its map would sit log10(2 pi) = 0.80 decade further right on its axis "
                     "than on ours (its axis would span f = 8 - 3183 Hz); at a given axis value "
                     "kappa would be (2 pi)^2 = 39.5 times and nu 2 pi times ours",
    "evidence": "the thesis finds no resonance only at the highest frequencies and lowest sigma "
                "(white lower-right corner, M = 250). Read in Hz that corner is f = 20 kHz, "
                "sigma = 1e7: no tau <= 1/2 at M = 250; the unpumped modes reach the subharmonic "
                "resonance from M ~ 1000, and a one-off check at M = 1024 and 2048 finds no "
                "subharmonic tau <= 0.70 (white for that kind; the harmonic would need M ~ 4096 "
                "to be certified, so the cell stays hatched). Read as omega = 20000 s^-1 (f = 3.2 kHz) it has "
                "tau_min = 0.049 (subharmonic) already at M = 250. So the Hz reading matches.",
}


def fig_5_18_scene(panel: str, size: int | None = None) -> dict:
    """The packaged scene of a Fig 5.18 panel ('human' or 'gerbil'), with ``size`` points per
    axis instead of its 200 (and lines cut into chunks of about size / 4 points)."""
    import tomllib
    from importlib import resources

    text = resources.files("spectralshell").joinpath(f"scenes/fig-5.18-{panel}.toml").read_text()
    scene = tomllib.loads(text)
    if size is not None:
        for axis in scene["grid"].values():
            axis["num"] = int(size)
        scene["sweep"] = {"chunk": max(1, -(-int(size) // 4))}
    return scene


def _minimum_over_kinds(ds) -> dict:
    """Per (frequency, sigma) cell: tau_min over kinds (None: no tau found <= tau_max), the
    kind, and whether the cell is uncertified (an empty answer the zero count could not prove:
    :func:`spectralshell.results.maps.uncertified`; then None is no "none")."""
    from ..results.maps import uncertified

    tau = ds["tau_min"].where(ds["has_tau"]).transpose("frequency", "sigma", "kind").values
    found = np.isfinite(tau).any(axis=-1)
    best = np.where(found, np.nanargmin(np.where(np.isfinite(tau), tau, np.inf), axis=-1), -1)
    kinds = list(ds["kind"].values)
    value = np.where(found, np.nanmin(np.where(np.isfinite(tau), tau, np.inf), axis=-1), np.nan)
    return {"tau_min": [[None if not np.isfinite(v) else float(v) for v in row] for row in value],
            "kind": [[kinds[i] if i >= 0 else None for i in row] for row in best],
            "uncertified": uncertified(ds).any("kind").transpose("frequency", "sigma")
            .values.tolist()}


def _cochlea_tau_maps(out: Path, *, progress: bool, workers: int | None,
                      size: int = FIG_5_18_SIZE) -> list[Path]:
    """Fig 5.18: minimum tau <= 1/2 over both kinds against frequency (Hz) and sigma, human and
    gerbil, each point's M refined to tol_spatial (Zarr stores kept: a rerun resumes)."""
    import time

    from ..plots import cochlea as cochlea_plots
    from ..plots.sweep_plot import unconverged
    from .._validate import REAL_MAX
    from ..runner import run_sweep
    from ..runner.layout import chunks, region
    from ..params.sweep_grid import sweep_spec

    panels, data, paths = [], {}, []
    for name, title in FIG_5_18_PANELS:
        scene = fig_5_18_scene(name, size)
        spec = sweep_spec(scene)
        plan = chunks(spec)
        cost = np.full(spec.shape, np.nan)

        def record(_, result, spec=spec, plan=plan, cost=cost) -> None:
            cost[region(spec, plan[result.index])] = result.point_seconds

        store = out / f"fig-5.18-{name}.zarr"
        t0 = time.perf_counter()
        # the figure's own grid: its cost is measured (point_seconds below), and the dense
        # price of its low-frequency corner (N = 400 at M = 32, ~4 h a point) overstates it
        run = run_sweep(spec, workers=workers, out=store, progress=progress, on_chunk=record,
                        max_seconds=REAL_MAX)
        ds = run.dataset
        panels.append((title, ds))
        m = ds["n_spatial"].values
        cost_fs = cost.transpose(spec.dims.index("frequency"), spec.dims.index("sigma"),
                                 spec.dims.index("kind")).sum(axis=-1)
        data[name] = {
            "scene": scene, "params": json.loads(ds.attrs["params"]),
            "frequency_hz": ds["frequency"].values.tolist(), "sigma": ds["sigma"].values.tolist(),
            **_minimum_over_kinds(ds),
            "n_spatial": ds["n_spatial"].transpose("frequency", "sigma", "kind").values.tolist(),
            "n_spatial_range": [int(m.min()), int(m.max())],
            "kind_solves_not_converged_in_m": int((~ds["spatial_converged"].values).sum()),
            "cells_hatched": int(unconverged(ds, "frequency", "sigma").sum()),
            "wall_seconds": round(time.perf_counter() - t0, 1), "points_computed": run.computed,
            "points_skipped": run.skipped, "executor": run.executor,
            "point_seconds": [[None if not np.isfinite(c) else round(float(c), 3) for c in row]
                              for row in cost_fs],
        }
        paths.append(store)
    lo = min(d["n_spatial_range"][0] for d in data.values())
    hi = max(d["n_spatial_range"][1] for d in data.values())
    options = json.loads(panels[0][1].attrs["solver_options"])
    caption = (f"Grid {size} × {size} (log-spaced f and σ; the packaged scenes: 200 × 200). "
               f"N raised per point until |Δτ_min| < tol = {options['tol']:g}; M refined per "
               f"point from 16 (doubling, ≤ 1024) until the smaller τ_min of the two kinds "
               f"changes by ≤ tol_spatial = "
               f"{options['tol_spatial']:g}; M used: {lo}–{hi}. Thesis: N = 20, M = 250 fixed. "
               "Frequency f in Hz, ω = 2πf rad/s (if the thesis's axis is ω in s⁻¹, its features "
               "sit log10(2π) ≈ 0.8 decade to the right of ours).")
    png = cochlea_plots.save_tau_maps(panels, out / "fig-5.18.png", caption=caption)
    summary = {"figure": "fig-5.18", "caption": caption, "grid_points_per_axis": size,
               "solver_options": options, "n_spatial_range": [lo, hi],
               "frequency": FIG_5_18_FREQUENCY,
               "sigma_units": "g cm^-2 s^-2 (= dyn/cm^3: stiffness per unit area of the BM)",
               "light_grey": "no marginal tau <= tau_max = 1/2 of either kind (has_tau false)",
               "hatched": "M refinement did not converge by M = 1024 (values at the last M "
                          "solved: 1024, or 512 where only the reach test failed and M = 512 "
                          "does not reach the resonance, so that M = 1024 could not settle it)",
               "other_kind": "over_kinds = 'minimum': the kind not attaining a cell's minimum "
                             "is resolved only below it (has_tau false, tau_min NaN, where it has "
                             "none there)",
               "point_seconds": "in-worker time of each point's two kind solves (s), this run",
               "panels": data}
    return [png, _write_json(out / "fig-5.18.json", summary), *paths]


def _sphere_p2(out: Path, *, progress: bool, workers: int | None,
               eps: np.ndarray | None = None) -> list[Path]:
    """Beyond the thesis: tau_min <= 1/2 of the sphere with kappa = kappa0 (1 + eps P_2(cos theta))
    against eps, kappa0 = 0.02, nu = 0.006, degrees <= 8: the subharmonic tau_min of degree 3
    splits into its orders |k| = 0..3."""
    eps = np.linspace(-0.5, 0.5, 20) if eps is None else eps   # eps = 0 (degenerate) left out
    case = {"kappa0": 0.02, "nu": 0.006, "l_max": 8, "tau_max": 0.5}
    rows = [row for e in tracked(eps, "fig-sphere-p2", "eps", progress)
            for row in p2_branches(eps=np.array([e]), **case)]
    png = nonuniform.save(rows, out / "fig-sphere-p2.png",
                          title=f"sphere, κ₀ = {case['kappa0']}, ν = {case['nu']}: branches of "
                                f"τ_min ≤ 1/2 (degrees ≤ {case['l_max']})")
    return [png, _write_json(out / "fig-sphere-p2.json", {**case, "branches": rows})]


FIGURES: dict[str, tuple[str, Callable[..., list[Path]]]] = {
    "fig-2.2": ("Ince-Strutt diagram of the undamped Mathieu equation (nu = 0)",
                lambda out, **kw: _diagrams("fig-2.2", out, [{"nu": 0.0}], kappa="0:3:301",
                                            columns=1, **kw)),
    "fig-2.3": ("Ince-Strutt diagrams of the damped Mathieu equation, nu = 0.01 and 0.1",
                lambda out, **kw: _diagrams("fig-2.3", out, [{"nu": 0.01}, {"nu": 0.1}],
                                            kappa="0:3:301", columns=2, **kw)),
    "fig-4.1": ("fibre: Ince-Strutt diagrams for m = 2, 3, 4 at nu = 2e-4 and 1e-3", _fibre_grid),
    "fig-4.2": ("fibre, m = 3, nu = 2e-4: stiffness pumped in both jumps, pressure only, tangential only",
                _fibre_forcing_split),
    "fig-4.3": ("fibre: marginal tau against wavenumber m = 2..10, nu = 2e-4, kappa = 0.02, 0.04, 0.08",
                lambda out, **kw: _fibre_against_m(
                    "fig-4.3", [{"nu": 2e-4, "kappa": k} for k in (0.02, 0.04, 0.08)], out, **kw)),
    "fig-4.4": ("fibre: marginal tau against wavenumber m = 2..10, kappa = 0.04, nu = 5e-5, 1e-3, 5e-3",
                lambda out, **kw: _fibre_against_m(
                    "fig-4.4", [{"nu": n, "kappa": 0.04} for n in (5e-5, 1e-3, 5e-3)], out, **kw)),
    "fig-6.2": ("sphere, inviscid: Ince-Strutt diagrams for m = 2, 3, 4",
                lambda out, **kw: _sphere_grid("fig-6.2", (0.0,), out, **kw)),
    "fig-6.3": ("sphere, viscous: Ince-Strutt diagrams for m = 2, 3, 4 at nu = 1e-3 and 6e-3",
                lambda out, **kw: _sphere_grid("fig-6.3", (1e-3, 6e-3), out, **kw)),
    "fig-6.6": ("sphere: marginal tau against degree m for the cases of Table 6.1",
                _table_6_1_degrees),
    "fig-6.12": ("sphere, cardiac (400 bpm, R = 2 cm): fingers against stiffness sigma, m = 2, 3, 4",
                 _cardiac_fingers),
    "fig-6.13": ("sphere, cardiac: minimum tau over m = 2..6 against stiffness and beat rate",
                 _cardiac_map),
    "fig-7.1": ("sphere: decay rate and frequency of the least-damped natural mode against zeta",
                _natural_modes_against_zeta),
    "fig-cylinder": ("periodic cylinder (thesis 8.1): minimum tau over m = 1..6 against k R and "
                     "kappa at nu = 2e-4, and the unstable (m, k R) at tau = 0.45",
                     _cylinder_map),
    "fig-sphere-p2": ("sphere, non-uniform stiffness kappa0 (1 + eps P_2(cos theta)): tau_min "
                      "against eps, one branch per degree and order (l, |k|)", _sphere_p2),
    "fig-5.5": ("cochlea: convergence of tau_min in N and M at omega = 1600 rad/s (Figs 5.5-5.6)",
                _cochlea_convergence),
    "fig-5.7": ("cochlea: zero contours of det T and the natural modes, zeta = 2e-5 and 1e-2",
                _cochlea_det_contours),
    "fig-5.8": ("cochlea: BM envelopes at tau_min, harmonic and subharmonic, omega = 400..1600",
                _cochlea_profiles),
    "fig-5.9": ("cochlea: envelope peak against response frequency, with the WKB place map",
                _cochlea_peaks),
    "fig-5.11": ("cochlea, uniform stiffness: marginal tau against the wavenumber k, omega = 500, 1000",
                 _cochlea_wavenumber),
    "fig-5.12": ("cochlea, uniform stiffness: marginal tau against omega for modes k = 1..6",
                 _cochlea_uniform),
    "fig-5.14": ("cochlea, graded stiffness: marginal tau against omega for M = 5, 10, 64",
                 _cochlea_graded),
    "fig-5.18": ("cochlea: minimum tau <= 1/2 against frequency (Hz) and stiffness sigma, human "
                 "and gerbil, M refined per point (a sweep; see spectralshell/scenes/)",
                 _cochlea_tau_maps),
}


def make_figure(name: str, out: str | Path, *, progress: bool = False,
                workers: int | None = None) -> list[Path]:
    """Compute and write figure ``name`` (PNG + data) into directory ``out``."""
    out = Path(out)
    return FIGURES[name][1](out, progress=progress, workers=workers)
