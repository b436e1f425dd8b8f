"""Natural modes: one result's modes in the complex gamma plane, and the least-damped mode
against zeta (thesis Fig 7.1): decay rate (top) and frequency (bottom)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from ._canvas import colours, save_figure, subplots
from ..results.base import format_params
from ..results.modes import NaturalModesResult


def draw(ax, result: NaturalModesResult) -> None:
    """The modes of ``result`` as points (Re gamma, Im gamma) with their error bars."""
    unit = result.params.get("units", "dimensionless")
    err = result.error_estimate
    ax.errorbar(result.gamma.real, result.gamma.imag, xerr=err, yerr=err, fmt="o", mfc="none",
                label="natural modes γ (X ~ exp(γt))")
    ax.axvline(0.0, color="0.4", linewidth=0.8)
    ax.set_xlabel(f"Re γ, growth rate (< 0: decaying; {unit})")
    ax.set_ylabel(f"Im γ, angular frequency ({unit})")
    ax.set_title(f"{result.model} natural modes: {format_params(result.params)}", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)


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
