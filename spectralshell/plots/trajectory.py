"""Figures of a time-stepped sphere: mode amplitudes against time (like thesis Figs 6.8-6.11, 7.2)
and snapshots of the membrane shape."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import matplotlib

import numpy as np

from ._canvas import colours, figure, save_figure, subplots
from ..results.trajectory import Trajectory

FLOOR = 1e-14   # lower limit of the log panel (relative amplitude)


def save_amplitudes(traj: Trajectory, path: str | Path) -> Path:
    """Top: each radial coefficient X^Y_{m,k}(t) rescaled to start at 1 (as the thesis's radial
    projections); bottom: |X^Y| on a log scale with the fitted envelope exp(growth_rate t)."""
    fig, (top, bottom) = subplots(2, 1, figsize=(7.5, 6.5), sharex=True)
    cycle = colours()
    fits = {(f.m, f.k): f for f in traj.fits}
    t = traj.times
    lowest = 1.0
    for j, ((m, k), colour) in enumerate(zip(traj.modes, cycle * 10)):
        x = traj.radial[:, j]
        x0 = x[0] if x[0] != 0 else np.max(np.abs(x)) or 1.0
        label = f"(m, k) = ({m}, {k})"
        fit = fits.get((m, k))
        if fit is not None:
            label += f": growth {fit.growth_rate:+.4g}, frequency {fit.frequency:.4g}"
        top.plot(t, x / x0, color=colour, linewidth=0.9, label=label)
        relative = np.maximum(np.abs(x / x0), FLOOR)
        lowest = min(lowest, np.min(relative[relative > FLOOR], initial=1.0))
        bottom.semilogy(t, relative, color=colour, linewidth=0.6)
        if fit is not None:
            bottom.semilogy(t, np.exp(fit.growth_rate * (t - t[0])), color=colour,
                            linestyle="--", linewidth=0.8)
    p = traj.params
    top.set_title(f"sphere: kappa = {p['kappa']}, nu = {p['nu']}, tau = {p['tau']}  "
                  f"({p['scheme']}, dt = {p['dt']:.3g})", fontsize=9)
    top.set_ylabel("X^Y(t) / X^Y(0)")
    bottom.set_ylabel("|X^Y(t) / X^Y(0)|  (dashed: exp(growth t))")
    bottom.set_xlabel("t (forcing period 2π)")
    bottom.set_ylim(bottom=max(FLOOR, lowest / 10))
    top.legend(fontsize=7)
    for ax in (top, bottom):
        ax.grid(alpha=0.3)
    return save_figure(fig, path, dpi=120)


def save_shape(theta: np.ndarray, phi: np.ndarray, displacements: Sequence[np.ndarray],
               times: Sequence[float], path: str | Path, *, size: float = 0.25) -> Path:
    """3D snapshots of the membrane r = 1 + a X^Y(theta, phi, t) at ``times``, each exaggerated
    (factor a per panel) to a largest displacement ``size``, coloured by the displacement
    (as thesis Fig 6.7 colours the distance from the origin)."""
    n = len(times)
    fig = figure(figsize=(3.2 * n, 3.6))
    th = np.concatenate([[0.0], theta, [np.pi]])
    ph = np.concatenate([phi, [2 * np.pi]])
    TH, PH = np.meshgrid(th, ph, indexing="ij")
    for i, (X, t) in enumerate(zip(displacements, times)):
        X = np.concatenate([X, X[:, :1]], axis=1)                 # close the seam at phi = 2 pi
        X = np.vstack([np.full((1, X.shape[1]), X[0].mean()), X,
                       np.full((1, X.shape[1]), X[-1].mean())])   # the poles
        peak = np.max(np.abs(X))
        a = size / peak if peak > 0 else 1.0
        R = 1.0 + a * X
        ax = fig.add_subplot(1, n, i + 1, projection="3d")
        x, y, z = R * np.sin(TH) * np.cos(PH), R * np.sin(TH) * np.sin(PH), R * np.cos(TH)
        shade = matplotlib.colormaps["coolwarm"](0.5 + 0.5 * X / (peak or 1.0))
        ax.plot_surface(x, y, z, facecolors=shade, rstride=1, cstride=1, linewidth=0,
                        antialiased=False, shade=False)
        ax.set_box_aspect((1, 1, 1))
        ax.set_axis_off()
        ax.set_title(f"t = {t:.4g}\nmax |X^Y| = {peak:.2e} (x{a:.3g})", fontsize=8)
    fig.suptitle("membrane shape r = 1 + a X^Y(theta, phi, t), exaggerated per panel "
                 "(red: outward, blue: inward)", fontsize=9)
    return save_figure(fig, path, dpi=100, rect=(0, 0, 1, 0.92))
