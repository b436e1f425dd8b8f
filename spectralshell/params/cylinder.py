"""Parameters of the periodic cylindrical membrane (thesis 8.1, membrane law of 6.1)."""

from __future__ import annotations

from dataclasses import dataclass, field

from .._validate import (invalid, require_choice, require_int_in_range, require_nonnegative,
                         require_positive)

#: Which decoupled set of components is computed: 'coupled' (the set containing X^r: all three
#: for m >= 1, k > 0; the sausage pair (X^r, X^z) for m = 0; the fibre pair (X^r, X^theta) for
#: k = 0), 'torsion' (X^theta alone, m = 0, k > 0) or 'axial' (X^z alone, k = 0, m >= 1).
COMPONENTS = ("coupled", "torsion", "axial")
#: Angular wavenumbers accepted (the Bessel-ratio kernels are tested up to order 200).
M_RANGE = (0, 200)


@dataclass(frozen=True, kw_only=True)
class CylinderParams:
    """Dimensionless parameters of one Fourier mode e^{i(m theta + k z)} of the cylinder.

    m : angular wavenumber >= 0.
    k : axial wavenumber k R = 2 pi j R / L >= 0; k = 0 is the 2D limit (the fibre, thesis 4).
    kappa : stiffness sigma / (rho R^3 omega^2) > 0 (as the sphere).
    nu : kinematic viscosity mu / (rho R^2 omega) >= 0; nu = 0 is the inviscid limit.
    component : 'coupled', 'torsion' or 'axial' (see COMPONENTS).

    The 'coupled' set needs m^2 + k^2 > 1: the elastic matrix E(m, k) has the eigenvalue
    q - sqrt(q), q = m^2 + k^2, so m = 0 with k < 1 is Rayleigh-Plateau unstable without pumping,
    m = 0, k = 1 is neutral, m = 1, k = 0 is a rigid translation and m = k = 0 a dilation, which
    the incompressible fluid inside forbids. Without viscosity the tangential components carry no
    mode (no inertia, no load), so 'torsion' and 'axial' need nu > 0.

    Raises
    ------
    ParameterError : a value out of range; the message names the parameter, value and range.
    """

    m: int = field(metadata={"help": "angular wavenumber m >= 0", "range": M_RANGE})
    k: float = field(metadata={"help": "axial wavenumber k R (dimensionless, >= 0; 0 = 2D fibre)"})
    kappa: float = field(metadata={"help": "stiffness kappa (dimensionless, > 0)"})
    nu: float = field(metadata={"help": "viscosity nu (dimensionless, >= 0; 0 = inviscid)"})
    component: str = field(default="coupled", metadata={"help": "coupled, torsion or axial"})

    def __post_init__(self) -> None:
        m = require_int_in_range("m", self.m, *M_RANGE)
        k = require_nonnegative("k", self.k)
        object.__setattr__(self, "m", m)
        object.__setattr__(self, "k", k)
        object.__setattr__(self, "kappa", require_positive("kappa", self.kappa))
        object.__setattr__(self, "nu", require_nonnegative("nu", self.nu))
        component = require_choice("component", self.component, COMPONENTS)
        object.__setattr__(self, "component", component)
        if component == "coupled" and m * m + k * k <= 1.0:
            raise invalid("k", self.k, f"> {(1.0 - m * m) ** 0.5:g} for m = {m} (m^2 + k^2 > 1: at or "
                          "below it the pressurised cylinder is Rayleigh-Plateau unstable or neutral "
                          "without pumping, m = 1, k = 0 is a rigid translation)")
        if component == "torsion" and (m != 0 or k == 0):
            raise invalid("component", component, "'coupled' or 'axial' unless m = 0 and k > 0 "
                          "(X^theta decouples only for m = 0; m = k = 0 is a rigid rotation)")
        if component == "axial" and (k != 0 or m == 0):
            raise invalid("component", component, "'coupled' or 'torsion' unless k = 0 and m >= 1 "
                          "(X^z decouples only for k = 0; m = k = 0 is a rigid axial shift)")
        if component != "coupled" and self.nu == 0.0:
            raise invalid("nu", self.nu, f"> 0 for component = {component!r} (without viscosity the "
                          "tangential component has no inertia and no load: no mode)")
