"""Minimum-tau maps (thesis Fig 6.13): colour = smallest tau of instability, bands labelled m H/S."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from ._canvas import plt, save_figure
import numpy as np
from matplotlib.patches import Rectangle
from scipy import ndimage

from ..results.maps import TauMapResult

LABELS = {"sigma": "σ, membrane stiffness (dyn/cm)", "bpm": "beat rate (beats/min)",
          "omega": "ω, forcing frequency (rad/s)", "kappa": "κ, stiffness (dimensionless)",
          "nu": "ν, viscosity (dimensionless)"}


def _band_labels(ax, res: TauMapResult, min_cells: int) -> None:
    code = np.where(res.has_tau, res.degree * 2 + (res.kind == "S"), -1)
    for value in np.unique(code[code >= 0]):
        regions, count = ndimage.label(code == value)
        for r in range(1, count + 1):
            iy, ix = np.nonzero(regions == r)
            if iy.size >= min_cells:
                m, kind = divmod(int(value), 2)
                ax.text(res.x[int(round(ix.mean()))], res.y[int(round(iy.mean()))],
                        f"{m}{'S' if kind else 'H'}", ha="center", va="center", fontsize=7)


def save(res: TauMapResult, path: str | Path, *,
         boxes: Sequence[tuple[tuple[float, float], tuple[float, float], str, str]] = (),
         min_cells: int = 6) -> Path:
    """Write the map as PNG; ``boxes`` are ((x0, x1), (y0, y1), label, colour) rectangles."""
    fig, ax = plt.subplots(figsize=(7.5, 5.8))
    shown = np.ma.masked_where(~res.has_tau, res.tau_min)
    # the colour scale stops short of white, which is reserved for "no instability"
    mesh = ax.pcolormesh(res.x, res.y, shown, cmap="Blues_r", vmin=0.0, vmax=1.3 * res.tau_max,
                         shading="nearest")
    bar = fig.colorbar(mesh, ax=ax, label=f"minimum τ of instability (white: none below {res.tau_max:g})")
    bar.ax.set_ylim(0.0, res.tau_max)
    _band_labels(ax, res, min_cells)
    for (x0, x1), (y0, y1), label, colour in boxes:
        ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, edgecolor=colour,
                               linestyle="-" if colour == "tab:blue" else "--", linewidth=1.5,
                               label=label))
    if boxes:
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.11), ncol=len(boxes), fontsize=7,
                  frameon=False)  # below the axes: inside, it would cover cells of the map
    ax.set_xlabel(LABELS.get(res.x_name, f"{res.x_name} ({res.units[res.x_name]})"))
    ax.set_ylabel(LABELS.get(res.y_name, f"{res.y_name} ({res.units[res.y_name]})"))
    ax.set_title(f"{res.model}: minimum τ over m = {res.degrees[0]}..{res.degrees[-1]} "
                 "(labels: m, H harmonic / S subharmonic)", fontsize=9)
    return save_figure(fig, path, dpi=120)
