"""Pictures of a stored sweep Dataset: tau_min along one axis, or a minimum-tau map over two.

The real-valued axes with more than one value are the picture's axes; the others (m, kind,
component, ...) are categories: one curve each in 1-D; in 2-D the colour is the smallest tau_min
over them and each band is labelled by the category attaining it, e.g. '3S' = m 3,
subharmonic (as thesis Fig 6.13). Points without a marginal tau <= tau_max (``has_tau`` false,
whatever ``tau_min`` holds there: tau_max or NaN), or not yet computed, are drawn in their own
light grey (:data:`NONE_COLOUR`, named in the legend), apart from every colour of the scale. Where a sweep refined the number of spatial modes per point (the cochlea), cells
whose refinement did not converge by its limit (M = 512 per kind, 1024 for the minimum over
kinds) for some category (``spatial_converged`` false) are drawn grey and hatched, whatever their
value, and the title counts them. Points where no tau was found but the zero count could not
prove that none exists (:func:`~spectralshell.results.maps.uncertified`; issue 23) are never
drawn as "none": cells are cross-hatched in red (:data:`UNCERTIFIED_COLOUR`), curves get a red
cross at the top of the axes, both named in the legend and counted in the title.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import xarray as xr
from matplotlib.colors import ListedColormap
from matplotlib.patches import Patch, Rectangle
from scipy import ndimage

from ._canvas import UNCERTIFIED_COLOUR, UNCERTIFIED_LABEL, colours, save_figure, subplots
from ..errors import ParameterError
from ..results.maps import minimum_map, uncertified

#: Cells without instability ("none": no tau <= tau_max): a neutral light grey, which neither
#: colour map used here (Blues_r up to a light blue, viridis up to yellow) contains.
NONE_COLOUR = "0.82"
#: Cells whose M refinement did not converge: a darker grey under black hatching.
UNCONVERGED_COLOUR = "0.55"

SYMBOLS = {"kappa": "κ", "nu": "ν", "sigma": "σ", "omega": "ω", "mu": "μ", "rho": "ρ",
           "radius": "R", "bpm": "beat rate", "frequency": "f", "length": "L",
           "lambda_c": "λ_c", "alpha": "α"}


def axis_label(coord: xr.DataArray) -> str:
    """'long name symbol (units)', e.g. 'membrane stiffness σ (dyn/cm)'."""
    name = str(coord.name)
    units = coord.attrs.get("units", "")
    units = "dimensionless" if units in ("1", "") else units
    long_name = coord.attrs.get("long_name", name)
    symbol = SYMBOLS.get(name, name)
    if symbol in long_name:
        text = long_name
    elif name in long_name.split():
        text = " ".join(symbol if w == name else w for w in long_name.split())
    else:
        text = f"{long_name} {symbol}"
    return f"{text} ({units})"


def picture_axes(ds: xr.Dataset) -> tuple[list[str], list[str]]:
    """(real axes with > 1 value, category dims) of ``tau_min``."""
    dims = list(ds["tau_min"].dims)
    real = [d for d in dims if ds[d].dtype.kind == "f" and ds.sizes[d] > 1]
    return real, [d for d in dims if d not in real]


def _title(ds: xr.Dataset, fixed: dict) -> str:
    done = ds["computed"].values
    extra = "" if done.all() else f" — incomplete: {int(done.sum())} of {done.size} points"
    unproved = int(uncertified(ds).sum())
    extra += f" — {unproved} points unproved (no τ found, none proved)" if unproved else ""
    shown = ", ".join(f"{k} = {v:g}" if isinstance(v, float) else f"{k} = {v}"
                      for k, v in fixed.items())
    return f"{ds.attrs.get('model', 'sweep')}: {shown}{extra}".strip()


def _fixed(ds: xr.Dataset, drop: list[str]) -> dict:
    import json

    out = dict(json.loads(ds.attrs.get("params", "{}")))
    for d in ds["tau_min"].dims:
        if d not in drop and ds.sizes[d] == 1:
            v = ds[d].values[0]
            out[d] = v.item() if hasattr(v, "item") else v
    return out


def _valid(ds: xr.Dataset) -> np.ndarray:
    return ds["has_tau"].values & ds["computed"].values


def _scale(ax, ds: xr.Dataset, name: str, which: str) -> None:
    if ds[name].attrs.get("spacing") == "log":
        getattr(ax, f"set_{which}scale")("log")


def _curve_label(ds: xr.Dataset, cats: list[str], index: tuple[int, ...]) -> str:
    """Legend text of one category combination, in words: 'm = 3, subharmonic' (each value
    with more than one choice; the kind always)."""
    return ", ".join(str(ds[d].values[i]) if d == "kind" else f"{d} = {ds[d].values[i]}"
                     for d, i in zip(cats, index) if ds.sizes[d] > 1 or d == "kind")


def _line(ax, ds: xr.Dataset, axis: str, cats: list[str]) -> None:
    tau = ds["tau_min"].transpose(axis, *cats).values
    ok = _valid(ds.transpose(axis, *cats))
    x = ds[axis].values
    order = np.argsort(x)
    styles = {"harmonic": "-", "subharmonic": "--"}
    cycle = colours()
    non_kind = [d for d in cats if d != "kind"]
    for index in itertools.product(*(range(ds.sizes[d]) for d in cats)):
        y = np.where(ok[(slice(None),) + index], tau[(slice(None),) + index], np.nan)
        kind = str(ds["kind"].values[index[cats.index("kind")]]) if "kind" in cats else ""
        group = tuple(i for d, i in zip(cats, index) if d != "kind")
        colour = cycle[(np.ravel_multi_index(group, [ds.sizes[d] for d in non_kind])
                        if group else 0) % len(cycle)]
        label = _curve_label(ds, cats, index) or None
        ax.plot(x[order], y[order], styles.get(kind, "-"), color=colour, label=label, lw=1.4)
    tau_max = float(ds.attrs.get("tau_max", np.nanmax(tau)))
    bad = uncertified(ds).any([d for d in cats]).transpose(axis).values if cats else \
        uncertified(ds).values
    if bad.any():
        ax.plot(x[bad], np.full(int(bad.sum()), 0.97 * tau_max), "x",
                color=UNCERTIFIED_COLOUR, label=UNCERTIFIED_LABEL, ms=7, mew=1.5)
    ax.set_ylim(0.0, tau_max)
    ax.set_xlabel(axis_label(ds[axis]))
    ax.set_ylabel(f"τ_min, smallest marginal τ ≤ {tau_max:g}")
    _scale(ax, ds, axis, "x")
    if cats or bad.any():
        ax.legend(fontsize=7, ncol=2)
    ax.set_title(_title(ds, _fixed(ds, [axis] + [d for d in cats if ds.sizes[d] > 1])),
                 fontsize=9)


def _band_labels(ax, x: np.ndarray, y: np.ndarray, code: np.ndarray, labels: list[str],
                 min_cells: int) -> None:
    for value in np.unique(code[code >= 0]):
        regions, count = ndimage.label(code == value)
        for r in range(1, count + 1):
            iy, ix = np.nonzero(regions == r)
            if iy.size >= min_cells and labels[value]:
                ax.text(x[int(round(ix.mean()))], y[int(round(iy.mean()))], labels[value],
                        ha="center", va="center", fontsize=7)


def cell_edges(ds: xr.DataArray) -> np.ndarray:
    """Cell edges around sorted axis values: geometric midpoints on a log axis, arithmetic
    otherwise (one value: a cell of +-10 %)."""
    v = np.asarray(ds.values, dtype=float)
    if v.size == 1:
        return np.array([0.9 * v[0], 1.1 * v[0]]) if v[0] else np.array([-0.5, 0.5])
    log = ds.attrs.get("spacing") == "log"
    w = np.log(v) if log else v
    mid = 0.5 * (w[1:] + w[:-1])
    e = np.concatenate([[2 * w[0] - mid[0]], mid, [2 * w[-1] - mid[-1]]])
    return np.exp(e) if log else e


def unconverged(ds: xr.Dataset, xname: str, yname: str) -> np.ndarray:
    """(y, x) mask of cells where some category's refinement in M did not converge (all false
    for a sweep without the variable ``spatial_converged``)."""
    if "spatial_converged" not in ds:
        return np.zeros((ds.sizes[yname], ds.sizes[xname]), dtype=bool)
    bad = ~ds["spatial_converged"] & ds["computed"]
    others = [d for d in bad.dims if d not in (xname, yname)]
    return bad.any(dim=others).transpose(yname, xname).values


def draw_map(ax, ds: xr.Dataset, xname: str, yname: str, *, min_cells: int = 6,
             labels: bool = True, cmap: str = "Blues_r", headroom: float = 1.0,
             boxes: Sequence[tuple[tuple[float, float], tuple[float, float], str, str]] = ()):
    """Minimum tau_min over the categories (:func:`~spectralshell.results.maps.minimum_map`)
    on the (x, y) cells of ``ax``: light grey (:data:`NONE_COLOUR`) where none <= tau_max (by
    ``has_tau``), grey hatched where the M refinement did not converge, red cross-hatched where
    an empty answer is not proved (``uncertified``); the colour scale runs to
    ``headroom`` x tau_max (above 1 it stops short of a colour map's white end). ``boxes`` are
    ((x0, x1), (y0, y1), label, colour) rectangles. A legend below the axes names "none", the
    hatchings and the boxes. Returns (mesh, number of hatched cells)."""
    ds = ds.sortby([xname, yname])
    mm = minimum_map(ds, xname, yname)
    found = mm["has_tau"].values
    values = mm["tau_min"].values
    tau_max = float(ds.attrs.get("tau_max", np.max(values[found], initial=0.0)))
    xe, ye = cell_edges(ds[xname]), cell_edges(ds[yname])
    ax.pcolormesh(xe, ye, np.ma.masked_where(found, np.zeros(found.shape)),
                  cmap=ListedColormap([NONE_COLOUR]), shading="flat")
    mesh = ax.pcolormesh(xe, ye, np.ma.masked_where(~found, values), cmap=cmap, vmin=0.0,
                         vmax=headroom * tau_max, shading="flat")
    unproved = mm["uncertified"].values
    handles = [Patch(facecolor=NONE_COLOUR, edgecolor="0.5", linewidth=0.5,
                     label=f"none: no τ ≤ {tau_max:g}")] if (~found & ~unproved).any() else []
    if unproved.any():  # over their colour: neither the value nor "none" is proved there
        ax.pcolor(xe, ye, np.ma.masked_where(~unproved, np.ones(found.shape)),
                  cmap=ListedColormap(["white"]), hatch="xxx", edgecolor=UNCERTIFIED_COLOUR,
                  linewidth=0.0)
        handles.append(Patch(facecolor="white", hatch="xxx", edgecolor=UNCERTIFIED_COLOUR,
                             label=UNCERTIFIED_LABEL))
    bad = unconverged(ds, xname, yname)
    if bad.any():
        ax.pcolor(xe, ye, np.ma.masked_where(~bad, np.ones(found.shape)),
                  cmap=ListedColormap([UNCONVERGED_COLOUR]), hatch="///", edgecolor="0.15",
                  linewidth=0.0)
        handles.append(Patch(facecolor=UNCONVERGED_COLOUR, hatch="///", edgecolor="0.15",
                             label="not converged in M"))
    for (x0, x1), (y0, y1), label, colour in boxes:
        handles.append(ax.add_patch(Rectangle(
            (x0, y0), x1 - x0, y1 - y0, fill=False, edgecolor=colour, label=label,
            linestyle="-" if colour == "tab:blue" else "--", linewidth=1.5)))
    if labels:
        names, code = np.unique(mm["label"].values, return_inverse=True)
        _band_labels(ax, ds[xname].values, ds[yname].values,
                     np.where(found & ~bad & ~unproved, code.reshape(found.shape), -1),
                     list(names),
                     min_cells)
    if handles:  # below the axes: inside, the legend would cover cells of the map
        ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.11),
                  ncol=len(handles), fontsize=7, frameon=False)
    ax.set_xlabel(axis_label(ds[xname]))
    ax.set_ylabel(axis_label(ds[yname]))
    _scale(ax, ds, xname, "x")
    _scale(ax, ds, yname, "y")
    ax.set_xlim(xe[0], xe[-1])
    ax.set_ylim(ye[0], ye[-1])
    return mesh, int(bad.sum())


def colour_label(tau_max: float) -> str:
    """Colour-bar label of a minimum-tau map."""
    return f"minimum τ of instability (≤ {tau_max:g})"


def hatch_note(ds, count: int, cells: int) -> str:
    """Title note counting the hatched cells ('' when there are none), with the largest M the
    refinement reached (the limit: 512 per kind, 1024 for the minimum over kinds)."""
    if not count:
        return ""
    largest = int(ds["n_spatial"].max()) if "n_spatial" in ds else None
    where = f"M ≤ {largest}" if largest else "M"
    return f"; hatched grey: {count} of {cells} points not converged in {where}"


def _map(ax, ds: xr.Dataset, xname: str, yname: str, cats: list[str], min_cells: int) -> None:
    tau_max = float(ds.attrs.get("tau_max", ds["tau_min"].max()))
    mesh, hatched = draw_map(ax, ds, xname, yname, min_cells=min_cells)
    ax.figure.colorbar(mesh, ax=ax, label=colour_label(tau_max))
    over = ", ".join(f"{d} = {', '.join(str(v) for v in ds[d].values)}" for d in cats
                     if ds.sizes[d] > 1)
    labels_note = " (labels: " + ("m, " if "m" in cats else "") + "H harmonic / S subharmonic)"
    fixed = _fixed(ds, [xname, yname] + [d for d in cats if ds.sizes[d] > 1])
    note = hatch_note(ds, hatched, ds.sizes[xname] * ds.sizes[yname])
    ax.set_title(_title(ds, fixed) + (f"\nminimum over {over}{labels_note}" if over else "")
                 + note, fontsize=8)


def draw(ax, ds: xr.Dataset, *, min_cells: int = 6) -> None:
    """Draw a sweep Dataset on ``ax``: a line plot for one real axis, a labelled minimum-tau
    map with its colour bar for two (the first grid axis horizontal).

    Raises
    ------
    ParameterError : the sweep has no tau_min/has_tau, or not one or two real axes with
        several values.
    """
    if "tau_min" not in ds or "has_tau" not in ds:
        raise ParameterError("sweep is invalid for plotting: it has no tau_min/has_tau variables")
    real, cats = picture_axes(ds)
    if len(real) == 1:
        _line(ax, ds, real[0], cats)
    elif len(real) == 2:
        _map(ax, ds, real[0], real[1], cats, min_cells)
    else:
        raise ParameterError(f"sweep axes {real!r} are invalid for a picture: plot draws one or "
                             "two real axes with several values")


def save(ds: xr.Dataset, path: str | Path, *, min_cells: int = 6, dpi: int = 120) -> Path:
    """Write :func:`draw` of a sweep Dataset to ``path`` (PNG, SVG or PDF by its suffix)."""
    two = len(picture_axes(ds)[0]) == 2 if "tau_min" in ds else False
    fig, ax = subplots(figsize=(7.5, 5.5) if two else (7.0, 4.5))
    draw(ax, ds, min_cells=min_cells)
    return save_figure(fig, path, dpi=dpi)
