"""The one matplotlib set-up of plots/: figures made without pyplot, and how one is written.

Figures are ``matplotlib.figure.Figure`` objects, drawn and saved without pyplot, so importing
the plots never selects or changes the user's backend (a notebook keeps its inline backend) and
no figure is left open in pyplot's registry.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib
from matplotlib.figure import Figure

__all__ = ["axes_or_new", "colours", "figure", "subplots", "save_figure"]


#: Points with no tau found whose emptiness is not proved (issue 23): red crosses on curves and
#: diagrams, red cross-hatching on maps, under this legend name.
UNCERTIFIED_COLOUR = "tab:red"
UNCERTIFIED_LABEL = "unproved: no τ found, none proved"


def figure(*, figsize: tuple[float, float]) -> Figure:
    """A new figure of ``figsize`` inches, outside pyplot."""
    return Figure(figsize=figsize)


def subplots(nrows: int = 1, ncols: int = 1, *, figsize: tuple[float, float], **kwargs):
    """(figure, axes) as ``pyplot.subplots`` returns them, outside pyplot."""
    fig = figure(figsize=figsize)
    return fig, fig.subplots(nrows, ncols, **kwargs)


def axes_or_new(ax, *, figsize: tuple[float, float] = (6.4, 4.6)):
    """``ax`` itself, or (``ax`` None) the axes of a new figure of ``figsize`` inches."""
    return ax if ax is not None else subplots(figsize=figsize)[1]


def colours() -> list[str]:
    """The colours of the current property cycle (matplotlib's rcParams)."""
    return matplotlib.rcParams["axes.prop_cycle"].by_key()["color"]


def save_figure(fig: Figure, path: str | Path, *, dpi: int = 120,
                rect: tuple[float, float, float, float] | None = None) -> Path:
    """Lay out ``fig`` (inside ``rect``, figure coordinates) and write it as PNG."""
    fig.tight_layout(rect=rect)
    path = Path(path)
    fig.savefig(path, dpi=dpi)
    return path
