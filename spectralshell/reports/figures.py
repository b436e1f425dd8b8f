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
}


def make_figure(name: str, out: str | Path, *, progress: bool = False,
                workers: int | None = None) -> list[Path]:
    """Compute and write figure ``name`` (PNG + data) into directory ``out``."""
    out = Path(out)
    return FIGURES[name][1](out, progress=progress, workers=workers)
