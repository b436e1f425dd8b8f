"""Parameters of the 2D box cochlea model (thesis chapter 5)."""

from __future__ import annotations

from dataclasses import dataclass, field

from .._validate import require_int_in_range, require_nonnegative, require_positive
from ..errors import ParameterError

#: Largest number of cosine modes accepted (the thesis's largest run is M = 250).
N_SPATIAL_MAX = 2000
MODE_RANGE = (1, N_SPATIAL_MAX)


@dataclass(frozen=True, kw_only=True)
class CochleaParams:
    """Dimensionless parameters of the basilar-membrane model (thesis 5.2, Table 5.1).

    kappa : stiffness sigma pi / (rho L omega^2) > 0 at the base x = 0.
    nu : kinematic viscosity mu pi^2 / (rho L^2 omega) >= 0; nu = 0 is the inviscid limit.
    alpha : stiffness grading lambda_c L / pi >= 0: K = kappa e^{-alpha x} (1 + 2 tau sin t) on
        x in [0, pi]; alpha = 0 is uniform stiffness, where the cosine modes decouple.
    n_spatial : number M of cosine modes cos(k x), k = 1..M (k = 0 is motionless, thesis 5.3);
        None (the default) lets :func:`spectralshell.api.floquet` raise M until tau_min converges.
    spatial_mode : with alpha = 0, the single cosine mode k = K to analyse alone (Table 5.2,
        Fig 5.12); None analyses modes 1..M together. Excludes ``n_spatial``.

    Raises
    ------
    ParameterError : a value out of range, spatial_mode with alpha != 0, or spatial_mode together
        with n_spatial; the message names the parameter, value and range.
    """

    kappa: float = field(metadata={"help": "stiffness kappa at the base (dimensionless, > 0)"})
    nu: float = field(metadata={"help": "viscosity nu (dimensionless, >= 0; 0 = inviscid)"})
    alpha: float = field(metadata={"help": "stiffness decay rate alpha = lambda_c L / pi (>= 0)"})
    n_spatial: int | None = field(default=None, metadata={
        "help": "number M of cosine modes (default: raised until tau_min converges)",
        "range": MODE_RANGE})
    spatial_mode: int | None = field(default=None, metadata={
        "help": "single cosine mode K (needs alpha = 0)", "range": MODE_RANGE})

    def __post_init__(self) -> None:
        object.__setattr__(self, "kappa", require_positive("kappa", self.kappa))
        object.__setattr__(self, "nu", require_nonnegative("nu", self.nu))
        object.__setattr__(self, "alpha", require_nonnegative("alpha", self.alpha))
        if self.n_spatial is not None:
            object.__setattr__(self, "n_spatial",
                               require_int_in_range("n_spatial", self.n_spatial, *MODE_RANGE))
        if self.spatial_mode is not None:
            mode = require_int_in_range("spatial_mode", self.spatial_mode, *MODE_RANGE)
            object.__setattr__(self, "spatial_mode", mode)
            if self.alpha != 0.0:
                raise ParameterError(f"spatial_mode = {mode} is invalid with alpha = {self.alpha:g}: "
                                     "a single mode needs alpha = 0 (graded stiffness couples all "
                                     "cosine modes)")
            if self.n_spatial is not None:
                raise ParameterError(f"n_spatial = {self.n_spatial} is invalid with spatial_mode = "
                                     f"{mode}: give one of them")
