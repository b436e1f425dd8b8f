"""Natural modes (tau = 0) of a model: a frozen result with provenance, and its JSON form."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .base import Plottable, Result, format_params
from .floquet import provenance
from .notebook import dataset, json_attr, result_attrs, table, variable
from .records import ModeRoots

if TYPE_CHECKING:
    import pandas as pd
    import xarray as xr

ON_CUT = ("mode(s) {} lie on the branch cut to within their error (|Re beta| <= error): the sheet is "
          "not resolved at this precision; to working accuracy they decay as real exponentials "
          "(raise `precision` to resolve the sheet where the Basset-type part of the load is not "
          "exponentially small)")
FEWER = ("count = {} asks for more modes than the dispersion relation has: all {} are returned (on "
         "the physical sheet it has no others; the rest of the spectrum is continuous, along the "
         "branch cut gamma <= 0)")
UNCOUNTED = ("mode(s) {} lie between the counted region and the branch cut (within its gap, "
             "|Re beta| <= 1e-6 k for the cylinder): found on the way, outside the "
             "argument-principle count, so the list may miss others there; the remaining modes "
             "are exactly the counted ones")
UNPHYSICAL = ("mode(s) {} lie on the unphysical sheet (Re beta < 0): roots of the dispersion relation "
              "whose exterior field grows at infinity, not decaying modes")
#: Im gamma/|Re gamma| below which a mode is labelled overdamped in practice: it then decays by
#: e^(-pi/ratio) < e^(-314) before its first sign change (the threshold of the mode-structure
#: notes of spectralshell.models.sphere_modes).
PRACTICALLY_REAL = 0.01


def mode_kind(gamma: complex, error: float) -> str:
    """Text label of a natural mode: real within its error, practically real, or oscillatory."""
    if gamma.imag <= error:
        return "overdamped"
    ratio = gamma.imag / abs(gamma.real) if gamma.real else math.inf
    if ratio < PRACTICALLY_REAL:
        return f"overdamped in practice: Im/|Re| = {ratio:.1e}"
    return "oscillatory"


@dataclass(frozen=True, kw_only=True, eq=False, repr=False)
class NaturalModesResult(Result, Plottable):
    """Least damped natural modes gamma (X ~ exp(gamma t)) of one model, least damped first.

    Attributes
    ----------
    gamma : complex rates, Im gamma >= 0 (one of each conjugate pair), sorted by decreasing
        Re gamma. Re gamma is the decay rate (< 0: decaying), Im gamma the angular frequency
        (thesis Fig. 7.1).
    error_estimate : absolute error bound of each gamma.
    principal_sheet : ``Re beta > error``: a resolved, genuine decaying mode (thesis (7.9)).
    on_cut : ``|Re beta| <= error``: the mode lies on the branch cut gamma <= 0 to within its error.
    precision : digits of the mpmath polish, or None (double precision).
    gamma_digits : with precision, (Re, Im) of each gamma as decimal strings.
    """

    model: str
    params: dict[str, Any]
    gamma: np.ndarray
    error_estimate: np.ndarray
    principal_sheet: np.ndarray
    on_cut: np.ndarray
    precision: int | None
    provenance: dict[str, Any]
    gamma_digits: tuple[tuple[str, str], ...] | None = None
    warnings: tuple[str, ...] = ()

    @classmethod
    def build(cls, *, model: str, params: dict[str, Any], roots: ModeRoots,
              options: dict[str, Any]) -> "NaturalModesResult":
        """The result of a root finder run, with provenance (solver options and statistics)."""
        prov = provenance(options)
        prov["solver"] = {"method": "newton", "evaluations": roots.evaluations,
                          "seeds_tried": roots.seeds_tried}
        if roots.double_error is not None:
            prov["solver"]["double_error"] = [float(e) for e in roots.double_error]
        warnings = []
        cut = [i for i, c in enumerate(roots.on_cut) if c]
        if cut:
            warnings.append(ON_CUT.format(", ".join(str(i) for i in cut)))
        if roots.uncounted is not None and roots.uncounted.any():
            warnings.append(UNCOUNTED.format(", ".join(str(i) for i, u in
                                                       enumerate(roots.uncounted) if u)))
        bad = [i for i, (p, c) in enumerate(zip(roots.principal_sheet, roots.on_cut)) if not p and not c]
        if bad:
            warnings.append(UNPHYSICAL.format(", ".join(str(i) for i in bad)))
        if (options.get("count") or 0) > len(roots.gamma):
            warnings.append(FEWER.format(options["count"], len(roots.gamma)))
        return cls(model=model, params=dict(params), gamma=roots.gamma,
                   error_estimate=roots.error_estimate, principal_sheet=roots.principal_sheet,
                   on_cut=roots.on_cut, precision=roots.precision, provenance=prov,
                   gamma_digits=roots.gamma_digits, warnings=tuple(warnings))

    @property
    def decay_rate(self) -> np.ndarray:
        """Re gamma (negative for a decaying mode), the top panel of thesis Fig. 7.1."""
        return self.gamma.real

    @property
    def frequency(self) -> np.ndarray:
        """Im gamma (angular frequency, >= 0), the bottom panel of thesis Fig. 7.1."""
        return self.gamma.imag

    def to_dict(self) -> dict[str, Any]:
        modes = []
        for i, g in enumerate(self.gamma):
            mode = {"gamma_re": float(g.real), "gamma_im": float(g.imag),
                    "error_estimate": float(self.error_estimate[i]),
                    "principal_sheet": bool(self.principal_sheet[i]), "on_cut": bool(self.on_cut[i])}
            if self.gamma_digits is not None:
                mode["gamma_re_digits"], mode["gamma_im_digits"] = self.gamma_digits[i]
            modes.append(mode)
        return {"model": self.model, "params": dict(self.params), "modes": modes,
                "precision": self.precision, "warnings": list(self.warnings),
                "provenance": self.provenance}

    def summary(self) -> str:
        """The parameters and units, then each gamma with its error and :func:`mode_kind`."""
        unit = self.params.get("units", "dimensionless, time unit 1/omega")
        lines = [f"{self.model} natural modes: {format_params(self.params)}   "
                 f"(X ~ exp(gamma t), {unit})"]
        for value, e, kind in self._rows():
            lines.append(f"  gamma = {value}   error <= {e:.1e}   ({kind})")
        return "\n".join(lines)

    def _rows(self) -> list[tuple[str, float, str]]:
        """Per mode: gamma as text (its decimal digits with a precision), error, mode_kind."""
        digits = self.gamma_digits or [None] * len(self.gamma)
        return [(f"{d[0]} {'' if d[1].startswith('-') else '+'}{d[1]}i" if d
                 else f"{g.real:+.12g} {g.imag:+.12g}i", e, mode_kind(g, e))
                for g, e, d in zip(self.gamma, self.error_estimate, digits)]

    def _html_table(self) -> tuple[list[str], list[list[Any]]]:
        return (["gamma", "error <=", "kind"],
                [[value, f"{e:.1e}", kind] for value, e, kind in self._rows()])

    def to_xarray(self) -> xr.Dataset:
        """Over ``mode`` (0 = least damped): decay_rate (Re gamma), frequency (Im gamma),
        error_estimate, principal_sheet, on_cut, mode_kind and, with a precision,
        gamma_real_digits and gamma_imag_digits; units those of the params ('1' when
        dimensionless); precision a JSON attr (null: double)."""
        dims = ("mode",)
        unit = self.params.get("units", "1")
        data = {"decay_rate": variable(dims, self.decay_rate, "decay rate Re gamma", unit),
                "frequency": variable(dims, self.frequency, "angular frequency Im gamma", unit),
                "error_estimate": variable(dims, self.error_estimate,
                                           "absolute error bound of gamma", unit),
                "principal_sheet": variable(dims, self.principal_sheet,
                                            "a resolved, genuine decaying mode"),
                "on_cut": variable(dims, self.on_cut, "on the branch cut within its error"),
                "mode_kind": variable(dims, [kind for *_, kind in self._rows()],
                                      "overdamped or oscillatory")}
        if self.gamma_digits is not None:
            for index, part in enumerate(("real", "imag")):
                data[f"gamma_{part}_digits"] = variable(
                    dims, [d[index] for d in self.gamma_digits], f"{part} part of gamma, digits")
        coords = {"mode": variable(dims, np.arange(self.gamma.size),
                                   "mode, least damped first")}
        attrs = {**result_attrs(self), "precision": json_attr(self.precision)}
        return dataset(data, coords, attrs)

    def to_dataframe(self) -> pd.DataFrame:
        """One row per mode: the variables of :meth:`to_xarray`."""
        return table(self.to_xarray(), ("mode",))
