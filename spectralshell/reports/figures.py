"""Figure registry: each thesis figure the package reproduces, by name (``spectralshell figure``)."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

from .. import api
from ..plots import ince_strutt


def _mathieu_diagrams(name: str, nus: tuple[float, ...], out: Path, *, progress: bool,
                      workers: int | None) -> list[Path]:
    results = [api.tongues("mathieu", kappa="0:3:301", nu=nu, progress=progress, workers=workers)
               for nu in nus]
    png = ince_strutt.save(results, out / f"{name}.png")
    data = out / f"{name}.json"
    data.write_text(json.dumps([r.to_dict() for r in results]))
    return [png, data]


FIGURES: dict[str, tuple[str, Callable[..., list[Path]]]] = {
    "fig-2.2": ("Ince-Strutt diagram of the undamped Mathieu equation (nu = 0)",
                lambda out, **kw: _mathieu_diagrams("fig-2.2", (0.0,), out, **kw)),
    "fig-2.3": ("Ince-Strutt diagrams of the damped Mathieu equation, nu = 0.01 and 0.1",
                lambda out, **kw: _mathieu_diagrams("fig-2.3", (0.01, 0.1), out, **kw)),
}


def make_figure(name: str, out: str | Path, *, progress: bool = False,
                workers: int | None = None) -> list[Path]:
    """Compute and write figure ``name`` (PNG + JSON data) into directory ``out``."""
    out = Path(out)
    return FIGURES[name][1](out, progress=progress, workers=workers)
