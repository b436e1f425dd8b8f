"""A time-stepped run of one model with its fitted dominant growth rate (fibre, cochlea)."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .base import Plottable, Result, format_params
from .notebook import dataset, result_attrs, variable
from .records import RateFit

if TYPE_CHECKING:
    import xarray as xr


@dataclass(frozen=True, kw_only=True, eq=False, repr=False)
class SteppedRun(Result, Plottable):
    """Time series of a time-stepped model and the growth rate fitted to them.

    The fit X ~ exp(growth_rate t) times an oscillation of angular frequency ``frequency`` (the
    Floquet exponent gamma = growth_rate + i frequency, the frequency folded into [0, 1/2] when
    forced) is that of the series ``fitted``; ``fit.error_estimate`` bounds both (absolute, per
    unit time: the fit's own spread, its change at step 2 dt and the spatial discretisation
    error), and is what ``error_estimate`` reports.

    Attributes
    ----------
    model : 'fibre' or 'cochlea'. params : the model's parameters, tau and the run settings
        (t_end, scheme, dt, amplitude, resolution).
    times : (n_t,) saved times.
    series : names of the columns of ``values`` (fibre: 'X^r', 'X^theta'; cochlea: the modal
        coordinates 'q1', ..., one per oscillatory natural mode, then the membrane's cosine
        coefficients 'h1', ..., 'hM').
    values : (n_t, len(series)) the series against time.
    fitted : the series whose fit is ``fit``.
    fit : :class:`~spectralshell.results.records.RateFit`.
    provenance : package version, scheme, step, resolution, spatial error, wall time.
    """

    model: str
    params: dict[str, Any]
    times: np.ndarray
    series: tuple[str, ...]
    values: np.ndarray
    fitted: str
    fit: RateFit
    provenance: dict[str, Any]
    warnings: tuple[str, ...] = field(default=())

    @property
    def growth_rate(self) -> float:
        """Fitted growth rate (Re gamma of the leading Floquet exponent)."""
        return float(self.fit.growth_rate)

    @property
    def frequency(self) -> float:
        """Fitted angular frequency (|Im gamma|; 0 or 1/2 when locked to the forcing)."""
        return float(self.fit.frequency)

    @property
    def error_estimate(self) -> float:
        """Bound on the error of growth_rate and frequency."""
        return float(self.fit.error_estimate)

    def column(self, name: str) -> np.ndarray:
        """The series ``name`` against time."""
        try:
            return self.values[:, self.series.index(name)]
        except ValueError:
            raise KeyError(f"series {name!r} is not in the run: {', '.join(self.series)}") from None

    def to_dict(self) -> dict[str, Any]:
        """The JSON of ``spectralshell simulate MODEL --json``."""
        q = complex(self.fit.multiplier)
        return {"model": self.model, "params": dict(self.params),
                "growth_rate": self.growth_rate, "frequency": self.frequency,
                "error_estimate": self.error_estimate,
                "multiplier": {"re": q.real, "im": q.imag}, "fitted": self.fitted,
                "window": [float(w) for w in self.fit.window], "samples": int(self.times.size),
                "warnings": list(self.warnings), "provenance": self.provenance}

    def summary(self) -> str:
        """The parameters and run settings, then the fitted growth rate and frequency."""
        return (f"{self.model}: {format_params(self.params)}\n"
                f"  growth rate {self.growth_rate:+.10f}   frequency {self.frequency:.10f}   "
                f"error <= {self.error_estimate:.1e}   (fit of {self.fitted} on t in "
                f"[{self.fit.window[0]:.6g}, {self.fit.window[1]:.6g}])")

    def _html_table(self) -> tuple[list[str], list[list[Any]]]:
        return (["series", "growth rate", "frequency", "error <="],
                [[self.fitted, f"{self.growth_rate:+.10f}", f"{self.frequency:.10f}",
                  f"{self.error_estimate:.1e}"]])

    def write_npz(self, path: str | Path) -> None:
        """Arrays times, values, series and the JSON form (metadata)."""
        with open(path, "wb") as handle:
            np.savez_compressed(handle, times=self.times, values=self.values,
                                series=np.array(self.series),
                                metadata=np.array(json.dumps(self.to_dict())))

    def to_xarray(self) -> xr.Dataset:
        """Over (t, series): values; scalars growth_rate, frequency, error_estimate and the
        fitted series' name in the attrs."""
        data = {"values": variable(("t", "series"), self.values, "stepped series", "1"),
                "growth_rate": variable((), self.growth_rate, "fitted growth rate", "1"),
                "frequency": variable((), self.frequency, "fitted angular frequency", "1"),
                "error_estimate": variable((), self.error_estimate,
                                           "error bound of growth rate and frequency", "1")}
        coords = {"t": variable(("t",), self.times, "time t (forcing period 2 pi)", "1"),
                  "series": variable(("series",), np.array(self.series), "series name")}
        return dataset(data, coords, {**result_attrs(self), "fitted": self.fitted})
