"""Basilar-membrane response to a pure tone or at a parametric resonance (thesis 5.5)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .base import Plottable, Result, format_params
from .notebook import dataset, json_attr, or_nan, result_attrs, variable

if TYPE_CHECKING:
    import xarray as xr


@dataclass(frozen=True, kw_only=True, eq=False, repr=False)
class ResponseResult(Result, Plottable):
    """Displacement envelope along the membrane for one tone frequency.

    Attributes
    ----------
    model, params : the model and its dimensionless parameters (n_spatial is the one used).
    kind : 'tone' (passive response to a load at the base oscillating at the forcing frequency),
        'harmonic' or 'subharmonic' (the Floquet solution at tau_min of that kind, thesis 5.5).
    response_frequency : angular frequency of the response in units of the forcing frequency
        (1 for tone and harmonic, 1/2 for subharmonic).
    x : positions in [0, pi] (dimensionless; x L / pi in cm).
    envelope : max over time of ``|h(x, t)|``, normalised to maximum 1.
    profile : h(x, t_peak) at the time of the largest displacement, same normalisation.
    peak_x : envelope peak (dimensionless x), from a parabola through the three grid points
        around the maximum; peak_error : ``|peak_x(M) - peak_x(M // 2)|`` plus the grid spacing / 10.
    wkb_peak_x : the leading-order WKB peak (LeVeque, Peskin & Lax; models.cochlea.wkb_peak), or
        None (nu = 0 or alpha = 0, where it does not exist).
    tau : the marginal amplitude (parametric kinds), else None.
    tau_error : its error estimate, ``max(|tau(M) - tau(M // 2)|, its error in N at M)``
        (the truncations in spatial modes and in time), else None.
    length : BM length L (cm) when given physically, else None (then no cm values).
    physical : the cgs inputs, or None.
    """

    model: str
    params: dict[str, Any]
    kind: str
    response_frequency: float
    x: np.ndarray
    envelope: np.ndarray
    profile: np.ndarray
    peak_x: float
    peak_error: float
    wkb_peak_x: float | None
    tau: float | None
    length: float | None
    physical: dict[str, float] | None
    provenance: dict[str, Any]
    warnings: tuple[str, ...] = ()
    tau_error: float | None = None

    def to_cm(self, x):
        """Dimensionless x in cm (x L / pi), or None without a physical length."""
        return None if self.length is None else np.asarray(x) * self.length / np.pi

    def to_dict(self) -> dict[str, Any]:
        out = {"model": self.model, "params": dict(self.params), "kind": self.kind,
               "response_frequency": self.response_frequency, "tau": self.tau,
               "tau_error": self.tau_error,
               "peak_x": self.peak_x, "peak_error": self.peak_error, "wkb_peak_x": self.wkb_peak_x,
               "x": self.x.tolist(), "envelope": self.envelope.tolist(),
               "profile": self.profile.tolist()}
        if self.length is not None:
            out["peak_cm"] = float(self.to_cm(self.peak_x))
            out["peak_error_cm"] = float(self.to_cm(self.peak_error))
            out["wkb_peak_cm"] = None if self.wkb_peak_x is None else float(self.to_cm(self.wkb_peak_x))
            out["response_frequency_rad_s"] = self.response_frequency * self.physical["omega"]
        if self.physical is not None:
            out["physical"] = dict(self.physical)
        out["warnings"] = list(self.warnings)
        out["provenance"] = self.provenance
        return out

    def summary(self) -> str:
        """The parameters (and tau), then the envelope peak with its error: at x (the
        dimensionless position, 0 to π along the membrane), as a share of the length, in cm."""
        cm = "" if self.length is None else (
            f" = {self.to_cm(self.peak_x):.4g} ± {self.to_cm(self.peak_error):.1g} cm"
            + ("" if self.wkb_peak_x is None else f" (WKB {self.to_cm(self.wkb_peak_x):.4g} cm)"))
        tau = "" if self.tau is None else (
            f"  tau = {self.tau:.10g}" + ("" if self.tau_error is None
                                          else f" ± {self.tau_error:.1e} (in M and N)"))
        return (f"{self.model} {self.kind} response: {format_params(self.params)}{tau}\n"
                f"  envelope peak at x = {self.peak_x:.6g} ± {self.peak_error:.1e} "
                f"({100 * self.peak_x / np.pi:.3g} % of the way from the base, x = 0, to the "
                f"apex, x = π){cm}")

    def _html_table(self) -> tuple[list[str], list[list[Any]]]:
        rows = [["envelope peak x (0 to π)", f"{self.peak_x:.6g}", f"{self.peak_error:.1e}"]]
        if self.wkb_peak_x is not None:
            rows.append(["WKB peak x (0 to π)", f"{self.wkb_peak_x:.6g}", ""])
        if self.length is not None:
            rows.append(["envelope peak (cm)", f"{self.to_cm(self.peak_x):.4g}",
                         f"{self.to_cm(self.peak_error):.1e}"])
        if self.tau is not None:
            rows.append(["tau", f"{self.tau:.10g}",
                         "" if self.tau_error is None else f"{self.tau_error:.1e}"])
        rows.append(["response frequency (of the forcing)", f"{self.response_frequency:g}", ""])
        return ["", "value", "+-"], rows

    def to_xarray(self) -> xr.Dataset:
        """Over ``x`` (and x_cm, with a physical length): envelope and profile; scalars peak_x,
        peak_error, wkb_peak_x, tau, tau_error, length (NaN where there is none) and
        response_frequency;
        kind and physical (JSON) in the attrs."""
        dims = ("x",)
        data = {"envelope": variable(dims, self.envelope, "max over time of |h(x, t)|, "
                                     "normalised to maximum 1", "1"),
                "profile": variable(dims, self.profile, "h(x, t_peak), same normalisation", "1"),
                "peak_x": variable((), self.peak_x, "envelope peak x", "1"),
                "peak_error": variable((), self.peak_error, "error estimate of peak_x", "1"),
                "wkb_peak_x": variable((), or_nan(self.wkb_peak_x), "leading-order WKB peak x",
                                       "1"),
                "tau": variable((), or_nan(self.tau), "marginal forcing amplitude tau", "1"),
                "tau_error": variable((), or_nan(self.tau_error), "error estimate of tau (in the "
                                      "spatial modes M and the truncation N)", "1"),
                "length": variable((), or_nan(self.length), "membrane length L", "cm"),
                "response_frequency": variable((), self.response_frequency, "angular frequency "
                                               "of the response / forcing frequency", "1")}
        coords = {"x": variable(dims, self.x, "position along the membrane x, 0 to pi", "1")}
        if self.length is not None:
            coords["x_cm"] = variable(dims, self.to_cm(self.x), "position x L / pi", "cm")
        attrs = {**result_attrs(self), "kind": self.kind, "physical": json_attr(self.physical)}
        return dataset(data, coords, attrs)
