"""Cochlea plots (thesis 5.4-5.6): membrane envelopes (Figs 5.8, 5.10), envelope peak against
frequency (Fig 5.9), the zero contours of det T (Fig 5.7) and Ince-Strutt diagrams (traced
boundaries) against the forcing frequency (Figs 5.12, 5.14) and the wavenumber (Fig 5.11)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ._canvas import save_figure, subplots
from ..results.records import Boundary
from ..results.response import ResponseResult

KIND_STYLE = {"tone": "-", "harmonic": "-", "subharmonic": "--"}


def _axis(res: ResponseResult):
    if res.length is not None:
        return res.to_cm(res.x), "distance from the base x (cm)", res.to_cm
    return res.x, "distance from the base x (dimensionless, [0, π])", lambda v: v


def response_title(res: ResponseResult) -> str:
    """'cochlea, tone at ω = 1000 rad/s: κ = 0.5386, ν = 1.61e-05, α = 1.56, M = 128' (the
    parameters that are set, in the thesis's symbols; tau for the parametric kinds)."""
    omega = f" at ω = {res.physical['omega']:g} rad/s" if res.physical else ""
    names = {"kappa": "κ", "nu": "ν", "alpha": "α", "n_spatial": "M", "spatial_mode": "mode k"}
    shown = [f"{names.get(k, k)} = {v:.4g}" if isinstance(v, float) else f"{names.get(k, k)} = {v}"
             for k, v in res.params.items() if v is not None]
    if res.tau is not None:
        shown.append(f"τ_min = {res.tau:.4g}")
    return f"{res.model}, {res.kind} response{omega}: " + ", ".join(shown)


def draw_response(ax, res: ResponseResult, *, label: str | None = None, envelope_only: bool = False) -> None:
    """Profile h(x, t_peak) and envelope (normalised), with the peak and the WKB peak marked;
    every line labelled."""
    x, xlabel, conv = _axis(res)
    style = KIND_STYLE[res.kind]
    freq = (f"{res.response_frequency * res.physical['omega']:g} rad/s" if res.physical
            else f"{res.response_frequency:g} ω")
    label = label or f"{res.kind} (response frequency {freq})"
    line = ax.plot(x, res.envelope, style, linewidth=1.6, label=f"{label}: envelope")[0]
    if not envelope_only:
        ax.plot(x, res.profile, style, color=line.get_color(), linewidth=0.7, alpha=0.7,
                label=f"{res.kind}: profile h(x) at the time of the peak")
    ax.axvline(conv(res.peak_x), color=line.get_color(), linewidth=0.8,
               label=f"{res.kind}: envelope peak")
    if res.wkb_peak_x is not None and 0 <= res.wkb_peak_x <= np.pi:
        ax.axvline(conv(res.wkb_peak_x), color=line.get_color(), linestyle=":", linewidth=1.2,
                   label=f"{res.kind}: WKB peak (LeVeque, Peskin & Lax)")
    ax.set_xlabel(xlabel)
    ax.set_ylabel("normalised BM displacement")
    ax.grid(alpha=0.3)


def save_responses(panels: Sequence[tuple[str, Sequence[ResponseResult]]], path: str | Path) -> Path:
    """One panel per (title, results), responses overlaid (Fig 5.8)."""
    fig, axes = subplots(len(panels), 1, figsize=(10.5, 2.8 * len(panels)), squeeze=False)
    for ax, (title, results) in zip(axes[:, 0], panels):
        for res in results:
            draw_response(ax, res)
        ax.set_title(title, fontsize=9)
        ax.legend(fontsize=6, loc="center left", bbox_to_anchor=(1.01, 0.5))  # beside the curves
    return save_figure(fig, path, dpi=120)


def save_peaks(series: Sequence[tuple[str, str, np.ndarray, np.ndarray, np.ndarray]],
               wkb: tuple[np.ndarray, np.ndarray], path: str | Path) -> Path:
    """Envelope peak (cm) against response frequency (rad/s, log axis), Fig 5.9: ``series`` of
    (label, marker, frequency, peak, error); ``wkb`` = (frequency, peak) of the WKB line."""
    fig, ax = subplots(figsize=(7.0, 4.5))
    for label, marker, f, peak, err in series:
        ax.errorbar(f, peak, yerr=err, fmt=marker, mfc="none", label=label)
    ax.semilogx(*wkb, "k-", linewidth=1, label="WKB, slope −7/(4 λ_c) per e-fold")
    ax.set_xlabel("response frequency (rad/s)")
    ax.set_ylabel("envelope peak, distance from base (cm)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    return save_figure(fig, path, dpi=120)


def save_det_contours(panels: Sequence[tuple[str, np.ndarray, np.ndarray, np.ndarray, np.ndarray]],
                      path: str | Path) -> Path:
    """Zero contours of Re det T (thick, blue) and Im det T (thin, red) over the s = gamma/sqrt(kappa)
    plane, with the computed modes marked and a legend naming each (Fig 5.7). ``panels``: (title, re grid, im grid,
    det values, modes)."""
    fig, axes = subplots(1, len(panels), figsize=(6.0 * len(panels), 4.6), squeeze=False)
    for ax, (title, re, im, det, modes) in zip(axes[0], panels):
        ax.contour(re, im, det.real, levels=[0.0], colors="tab:blue", linewidths=1.8)
        ax.contour(re, im, det.imag, levels=[0.0], colors="tab:red", linewidths=0.7)
        ax.plot([], [], color="tab:blue", linewidth=1.8, label="Re det T = 0")
        ax.plot([], [], color="tab:red", linewidth=0.7, label="Im det T = 0")
        # markers are unclipped so that those on an edge stay whole; modes beyond the plotted
        # range are left out (unclipped, they would be drawn far outside and break the layout)
        shown = modes[(modes.real >= re.min()) & (modes.real <= re.max())
                      & (modes.imag >= im.min()) & (modes.imag <= im.max())]
        ax.plot(shown.real, shown.imag, "ko", mfc="none", markersize=6, clip_on=False,
                label="computed modes (both zero)")
        ax.set_xlim(re.min(), re.max())
        ax.set_ylim(im.min(), im.max())
        ax.set_xlabel("Re γ/√κ (decay rate)")
        ax.set_ylabel("Im γ/√κ (frequency)")
        ax.set_title(title, fontsize=9)
    # one legend for the figure, below the panels: inside, it would hide contours
    fig.legend(*axes[0, 0].get_legend_handles_labels(), loc="lower center", ncol=3, fontsize=8,
               frameon=False)
    return save_figure(fig, path, dpi=120, rect=(0, 0.06, 1, 1))


TAU_STYLE = {"harmonic": dict(marker="+", color="tab:blue", linestyle="none", label="harmonic"),
             "subharmonic": dict(marker="o", mfc="none", color="tab:red", linestyle="none",
                                 label="subharmonic")}


def _finger_axes(ax, title: str, *, tau_max: float, x_range, xlabel: str) -> None:
    """The frame of one Ince-Strutt panel: the tau = 1/2 line, limits (a margin below tau = 0
    so that markers there stay whole), labels."""
    ax.axhline(0.5, color="0.4", linestyle="--", linewidth=1, label="τ = 1/2")
    ax.set_ylim(-0.025 * tau_max, tau_max)
    if x_range is not None:
        ax.set_xlim(*x_range)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("τ, forcing amplitude")
    ax.set_title(title, fontsize=9)


def save_convergence(series: Sequence[tuple[str, np.ndarray, dict[str, np.ndarray]]],
                     path: str | Path) -> Path:
    """Error estimates |tau(2n) - tau(n)| against the truncation n (Figs 5.5, 5.6): per panel
    (x label, n values, {kind: errors}), log-log."""
    fig, axes = subplots(1, len(series), figsize=(5.5 * len(series), 4.0), squeeze=False)
    for ax, (xlabel, n, errors) in zip(axes[0], series):
        for kind, err in errors.items():
            ax.loglog(n, np.maximum(err, 1e-17), TAU_STYLE[kind]["marker"] + "-",
                      color=TAU_STYLE[kind]["color"], mfc="none", label=kind)
        ax.set_xlabel(xlabel)
        ax.set_ylabel("|τ_min(2n) − τ_min(n)|")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8)
    return save_figure(fig, path, dpi=120)


#: Legend entries of a traced diagram at most: per kind boundary, unstable region, tips and
#: points, the tau = 1/2 line and the integer-k segments.
LEGEND_ENTRIES = 10


def save_traced(panels: Sequence[tuple], path: str | Path, *, xlabel: str,
                tau_max: float = 1.0, columns: int | None = None,
                x_range: tuple[float, float] | None = None) -> Path:
    """Ince-Strutt diagrams against a parameter of the cochlea (the wavenumber k, Fig 5.11; the
    forcing frequency omega, Figs 5.12 and 5.14): per panel (title, traced boundaries (the
    parameter as kappa), kinds, finger tips [(kind, x, tau)], {integer k: tau_min <= 1/2}),
    each kind's boundaries as curves with its unstable region shaded
    (:func:`spectralshell.plots.ince_strutt.draw_boundaries`), the tips as black markers, the
    tau = 1/2 line, at each integer (physical) wavenumber unstable below it a vertical green
    segment from tau_min to 1/2 (only where the dict is not empty), one legend below the panels;
    a panel (title, {kind: (x, tau)}) is drawn as points (harmonic '+', subharmonic 'o');
    ``columns`` panels per row (default: all in one row)."""
    from .ince_strutt import draw_boundaries, legend_entries

    columns = columns or len(panels)
    rows = -(-len(panels) // columns)
    legend_columns = min(4, 2 * columns)
    below = 0.3 + 0.2 * -(-LEGEND_ENTRIES // legend_columns)  # inches for the legend
    fig, axes = subplots(rows, columns, figsize=(6.0 * columns, 3.9 * rows + below),
                         squeeze=False)
    for ax, panel in zip(axes.flat, panels):
        if len(panel) == 2:
            title, points = panel
            for kind, (x, tau) in points.items():
                keep = tau <= tau_max
                ax.plot(x[keep], tau[keep], markersize=3,
                        **{**TAU_STYLE[kind], "label": f"{kind} marginal τ (points)"})
            _finger_axes(ax, title, tau_max=tau_max, x_range=x_range, xlabel=xlabel)
            continue
        title, boundaries, kinds, tips, unstable = panel
        for kind in kinds:
            draw_boundaries(ax, boundaries, kind, tau_max=tau_max)
        for kind, x, tau in tips:
            ax.plot(x, tau, marker=TAU_STYLE[kind]["marker"], color="k", markersize=7,
                    linestyle="none", mfc="k", zorder=4, label=f"{kind} finger tips")
        for k, tau in unstable.items():
            ax.plot([k, k], [tau, 0.5], color="tab:green", linewidth=2.2)
        if unstable:
            ax.plot([], [], color="tab:green", linewidth=2.2,
                    label="integer k unstable for τ ≤ 1/2")
        _finger_axes(ax, title, tau_max=tau_max, x_range=x_range, xlabel=xlabel)
    for ax in list(axes.flat)[len(panels):]:
        ax.set_visible(False)
    fig.legend(*legend_entries(axes.flat), loc="lower center", ncol=legend_columns, fontsize=8,
               frameon=False)
    return save_figure(fig, path, dpi=120, rect=(0, below / (3.9 * rows + below), 1, 1))


def save_tau_maps(panels: Sequence[tuple[str, "xr.Dataset"]], path: str | Path, *,
                  caption: str = "") -> Path:
    """Minimum-tau maps of cochlea sweeps over (frequency in Hz, sigma), Fig 5.18: one panel per
    (title, Dataset), frequency horizontal (log, with omega = 2 pi f in rad/s on the top axis),
    sigma vertical (log), one colour bar (viridis: dark blue small tau, through green to yellow
    at tau_max; no tau <= tau_max in light grey, named in the legend), cells whose M refinement
    did not converge grey hatched (counted in the panel title and the legend)."""
    from . import sweep_plot

    fig, axes = subplots(len(panels), 1, figsize=(7.6, 3.9 * len(panels) + 1.4), squeeze=False)
    mesh, tau_max = None, 0.5
    for ax, (title, ds) in zip(axes[:, 0], panels):
        tau_max = float(ds.attrs.get("tau_max", tau_max))
        mesh, hatched = sweep_plot.draw_map(ax, ds, "frequency", "sigma", labels=False,
                                            cmap="viridis")
        ax.set_xlabel("forcing frequency f (Hz)")
        ax.set_ylabel("BM stiffness σ (g cm⁻² s⁻² = dyn/cm³)")
        top = ax.secondary_xaxis("top", functions=(lambda f: 2 * np.pi * f,
                                                   lambda w: w / (2 * np.pi)))
        top.set_xlabel("ω = 2πf (rad/s)", fontsize=8)
        cells = ds.sizes["frequency"] * ds.sizes["sigma"]
        note = sweep_plot.hatch_note(ds, hatched, cells).removeprefix("; ")
        ax.set_title(title + (f"\n{note}" if note else ""), fontsize=8)
    bottom, top = (0.14 if caption else 0.07), 0.89
    fig.subplots_adjust(left=0.12, right=0.82, top=top, bottom=bottom, hspace=0.7)
    cax = fig.add_axes((0.86, bottom + 0.1, 0.025, top - bottom - 0.2))
    fig.colorbar(mesh, cax=cax, label=sweep_plot.colour_label(tau_max))
    entries = {}  # the panels' legends as one, under the colour bar (below a short panel it
    for ax in axes[:, 0]:  # would cover the frequency axis label)
        if ax.get_legend() is not None:
            legend = ax.get_legend()
            entries.update({t.get_text(): h for t, h in zip(legend.get_texts(),
                                                            legend.legend_handles)})
            legend.remove()
    if entries:
        fig.legend(list(entries.values()), list(entries), loc="upper right", fontsize=7,
                   bbox_to_anchor=(0.995, bottom + 0.085), frameon=False)
    if caption:
        import textwrap

        fig.text(0.02, 0.01, textwrap.fill(caption, 150), fontsize=6.5, va="bottom", ha="left")
    path = Path(path)
    fig.savefig(path, dpi=120)
    return path
