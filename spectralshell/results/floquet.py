"""Result objects of the Floquet computations (frozen, with provenance) and their file forms."""

from __future__ import annotations

import csv
import json
import math
from collections.abc import Callable, Mapping
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .._version import stamp
from ..params.stiffness import amplitude_warnings
from .base import Plottable, Result, format_params
from .notebook import (Variable, coordinate, dataset, named, or_nan, padded, result_attrs, table,
                       variable)
from .maps import uncertified_note
from .records import Boundary, Exponents, MarginalTau, Tip

if TYPE_CHECKING:
    import pandas as pd
    import xarray as xr

#: The forcing amplitude tau as a scalar coordinate of a Dataset.
TAU_LONG_NAME = "forcing amplitude tau"


def provenance(options: dict[str, Any]) -> dict[str, Any]:
    """Package and library versions (:func:`spectralshell._version.stamp`) and the solver
    options that produced a result."""
    return {**stamp(), "options": dict(options)}


def _float(x) -> float | None:
    return None if x is None else float(x)


def marginal_dict(m: MarginalTau) -> dict[str, Any]:
    """JSON form of one kind: tau (list), tau_min, n_temporal, error_estimate, method and
    complete_to (``tau`` holds every real tau up to it, in the sense of
    :func:`spectralshell.solvers.marginal.converged_pair`; null: no bound, a model without
    forcing)."""
    return {"tau": [float(t) for t in m.tau], "tau_min": _float(m.tau_min),
            "n_temporal": m.n_temporal, "error_estimate": _float(m.error_estimate),
            "method": m.method,
            "complete_to": None if np.isinf(m.complete_to) else float(m.complete_to)}


def certification_warnings(res: Mapping[str, MarginalTau],
                           tau_max: float | None = None) -> list[str]:
    """A flag for each kind whose list is not proved complete up to its tau_min, or, with
    ``tau_max``, whose empty answer is not proved up to tau_max (complete_to below it: the zero
    count could not prove it at a fixed n_temporal; the converging loop raises instead)."""
    out = [f"{kind} tau_min = {m.tau_min:.6g} is not certified: a smaller real tau is excluded "
           f"only below complete_to = {m.complete_to:.4g} at this truncation"
           for kind, m in res.items() if m.tau_min is not None and m.complete_to < m.tau_min]
    if tau_max is not None:
        out += [f"{kind}: no marginal tau <= {tau_max:g} was found, but none is proved only "
                f"below complete_to = {m.complete_to:.4g} at this truncation (the zero count "
                "could not prove it): leave n_temporal unset to have it proved or refused"
                for kind, m in res.items() if m.unproved_empty(tau_max)]
    return out


#: Why a converged tau_min has an error estimate above tol: the truncation has converged
#: (|change| < tol) but rounding limits the value, e.g. tau = 0 as a multiple eigenvalue at a
#: finger tip on the axis, which double precision splits by ~sqrt(eps) (see
#: :func:`spectralshell.solvers.marginal.qz_taus`); no larger N helps.
ROUNDING = ("rounding limits it (a multiple eigenvalue at tau = 0, or eps x tau_min), not the "
            "truncation")


def above_tol(m: MarginalTau, tol: float | None) -> bool:
    """Whether the kind ``m`` has a tau_min whose error estimate exceeds ``tol``."""
    return (tol is not None and m.tau_min is not None and m.error_estimate is not None
            and m.error_estimate > tol)


def resolution_warnings(res: Mapping[str, MarginalTau], tol: float,
                        reason: Callable[[str, MarginalTau], str] = lambda kind, m: ROUNDING
                        ) -> list[str]:
    """A flag for each kind whose tau_min has an error estimate above ``tol``, saying why
    (``reason(kind, m)``; by default :data:`ROUNDING`, that of a converged truncation)."""
    return [f"{kind} tau_min = {m.tau_min:.6g} is resolved only to {m.error_estimate:.1e}, above "
            f"tol = {tol:g}: {reason(kind, m)}" for kind, m in res.items() if above_tol(m, tol)]


def marginal_variables(cells: np.ndarray, dims: tuple[str, ...]) -> dict[str, Variable]:
    """Dataset variables of the MarginalTau records ``cells`` (an object array over ``dims``):
    tau_min and error_estimate (NaN where there is no tau), has_tau, n_temporal, complete_to,
    method, and every marginal tau over a further dimension 'root' (NaN-padded)."""
    flat = cells.ravel()

    def of(get) -> np.ndarray:
        return np.array([get(m) for m in flat]).reshape(cells.shape)

    return {"tau_min": named(dims, of(lambda m: or_nan(m.tau_min)), "tau_min"),
            "has_tau": named(dims, of(lambda m: m.tau_min is not None), "has_tau", ""),
            "error_estimate": named(dims, of(lambda m: or_nan(m.error_estimate)),
                                    "error_estimate"),
            "n_temporal": named(dims, of(lambda m: m.n_temporal), "n_temporal", ""),
            "complete_to": variable(dims, of(lambda m: m.complete_to), "tau holds every real "
                                    "marginal tau up to this value (inf: all)", "1"),
            "method": variable(dims, of(lambda m: m.method), "eigensolver at the final N"),
            "tau": variable((*dims, "root"), padded((m.tau for m in flat), cells.shape),
                            "marginal tau, ascending (NaN after the last)", "1")}


def _or_none(value: float | None, spec: str, missing: str = "none") -> str:
    """``value`` formatted with ``spec``, ``missing`` for None."""
    return missing if value is None else format(value, spec)


@dataclass(frozen=True, kw_only=True, eq=False, repr=False)
class FloquetResult(Result, Plottable):
    """Marginal amplitudes of each requested Floquet kind (None for a kind not asked)."""

    model: str
    params: dict[str, Any]
    harmonic: MarginalTau | None
    subharmonic: MarginalTau | None
    provenance: dict[str, Any]
    warnings: tuple[str, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        out = {"model": self.model, "params": dict(self.params)}
        for kind in ("harmonic", "subharmonic"):
            m = getattr(self, kind)
            out[kind] = None if m is None else marginal_dict(m)
        out["warnings"] = list(self.warnings)
        out["provenance"] = self.provenance
        return out

    def summary(self) -> str:
        """The parameters, then per kind tau_min, its error, N and the first six marginal tau."""
        lines = [f"{self.model}: {format_params(self.params)}   (K(t) = kappa (1 + 2 tau sin t))"]
        for kind in ("harmonic", "subharmonic"):
            m = getattr(self, kind)
            if m is None:
                continue
            complete = "" if math.isinf(m.complete_to) else f" (complete to {m.complete_to:.4g})"
            if m.tau_min is None:
                bound = self.provenance.get("options", {}).get("tau_max")
                below = "" if bound is None else f" <= {bound:g}"
                lines.append(f"  {kind:<12} no marginal tau{below}{complete} "
                             f"(N = {m.n_temporal})")
                continue
            taus = ", ".join(f"{t:.10g}" for t in m.tau[:6]) + (" ..." if m.tau.size > 6 else "")
            lines.append(f"  {kind:<12} tau_min = {m.tau_min:.12g}   error <= "
                         f"{m.error_estimate:.1e}   N = {m.n_temporal}   all tau{complete}: {taus}")
            tol = self.provenance.get("options", {}).get("tol")
            if above_tol(m, tol):
                lines.append(f"  {'':<12} error above tol = {tol:g}: {self.error_reason(kind, m)}")
        return "\n".join(lines)

    def error_reason(self, kind: str, m: MarginalTau) -> str:
        """Why the error estimate of ``kind`` (its MarginalTau ``m``) is above tol: a fixed
        truncation N, or else rounding (:data:`ROUNDING`)."""
        fixed = self.provenance.get("options", {}).get("n_temporal")
        if fixed is not None:
            return f"N is fixed (n_temporal = {fixed}), so it is not raised until tol is met"
        return ROUNDING

    def marginals(self) -> list[MarginalTau]:
        """The MarginalTau of each kind that was asked (harmonic first)."""
        return [m for m in (self.harmonic, self.subharmonic) if m is not None]

    def _html_table(self) -> tuple[list[str], list[list[Any]]]:
        return (["kind", "tau_min", "error <=", "N", "complete to"],
                [[m.kind, _or_none(m.tau_min, ".12g"), _or_none(m.error_estimate, ".1e", ""),
                  m.n_temporal, f"{m.complete_to:.4g}"] for m in self.marginals()])

    def to_xarray(self) -> xr.Dataset:
        """Variables over ``kind`` (:func:`marginal_variables`): tau_min, has_tau,
        error_estimate, n_temporal, complete_to, method, and tau(kind, root)."""
        marginals = self.marginals()
        cells = np.empty(len(marginals), dtype=object)
        cells[:] = marginals
        return dataset(marginal_variables(cells, ("kind",)),
                       {"kind": coordinate(self.model, "kind", [m.kind for m in marginals])},
                       result_attrs(self))

    def to_dataframe(self) -> pd.DataFrame:
        """One row per kind: the variables of :meth:`to_xarray` over ``kind``."""
        return table(self.to_xarray(), ("kind",))


@dataclass(frozen=True, kw_only=True, eq=False, repr=False)
class ExponentsResult(Result):
    """Floquet exponents gamma (growth rate Re gamma per unit time) at one tau.

    ``error_estimate`` covers the temporal truncation N and, for a model with spatial modes
    (the cochlea at ``n_spatial`` = M), the spatial one: ``spatial_change`` is the largest
    distance (modulo i) from a listed exponent to the nearest exponent at
    ``n_spatial_previous`` = M // 2 (both None without spatial modes, for a single decoupled
    mode or at M = 1)."""

    model: str
    params: dict[str, Any]
    tau: float
    gamma: np.ndarray
    n_temporal: int
    error_estimate: float
    provenance: dict[str, Any]
    warnings: tuple[str, ...] = ()
    complete_in: tuple[float, float] | None = None
    n_spatial_previous: int | None = None
    spatial_change: float | None = None

    @classmethod
    def build(cls, *, model, params, tau, exponents: Exponents, options,
              coarser: tuple[int, float] | None = None,
              warnings: tuple[str, ...] = ()) -> "ExponentsResult":
        """The result of ``exponents``; ``coarser``: (M // 2, the spatial change) when the
        exponents were compared with those of the coarser spatial truncation."""
        previous, change = coarser if coarser is not None else (None, None)
        error = exponents.error_estimate if change is None else max(exponents.error_estimate,
                                                                    change)
        return cls(model=model, params=params, tau=tau, gamma=exponents.gamma,
                   n_temporal=exponents.n_temporal, error_estimate=error,
                   provenance=provenance(options),
                   warnings=(*amplitude_warnings(tau), *warnings),
                   complete_in=exponents.complete_in, n_spatial_previous=previous,
                   spatial_change=change)

    @property
    def multipliers(self) -> np.ndarray:
        """Floquet multipliers exp(2 pi gamma) over one forcing period."""
        return np.exp(2 * np.pi * self.gamma)

    def to_dict(self) -> dict[str, Any]:
        return {"model": self.model, "params": dict(self.params), "tau": self.tau,
                "exponents": [{"re": float(g.real), "im": float(g.imag)} for g in self.gamma],
                "n_temporal": self.n_temporal, "error_estimate": self.error_estimate,
                "n_spatial_previous": self.n_spatial_previous,
                "spatial_change": self.spatial_change,
                "complete_in": None if self.complete_in is None else list(self.complete_in),
                "warnings": list(self.warnings), "provenance": self.provenance}

    def summary(self) -> str:
        """The parameters and N, then each exponent gamma with its multiplier, and where the
        list is proved complete."""
        spatial = ("" if self.spatial_change is None else
                   f"; {self.spatial_change:.1e} from n_spatial = {self.n_spatial_previous}")
        head = (f"{self.model}: {format_params(self.params)}  tau = {self.tau:g}   "
                f"(N = {self.n_temporal}, error <= {self.error_estimate:.1e}{spatial})")
        lines = [head, *(f"  gamma = {g_re} {g_im}i   multiplier = {q_re} {q_im}i"
                         for g_re, g_im, q_re, q_im in self._cells())]
        if self.complete_in is not None:
            lo, hi = self.complete_in
            lines.append(f"  every exponent with {lo:.4g} < Re gamma <= {hi:.4g} is listed "
                         "(argument-principle count; the fluid's continuous spectrum on the "
                         "negative real axis excluded)")
        return "\n".join(lines)

    def _cells(self) -> list[tuple[str, str, str, str]]:
        """Re and Im of each gamma and of its multiplier, as the summary prints them."""
        return [(f"{g.real:+.12f}", f"{g.imag:+.12f}", f"{q.real:+.10f}", f"{q.imag:+.10f}")
                for g, q in zip(self.gamma, self.multipliers)]

    def _html_table(self) -> tuple[list[str], list[list[Any]]]:
        return (["Re gamma", "Im gamma", "Re multiplier", "Im multiplier"],
                [list(cells) for cells in self._cells()])

    def to_xarray(self) -> xr.Dataset:
        """Over ``exponent`` (0 = largest Re gamma): gamma_real, gamma_imag, multiplier_real,
        multiplier_imag; scalars n_temporal and error_estimate; tau a scalar coordinate."""
        dims = ("exponent",)
        q = self.multipliers
        data = {"gamma_real": variable(dims, self.gamma.real, "growth rate Re gamma", "1"),
                "gamma_imag": variable(dims, self.gamma.imag, "Im gamma, in (-1/2, 1/2]", "1"),
                "multiplier_real": variable(dims, q.real, "Re exp(2 pi gamma)", "1"),
                "multiplier_imag": variable(dims, q.imag, "Im exp(2 pi gamma)", "1"),
                "n_temporal": named((), self.n_temporal, "n_temporal", ""),
                "error_estimate": variable((), self.error_estimate, "max |change| of the "
                                           "exponents between N and the previous N (and "
                                           "between M and M // 2)", "1")}
        coords = {"exponent": variable(dims, np.arange(self.gamma.size),
                                       "exponent, by decreasing Re gamma"),
                  "tau": variable((), self.tau, TAU_LONG_NAME, "1")}
        return dataset(data, coords, result_attrs(self))

    def to_dataframe(self) -> pd.DataFrame:
        """One row per exponent: the variables of :meth:`to_xarray` over ``exponent``."""
        return table(self.to_xarray(), ("exponent",))

    def headline(self) -> str:
        """One line: the largest growth rate Re gamma, stable or not (a scene's summary)."""
        g = self.gamma[0]
        state = "unstable" if g.real > 0 else "stable"
        return (f"  exponents at tau = {self.tau:g}: largest growth rate Re gamma = "
                f"{g.real:+.10f} ({state}), Im gamma = {g.imag:+.6f}")


@dataclass(frozen=True, kw_only=True, eq=False, repr=False)
class TonguesResult(Result, Plottable):
    """An Ince-Strutt diagram: marginal tau of each kind at every kappa, the finger tips, and
    the boundary curves traced through them (``boundaries``: :class:`Boundary` records, empty
    when not traced); ``uncertified``: the (kappa, kind) whose row has no tau <= tau_max but
    whose emptiness the zero count could not prove (issue 23: not "none")."""

    model: str
    params: dict[str, Any]
    kappa: np.ndarray
    kinds: tuple[str, ...]
    rows: tuple[dict[str, MarginalTau], ...]
    tips: tuple[Tip, ...]
    provenance: dict[str, Any]
    warnings: tuple[str, ...] = field(default=())
    boundaries: tuple[Boundary, ...] = field(default=())
    uncertified: tuple[tuple[float, str], ...] = field(default=())

    def uncertified_note(self) -> str:
        """The warning on the ``uncertified`` points and what to change ('' if none)."""
        if not self.uncertified:
            return ""
        return uncertified_note(len(self.uncertified), self.kappa.size * len(self.kinds),
                                float(self.provenance["options"]["tau_max"]))

    def points(self, kind: str) -> tuple[np.ndarray, np.ndarray]:
        """All (kappa, tau) points of one kind, flattened (for plotting and CSV)."""
        ks = [np.full(r[kind].tau.size, k) for k, r in zip(self.kappa, self.rows)]
        ts = [r[kind].tau for r in self.rows]
        return (np.concatenate(ks) if ks else np.empty(0)), (np.concatenate(ts) if ts else np.empty(0))

    def to_dict(self) -> dict[str, Any]:
        out = {"model": self.model, "params": dict(self.params),
               "kappa": [float(k) for k in self.kappa]}
        for kind in self.kinds:
            out[kind] = {key: [marginal_dict(r[kind])[key] for r in self.rows]
                         for key in ("tau", "tau_min", "n_temporal", "error_estimate",
                                     "complete_to")}
        out["tips"] = [{k: (float(v) if k != "kind" else v) for k, v in asdict(t).items()}
                       for t in self.tips]
        out["boundaries"] = [{"kind": b.kind, "kappa": b.kappa.tolist(), "tau": b.tau.tolist()}
                             for b in self.boundaries]
        out["uncertified"] = [{"kappa": k, "kind": kind} for k, kind in self.uncertified]
        out["warnings"] = list(self.warnings)
        out["provenance"] = self.provenance
        return out

    def summary(self) -> str:
        """The parameters and kappa range, then each finger tip with its errors."""
        head = (f"{self.model} Ince-Strutt diagram: {format_params(self.params)}, kappa in "
                f"[{self.kappa.min():g}, {self.kappa.max():g}] ({self.kappa.size} points)")
        return "\n".join([head, *(f"  {kind:<12} finger tip: kappa = {kappa} (+-{dk})  "
                                  f"tau = {tau} (+-{dt})"
                                  for kind, kappa, dk, tau, dt in self._tip_cells())])

    def _tip_cells(self) -> list[tuple[str, str, str, str, str]]:
        """Kind, kappa, its error, tau and its error of each tip, as the summary prints them."""
        return [(t.kind, f"{t.kappa:.12g}", f"{t.kappa_error:.0e}", f"{t.tau:.12g}",
                 f"{t.tau_error:.0e}") for t in self.tips]

    def _html_table(self) -> tuple[list[str], list[list[Any]]]:
        return ["finger tip", "kappa", "+-", "tau", "+-"], [list(c) for c in self._tip_cells()]

    def to_xarray(self) -> xr.Dataset:
        """Over (kappa, kind) the variables of :func:`marginal_variables` (tau_min NaN and
        has_tau false where there is none); over ``tip`` the finger tips tip_kind, tip_kappa,
        tip_kappa_error, tip_tau, tip_tau_error (left out when there are none)."""
        cells = np.empty((self.kappa.size, len(self.kinds)), dtype=object)
        cells[:] = [[r[kind] for kind in self.kinds] for r in self.rows]
        data = marginal_variables(cells, ("kappa", "kind"))
        tips = {"kind": "Floquet kind of the finger", "kappa": "stiffness kappa at the tip",
                "kappa_error": "width of the final bracket of the tip's kappa",
                "tau": "marginal tau at the tip", "tau_error": "Floquet error estimate of tau"}
        for name, long_name in tips.items():
            values = np.array([getattr(t, name) for t in self.tips],
                              dtype=str if name == "kind" else float)
            data[f"tip_{name}"] = variable(("tip",), values, long_name,
                                           "" if name == "kind" else "1")
        coords = {"kappa": coordinate(self.model, "kappa", self.kappa),
                  "kind": coordinate(self.model, "kind", list(self.kinds))}
        return dataset(data, coords, result_attrs(self))

    def to_dataframe(self) -> pd.DataFrame:
        """One row per (kappa, kind): tau_min (NaN where none), has_tau, error_estimate,
        n_temporal, complete_to, method."""
        return table(self.to_xarray(), ("kappa", "kind"))

    def write_csv(self, path: str | Path) -> None:
        """Rows kind,kappa,tau (one per marginal point)."""
        with open(path, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["kind", "kappa", "tau"])
            for kind in self.kinds:
                for k, t in zip(*self.points(kind)):
                    w.writerow([kind, repr(float(k)), repr(float(t))])

    def write_npz(self, path: str | Path) -> None:
        """Arrays kappa, <kind>_kappa / <kind>_tau (points), <kind>_tau_min with
        <kind>_has_tau_min (False where there is none), tips, and the JSON metadata."""
        arrays: dict[str, Any] = {"kappa": self.kappa}
        for kind in self.kinds:
            arrays[f"{kind}_kappa"], arrays[f"{kind}_tau"] = self.points(kind)
            tmin = [r[kind].tau_min for r in self.rows]
            arrays[f"{kind}_has_tau_min"] = np.array([t is not None for t in tmin])
            arrays[f"{kind}_tau_min"] = np.array([t if t is not None else 0.0 for t in tmin])
        arrays["metadata"] = np.array(json.dumps({k: v for k, v in self.to_dict().items()
                                                  if k in ("model", "params", "tips", "provenance")}))
        np.savez(path, **arrays)


@dataclass(frozen=True, kw_only=True, eq=False, repr=False)
class StabilityResult(Result):
    """Stability of each degree m (and each value of the ``swept`` parameters) at one forcing
    amplitude tau.

    ``modes`` holds, per m (per point, m outermost, with the swept parameters' values):
    ``unstable``,
    ``kind`` (the kind whose instability has the lower threshold, None if stable), and the
    marginal tau of each kind below the given tau; a point the model refuses has ``defined``
    False and its ``reason`` instead (the key is absent where the point is defined); a point
    whose verdict could not be proved (issue 23) has ``proved`` False and its ``reason``
    (absent where proved), and ``unstable`` False there means nothing.
    """

    model: str
    tau: float
    params: dict[str, Any]
    modes: tuple[dict[str, Any], ...]
    provenance: dict[str, Any]
    warnings: tuple[str, ...] = ()
    swept: tuple[str, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        return {"model": self.model, "tau": self.tau, "params": dict(self.params),
                "swept": list(self.swept), "modes": [dict(m) for m in self.modes],
                "warnings": list(self.warnings), "provenance": self.provenance}

    def unproved(self) -> int:
        """The number of points whose verdict could not be proved."""
        return sum(not mode.get("proved", True) for mode in self.modes)

    def unproved_note(self) -> str:
        """One line on the unproved points and what to change ('' if none)."""
        count = self.unproved()
        if not count:
            return ""
        first = next(mode for mode in self.modes if not mode.get("proved", True))
        return (f"{count} of {len(self.modes)} points have no proved verdict at tau = "
                f"{self.tau:g} (first {self._point(first)}: {first['reason']})")

    def _point(self, mode: dict[str, Any]) -> str:
        return ", ".join([f"m = {mode['m']}"] + [f"{n} = {mode[n]:.4g}" for n in self.swept])

    def summary(self) -> str:
        """One line per degree m (per point): stable, unstable (which kind) or not defined (why),
        and the marginal tau below tau."""
        lines = [f"{self.model} at tau = {self.tau:g}: {format_params(self.params)}"]
        width = max((len(self._point(mode)) for mode in self.modes), default=0) + 2
        for mode in self.modes:
            if not mode.get("defined", True) or not mode.get("proved", True):
                what = "not defined" if not mode.get("defined", True) else "not proved"
                lines.append(f"  {self._point(mode):<{width}}{what}: {mode['reason']}")
                continue
            below = "; ".join(f"{k[4:]} tau below: {_taus(v)}"
                              for k, v in mode.items() if k.startswith("tau_"))
            lines.append(f"  {self._point(mode):<{width}}{_state(mode):<24} {below}")
        return "\n".join(lines)

    def kinds(self) -> list[str]:
        """The Floquet kinds whose marginal tau the modes list."""
        return [k[4:] for k in (self.modes[0] if self.modes else {}) if k.startswith("tau_")]

    def _html_table(self) -> tuple[list[str], list[list[Any]]]:
        kinds = self.kinds()
        return (["m", *self.swept, "state", *(f"{kind} tau below" for kind in kinds)],
                [[mode["m"], *(f"{mode[n]:.4g}" for n in self.swept), _state(mode),
                  *(_taus(mode[f"tau_{kind}"]) for kind in kinds)] for mode in self.modes])

    def to_xarray(self) -> xr.Dataset:
        """Over degree ``m`` (and the swept parameters): defined, unstable, proved, unstable_kind
        ('' where stable or not defined); over those and kind: tau_min (the smallest marginal
        tau below tau, NaN where none), has_tau, and every marginal tau below tau over 'root'
        (NaN-padded); tau a scalar coordinate."""
        kinds = self.kinds()
        axes = ("m", *self.swept)
        values = {n: list(dict.fromkeys(mode[n] for mode in self.modes)) for n in axes}
        points = tuple(len(values[n]) for n in axes)  # the modes are their product, m outermost
        below = [[mode[f"tau_{kind}"] for kind in kinds] for mode in self.modes]
        lowest = np.array([[min(v, default=np.nan) for v in row] for row in below],
                          dtype=float).reshape(*points, len(kinds))
        dims = (*axes, "kind")

        def per_point(values: list) -> np.ndarray:
            return np.array(values).reshape(points)

        data = {"defined": variable(axes, per_point([m.get("defined", True) for m in self.modes]),
                                    "the model defines this point"),
                "unstable": variable(axes, per_point([m["unstable"] for m in self.modes]),
                                     "unstable at tau"),
                "proved": variable(axes, per_point([m.get("proved", True) for m in self.modes]),
                                   "the verdict is proved (false: unstable means nothing)"),
                "unstable_kind": variable(axes, per_point([m["kind"] or "" for m in self.modes]),
                                          "kind with the lower threshold ('' if stable)"),
                "tau_min": variable(dims, lowest, "smallest marginal tau below tau", "1"),
                "has_tau": variable(dims, np.isfinite(lowest), "a marginal tau below tau exists"),
                "tau_below": variable((*dims, "root"),
                                      padded((v for row in below for v in row),
                                             (*points, len(kinds))),
                                      "marginal tau below tau, ascending (NaN after the last)",
                                      "1")}
        coords = {**{n: coordinate(self.model, n, values[n]) for n in axes},
                  "kind": coordinate(self.model, "kind", kinds),
                  "tau": variable((), self.tau, TAU_LONG_NAME, "1")}
        return dataset(data, coords, result_attrs(self))

    def to_dataframe(self) -> pd.DataFrame:
        """One row per degree m (per point): defined, unstable, unstable_kind and
        tau_min_<kind> of each kind."""
        ds = self.to_xarray()
        axes = ("m", *self.swept)
        lowest = ds["tau_min"].drop_vars("tau").to_dataframe()["tau_min"].unstack("kind")
        return table(ds, axes).join(lowest.add_prefix("tau_min_"))


def _state(mode: dict[str, Any]) -> str:
    """'stable', 'UNSTABLE (kind)' or 'not proved' of one degree of a
    :class:`StabilityResult`."""
    if not mode.get("proved", True):
        return "not proved"
    return f"UNSTABLE ({mode['kind']})" if mode["unstable"] else "stable"


def _taus(taus: list[float]) -> str:
    """Marginal tau as a list '0.355, 1.2', or 'none'."""
    return ", ".join(f"{t:.6g}" for t in taus) or "none"
