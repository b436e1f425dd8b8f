"""A user's benchmark run against the reference: one panel per scored quantity."""

from __future__ import annotations

from pathlib import Path

from ._canvas import colours, save_figure, subplots


def score_figure(ds, user: tuple, path: str | Path) -> Path:
    """Reference (line, where it has the quantity) and the user's samples (dots) of each
    quantity the user gave, against the reference's axis (time in s, or cochlea-tone's x in
    cm), written to ``path``; ``user`` = (axis values, {quantity: values})."""
    t_user, columns = user
    (dim,) = ds.dims
    names = list(columns)
    fig, axes = subplots(len(names), 1, figsize=(7.0, 2.4 * len(names) + 0.6), sharex=True,
                         squeeze=False)
    ref_colour, user_colour = colours()[:2]
    for ax, name in zip(axes[:, 0], names):
        units = "your units"
        if name in ds:
            ax.plot(ds[dim].values, ds[name].values, color=ref_colour, lw=1.2, label="reference")
            units = ds[name].attrs.get("units", "")
        ax.plot(t_user, columns[name], ".", color=user_colour, ms=3, label="your run")
        ax.set_ylabel(f"{name} ({units})")
        ax.legend(loc="upper right", fontsize="small")
    axes[-1, 0].set_xlabel(f"{ds[dim].attrs['long_name']} ({ds[dim].attrs['units']})")
    fig.suptitle(f"benchmark {ds.attrs['problem']}")
    return save_figure(fig, path)
