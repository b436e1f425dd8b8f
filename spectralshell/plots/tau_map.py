"""Minimum-tau maps (thesis Fig 6.13): colour = smallest tau of instability over the degrees m
and kinds of a tau-map sweep, bands labelled m H/S, optional labelled boxes."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from ._canvas import save_figure, subplots
from ..errors import ParameterError
from .sweep_plot import colour_label, draw_map, picture_axes

if TYPE_CHECKING:
    import xarray as xr

#: The colour scale runs to this multiple of tau_max, so that its largest values stay visibly
#: blue, apart from the light grey of "no instability".
HEADROOM = 1.3


def draw(ax, ds: xr.Dataset, *,
         boxes: Sequence[tuple[tuple[float, float], tuple[float, float], str, str]] = (),
         min_cells: int = 6) -> None:
    """Draw the map of a tau-map sweep (:func:`spectralshell.tau_map`) on ``ax`` with its colour
    bar, its first real axis horizontal; ``boxes`` are ((x0, x1), (y0, y1), label, colour)
    rectangles, named with "none" in a legend below the axes."""
    real, cats = picture_axes(ds)
    if len(real) != 2:
        raise ParameterError(f"tau map axes {real!r} are invalid for a map picture: it needs "
                             "two real axes with several values each")
    x, y = real
    tau_max = float(ds.attrs["tau_max"])
    mesh, _ = draw_map(ax, ds, x, y, min_cells=min_cells, headroom=HEADROOM, boxes=boxes)
    bar = ax.figure.colorbar(mesh, ax=ax, label=colour_label(tau_max))
    bar.ax.set_ylim(0.0, tau_max)
    over = " over m = {}..{}".format(*ds["m"].values[[0, -1]]) if "m" in cats else ""
    ax.set_title(f"{ds.attrs.get('model', '')}: minimum τ{over} "
                 "(labels: m, H harmonic / S subharmonic)", fontsize=9)


def save(ds: xr.Dataset, path: str | Path, *,
         boxes: Sequence[tuple[tuple[float, float], tuple[float, float], str, str]] = (),
         min_cells: int = 6) -> Path:
    """Write :func:`draw` of a tau-map sweep to ``path`` (PNG, SVG or PDF by its suffix)."""
    fig, ax = subplots(figsize=(7.5, 5.8))
    draw(ax, ds, boxes=boxes, min_cells=min_cells)
    return save_figure(fig, path, dpi=120)
