"""Notebook forms of a result: a bounded HTML table, and the pieces of its xarray Dataset.

The Dataset follows the sweep store's conventions (:func:`spectralshell.runner.store.to_dataset`):
coordinates and variables carry ``long_name`` and ``units`` ('1': dimensionless; none for a
label such as ``kind``), with the long names and units of
:mod:`spectralshell.params.sweep_grid`. NetCDF attributes are flat, so a result's params,
provenance and warnings are stored as JSON strings. Missing values are NaN (floats) or ''
(labels), and a dimension of length 0 is left out with its variables (NetCDF 3 cannot hold
one), so that every Dataset round-trips through ``to_netcdf`` and ``xr.open_dataset``.
xarray and pandas are imported on first use (~0.3 s).
"""

from __future__ import annotations

import html
import json
from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..params.sweep_grid import LONG_NAMES, VARIABLE_LONG_NAMES, units
from .records import encode

if TYPE_CHECKING:
    import pandas as pd
    import xarray as xr

#: Rows of a result's HTML table at most (the rest are counted, not shown).
HTML_ROWS = 12
#: Warnings shown in a result's HTML at most.
HTML_WARNINGS = 5

#: A variable as (dims, values, attrs), the form ``xr.Dataset`` accepts.
Variable = tuple[tuple[str, ...], Any, dict[str, str]]


def _cell(tag: str, text: Any) -> str:
    return f"<{tag}>{html.escape(str(text))}</{tag}>"


def html_table(headers: Sequence[str], rows: Sequence[Sequence[Any]],
               limit: int = HTML_ROWS) -> str:
    """An HTML table of ``rows`` (escaped text), the first ``limit`` of them and a line that
    counts the others."""
    head = "<tr>" + "".join(_cell("th", h) for h in headers) + "</tr>"
    body = "".join("<tr>" + "".join(_cell("td", c) for c in row) + "</tr>"
                   for row in rows[:limit])
    table = f"<table><thead>{head}</thead><tbody>{body}</tbody></table>"
    more = len(rows) - limit
    if more > 0:
        table += (f"<p>... {more} more row{'s' if more > 1 else ''} "
                  "(all in .to_xarray())</p>")
    return table


def result_html(name: str, caption: str, table: str, warnings: Sequence[str]) -> str:
    """The HTML of a result: its type ``name`` and ``caption`` (escaped), the ``table`` (HTML)
    and the first :data:`HTML_WARNINGS` warnings."""
    parts = [f"<div class=\"spectralshell-result\"><p><strong>{html.escape(name)}</strong> "
             f"{html.escape(caption)}</p>", table]
    if warnings:
        items = "".join(_cell("li", w) for w in warnings[:HTML_WARNINGS])
        more = len(warnings) - HTML_WARNINGS
        if more > 0:
            items += _cell("li", f"... {more} more (.warnings)")
        parts.append(f"<p>Warnings:</p><ul>{items}</ul>")
    return "".join(parts) + "</div>"


def json_attr(value: Any) -> str:
    """``value`` as a JSON string (a flat NetCDF attribute), sorted keys, strict JSON."""
    return json.dumps(encode(value), sort_keys=True, allow_nan=False)


def result_attrs(result: Any) -> dict[str, str]:
    """Dataset attributes of a result: a title, its type and model, and its params, provenance
    and warnings as JSON strings."""
    name = type(result).__name__
    return {"title": f"spectralshell {name}: {result.model}", "result_type": name,
            "model": result.model, "params": json_attr(result.params),
            "provenance": json_attr(result.provenance),
            "warnings": json_attr(list(result.warnings))}


def variable(dims: tuple[str, ...], values: Any, long_name: str, unit: str = "") -> Variable:
    """A Dataset variable with its ``long_name`` and (when not '') ``units``."""
    attrs = {"long_name": long_name, **({"units": unit} if unit else {})}
    return dims, np.asarray(values), attrs


def named(dims: tuple[str, ...], values: Any, name: str, unit: str = "1") -> Variable:
    """A Dataset variable with the sweep store's long name of ``name``
    (:data:`~spectralshell.params.sweep_grid.VARIABLE_LONG_NAMES`)."""
    return variable(dims, values, VARIABLE_LONG_NAMES[name], unit)


def coordinate(model: str, name: str, values: Any) -> Variable:
    """The coordinate ``name`` over its own dimension, labelled as the sweep labels its axes
    (:data:`~spectralshell.params.sweep_grid.LONG_NAMES`, :func:`units`); labels (strings,
    such as ``kind``) have no units."""
    values = np.asarray(values)
    unit = "" if values.dtype.kind in "US" else units(model, name)
    return variable((name,), values, LONG_NAMES.get(name, name), unit)


def or_nan(value: float | None) -> float:
    """``value`` as a float, NaN for None."""
    return np.nan if value is None else float(value)


def padded(lists: Iterable[Iterable[float]], shape: tuple[int, ...] = ()) -> np.ndarray:
    """Ragged float lists as an array (``shape`` + (width,)), NaN after each list's end; width
    at least 1 (NetCDF 3 has no empty dimensions)."""
    rows = [np.asarray(v, dtype=float).ravel() for v in lists]
    out = np.full((len(rows), max([1, *(r.size for r in rows)])), np.nan)
    for row, values in zip(out, rows):
        row[:values.size] = values
    return out.reshape(*(shape or (len(rows),)), out.shape[1])


def dataset(data: dict[str, Variable], coords: dict[str, Variable],
            attrs: dict[str, Any]) -> xr.Dataset:
    """The Dataset of ``data`` and ``coords``, leaving out those with a dimension of length 0."""
    import xarray as xr  # lazy: ~0.3 s to import

    def kept(items: dict[str, Variable]) -> dict[str, Variable]:
        return {k: v for k, v in items.items() if np.asarray(v[1]).size}

    return xr.Dataset(kept(data), coords=kept(coords), attrs=attrs)


def table(ds: xr.Dataset, dims: tuple[str, ...]) -> pd.DataFrame:
    """The variables of ``ds`` over exactly ``dims`` as a DataFrame indexed by those dims
    (coordinates along them are columns; scalar coordinates are left out)."""
    names = [n for n, v in ds.data_vars.items() if v.dims == dims]
    scalars = [n for n, c in ds.coords.items() if c.ndim == 0]
    return ds[names].drop_vars(scalars, errors="ignore").to_dataframe()
