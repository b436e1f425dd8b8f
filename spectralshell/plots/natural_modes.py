"""Natural modes against zeta (thesis Fig 7.1): decay rate (top) and frequency (bottom)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from ._canvas import colours, save_figure, subplots
from ..results.modes import NaturalModesResult


def save(zeta: np.ndarray, by_degree: Mapping[int, Sequence[NaturalModesResult]],
         inviscid: Mapping[int, float], path: str | Path) -> Path:
    """``by_degree[m][i]`` holds the modes at ``zeta[i]`` (kappa = 1, so gamma is gamma/sqrt(kappa))."""
    fig, (top, bottom) = subplots(2, 1, figsize=(7.0, 7.5), sharex=True)
    for (m, results), colour in zip(by_degree.items(), colours()):
        gamma = np.array([r.gamma[0] for r in results])  # the least-damped mode
        top.semilogx(zeta, gamma.real, color=colour, label=f"m = {m}")
        bottom.semilogx(zeta, gamma.imag, color=colour, label=f"m = {m}")
        bottom.axhline(inviscid[m], color=colour, linestyle="--", linewidth=0.8)
    top.set_ylabel("decay rate Re γ / √κ (dimensionless)")
    bottom.set_ylabel("frequency Im γ / √κ (dimensionless)")
    bottom.set_xlabel("ζ = ν / √κ")
    top.set_title("least-damped natural mode of the sphere (dashed: inviscid λ0, (7.4))", fontsize=9)
    for ax in (top, bottom):
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    return save_figure(fig, path, dpi=120)
