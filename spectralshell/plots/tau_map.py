"""Minimum-tau maps (thesis Fig 6.13): colour = smallest tau of instability over the degrees m
and kinds of a tau-map sweep, bands labelled m H/S, optional labelled boxes."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ._canvas import save_figure, subplots
from ..errors import ParameterError
from ..results.maps import uncertified, unstable_at
from .sweep_plot import axis_label, cell_edges, colour_label, draw_map, picture_axes

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


#: Colours of the unstable-pairs panel (:func:`draw_unstable_pairs`), by which kinds are unstable.
PAIR_COLOURS = {"stable": "0.93", "harmonic": "tab:blue", "subharmonic": "tab:red",
                "both": "tab:purple", "unproved": "black"}


def draw_unstable_pairs(ax, ds: xr.Dataset, x: str, at: dict[str, float], tau: float) -> None:
    """Which (x, m) of a tau-map sweep ``ds`` are unstable at forcing amplitude ``tau``, at the
    grid values ``at`` of its other real axes: a cell per (x, m) coloured by the kinds whose
    tau_min <= tau (harmonic, subharmonic, both, or stable), x horizontal, m vertical; black
    ("unproved") where neither is unstable but an empty answer below tau is not proved
    (:func:`~spectralshell.results.maps.uncertified`)."""
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    unstable = unstable_at(ds, x, at, tau)
    harmonic = unstable.sel(kind="harmonic").values
    subharmonic = unstable.sel(kind="subharmonic").values
    code = np.where(harmonic & subharmonic, 3, np.where(subharmonic, 2, harmonic.astype(int)))
    unproved = uncertified(ds).sel(at).any("kind").transpose("m", x).values
    code = np.where((code == 0) & unproved, 4, code)
    names = ("stable", "harmonic", "subharmonic", "both", "unproved")
    ax.pcolormesh(cell_edges(ds[x]), cell_edges(ds["m"]), code, vmin=-0.5, vmax=4.5,
                  cmap=ListedColormap([PAIR_COLOURS[n] for n in names]))
    ax.set_yticks(ds["m"].values)
    ax.set_xlabel(axis_label(ds[x]))
    ax.set_ylabel("m, azimuthal wavenumber")
    where = ", ".join(f"{k} = {v:.4g}" for k, v in at.items())
    ax.set_title(f"unstable (m, {x}) at τ = {tau:g} ({where})", fontsize=9)
    shown = [n for n in names if n != "unproved" or unproved.any()]
    ax.legend(handles=[Patch(color=PAIR_COLOURS[n], label=n) for n in shown],
              loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=len(shown), fontsize=7,
              frameon=False)


def save_with_pairs(ds: xr.Dataset, path: str | Path, *, x: str, at: dict[str, float],
                    tau: float) -> Path:
    """:func:`draw` of the sweep beside :func:`draw_unstable_pairs` at ``at`` and ``tau``."""
    fig, (left, right) = subplots(1, 2, figsize=(13.0, 5.8),
                                  gridspec_kw={"width_ratios": [1.35, 1.0]})
    draw(left, ds)
    draw_unstable_pairs(right, ds, x, at, tau)
    return save_figure(fig, path, dpi=120)
