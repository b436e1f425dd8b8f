"""Parameters of the immersed circular fibre (thesis chapter 4)."""

from __future__ import annotations

from dataclasses import dataclass, field

from .._validate import require_choice, require_int_in_range, require_nonnegative, require_positive
from ..errors import ParameterError

#: Where the pumped stiffness K(t) enters (thesis 4.2, Fig 4.2): both jump conditions (the model),
#: only the pressure jump (4.15), or only the tangential-stress jump (4.16).
FORCINGS = ("both", "pressure", "tangential")

#: Largest wavenumber accepted (the Bessel-ratio kernels are tested up to order 200).
M_MAX = 200
M_RANGE = (2, M_MAX)


@dataclass(frozen=True, kw_only=True)
class FibreParams:
    """Dimensionless parameters of one angular wavenumber of the fibre (thesis 4.1.1-4.2).

    m : wavenumber >= 2. m = 0 changes the enclosed area, which the incompressible fluid inside
        forbids (its radial velocity at r = 1 must vanish), and the elastic load of a uniform
        dilation is zero anyway. m = 1 is a rigid translation, on which the linearised membrane
        load -K(t) [[m^2, m], [m, m^2]] X vanishes (the matrix is singular at m = 1).
    kappa : stiffness sigma / (rho R^2 omega^2) > 0 (4.6).
    nu : kinematic viscosity mu / (rho R^2 omega) >= 0 (4.5); nu = 0 is the inviscid limit.
    forcing : where K(t) = kappa (1 + 2 tau sin t) is pumped: 'both' (the model), 'pressure'
        (pressure jump (4.15) only) or 'tangential' (tangential-stress jump (4.16) only), the
        split of Fig 4.2; the other jump then uses the constant kappa.

    Raises
    ------
    ParameterError : a value out of range; the message names the parameter, value and range.
    """

    m: int = field(metadata={"help": "angular wavenumber m >= 2", "range": M_RANGE})
    kappa: float = field(metadata={"help": "stiffness kappa (dimensionless, > 0)"})
    nu: float = field(metadata={"help": "viscosity nu (dimensionless, >= 0; 0 = inviscid)"})
    forcing: str = field(default="both", metadata={"help": "both, pressure or tangential"})

    def __post_init__(self) -> None:
        try:
            m = require_int_in_range("m", self.m, *M_RANGE)
        except ParameterError as exc:
            raise ParameterError(f"{exc} (m = 0 changes the enclosed area and m = 1 is a rigid "
                                 "translation: neither is a fibre mode)") from None
        object.__setattr__(self, "m", m)
        object.__setattr__(self, "kappa", require_positive("kappa", self.kappa))
        object.__setattr__(self, "nu", require_nonnegative("nu", self.nu))
        object.__setattr__(self, "forcing", require_choice("forcing", self.forcing, FORCINGS))
