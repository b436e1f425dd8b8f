"""Figures of a time-stepped sphere: mode amplitudes against time (like thesis Figs 6.8-6.11, 7.2)
and snapshots of the membrane shape."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import matplotlib
import matplotlib.cm
import matplotlib.colors

import numpy as np

from ._canvas import colours, figure, save_figure, subplots
from ..results.trajectory import Trajectory

FLOOR = 1e-14   # lower limit of the log panel (relative amplitude)


def _rescaled(traj: Trajectory):
    """Per mode: (label, colour, fit or None, X^Y(t) / X^Y(0)) (the largest |X^Y| where X^Y(0) = 0)."""
    fits = {(f.m, f.k): f for f in traj.fits}
    for j, ((m, k), colour) in enumerate(zip(traj.modes, colours() * 10)):
        x = traj.radial[:, j]
        x0 = x[0] if x[0] != 0 else np.max(np.abs(x)) or 1.0
        label = f"(m, k) = ({m}, {k})"
        fit = fits.get((m, k))
        if fit is not None:
            label += f": growth {fit.growth_rate:+.4g}, frequency {fit.frequency:.4g}"
        yield label, colour, fit, x / x0


def _title(traj: Trajectory) -> str:
    p = traj.params
    return (f"sphere: κ = {p['kappa']:g}, ν = {p['nu']:g}, τ = {p['tau']:g}  "
            f"({p['scheme']}, Δt = {p['dt']:.3g})")


def draw_amplitudes(ax, traj: Trajectory) -> None:
    """Each radial coefficient X^Y_{m,k}(t) rescaled to start at 1 (as the thesis's radial
    projections), one labelled line per mode."""
    for label, colour, _, y in _rescaled(traj):
        ax.plot(traj.times, y, color=colour, linewidth=0.9, label=label)
    ax.set_title(_title(traj), fontsize=9)
    ax.set_ylabel(r"$X^Y(t)\,/\,X^Y(0)$")
    ax.set_xlabel("t (forcing period 2π)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)


def draw_log_amplitudes(ax, traj: Trajectory) -> None:
    """|X^Y(t) / X^Y(0)| on a log scale, each with its fitted envelope exp(growth_rate t) dashed."""
    t = traj.times
    lowest = 1.0
    for label, colour, fit, y in _rescaled(traj):
        relative = np.maximum(np.abs(y), FLOOR)
        lowest = min(lowest, np.min(relative[relative > FLOOR], initial=1.0))
        ax.semilogy(t, relative, color=colour, linewidth=0.6, label=label.split(":")[0])
        if fit is not None:
            ax.semilogy(t, np.exp(fit.growth_rate * (t - t[0])), color=colour, linestyle="--",
                        linewidth=0.8, label=f"fitted envelope exp({fit.growth_rate:+.3g} t)")
    ax.set_ylabel(r"$|X^Y(t)\,/\,X^Y(0)|$")
    ax.set_xlabel("t (forcing period 2π)")
    ax.set_ylim(bottom=max(FLOOR, lowest / 10))
    ax.grid(alpha=0.3)


def save_amplitudes(traj: Trajectory, path: str | Path) -> Path:
    """Top: :func:`draw_amplitudes`; bottom: :func:`draw_log_amplitudes`."""
    fig, (top, bottom) = subplots(2, 1, figsize=(7.5, 6.5), sharex=True)
    draw_amplitudes(top, traj)
    top.set_xlabel("")
    draw_log_amplitudes(bottom, traj)
    bottom.legend(fontsize=6, ncol=2)
    return save_figure(fig, path, dpi=120)


def save_shape(theta: np.ndarray, phi: np.ndarray, displacements: Sequence[np.ndarray],
               times: Sequence[float], path: str | Path, *, size: float = 0.25) -> Path:
    """3D snapshots of the membrane r = 1 + a X^Y(theta, phi, t) at ``times``, each exaggerated
    (factor a per panel) to a largest displacement ``size``, coloured by the displacement
    (as thesis Fig 6.7 colours the distance from the origin)."""
    n = len(times)
    fig = figure(figsize=(3.2 * n + 1.0, 3.8))
    th = np.concatenate([[0.0], theta, [np.pi]])
    ph = np.concatenate([phi, [2 * np.pi]])
    TH, PH = np.meshgrid(th, ph, indexing="ij")
    cmap = matplotlib.colormaps["coolwarm"]
    for i, (X, t) in enumerate(zip(displacements, times)):
        X = np.concatenate([X, X[:, :1]], axis=1)                 # close the seam at phi = 2 pi
        X = np.vstack([np.full((1, X.shape[1]), X[0].mean()), X,
                       np.full((1, X.shape[1]), X[-1].mean())])   # the poles
        peak = np.max(np.abs(X))
        a = size / peak if peak > 0 else 1.0
        R = 1.0 + a * X
        ax = fig.add_subplot(1, n, i + 1, projection="3d")
        x, y, z = R * np.sin(TH) * np.cos(PH), R * np.sin(TH) * np.sin(PH), R * np.cos(TH)
        ax.plot_surface(x, y, z, facecolors=cmap(0.5 + 0.5 * X / (peak or 1.0)), rstride=1,
                        cstride=1, linewidth=0, antialiased=False, shade=False)
        ax.set_box_aspect((1, 1, 1))
        ax.set_axis_off()
        ax.set_title(f"t = {t:.4g}\n" + r"max $|X^Y|$" + f" = {peak:.2e} (×{a:.3g})", fontsize=8)
    # each panel is coloured by X^Y / max|X^Y| of its own snapshot: one shared scale [-1, 1]
    scale = matplotlib.cm.ScalarMappable(norm=matplotlib.colors.Normalize(-1.0, 1.0), cmap=cmap)
    fig.subplots_adjust(left=0.0, right=0.88, bottom=0.02, top=0.8, wspace=0.05)
    cax = fig.add_axes((0.9, 0.12, 0.015, 0.6))
    fig.colorbar(scale, cax=cax, label=r"$X^Y\,/\,\max|X^Y|$ (red: outward, blue: inward)")
    fig.suptitle(r"membrane shape $r = 1 + a\,X^Y(\theta, \phi, t)$, exaggerated per panel "
                 "by the factor a", fontsize=9)
    path = Path(path)
    fig.savefig(path, dpi=100)
    return path
