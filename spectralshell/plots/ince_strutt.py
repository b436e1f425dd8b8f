"""Ince-Strutt diagrams (thesis Figs 2.2, 2.3, 4.1, 6.2, 6.3, 6.12): tau against kappa, each
boundary a traced curve (harmonic blue, subharmonic red), the unstable region of each kind
shaded in its colour, the finger tips starred."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path as FilePath

import numpy as np
from matplotlib.patches import PathPatch
from matplotlib.path import Path

from ._canvas import UNCERTIFIED_COLOUR, UNCERTIFIED_LABEL, save_figure, subplots
from ..results.floquet import FloquetResult, TonguesResult
from ..results.records import Boundary

STYLE = {"harmonic": dict(marker="+", color="tab:blue", label="harmonic (γ = 0)"),
         "subharmonic": dict(marker="o", mfc="none", color="tab:red", label="subharmonic (γ = i/2)")}
#: Opacity of the shaded unstable regions (where both kinds are unstable the colours mix).
SHADE_ALPHA = 0.2


def unstable_bands(boundaries: Sequence[Boundary], tau_max: float) -> list[np.ndarray]:
    """Polygons (n x 2 arrays of (kappa, tau)) covering the unstable region of one kind.

    Between neighbouring vertex kappa, every boundary segment spanning the interval is a line;
    ordered by height, the tau between the 1st and 2nd line, the 3rd and 4th, ... (and from the
    last line to ``tau_max`` when their number is odd) are unstable: each boundary crossed
    moves one real Floquet multiplier of the kind through +1 (harmonic) or -1 (subharmonic),
    and at small tau none lies beyond. This is the parity of those multipliers: where two
    fingers of one kind overlap (two beyond), the overlap is left unshaded. A band that
    continues into the next interval (same lines where they meet) extends the same polygon, so
    that no seams show.
    """
    k0, k1, t0, t1 = [], [], [], []
    for b in boundaries:
        a, c = b.kappa[:-1], b.kappa[1:]
        flip = a > c
        k0.append(np.where(flip, c, a))
        k1.append(np.where(flip, a, c))
        t0.append(np.where(flip, b.tau[1:], b.tau[:-1]))
        t1.append(np.where(flip, b.tau[:-1], b.tau[1:]))
    if not k0:
        return []
    k0, k1, t0, t1 = (np.concatenate(v) for v in (k0, k1, t0, t1))
    columns = np.unique(np.concatenate([k0, k1]))
    done, open_ = [], []           # bands as (lower edge, upper edge) point lists
    for left, right in zip(columns[:-1], columns[1:]):
        span = (k0 <= left) & (k1 >= right) & (k1 > k0)
        w = (np.array([left, right])[:, None] - k0[span]) / (k1[span] - k0[span])
        ends = t0[span] + w * (t1[span] - t0[span])            # 2 x lines: tau at left, right
        ends = ends[:, np.argsort(ends.sum(axis=0))]
        if ends.shape[1] % 2:
            ends = np.hstack([ends, [[tau_max], [tau_max]]])
        still = []
        for lo, hi in zip(ends.T[0::2], ends.T[1::2]):
            band = next((b for b in open_ if np.isclose(b[0][-1][1], lo[0], rtol=0, atol=1e-12)
                         and np.isclose(b[1][-1][1], hi[0], rtol=0, atol=1e-12)), None)
            if band is None:
                band = ([(left, lo[0])], [(left, hi[0])])
            else:
                open_.remove(band)
            band[0].append((right, lo[1]))
            band[1].append((right, hi[1]))
            still.append(band)
        done += open_
        open_ = still
    return [np.array(lower + upper[::-1]) for lower, upper in done + open_]


def _points(ax, result: TonguesResult, kind: str, tau_max: float, x_scale: float) -> None:
    """The marginal points of one kind, for a result whose boundaries were not traced."""
    k, t = result.points(kind)
    keep = t <= tau_max
    ax.plot(x_scale * k[keep], t[keep], linestyle="none", markersize=3, **STYLE[kind])


def draw_boundaries(ax, boundaries: Sequence[Boundary], kind: str, *, tau_max: float,
                    x_scale: float = 1.0) -> None:
    """The boundary curves of one kind and its shaded unstable region (:func:`unstable_bands`),
    the abscissa ``x_scale * kappa``."""
    curves = [b for b in boundaries if b.kind == kind]
    colour = STYLE[kind]["color"]
    bands = [Path(np.vstack([q, q[:1]]) * (x_scale, 1.0), closed=True)
             for q in unstable_bands(curves, tau_max)]
    for i, b in enumerate(curves):
        ax.plot(x_scale * b.kappa, b.tau, color=colour, linewidth=1.3,
                label=f"{kind} boundary" if i == 0 else None)
    gamma = "γ = 0" if kind == "harmonic" else "γ = i/2"
    if bands:  # one compound path: bands that meet are filled without a seam between
        ax.add_patch(PathPatch(Path.make_compound_path(*bands), facecolor=colour,
                               alpha=SHADE_ALPHA, linewidth=0, label=f"{kind} unstable ({gamma})"))


def draw(ax, result: TonguesResult, *, tau_max: float = 1.0, title: str | None = None,
         x_scale: float = 1.0, x_label: str = "κ, stiffness (dimensionless)",
         legend: bool = True) -> None:
    """Draw one diagram on ``ax``: each traced boundary as a curve, the unstable region of
    each kind shaded (:func:`draw_boundaries`), the finger tips, the tau = 1/2 line, and (with
    ``legend``) a legend below the axes. A result traced without boundaries shows its marginal
    points instead. Its ``uncertified`` kappa (no tau found, none proved) get red crosses at
    the top, named in the legend.

    The abscissa is ``x_scale * kappa`` (e.g. sigma = rho R^3 omega^2 kappa, in dyn/cm)."""
    for kind in result.kinds:
        if any(b.kind == kind for b in result.boundaries):
            draw_boundaries(ax, result.boundaries, kind, tau_max=tau_max, x_scale=x_scale)
        else:
            _points(ax, result, kind, tau_max, x_scale)
    tips = [tip for tip in result.tips if tip.tau <= tau_max]
    if tips:
        ax.plot([x_scale * t.kappa for t in tips], [t.tau for t in tips], "k*", markersize=9,
                label="finger tips", zorder=4)
    if result.uncertified:  # no tau found there, none proved: not the blank of "none"
        ax.plot([x_scale * k for k, _ in result.uncertified],
                [0.97 * tau_max] * len(result.uncertified), "x", color=UNCERTIFIED_COLOUR,
                ms=7, mew=1.5, label=UNCERTIFIED_LABEL, zorder=5)
    ax.axhline(0.5, color="0.4", linestyle="--", linewidth=1,
               label="τ = 1/2 (stiffness reaches 0)")
    ax.set_xlim(x_scale * result.kappa.min(), x_scale * result.kappa.max())
    ax.set_ylim(-0.025 * tau_max, tau_max)  # a margin: markers on tau = 0 stay whole
    ax.set_xlabel(x_label)
    ax.set_ylabel("τ, forcing amplitude (dimensionless)")
    names = {"nu": "ν", "m": "m"}
    label = ", ".join(f"{names.get(k, k)} = {v:g}" if isinstance(v, (int, float)) else f"{v}"
                      for k, v in result.params.items())
    ax.set_title(title or f"{result.model}: {label}", fontsize=9)
    if legend:  # below the axes: inside, it would hide part of the diagram wherever it stood
        ax.legend(*legend_entries([ax]), loc="upper center", bbox_to_anchor=(0.5, -0.14),
                  ncol=3, fontsize=7, frameon=False)


def legend_entries(axes) -> tuple[list, list[str]]:
    """(handles, labels) of every distinct label drawn on ``axes`` (one legend per figure)."""
    entries: dict[str, object] = {}
    for ax in axes:
        for handle, label in zip(*ax.get_legend_handles_labels()):
            entries.setdefault(label, handle)
    return list(entries.values()), list(entries)


def draw_marginals(ax, result: FloquetResult, *, tau_max: float | None = None) -> None:
    """Every marginal tau of each kind of a Floquet result on a tau axis (one row per kind),
    tau_min ringed, the tau = 1/2 line; up to ``tau_max`` (default: the largest shown, or 1)."""
    kinds = result.marginals()
    if tau_max is None:
        tau_max = max([1.0, *(float(m.tau.max()) for m in kinds if m.tau.size)])
    for row, m in enumerate(kinds):
        shown = m.tau[m.tau <= tau_max]
        ax.plot(shown, [row] * shown.size, linestyle="none", markersize=7, **STYLE[m.kind])
        if m.tau_min is not None:
            ax.plot([m.tau_min], [row], "k*", markersize=10, label=f"{m.kind} τ_min = {m.tau_min:.6g}")
    ax.axvline(0.5, color="0.4", linestyle="--", linewidth=1, label="τ = 1/2 (stiffness reaches 0)")
    ax.set_yticks(range(len(kinds)), [m.kind for m in kinds])
    ax.set_ylabel("Floquet kind")
    ax.set_ylim(-0.7, len(kinds) - 0.3)
    ax.set_xlim(0, tau_max)
    ax.set_xlabel("τ, forcing amplitude (dimensionless): marginal values (a multiplier on ±1)")
    names = {"nu": "ν", "kappa": "κ", "m": "m"}
    ax.set_title(f"{result.model}: " + ", ".join(
        f"{names.get(k, k)} = {v:g}" if isinstance(v, (int, float)) else f"{k} = {v}"
        for k, v in result.params.items() if v is not None), fontsize=9)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.3), ncol=3, fontsize=7, frameon=False)


def save(results: Sequence[TonguesResult], path: str | FilePath, *, tau_max: float = 1.0,
         columns: int | None = None, **draw_options) -> FilePath:
    """Write one figure with a panel per result (row-major, ``columns`` per row; default one
    row) and one legend below the panels."""
    columns = columns or len(results)
    rows = -(-len(results) // columns)
    fig, axes = subplots(rows, columns, figsize=(6.4 * columns, 4.3 * rows), squeeze=False)
    for ax, res in zip(axes.flat, results):
        draw(ax, res, tau_max=tau_max, legend=False, **draw_options)
    handles, labels = legend_entries(axes.flat)
    ncol = 4 if columns > 1 else 2
    margin = 0.15 + 0.22 * -(-len(labels) // ncol)        # inches under the panels
    fig.set_size_inches(6.4 * columns, 4.3 * rows + margin)
    fig.legend(handles, labels, loc="lower center", ncol=ncol, fontsize=8, frameon=False)
    return save_figure(fig, path, dpi=120, rect=(0, margin / (4.3 * rows + margin), 1, 1))
