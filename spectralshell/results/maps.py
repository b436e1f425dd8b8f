"""Minimum-tau maps (thesis Fig 6.13, Fig 5.18) of a sweep Dataset, and their file forms.

A map is a sweep (:func:`spectralshell.sweep`, or :func:`spectralshell.tau_map`, which runs one
in memory) over two real axes x, y and any categories (degree m, kind, ...). Its minimum map is
the smallest tau_min over the categories at each (x, y) cell, with the category attaining it
(labelled as the thesis's Fig 6.13: '3S' = m 3, subharmonic).
"""

from __future__ import annotations

import itertools
import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    import xarray as xr


def categories(ds: xr.Dataset, x: str, y: str) -> list[str]:
    """The dims of ``tau_min`` other than the map's axes ``x`` and ``y``, in order."""
    return [d for d in ds["tau_min"].dims if d not in (x, y)]


def category_label(ds: xr.Dataset, cats: list[str], index: tuple[int, ...]) -> str:
    """Label of one category combination: each value with more than one choice, a kind by its
    initial ('3S' = m 3, subharmonic; 'H' for a harmonic with one m)."""
    parts = []
    for d, i in zip(cats, index):
        if ds.sizes[d] == 1 and d != "kind":
            continue
        v = ds[d].values[i]
        parts.append(str(v)[0].upper() if d == "kind" else str(v))
    return "".join(parts)


def uncertified(ds: xr.Dataset) -> xr.DataArray:
    """The points of a sweep ``ds`` (over every dim of tau_min) whose empty answer is not
    proved: computed, and either no tau found (``has_tau`` false) with ``complete_to`` below
    the point's bound -- tau_max, or the smallest tau_min of the other kinds at the point where
    one has a tau (a minimum needs the other kinds proved empty only below it) -- or a tau_min
    with ``complete_to`` below it (nothing smaller is proved absent: the non-uniform sphere's
    sectors solved below it, or a fixed n_temporal). The zero count could not exclude a real
    tau there (issue 23): such a point is no "none", and a larger n_temporal or another tau_max
    may settle it. All false for a Dataset without ``complete_to``."""
    import xarray as xr  # lazy: ~0.35 s to import

    empty = ds["computed"] & ~ds["has_tau"]
    if "complete_to" not in ds:
        return empty & False
    bound = xr.full_like(ds["tau_min"], float(ds.attrs.get("tau_max", np.inf)), dtype=float)
    if "kind" in ds["tau_min"].dims:
        found = ds["tau_min"].where(ds["has_tau"] & ds["computed"]).min("kind")
        bound = bound.where(~(found < bound), found)
    unproved = ds["computed"] & ds["has_tau"] & (ds["complete_to"] < ds["tau_min"])
    return ((empty & (ds["complete_to"] < bound)) | unproved).transpose(*ds["tau_min"].dims)


def uncertified_note(count: int, points: int, tau_max: float) -> str:
    """One line on ``count`` uncertified points of ``points`` (:func:`uncertified`) and what to
    change: the API's warning and the CLI's exit-1 line."""
    return (f"{count} of {points} points found no marginal tau <= {tau_max:g} (or none below "
            "their tau_min), but the zero count cannot prove that none exists there (kept as uncertified: complete_to below "
            "the bound, drawn hatched, never as 'none'); rerun with a smaller or larger "
            "tau_max, or a fixed n_temporal")


def minimum_map(ds: xr.Dataset, x: str, y: str) -> xr.Dataset:
    """The smallest tau_min over the categories of the sweep ``ds`` at each (y, x) cell.

    Only computed points with a marginal tau <= tau_max count; ties go to the first category in
    the sweep's order (lower m, then harmonic). Variables, each (y, x): ``tau_min`` (NaN
    where none), ``has_tau``, ``error_estimate`` (0 where none), ``label``
    (:func:`category_label`, '' where none) and, per category dim d, ``d`` the value attaining
    the minimum (0 or '' where none), and ``uncertified``: some category's empty answer at
    the cell is not proved below the cell's value (:func:`uncertified`), so neither is the
    value (nor "none"). Coordinates x and y and the attrs are the sweep's.
    """
    import xarray as xr  # lazy: ~0.35 s to import

    cats = categories(ds, x, y)
    order = [y, x, *cats]
    tau = ds["tau_min"].transpose(*order).values
    ok = (ds["has_tau"] & ds["computed"]).transpose(*order).values
    err = ds["error_estimate"].transpose(*order).values
    shape = tau.shape[:2]
    flat = np.where(ok, tau, np.inf).reshape(*shape, -1)
    best = flat.argmin(axis=-1)
    value = np.take_along_axis(flat, best[..., None], axis=-1)[..., 0]
    found = np.isfinite(value)
    error = np.take_along_axis(err.reshape(*shape, -1), best[..., None], axis=-1)[..., 0]
    combos = list(itertools.product(*(range(ds.sizes[d]) for d in cats)))
    names = np.array([category_label(ds, cats, c) for c in combos] or [""])
    data = {"tau_min": ((y, x), np.where(found, value, np.nan)),
            "has_tau": ((y, x), found),
            "error_estimate": ((y, x), np.where(found, error, 0.0)),
            "label": ((y, x), np.where(found, names[best], "")),
            "uncertified": ((y, x), uncertified(ds).transpose(*order).values
                            .reshape(*shape, -1).any(axis=-1))}
    for j, d in enumerate(cats):
        values = ds[d].values
        picked = values[np.array([c[j] for c in combos])[best]]
        blank = "" if values.dtype.kind in "US" else 0
        data[d] = ((y, x), np.where(found, picked, blank))
    return xr.Dataset(data, coords={x: ds[x], y: ds[y]}, attrs=dict(ds.attrs))


def unstable_at(ds: xr.Dataset, x: str, at: dict[str, float], tau: float) -> xr.DataArray:
    """Whether each (m, x, kind) of a tau-map sweep ``ds`` is unstable at forcing amplitude
    ``tau`` (a marginal tau_min <= tau), at the grid values ``at`` of its other real axes."""
    cut = ds.sel(at)
    return (cut["has_tau"] & (cut["tau_min"] <= tau)).transpose("m", x, "kind")


def map_dict(mm: xr.Dataset) -> dict[str, Any]:
    """JSON form of a :func:`minimum_map`: axes with units, tau_min rows (None where no
    instability), the category values attaining it, the largest error estimate, provenance."""
    y, x = mm["tau_min"].dims
    out: dict[str, Any] = {"x_name": x, "y_name": y,
                           "units": {n: mm[n].attrs.get("units", "1") for n in (x, y)},
                           "x": mm[x].values.tolist(), "y": mm[y].values.tolist(),
                           "tau_min": [[float(v) if h else None for v, h in zip(row, hrow)]
                                       for row, hrow in zip(mm["tau_min"].values,
                                                            mm["has_tau"].values)]}
    for name in mm.data_vars:
        if name not in ("tau_min", "has_tau", "error_estimate"):
            out[str(name)] = mm[name].values.tolist()
    out["max_error_estimate"] = float(mm["error_estimate"].values.max(initial=0.0))
    out["attrs"] = {k: v.item() if hasattr(v, "item") else v for k, v in mm.attrs.items()}
    return out


def write_npz(mm: xr.Dataset, path: str | Path) -> Path:
    """A :func:`minimum_map` as NPZ: every variable and both axes as arrays (``tau_min`` NaN
    where ``has_tau`` is false), the rest of :func:`map_dict` (units, provenance) as JSON in
    ``metadata``."""
    y, x = mm["tau_min"].dims
    arrays = {str(n): mm[n].values for n in (x, y, *mm.data_vars)}
    meta = {k: v for k, v in map_dict(mm).items() if k in ("x_name", "y_name", "units", "attrs")}
    np.savez(path, **arrays, metadata=np.array(json.dumps(meta)))
    return Path(path)
