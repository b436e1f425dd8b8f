"""The figure of a time-stepped fibre or cochlea (``spectralshell simulate fibre|cochlea --png``):
the fitted series' amplitude on a log axis against time in forcing periods, with the fitted growth
and, when given, the slope of the leading Floquet exponent that the run checks.

A linear run grows (or decays) as |x(t)| ~ C exp(Re gamma t) times a bounded oscillation, so on
the log axis the fit and the exponent are straight lines of slope Re gamma per unit t, i.e.
2 pi Re gamma per forcing period. Both are drawn through the run's largest |x| in the first
forcing period of the fit window, over that window.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ._canvas import colours, save_figure, subplots
from ..results.stepped import SteppedRun

FLOOR = 1e-300    # |x| below this is drawn at it (log axis)
PERIOD = 2 * np.pi


def _symbol(name: str) -> str:
    """A series name in mathtext: 'X^r' -> $X^r$, 'q1' -> $q_{1}$."""
    if name[0] in "qh" and name[1:].isdigit():
        return f"${name[0]}_{{{name[1:]}}}$"
    return f"${name}$"


def _title(run: SteppedRun) -> str:
    p = run.params
    names = {"m": "m", "kappa": "κ", "nu": "ν", "alpha": "α", "n_spatial": "M", "tau": "τ"}
    shown = "  ".join(f"{symbol} = {p[key]:g}" for key, symbol in names.items() if key in p)
    forcing = f"  ({p['forcing']} pumping)" if p.get("forcing", "both") != "both" else ""
    return f"{run.model}: {shown}{forcing}  ({p['scheme']}, Δt = {p['dt']:.3g})"


def draw(ax, run: SteppedRun, *, exponent: complex | None = None) -> None:
    """|x(t)| / max_{t <= 2 pi} |x| of the fitted series x on a log axis against t / 2 pi, the
    fitted growth exp(growth_rate t) dashed over the fit window and, with ``exponent`` (the
    leading Floquet exponent gamma of ``ss.exponents`` at the run's parameters), the slope
    exp(Re gamma t) dotted through the same point (module docstring)."""
    t = run.times
    x = np.abs(run.column(run.fitted))
    scale = np.max(x[t <= PERIOD]) or np.max(x) or 1.0
    y = np.maximum(x / scale, FLOOR)
    line, fit_colour, ref_colour = colours()[:3]
    symbol = _symbol(run.fitted)
    ax.semilogy(t / PERIOD, y, color=line, linewidth=0.6, label=f"stepped {symbol}")
    t_a, t_b = run.fit.window
    inside = (t >= t_a) & (t <= t_b)
    first = inside & (t <= t[inside][0] + PERIOD)
    anchor_t = t[first][np.argmax(y[first])]
    anchor = np.max(y[first])
    span = t[inside]
    ax.semilogy(span / PERIOD, anchor * np.exp(run.growth_rate * (span - anchor_t)),
                color=fit_colour, linestyle="--", linewidth=1.2,
                label=f"fitted growth rate {run.growth_rate:+.6g} ± {run.error_estimate:.1g} "
                      "per unit t")
    if exponent is not None:
        rate = complex(exponent).real
        ax.semilogy(span / PERIOD, anchor * np.exp(rate * (span - anchor_t)), color=ref_colour,
                    linestyle=":", linewidth=1.6,
                    label=f"Floquet exponent Re γ = {rate:+.6g} (exponents)")
    ax.set_xlabel("time t / 2π (forcing periods)")
    ax.set_ylabel(rf"$|x(t)|\,/\,\max_{{t \leq 2\pi}}|x|$ of x = {symbol} (dimensionless)")
    ax.set_title(_title(run), fontsize=9)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)


def save(run: SteppedRun, path: str | Path, *, exponent: complex | None = None) -> Path:
    """:func:`draw` on a new figure, written to ``path`` (format from the suffix)."""
    fig, ax = subplots(figsize=(7.5, 4.5))
    draw(ax, run, exponent=exponent)
    return save_figure(fig, path, dpi=120)
