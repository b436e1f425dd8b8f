"""Parameters of the immersed spherical membrane (thesis chapter 6)."""

from __future__ import annotations

from dataclasses import dataclass, field

from .._validate import require_choice, require_int_in_range, require_nonnegative, require_positive
from ..errors import ParameterError

COMPONENTS = ("poloidal", "toroidal")
#: Degrees m accepted (the spherical kernels are tested up to 200).
M_RANGE = (2, 200)


@dataclass(frozen=True, kw_only=True)
class SphereParams:
    """Dimensionless parameters of one spherical-harmonic degree of the membrane (thesis 6.1-6.2).

    m : degree >= 2. Degree 0 would change the enclosed volume (forbidden by incompressibility)
        and degree 1 is a rigid translation, on which the membrane force -(m-1)(m+2) K X vanishes.
    kappa : stiffness sigma / (rho R^3 omega^2) > 0.
    nu : kinematic viscosity mu / (rho R^2 omega) >= 0; nu = 0 is the inviscid model.
    component : 'poloidal' (X^Y, X^Psi: radial and tangential-divergent shape changes) or
        'toroidal' (X^Phi, which decouples, thesis (6.29)); only the asked one is computed.
    """

    m: int = field(metadata={"help": "spherical-harmonic degree m >= 2",
                                    "range": M_RANGE})
    kappa: float = field(metadata={"help": "stiffness kappa (dimensionless, > 0)"})
    nu: float = field(metadata={"help": "viscosity nu (dimensionless, >= 0; 0 = inviscid)"})
    component: str = field(default="poloidal", metadata={"help": "poloidal or toroidal"})

    def __post_init__(self) -> None:
        try:
            m = require_int_in_range("m", self.m, *M_RANGE)
        except ParameterError as exc:
            raise ParameterError(f"{exc} (m = 0 changes the enclosed volume and m = 1 is a rigid "
                                 "translation: neither is a membrane mode)") from None
        object.__setattr__(self, "m", m)
        object.__setattr__(self, "kappa", require_positive("kappa", self.kappa))
        object.__setattr__(self, "nu", require_nonnegative("nu", self.nu))
        object.__setattr__(self, "component", require_choice("component", self.component, COMPONENTS))
