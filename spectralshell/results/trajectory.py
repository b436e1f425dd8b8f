"""A time-stepped trajectory of the sphere's membrane: mode amplitudes, fitted rates, provenance."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .base import Plottable, Result
from .notebook import Variable, dataset, result_attrs, variable
from .records import RateFit

if TYPE_CHECKING:
    import xarray as xr


@dataclass(frozen=True, kw_only=True)
class ModeFit:
    """Fitted dominant behaviour of one mode (m, k): X ~ exp(growth_rate t) times an oscillation
    of angular frequency ``frequency``; ``error_estimate`` bounds both (absolute, per unit time).
    ``multiplier``: the Floquet multiplier over 2 pi (forced) or exp(gamma h) (unforced)."""

    m: int
    k: int
    growth_rate: float
    frequency: float
    error_estimate: float
    multiplier: complex

    def to_dict(self) -> dict[str, Any]:
        return {"m": self.m, "k": self.k, "growth_rate": self.growth_rate,
                "frequency": self.frequency, "error_estimate": self.error_estimate}


@dataclass(frozen=True, kw_only=True, eq=False, repr=False)
class Trajectory(Result, Plottable):
    """Membrane displacement coefficients against time, per real harmonic mode (m, k).

    Attributes
    ----------
    model : 'sphere'. params : kappa, nu, tau and the run settings (t_end, scheme, dt).
    times : (n_t,) saved times.
    modes : ((m, k), ...) the allocated modes (real orthonormal harmonics Yr_{m,k},
        :mod:`spectralshell.discretise.shtns_adapter`).
    radial : (n_t, n_modes) X^Y coefficients (the radial displacement).
    tangential : (n_t, n_modes) X^Psi (spheroidal) coefficients, 0 when inviscid.
    toroidal_modes, toroidal : the same for the toroidal X^Phi (empty unless excited).
    fits : one :class:`ModeFit` per excited mode (radial first, then toroidal).
    provenance : package version, scheme, step, radial resolution and spatial error per degree,
        wall time.
    """

    model: str
    params: dict[str, Any]
    times: np.ndarray
    modes: tuple[tuple[int, int], ...]
    radial: np.ndarray
    tangential: np.ndarray
    toroidal_modes: tuple[tuple[int, int], ...]
    toroidal: np.ndarray
    fits: tuple[ModeFit, ...]
    provenance: dict[str, Any]
    warnings: tuple[str, ...] = field(default=())

    record_types = (ModeFit,)

    @staticmethod
    def fit_of(m: int, k: int, fit: RateFit, extra_error: float) -> ModeFit:
        """A ModeFit from a rate fit, with ``extra_error`` added to the fit's own estimate."""
        return ModeFit(m=m, k=k, growth_rate=fit.growth_rate, frequency=fit.frequency,
                       error_estimate=float(fit.error_estimate + extra_error),
                       multiplier=complex(fit.multiplier))

    def coefficient(self, m: int, k: int) -> np.ndarray:
        """X^Y(t) of mode (m, k)."""
        try:
            return self.radial[:, self.modes.index((m, k))]
        except ValueError:
            raise KeyError(f"mode ({m}, {k}) is not in the trajectory: {self.modes}") from None

    def to_dict(self) -> dict[str, Any]:
        """The JSON of ``spectralshell simulate --json``: model, params, modes (fits)."""
        return {"model": self.model, "params": dict(self.params),
                "modes": [f.to_dict() for f in self.fits]}

    def summary(self) -> str:
        """The parameters and run settings, then each mode's fitted growth rate and frequency."""
        p = self.params
        head = (f"{self.model}: kappa = {p['kappa']}  nu = {p['nu']:g}  tau = {p['tau']:g}   "
                f"t_end = {p['t_end']:.6g}  {p['scheme']}  dt = {p['dt']:.4g}")
        return "\n".join([head, *(f"  (m, k) = ({m}, {k}):  growth rate {rate}   frequency "
                                  f"{frequency}   error <= {error}"
                                  for m, k, rate, frequency, error in self._fit_cells())])

    def _fit_cells(self) -> list[tuple[int, int, str, str, str]]:
        """m, k, growth rate, frequency and error of each fit, as the summary prints them."""
        return [(f.m, f.k, f"{f.growth_rate:+.10f}", f"{f.frequency:.10f}",
                 f"{f.error_estimate:.1e}") for f in self.fits]

    def _html_table(self) -> tuple[list[str], list[list[Any]]]:
        return (["m", "k", "growth rate", "frequency", "error <="],
                [list(cells) for cells in self._fit_cells()])

    def to_xarray(self) -> xr.Dataset:
        """Over (t, mode): radial and tangential, with coordinates m and k along ``mode``;
        over (t, toroidal_mode): toroidal (left out when empty); over ``fit``: fit_m, fit_k,
        growth_rate, frequency, error_estimate, multiplier_real and multiplier_imag."""
        fit = ("fit",)
        q = np.array([f.multiplier for f in self.fits], dtype=complex)

        def of(name: str, dtype: type = float) -> np.ndarray:
            return np.array([getattr(f, name) for f in self.fits], dtype=dtype)

        data = {"radial": variable(("t", "mode"), self.radial, "radial coefficient X^Y", "1"),
                "tangential": variable(("t", "mode"), self.tangential,
                                       "spheroidal coefficient X^Psi", "1"),
                "toroidal": variable(("t", "toroidal_mode"), self.toroidal,
                                     "toroidal coefficient X^Phi", "1"),
                "fit_m": variable(fit, of("m", int), "degree m of the fitted mode"),
                "fit_k": variable(fit, of("k", int), "order k of the fitted mode"),
                "growth_rate": variable(fit, of("growth_rate"), "fitted growth rate", "1"),
                "frequency": variable(fit, of("frequency"), "fitted angular frequency", "1"),
                "error_estimate": variable(fit, of("error_estimate"),
                                           "error bound of growth rate and frequency", "1"),
                "multiplier_real": variable(fit, q.real, "Re multiplier", "1"),
                "multiplier_imag": variable(fit, q.imag, "Im multiplier", "1")}
        coords = {"t": variable(("t",), self.times, "time t (forcing period 2 pi)", "1"),
                  **_mode_coords("mode", self.modes, ""),
                  **_mode_coords("toroidal_mode", self.toroidal_modes, "toroidal_")}
        return dataset(data, coords, result_attrs(self))

    def write_npz(self, path: str | Path) -> None:
        """Arrays times, m, k, radial, tangential (and toroidal_*), fits, plus JSON metadata."""
        arrays = {"times": self.times,
                  "m": np.array([m for m, _ in self.modes], dtype=int),
                  "k": np.array([k for _, k in self.modes], dtype=int),
                  "radial": self.radial, "tangential": self.tangential,
                  "toroidal_m": np.array([m for m, _ in self.toroidal_modes], dtype=int),
                  "toroidal_k": np.array([k for _, k in self.toroidal_modes], dtype=int),
                  "toroidal": self.toroidal,
                  "fit_growth_rate": np.array([f.growth_rate for f in self.fits]),
                  "fit_frequency": np.array([f.frequency for f in self.fits]),
                  "fit_error_estimate": np.array([f.error_estimate for f in self.fits]),
                  "metadata": np.array(json.dumps({**self.to_dict(),
                                                   "provenance": self.provenance,
                                                   "warnings": list(self.warnings)}))}
        with open(path, "wb") as handle:
            np.savez_compressed(handle, **arrays)


def _mode_coords(dim: str, modes: tuple[tuple[int, int], ...], prefix: str) -> dict[str, Variable]:
    """Coordinates m and k (named with ``prefix``) of the modes (m, k) along ``dim``."""
    return {f"{prefix}{name}": variable((dim,), np.array([mk[i] for mk in modes], dtype=int),
                                        f"{'degree' if name == 'm' else 'order'} {name}")
            for i, name in enumerate(("m", "k"))}
