"""Ince-Strutt diagrams (thesis Figs 2.2, 2.3, 6.2, 6.3, 6.12): tau against kappa, harmonic '+', subharmonic 'o'."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from ._canvas import save_figure, subplots
from ..results.floquet import FloquetResult, TonguesResult

STYLE = {"harmonic": dict(marker="+", color="tab:blue", label="harmonic (γ = 0)"),
         "subharmonic": dict(marker="o", mfc="none", color="tab:red", label="subharmonic (γ = i/2)")}


def draw(ax, result: TonguesResult, *, tau_max: float = 1.0, title: str | None = None,
         x_scale: float = 1.0, x_label: str = "κ, stiffness (dimensionless)") -> None:
    """Draw one diagram on ``ax``: marginal points, finger tips, the tau = 1/2 line.

    The abscissa is ``x_scale * kappa`` (e.g. sigma = rho R^3 omega^2 kappa, in dyn/cm)."""
    for kind in result.kinds:
        k, t = result.points(kind)
        keep = t <= tau_max
        ax.plot(x_scale * k[keep], t[keep], linestyle="none", markersize=3, **STYLE[kind])
    tips = [tip for tip in result.tips if tip.tau <= tau_max]
    if tips:
        ax.plot([x_scale * t.kappa for t in tips], [t.tau for t in tips], "k*", markersize=9,
                label="finger tips")
    ax.axhline(0.5, color="0.4", linestyle="--", linewidth=1,
               label="τ = 1/2 (stiffness reaches 0)")
    ax.set_xlim(x_scale * result.kappa.min(), x_scale * result.kappa.max())
    ax.set_ylim(0, tau_max)
    ax.set_xlabel(x_label)
    ax.set_ylabel("τ, forcing amplitude (dimensionless)")
    names = {"nu": "ν", "m": "m"}
    label = ", ".join(f"{names.get(k, k)} = {v:g}" if isinstance(v, (int, float)) else f"{v}"
                      for k, v in result.params.items())
    ax.set_title(title or f"{result.model}: {label}", fontsize=9)
    # below the axes: inside, the legend would hide marginal points wherever it stood
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=4, fontsize=7, frameon=False)


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


def save(results: Sequence[TonguesResult], path: str | Path, *, tau_max: float = 1.0,
         columns: int | None = None, **draw_options) -> Path:
    """Write one PNG with a panel per result (row-major, ``columns`` per row; default one row)."""
    columns = columns or len(results)
    rows = -(-len(results) // columns)
    fig, axes = subplots(rows, columns, figsize=(6.4 * columns, 4.6 * rows), squeeze=False)
    for ax, res in zip(axes.flat, results):
        draw(ax, res, tau_max=tau_max, **draw_options)
    return save_figure(fig, path, dpi=120)
