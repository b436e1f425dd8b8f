"""Ince-Strutt diagrams (thesis Figs 2.2, 2.3): tau against kappa, harmonic '+', subharmonic 'o'."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from ..results.floquet import TonguesResult  # noqa: E402

STYLE = {"harmonic": dict(marker="+", color="tab:blue", label="harmonic (γ = 0)"),
         "subharmonic": dict(marker="o", mfc="none", color="tab:red", label="subharmonic (γ = i/2)")}


def draw(ax, result: TonguesResult, *, tau_max: float = 1.0, title: str | None = None) -> None:
    """Draw one diagram on ``ax``: marginal points, finger tips, the tau = 1/2 line."""
    for kind in result.kinds:
        k, t = result.points(kind)
        keep = t <= tau_max
        ax.plot(k[keep], t[keep], linestyle="none", markersize=3, **STYLE[kind])
    tips = [tip for tip in result.tips if tip.tau <= tau_max]
    if tips:
        ax.plot([t.kappa for t in tips], [t.tau for t in tips], "k*", markersize=9,
                label="finger tips")
    ax.axhline(0.5, color="0.4", linestyle="--", linewidth=1,
               label="τ = 1/2 (stiffness reaches 0)")
    ax.set_xlim(result.kappa.min(), result.kappa.max())
    ax.set_ylim(0, tau_max)
    ax.set_xlabel("κ, stiffness (dimensionless)")
    ax.set_ylabel("τ, forcing amplitude (dimensionless)")
    names = {"nu": "ν", "m": "m"}
    label = ", ".join(f"{names.get(k, k)} = {v:g}" if isinstance(v, (int, float)) else f"{v}"
                      for k, v in result.params.items())
    ax.set_title(title or f"{result.model}: {label}")
    ax.legend(loc="upper right", fontsize=7)


def save(results: Sequence[TonguesResult], path: str | Path, *, tau_max: float = 1.0) -> Path:
    """Write one PNG with a panel per result (side by side)."""
    fig, axes = plt.subplots(1, len(results), figsize=(6.4 * len(results), 4.8), squeeze=False)
    for ax, res in zip(axes[0], results):
        draw(ax, res, tau_max=tau_max)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
