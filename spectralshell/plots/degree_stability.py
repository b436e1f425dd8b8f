"""Marginal tau against the degree m at fixed (nu, kappa) (thesis Fig 6.6), unstable m highlighted."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from ._canvas import save_figure, subplots
from ..results.floquet import StabilityResult
from .ince_strutt import STYLE


def save(panels: Sequence[tuple[str, dict[int, object], StabilityResult]], path: str | Path, *,
         tau_max: float = 1.0, x_label: str = "m, spherical-harmonic degree") -> Path:
    """One panel per (title, {m: FloquetResult}, StabilityResult at the reference tau)."""
    fig, axes = subplots(1, len(panels), figsize=(4.2 * len(panels), 4.6), squeeze=False)
    for ax, (title, by_degree, stab) in zip(axes[0], panels):
        for kind in ("harmonic", "subharmonic"):
            xs, ys = [], []
            for m, res in by_degree.items():
                taus = [t for t in getattr(res, kind).tau if t <= tau_max]
                xs += [m] * len(taus)
                ys += taus
            ax.plot(xs, ys, linestyle="none", markersize=5, **STYLE[kind])
        for mode in stab.modes:
            if mode["unstable"]:
                ax.axvline(mode["m"], color="tab:green", linewidth=3, alpha=0.4,
                           label=f"unstable at τ = {stab.tau:g}: m = {mode['m']} ({mode['kind']})")
        ax.axhline(stab.tau, color="tab:green", linestyle=":", linewidth=1,
                   label=f"τ = {stab.tau:g} (the reference amplitude)")
        ax.axhline(0.5, color="0.4", linestyle="--", linewidth=1, label="τ = 1/2")
        ax.set_xticks(sorted(by_degree))
        ax.set_ylim(0, tau_max)
        ax.set_xlabel(x_label)
        ax.set_ylabel("τ, forcing amplitude (dimensionless)")
        ax.set_title(title, fontsize=9)
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, fontsize=6,
                  frameon=False)  # below the axes, where it hides no point
    return save_figure(fig, path, dpi=120)
