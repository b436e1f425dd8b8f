"""Parameters of the immersed spherical membrane (thesis chapter 6)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from .._validate import require_choice, require_int_in_range, require_nonnegative, require_positive
from ..errors import ParameterError
from .expression import parse_expression

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
    kappa: float = field(metadata={"help": "stiffness kappa (dimensionless, > 0); floquet, "
                                           "exponents and sweeps also take an expression in "
                                           "theta, phi: a non-uniform kappa, whose degrees "
                                           "couple"})
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


#: Degree truncations l_max of a non-uniform stiffness.
L_MAX_RANGE = (4, 64)
NONUNIFORM_KEYS = ("kappa", "nu", "l_max")


@dataclass(frozen=True, kw_only=True)
class NonUniformSphereParams:
    """The sphere with stiffness kappa(theta, phi) = kappa0 f(theta, phi) (beyond the thesis).

    kappa : an expression in theta, phi (:mod:`spectralshell.params.expression`), > 0 everywhere.
    nu : viscosity > 0 (the coupled tangential loads need the viscous fluid).
    l_max : 'auto' (raised until tau_min settles) or the degree truncation, an integer in
        L_MAX_RANGE.
    """

    kappa: str
    nu: float
    l_max: int | str = "auto"

    def __post_init__(self) -> None:
        parse_expression("kappa", self.kappa, positive=True)
        if self.nu == 0:
            raise ParameterError("nu = 0 is invalid with a non-uniform kappa: must be > 0 (the "
                                 "coupled tangential loads need the viscous fluid)")
        object.__setattr__(self, "nu", require_positive("nu", self.nu))
        if self.l_max != "auto":
            object.__setattr__(self, "l_max", require_int_in_range("l_max", self.l_max,
                                                                   *L_MAX_RANGE))


def is_nonuniform(model: str, values: Mapping[str, Any]) -> bool:
    """Whether ``values`` of ``model`` ask for the non-uniform sphere: a kappa given as text (an
    expression) or an l_max."""
    return model == "sphere" and (isinstance(values.get("kappa"), str) or "l_max" in values)


def nonuniform_params(values: Mapping[str, Any]) -> NonUniformSphereParams:
    """Validated parameters of the non-uniform sphere from a name -> value mapping.

    Raises
    ------
    ParameterError : kappa not an expression, another parameter (m, component), nu missing, a
        value out of range.
    """
    if not isinstance(values.get("kappa"), str):
        raise ParameterError(f"l_max = {values.get('l_max')!r} is invalid with kappa = "
                             f"{values.get('kappa')!r}: l_max is the degree truncation of a "
                             "non-uniform kappa (an expression in theta, phi)")
    extra = sorted(set(values) - set(NONUNIFORM_KEYS))
    if extra:
        raise ParameterError(f"{extra[0]} = {values[extra[0]]!r} is invalid with a non-uniform "
                             "kappa: the degrees and components couple, so only kappa, nu and "
                             "l_max are parameters")
    if "nu" not in values:
        raise ParameterError("nu is missing: the sphere with a non-uniform kappa needs kappa "
                             "and nu")
    return NonUniformSphereParams(**values)
