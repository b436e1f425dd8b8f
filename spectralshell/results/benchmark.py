"""Benchmark reference data (an xarray Dataset) written as NetCDF and CSV, a user's CSV read
back, and the score of a user's run.

CSV format (what ``spectralshell benchmark write`` writes and ``score`` reads): optional comment
lines starting with '#', then one header line of comma-separated column names, then one row of
numbers per sample. The first column is the problem's axis (:func:`axis`: ``t``, time in s, or
for cochlea-tone ``x``, position in cm; strictly increasing); the others are quantity names of
the problem (``spectralshell benchmark show NAME``) in the units stated there; columns ending
in ``_error`` (the reference's error bounds) are ignored by ``score``.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ParameterError

if TYPE_CHECKING:
    import xarray as xr

ERROR_SUFFIX = "_error"


def reference_columns(ds: xr.Dataset) -> list[str]:
    """The quantity variables of a reference Dataset (not their error bounds), in order."""
    return [str(v) for v in ds.data_vars if not str(v).endswith(ERROR_SUFFIX)]


def axis(ds: xr.Dataset) -> str:
    """The one dimension of a reference Dataset: 't' (time series) or 'x' (cochlea-tone)."""
    (name,) = ds.dims
    return str(name)


def write_netcdf(ds: xr.Dataset, path: str | Path) -> Path:
    """``ds`` as NetCDF 3 (scipy engine: no timestamps in the file, so the bytes depend on
    the data and attributes only)."""
    ds.to_netcdf(path, engine="scipy", format="NETCDF3_64BIT")
    return Path(path)


def write_csv(ds: xr.Dataset, path: str | Path) -> Path:
    """``ds`` as CSV: '# key: value' lines (attributes; each line of a multi-line value
    commented), the header <axis>,<q>,<q>_error,..., rows
    with 17 significant digits (the doubles exactly)."""
    names = [axis(ds)] + [n for q in reference_columns(ds) for n in (q, q + ERROR_SUFFIX)]
    units = [ds[names[0]].attrs.get("units", "")] + [ds[n].attrs.get("units", "") for n in names[1:]]
    lines = [f"# {line}" for k, v in ds.attrs.items() for line in f"{k}: {v}".splitlines()]
    lines.append("# units: " + ",".join(units))
    lines.append(",".join(names))
    table = np.column_stack([ds[n].values for n in names])
    lines += [",".join(f"{v:.17g}" for v in row) for row in table]
    Path(path).write_text("\n".join(lines) + "\n")
    return Path(path)


def read_series(path: str | Path, first: str = "t") -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """(axis values, {column: values}) of a CSV in the format of the module docstring, its
    first column named ``first``; ParameterError (one line, naming the file and line) when it
    is not."""
    path = Path(path)
    try:
        text = path.read_text()
    except (OSError, UnicodeDecodeError) as exc:
        raise ParameterError(f"user data {str(path)!r} cannot be read: "
                             f"{getattr(exc, 'strerror', None) or exc}") from None
    rows = [(i + 1, line) for i, line in enumerate(text.splitlines())
            if line.strip() and not line.lstrip().startswith("#")]
    if len(rows) < 2:
        raise ParameterError(f"user data {str(path)!r} is invalid: needs a header line and rows")
    header = [h.strip() for h in rows[0][1].split(",")]
    if header[0] != first or len(header) < 2 or len(set(header)) != len(header):
        raise ParameterError(f"user data {str(path)!r} header {rows[0][1]!r} is invalid: must be "
                             f"{first} followed by distinct quantity names")
    values = []
    for number, line in rows[1:]:
        cells = line.split(",")
        try:
            row = [float(c) for c in cells]
        except ValueError:
            row = []
        if len(row) != len(header) or not np.all(np.isfinite(row)):
            raise ParameterError(f"user data {str(path)!r} line {number} is invalid: must be "
                                 f"{len(header)} finite numbers")
        values.append(row)
    data = np.array(values)
    t = data[:, 0]
    if np.any(np.diff(t) <= 0):
        raise ParameterError(f"user data {str(path)!r} column {first} is invalid: its values "
                             "must be strictly increasing")
    return t, {name: data[:, j] for j, name in enumerate(header) if j > 0}


@dataclass(frozen=True, kw_only=True)
class QuantityScore:
    """How a user's series of one quantity compares with the reference.

    relative_l2 : ||user - ref|| / ||ref|| over the reference times inside the user's range;
    max_error : max |user - ref| there (the quantity's units); reference_error : the largest
    error bound of the reference there (these three None for a series the reference has no
    samples of, fibre-parametric's: its rate alone is scored); exact_growth_rate,
    exact_frequency : what the late part of the quantity follows (1/s, rad/s: the natural
    mode, or the Floquet exponent with its locked frequency); growth_rate, frequency,
    fit_error : fitted from the user's own samples in the score's fit window (1/s, rad/s;
    None if the fit failed); reference_growth_rate, reference_frequency : the same fit of the
    reference series (the fit's own bias: compare the user's fit with these, and both with the
    exact values; None without a reference series); samples : the number of reference times
    compared (without a reference series: the user's samples in the fit window)."""

    name: str
    units: str
    relative_l2: float | None
    max_error: float | None
    reference_error: float | None
    exact_growth_rate: float
    exact_frequency: float
    growth_rate: float | None
    frequency: float | None
    fit_error: float | None
    reference_growth_rate: float | None
    reference_frequency: float | None
    samples: int

    def to_dict(self) -> dict[str, Any]:
        return {k: getattr(self, k) for k in ("units", "relative_l2", "max_error",
                                               "reference_error", "exact_growth_rate",
                                               "exact_frequency", "growth_rate", "frequency",
                                               "fit_error", "reference_growth_rate",
                                               "reference_frequency", "samples")}


@dataclass(frozen=True, kw_only=True)
class BenchmarkScore:
    """The score of a user's run: per quantity, and the exact late-time rate and frequency
    when the problem has one for all its quantities (None otherwise: sphere-parametric's
    series have one each)."""

    problem: str
    params: dict[str, Any]
    exact_growth_rate: float | None
    exact_frequency: float | None
    fit_window: tuple[float, float]
    quantities: tuple[QuantityScore, ...]

    def to_dict(self) -> dict[str, Any]:
        """The JSON of ``spectralshell benchmark score --json``."""
        return {"problem": self.problem, "params": dict(self.params),
                "exact": {"growth_rate": self.exact_growth_rate,
                          "frequency": self.exact_frequency},
                "fit_window": list(self.fit_window),
                "quantities": {q.name: q.to_dict() for q in self.quantities}}

    def summary(self) -> str:
        """One line per quantity: errors, then fitted against exact rate and frequency."""
        head = f"{self.problem}: fit window {self.fit_window[0]:.4g}..{self.fit_window[1]:.4g} s"
        lines = [head]
        for q in self.quantities:
            same = ("" if q.reference_growth_rate is None else
                    f"same fit of the reference {q.reference_growth_rate:+.8g}, "
                    f"{q.reference_frequency:.8g}; ")
            fit = ("no fit" if q.growth_rate is None else
                   f"rate {q.growth_rate:+.8g} frequency {q.frequency:.8g} (+- {q.fit_error:.1e}; "
                   f"{same}exact {q.exact_growth_rate:+.10g} 1/s, "
                   f"{q.exact_frequency:.10g} rad/s)")
            errors = ("no reference series" if q.relative_l2 is None else
                      f"relative L2 {q.relative_l2:.3e}  max error {q.max_error:.3e} {q.units} "
                      f"(reference <= {q.reference_error:.1e})")
            lines.append(f"  {q.name}: {errors}  {fit}  [{q.samples} samples]")
        return "\n".join(lines)


@dataclass(frozen=True, kw_only=True)
class PeakScore:
    """How a user's envelope along the membrane compares with cochlea-tone's reference.

    scale : the largest sample of the user's envelope, by which it is divided first (the reference is normalised to maximum 1); relative_l2, max_error : of the
    normalised envelope against the reference over the reference x inside the user's range;
    reference_error : the largest error bound of the reference there; peak_x, exact_peak_x,
    exact_peak_error : the user's peak position (maximum of the spline past the load), the
    reference's and its error bound (cm); samples : the reference points compared."""

    problem: str
    params: dict[str, Any]
    scale: float
    relative_l2: float
    max_error: float
    reference_error: float
    peak_x: float
    exact_peak_x: float
    exact_peak_error: float
    samples: int

    def to_dict(self) -> dict[str, Any]:
        """The JSON of ``spectralshell benchmark score --json``."""
        return {"problem": self.problem, "params": dict(self.params),
                "quantities": {"envelope": {k: getattr(self, k) for k in (
                    "scale", "relative_l2", "max_error", "reference_error", "samples")}},
                "peak": {"x_cm": self.peak_x, "exact_x_cm": self.exact_peak_x,
                         "exact_error_cm": self.exact_peak_error,
                         "difference_cm": self.peak_x - self.exact_peak_x}}

    def summary(self) -> str:
        """The envelope's errors, then the peak position against the exact one."""
        return (f"{self.problem}: envelope (yours divided by its maximum {self.scale:.6g}): "
                f"relative L2 {self.relative_l2:.3e}  max error {self.max_error:.3e} "
                f"(reference <= {self.reference_error:.1e}) [{self.samples} samples]\n"
                f"  peak at x = {self.peak_x:.6g} cm (exact {self.exact_peak_x:.6g} +- "
                f"{self.exact_peak_error:.1e} cm; difference "
                f"{self.peak_x - self.exact_peak_x:+.3e} cm)")


def attrs_json(ds: xr.Dataset, key: str) -> Any:
    """A JSON attribute of a reference Dataset, decoded."""
    return json.loads(ds.attrs[key])
