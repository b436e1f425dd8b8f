"""Figure registry: each thesis figure the package reproduces, by name (``spectralshell figure``).

Every figure writes a PNG (labelled axes, units) and the data behind it as JSON (maps also NPZ).
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

import numpy as np

from .. import api
from ..params.physical import CARDIAC, TABLE_6_1, PhysicalSphere, bpm_to_rad_per_s
from ..models.sphere import lambda0_squared
from ..plots import degree_stability, ince_strutt, natural_modes, tau_map


def _write_json(path: Path, data) -> Path:
    path.write_text(json.dumps(data))
    return path


def _diagrams(name: str, out: Path, cases: list[dict], *, kappa: str, columns: int,
              model: str = "mathieu", progress: bool, workers: int | None, **draw) -> list[Path]:
    results = [api.tongues(model, kappa=kappa, progress=progress, workers=workers, tau_max=1.0,
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
        by_degree = {m: api.floquet("sphere", m=m, **dimless) for m in range(2, 9)}
        stab = api.stability("sphere", tau=0.45, m="2:8", **dimless)
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
    res = api.tau_map("sphere", x=("sigma", f"{sigma[0]}:{sigma[1]}:{size}"),
                      y=("bpm", f"50:650:{size}"), m="2:6", progress=progress, workers=workers,
                      physical={k: CARDIAC[k] for k in ("rho", "mu", "radius")})
    boxes = [(sigma, CARDIAC["bpm_healthy"], "healthy heart", "tab:blue"),
             (sigma, CARDIAC["bpm_svt"], "SVT", "tab:red")]
    png = tau_map.save(res, out / "fig-6.13.png", boxes=boxes)
    res.write_npz(out / "fig-6.13.npz")
    return [png, _write_json(out / "fig-6.13.json", res.to_dict()), out / "fig-6.13.npz"]


def _natural_modes_against_zeta(out: Path, *, progress: bool, workers: int | None) -> list[Path]:
    """Fig 7.1: least-damped mode (decay rate, frequency) of m = 2, 3, 4 for zeta in [1e-3, 10]."""
    zeta = np.logspace(-3, 1, 161)
    by_degree = {m: [api.natural_modes("sphere", m=m, zeta=z) for z in zeta] for m in (2, 3, 4)}
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
        by_degree = {m: api.floquet("fibre", m=m, tau_max=1.0, **case) for m in range(lo, hi + 1)}
        stab = api.stability("fibre", tau=FIBRE_TAU, m=f"{lo}:{hi}", **case)
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
    zeta = 2e-5 and 1e-2, with the modes of api.natural_modes marked."""
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
        res = api.natural_modes("cochlea", zeta=zeta, alpha=1.56, n_spatial=M)
        panels.append((f"ζ = {zeta:g}, α = 1.56, M = {M}", re, im, det, res.gamma))
        data[str(zeta)] = res.to_dict()
    png = cochlea_plots.save_det_contours(panels, out / "fig-5.7.png")
    return [png, _write_json(out / "fig-5.7.json", data)]


COCHLEA_RESPONSE_MODES = 64


def _cochlea_profiles(out: Path, **_) -> list[Path]:
    """Fig 5.8: normalised BM envelope and profile of the harmonic (solid) and subharmonic
    (dashed) solutions at tau_min, omega = 400, 800, 1200, 1600 rad/s (M = 64)."""
    from ..plots import cochlea as cochlea_plots

    panels, data = [], []
    for omega in (400.0, 800.0, 1200.0, 1600.0):
        res = [api.response("cochlea", omega=omega, kind=k, n_spatial=COCHLEA_RESPONSE_MODES)
               for k in ("harmonic", "subharmonic")]
        panels.append((f"ω = {omega:g} rad/s", res))
        data.append({"omega": omega, "responses": [r.to_dict() for r in res]})
    png = cochlea_plots.save_responses(panels, out / "fig-5.8.png")
    return [png, _write_json(out / "fig-5.8.json", data)]


def _cochlea_peaks(out: Path, **_) -> list[Path]:
    """Fig 5.9: envelope peak against response frequency for the harmonic (+, at omega) and
    subharmonic (o, at omega/2) solutions at tau_min and the passive tone, with the WKB line."""
    from ..models.cochlea import wkb_peak
    from ..params.physical import TABLE_5_1, cochlea_forced
    from ..plots import cochlea as cochlea_plots

    omegas = np.array([400.0, 600.0, 800.0, 1000.0, 1200.0, 1400.0, 1600.0])
    series, data = [], {}
    for kind, marker, factor in (("harmonic", "+", 1.0), ("subharmonic", "o", 0.5), ("tone", "x", 1.0)):
        res = [api.response("cochlea", omega=om, kind=kind, n_spatial=COCHLEA_RESPONSE_MODES)
               for om in omegas]
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


def _tau_points(results: list, omegas: np.ndarray) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    points = {}
    for kind in ("harmonic", "subharmonic"):
        om = [np.full(getattr(r, kind).tau.size, w) for r, w in zip(results, omegas)]
        points[kind] = (np.concatenate(om), np.concatenate([getattr(r, kind).tau for r in results]))
    return points


def _cochlea_uniform(out: Path, **_) -> list[Path]:
    """Fig 5.12: marginal tau against omega for the single modes k = 1..6, alpha = 0 (Table 5.1)."""
    from ..plots import cochlea as cochlea_plots

    omegas = np.linspace(200.0, 2000.0, 181)
    panels, data = [], {}
    for k in range(1, 7):
        res = [api.floquet("cochlea", omega=w, alpha=0.0, spatial_mode=k, tau_max=1.0) for w in omegas]
        panels.append((f"k = {k}, α = 0", _tau_points(res, omegas)))
        data[k] = [r.to_dict() for r in res]
    png = cochlea_plots.save_tau_against_omega(panels, out / "fig-5.12.png", columns=2,
                                               omega_range=(omegas[0], omegas[-1]))
    return [png, _write_json(out / "fig-5.12.json", {"omega": omegas.tolist(), "modes": data})]


def _cochlea_graded(out: Path, **_) -> list[Path]:
    """Fig 5.14: marginal tau against omega, alpha = 1.56, M = 5, 10 and 64 (the thesis: 250), N
    converged to 1e-10; each point's error estimate includes |tau(M) - tau(M/2)|."""
    from ..plots import cochlea as cochlea_plots

    omegas = np.linspace(400.0, 1600.0, 61)
    panels, data = [], {}
    for M in (5, 10, 64):
        res = [api.floquet("cochlea", omega=w, n_spatial=M, tau_max=1.0) for w in omegas]
        panels.append((f"α = 1.56, M = {M}", _tau_points(res, omegas)))
        data[M] = [r.to_dict() for r in res]
    png = cochlea_plots.save_tau_against_omega(panels, out / "fig-5.14.png",
                                               omega_range=(omegas[0], omegas[-1]))
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
    "fig-5.5": ("cochlea: convergence of tau_min in N and M at omega = 1600 rad/s (Figs 5.5-5.6)",
                _cochlea_convergence),
    "fig-5.7": ("cochlea: zero contours of det T and the natural modes, zeta = 2e-5 and 1e-2",
                _cochlea_det_contours),
    "fig-5.8": ("cochlea: BM envelopes at tau_min, harmonic and subharmonic, omega = 400..1600",
                _cochlea_profiles),
    "fig-5.9": ("cochlea: envelope peak against response frequency, with the WKB place map",
                _cochlea_peaks),
    "fig-5.12": ("cochlea, uniform stiffness: marginal tau against omega for modes k = 1..6",
                 _cochlea_uniform),
    "fig-5.14": ("cochlea, graded stiffness: marginal tau against omega for M = 5, 10, 64",
                 _cochlea_graded),
}


def make_figure(name: str, out: str | Path, *, progress: bool = False,
                workers: int | None = None) -> list[Path]:
    """Compute and write figure ``name`` (PNG + data) into directory ``out``."""
    out = Path(out)
    return FIGURES[name][1](out, progress=progress, workers=workers)
