"""Minimum-tau maps over two parameter axes (thesis Fig 6.13, Fig 5.18): result and file forms."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np


@dataclass(frozen=True, kw_only=True, eq=False)
class TauMapResult:
    """Smallest marginal tau <= tau_max over the degrees m and kinds, at every (x, y) point.

    Attributes
    ----------
    x_name, y_name : the axes' parameter names (with units in ``units``).
    x, y : grids (1-D). tau_min : array (len(y), len(x)), NaN-free: ``has_tau`` marks points with
        an instability below tau_max; elsewhere tau_min holds tau_max.
    degree : the m attaining tau_min (0 where none). kind : 'H', 'S' or '' per point.
    error_estimate : Floquet error estimate of tau_min (0 where none).
    """

    model: str
    params: dict[str, Any]
    x_name: str
    y_name: str
    units: dict[str, str]
    x: np.ndarray
    y: np.ndarray
    degrees: tuple[int, ...]
    tau_max: float
    tau_min: np.ndarray
    has_tau: np.ndarray
    degree: np.ndarray
    kind: np.ndarray
    error_estimate: np.ndarray
    provenance: dict[str, Any]

    def to_dict(self) -> dict[str, Any]:
        return {"model": self.model, "params": dict(self.params), "x_name": self.x_name,
                "y_name": self.y_name, "units": dict(self.units), "x": self.x.tolist(),
                "y": self.y.tolist(), "degrees": list(self.degrees), "tau_max": self.tau_max,
                "tau_min": [[float(v) if h else None for v, h in zip(row, hrow)]
                            for row, hrow in zip(self.tau_min, self.has_tau)],
                "degree": self.degree.tolist(), "kind": self.kind.tolist(),
                "max_error_estimate": float(self.error_estimate.max(initial=0.0)),
                "provenance": self.provenance}

    def write_npz(self, path: str | Path) -> None:
        """Arrays x, y, tau_min, has_tau, degree, kind, error_estimate and JSON metadata."""
        meta = {k: v for k, v in self.to_dict().items()
                if k in ("model", "params", "x_name", "y_name", "units", "degrees", "tau_max",
                         "provenance")}
        np.savez(path, x=self.x, y=self.y, tau_min=self.tau_min, has_tau=self.has_tau,
                 degree=self.degree, kind=self.kind.astype("U1"), error_estimate=self.error_estimate,
                 metadata=np.array(json.dumps(meta)))
