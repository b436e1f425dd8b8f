"""Parameters of the periodic cylindrical membrane (thesis 8.1, membrane law of 6.1)."""

from __future__ import annotations

import math
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
        if component == "coupled" and m <= 1 and k <= 1 - m:  # m^2 + k^2 <= 1, exactly
            raise invalid("k", self.k, f"> {1 - m} for m = {m} (m^2 + k^2 > 1: at or "
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


#: cgs inputs of the cylinder's Floquet computations (the sphere's scalings, thesis 6.1, with the
#: axial period L and mode number j in place of k = 2 pi j R / L).
CYLINDER_UNITS = {"rho": "g/cm^3", "mu": "g/(cm s)", "radius": "cm", "sigma": "dyn/cm",
                  "omega": "rad/s", "period": "cm", "j": "axial mode number, k = 2 pi j R/L"}
_REQUIRED = ("rho", "mu", "radius", "sigma", "omega")
#: Which physical quantity each dimensionless parameter replaces when both are given.
_SOURCE = {"kappa": "sigma", "nu": "mu", "k": "period"}


def cylinder_physical(values: dict) -> tuple[dict, dict | None]:
    """(cylinder parameters, the cgs inputs used or None when none was given).

    kappa = sigma/(rho R^3 omega^2), nu = mu/(rho R^2 omega) and, with ``period`` L and ``j``,
    k = 2 pi j R/L. rho, mu, radius, sigma and omega are then all required; k may instead be
    given directly. A dimensionless value given together with the quantity it replaces is refused.

    Raises
    ------
    ParameterError : a missing, contradictory or out-of-range input (the message names it).
    """
    if not any(name in CYLINDER_UNITS for name in values):
        return dict(values), None
    from .physical import _derived, physical_inputs

    phys = physical_inputs({n: v for n, v in values.items() if n in CYLINDER_UNITS},
                           CYLINDER_UNITS, _REQUIRED)
    rest = {n: v for n, v in values.items() if n not in CYLINDER_UNITS}
    for name, source in _SOURCE.items():
        if name in rest and source in phys:
            raise invalid(name, rest[name], f"absent together with {source} = {phys[source]!r}: "
                          "give one of them")
    for name in ("rho", "radius", "sigma", "omega"):
        require_positive(name, phys[name])
    require_nonnegative("mu", phys["mu"])
    rho, radius, omega = phys["rho"], phys["radius"], phys["omega"]
    out = {**rest,
           "nu": _derived("nu", "mu / (rho R^2 omega)", phys["mu"], rho * radius**2 * omega, phys,
                          zero_ok=True),
           "kappa": _derived("kappa", "sigma / (rho R^3 omega^2)", phys["sigma"],
                             rho * radius**3 * omega**2, phys)}
    if ("period" in phys) != ("j" in phys):
        missing = "j" if "period" in phys else "period"
        raise invalid(missing, None, "given with the other of period and j (k = 2 pi j R/L)")
    if "period" in phys:
        j = require_int_in_range("j", phys["j"], 0)
        out["k"] = _derived("k", "2 pi j R / L", 2 * math.pi * j * radius,
                            require_positive("period", phys["period"]), phys, zero_ok=True)
    return out, phys
