"""Floquet result of a model with a spatial truncation (number of spatial modes, e.g. the cochlea)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from .floquet import FloquetResult
from .records import MarginalTau
from .notebook import json_attr, named, or_nan, variable

if TYPE_CHECKING:
    import xarray as xr


def truncation_reason(m: MarginalTau, change: float | None, provenance: dict[str, Any], *,
                      pair: str, what: str, size: str, fixed: str) -> str | None:
    """Why the error estimate of ``m`` is above tol when a spatial truncation (``what``, its
    ``size`` compared between ``pair``) changes tau_min by ``change``: a tau_min at one of the
    pair only, or the change, stopped by tol_spatial (from ``provenance``) or ``fixed``; None
    when the temporal estimate is the larger part."""
    if change is None:
        return f"there is a tau_min at only one of {pair}, so the estimate is tau_min itself"
    if change < m.error_estimate:
        return None
    tol_spatial = provenance.get("options", {}).get("tol_spatial")
    stop = (fixed if tol_spatial is None else
            f"{size} is refined only until this change is <= tol_spatial = {tol_spatial:g}")
    return f"{what}: tau_min changes by {change:.1e} between {pair} ({stop})"


@dataclass(frozen=True, kw_only=True, eq=False, repr=False)
class SpatialFloquetResult(FloquetResult):
    """Marginal amplitudes at a spatial truncation, with the spatial part of the error estimate.

    The attributes of :class:`FloquetResult`, and these:

    Attributes
    ----------
    n_spatial : number of spatial modes of the reported values (1 for a single-mode run).
    n_spatial_previous : the coarsest truncation they were compared with, n_spatial // 2 (None:
        no comparison, a single decoupled mode, which is exact in space).
    spatial_change : per kind, ``|tau_min(n_spatial) - tau_min(n_spatial_previous)|`` at a
        fixed n_spatial; refined in M, the larger of that and the change from the M between
        them (3/4 or 2/3 n_spatial). None when there is no comparison or a kind has no tau_min
        at one of them. Each kind's
        ``error_estimate`` is the larger of this and the temporal estimate.
    physical : the cgs inputs the dimensionless parameters were converted from, or None.
    """

    n_spatial: int
    n_spatial_previous: int | None
    spatial_change: dict[str, float | None]
    physical: dict[str, float] | None = None

    def to_dict(self) -> dict[str, Any]:
        out = super().to_dict()
        out["n_spatial"] = self.n_spatial
        out["n_spatial_previous"] = self.n_spatial_previous
        out["spatial_change"] = dict(self.spatial_change)
        if self.physical is not None:
            out["physical"] = dict(self.physical)
        return out

    def error_reason(self, kind: str, m: MarginalTau) -> str:
        """Why the error estimate of ``kind`` is above tol: the change of tau_min between the
        last two numbers M of spatial modes, where that is the larger part of the estimate
        (the refinement in M stops at tol_spatial, or M is fixed); a tau_min found at one M
        only; otherwise that of :meth:`FloquetResult.error_reason`."""
        if self.n_spatial_previous is None:
            return super().error_reason(kind, m)
        reason = truncation_reason(
            m, self.spatial_change.get(kind), self.provenance,
            pair=f"M = {self.n_spatial_previous} and M = {self.n_spatial} spatial modes",
            what="the spatial truncation", size="M", fixed="n_spatial is fixed")
        return super().error_reason(kind, m) if reason is None else reason

    def to_xarray(self) -> xr.Dataset:
        """The Dataset of :meth:`FloquetResult.to_xarray`, with n_spatial (a scalar),
        spatial_change over ``kind`` (NaN where there is none), and n_spatial_previous and
        physical as JSON attrs (null: none)."""
        ds = super().to_xarray()
        change = [or_nan(self.spatial_change.get(str(k))) for k in ds["kind"].values]
        ds["n_spatial"] = named((), self.n_spatial, "n_spatial", "")
        ds["spatial_change"] = variable(("kind",), change, "|tau_min(n_spatial) - "
                                        "tau_min(n_spatial_previous)|", "1")
        ds.attrs.update(n_spatial_previous=json_attr(self.n_spatial_previous),
                        physical=json_attr(self.physical))
        return ds
