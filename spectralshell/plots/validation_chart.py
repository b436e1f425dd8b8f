"""Charts of the validation report and the benchmark table: error against tolerance per case, and
run time against a resolution parameter with the fitted power law."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import matplotlib.ticker
import numpy as np

from ._canvas import subplots


FLOOR = 1e-17  # errors of exactly 0 are drawn here (log axis)


def save_errors(rows: Sequence[tuple[str, float, float, bool]], path: str | Path) -> Path:
    """One bar per case: (name, error, tolerance, passed); x = error / tolerance on a log axis.

    Exact-match cases (tolerance 0) are drawn at 1e-17 when they match and at 1e3 when not.
    """
    names = [r[0] for r in rows]
    ratios = []
    for _, err, tol, ok in rows:
        if tol > 0:
            ratios.append(max(err / tol, FLOOR) if np.isfinite(err) else 1e3)
        else:
            ratios.append(FLOOR if ok else 1e3)
    height = max(3.0, 0.22 * len(rows) + 1.2)
    fig, ax = subplots(figsize=(8.0, height))
    y = np.arange(len(rows))
    colours = ["tab:green" if r[3] else "tab:red" for r in rows]
    ax.barh(y, np.array(ratios) - FLOOR, left=FLOOR, color=colours, height=0.6, alpha=0.5)
    ax.scatter(ratios, y, c=colours, s=14, zorder=3)
    ax.set_xscale("log")
    ax.axvline(1.0, color="0.2", linestyle="--", linewidth=1, label="error = tolerance")
    ax.set_yticks(y)
    ax.set_yticklabels(names, fontsize=7)
    ax.invert_yaxis()
    ax.set_xlim(FLOOR, 1e4)
    ax.set_xlabel("error / tolerance (log scale; < 1 passes; exact matches drawn at 1e-17)")
    ax.set_title("spectralshell validation: achieved error relative to each case's tolerance", fontsize=9)
    ax.legend(loc="lower right", fontsize=7)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=110)
    return path


def save_growth(series: Sequence[dict], path: str | Path) -> Path:
    """Log-log run time against a resolution parameter, one panel per parameter.

    Each series: {"label", "parameter", "values", "seconds", "exponent"} (the fitted slope of
    log time against log parameter, drawn as a dashed line over the fitted range).
    """
    parameters = list(dict.fromkeys(s["parameter"] for s in series))
    fig, axes = subplots(1, len(parameters), figsize=(4.6 * len(parameters), 4.0), squeeze=False)
    for ax, parameter in zip(axes[0], parameters):
        for s in (s for s in series if s["parameter"] == parameter):
            x, t = np.asarray(s["values"], float), np.asarray(s["seconds"], float)
            line, = ax.loglog(x, t, "o-", markersize=4, label=f"{s['label']}: t ~ {parameter}^{s['exponent']:.2f}")
            fit = np.exp(np.polyval(np.polyfit(np.log(x), np.log(t), 1), np.log(x)))
            ax.loglog(x, fit, "--", color=line.get_color(), linewidth=1)
        ticks = sorted({v for s in series if s["parameter"] == parameter for v in s["values"]})
        ax.xaxis.set_major_locator(matplotlib.ticker.FixedLocator(ticks))
        ax.xaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_xlabel(f"{parameter} (resolution)")
        ax.set_ylabel("wall time (s) per solve or step")
        ax.set_title(f"cost growth with {parameter}", fontsize=9)
        ax.legend(fontsize=6, loc="upper left")
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=110)
    return path
