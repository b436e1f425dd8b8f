"""Physical units (cgs) <-> dimensionless sphere parameters, and the thesis's named parameter sets.

Units: density rho in g/cm^3, dynamic viscosity mu in g/(cm s) (poise), radius R in cm, membrane
stiffness sigma in dyn/cm = g/s^2, forcing frequency omega in rad/s (an angular frequency: a beat
rate of b beats per minute is omega = 2 pi b / 60 rad/s, ERRATA chapter 6).

Forced problem (time unit 1/omega, thesis 6.1.1):

    nu = mu / (rho R^2 omega)             (6.4)
    kappa = sigma / (rho R^3 omega^2)     (6.5)

Unforced problem (natural modes, thesis 7.2; time unit T = sqrt(rho R^3 / sigma), so kappa = 1):

    zeta = nu / sqrt(kappa) = mu / sqrt(rho R sigma),   gamma_physical = gamma / T  (s^-1)

and the inviscid natural angular frequency (Lamb, (6.24)/(7.5))
omega_0^2 = sigma m(m+1)(m-1)(m+2) / (rho R^3 (2m+1)).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass

from .._validate import require_nonnegative, require_positive, require_real
from ..errors import ParameterError


def physical_inputs(values: object, allowed: Iterable[str],
                    required: Iterable[str] = ()) -> dict[str, float]:
    """``values`` (a mapping of cgs quantities: keys from ``allowed``, all of ``required``) with
    each value a real number (:func:`spectralshell._validate.require_real`); the ranges are
    checked where the quantities are used."""
    allowed = tuple(allowed)
    if not isinstance(values, Mapping):
        raise ParameterError(f"physical = {values!r} is invalid: must be a mapping of "
                             f"{', '.join(allowed)}")
    unknown = sorted(set(values) - set(allowed))
    if unknown:
        raise ParameterError(f"physical {unknown[0]} is unknown: expected {', '.join(allowed)}")
    missing = [k for k in required if k not in values]
    if missing:
        raise ParameterError(f"physical {missing[0]} is missing: needs {', '.join(required)}")
    return {k: require_real(k, v) for k, v in values.items()}


def _derived(name: str, formula: str, numerator: float, denominator: float,
             inputs: Mapping[str, float], *, zero_ok: bool = False) -> float:
    """Dimensionless ``name`` = ``formula`` = numerator / denominator, computed from the cgs
    ``inputs`` and checked as a parameter (> 0, or >= 0 with ``zero_ok``, in the range of
    :mod:`spectralshell._validate`); a refusal names the formula and the inputs. Products of
    inputs overflow to inf or underflow to 0 only where the quotient lies far outside that
    range, so an accepted value is exact to rounding."""
    value = numerator / denominator if denominator else math.inf
    try:
        return (require_nonnegative if zero_ok else require_positive)(name, value)
    except ParameterError as exc:
        given = ", ".join(f"{k} = {v:g}" for k, v in inputs.items())
        raise ParameterError(f"{exc} ({name} = {formula} from {given})") from None


def bpm_to_rad_per_s(bpm: float) -> float:
    """Angular frequency in rad/s of a rate given in beats (cycles) per minute."""
    return 2.0 * math.pi * require_positive("bpm", bpm) / 60.0


@dataclass(frozen=True, kw_only=True)
class PhysicalSphere:
    """A spherical membrane in a fluid, in cgs units (see the module docstring).

    rho : fluid density, g/cm^3. mu : dynamic viscosity, g/(cm s). radius : cm.
    sigma : membrane stiffness, dyn/cm. omega : forcing angular frequency, rad/s (None when
    the membrane is unforced).
    """

    rho: float
    mu: float
    radius: float
    sigma: float
    omega: float | None = None

    def __post_init__(self) -> None:
        for name in ("rho", "radius", "sigma"):
            object.__setattr__(self, name, require_positive(name, getattr(self, name)))
        object.__setattr__(self, "mu", require_nonnegative("mu", self.mu))
        if self.omega is not None:
            object.__setattr__(self, "omega", require_positive("omega", self.omega))

    def forced(self) -> dict[str, float]:
        """Dimensionless ``{"nu", "kappa"}`` of the forced problem, (6.4) and (6.5)."""
        if self.omega is None:
            raise ParameterError("omega = None is invalid: the forced problem needs a forcing "
                                 "frequency omega > 0 (rad/s)")
        rho, r, omega, inputs = self.rho, self.radius, self.omega, self._inputs()
        return {"nu": _derived("nu", "mu / (rho R^2 omega)", self.mu, rho * r * r * omega, inputs,
                               zero_ok=True),
                "kappa": _derived("kappa", "sigma / (rho R^3 omega^2)", self.sigma,
                                  rho * r * r * r * omega * omega, inputs)}

    def _inputs(self) -> dict[str, float]:
        return {k: v for k, v in (("rho", self.rho), ("mu", self.mu), ("radius", self.radius),
                                  ("sigma", self.sigma), ("omega", self.omega)) if v is not None}

    @property
    def time_scale(self) -> float:
        """T = sqrt(rho R^3 / sigma) in s: the time unit of the unforced problem (kappa = 1)."""
        r = self.radius
        return math.sqrt(_derived("T^2", "rho R^3 / sigma", self.rho * r * r * r, self.sigma,
                                  self._inputs()))

    @property
    def zeta(self) -> float:
        """zeta = mu / sqrt(rho R sigma) = nu / sqrt(kappa), the only parameter of the natural modes."""
        return _derived("zeta", "mu / sqrt(rho R sigma)", self.mu,
                        math.sqrt(self.rho * self.radius * self.sigma), self._inputs(),
                        zero_ok=True)

    def lamb_frequency(self, m: int) -> float:
        """Inviscid natural angular frequency omega_0 (rad/s) of degree m, (6.24)/(7.5)."""
        return math.sqrt(self.sigma * m * (m + 1) * (m - 1) * (m + 2)
                         / (self.rho * self.radius**3 * (2 * m + 1)))


#: The cgs quantities every physical sphere input has (the forced problem adds omega or bpm).
SPHERE_INPUTS = ("rho", "mu", "radius", "sigma")

#: The cgs quantities that may replace (nu, kappa) of the sphere, with their units.
PHYSICAL_UNITS = {"rho": "g/cm^3", "mu": "g/(cm s)", "radius": "cm", "sigma": "dyn/cm",
                  "omega": "rad/s", "bpm": "beats/min"}


def sphere_forced_params(values: dict) -> dict:
    """``values`` with its cgs quantities (rho, mu, radius, sigma and omega or bpm) replaced by
    the dimensionless nu and kappa of (6.4)-(6.5); the other entries pass through."""
    rest = {k: v for k, v in values.items() if k not in PHYSICAL_UNITS}
    given = tuple((k, type(v), v) for k, v in values.items() if k in PHYSICAL_UNITS)
    try:
        return {**rest, **_forced_from(given)}
    except TypeError:  # an unhashable value: checked (and refused) without the cache
        return {**rest, **_forced_uncached(given)}


@functools.lru_cache(maxsize=1024)
def _forced_from(given: tuple) -> dict:
    """:func:`_forced_uncached`, kept per process: a map's sweep converts the same (sigma, bpm)
    once per degree m (its chunks run along bpm at one sigma and m). The key holds each value's
    type (True and 1 are equal keys, but bool is refused); a refusal raises (and is not kept);
    the dict returned is read only by unpacking."""
    return _forced_uncached(given)


def _forced_uncached(given: tuple) -> dict:
    """{"nu", "kappa"} of the cgs (name, type, value) triples ``given``, each checked."""
    phys = physical_inputs({k: v for k, _, v in given}, PHYSICAL_UNITS, required=SPHERE_INPUTS)
    if "bpm" in phys:
        if "omega" in phys:
            raise ParameterError(f"bpm = {phys['bpm']!r} is invalid together with omega = "
                                 f"{phys['omega']!r}: give one of them (omega = 2 pi bpm / 60)")
        phys["omega"] = bpm_to_rad_per_s(phys.pop("bpm"))
    if "omega" not in phys:
        raise ParameterError("physical omega is missing: the forced sphere needs omega (rad/s) or "
                             "bpm")
    return PhysicalSphere(**phys).forced()


def young_laplace_sigma(pressure: float, radius: float) -> float:
    """Effective stiffness sigma = [[p]] R / 2 (dyn/cm) from the Young-Laplace law (7.23)."""
    return require_positive("pressure", pressure) * require_positive("radius", radius) / 2.0


#: Table 6.1 (simulation cases 1-4): physical values; the printed (nu, kappa) are the check.
TABLE_6_1 = {
    1: PhysicalSphere(rho=1.0, mu=0.006, radius=1.0, sigma=0.02, omega=1.0),
    2: PhysicalSphere(rho=1.0, mu=0.01, radius=0.5, sigma=3.0, omega=20.0),
    3: PhysicalSphere(rho=1.0, mu=0.005, radius=0.5, sigma=0.375, omega=20.0),
    4: PhysicalSphere(rho=1.0, mu=0.02, radius=10.0, sigma=0.625, omega=0.05),
}

#: Thesis 6.5, an atrium: R = 2 cm, blood rho = 1 g/cm^3, mu = 0.04 g/(cm s); stiffness measured
#: between 1e3 and 2e4 dyn/cm; beat rates 60-100 bpm (healthy) and 100-600 bpm (SVT, 400 typical).
CARDIAC = {"rho": 1.0, "mu": 0.04, "radius": 2.0, "sigma_range": (1e3, 2e4),
           "bpm_healthy": (60.0, 100.0), "bpm_svt": (300.0, 600.0), "bpm_typical_svt": 400.0}

#: Table 7.2 (water balloons in a pool, water rho = 1, mu = 0.01): type, radius R (cm) and the
#: measured pressure difference (dyn/cm^2); sigma follows from (7.23).
BALLOONS = (("A", 6.0, 30990.0), ("A", 9.0, 21900.0), ("A", 12.0, 25900.0),
            ("B", 9.0, 25300.0), ("B", 12.0, 21720.0), ("B", 15.0, 20500.0),
            ("C", 15.0, 19850.0), ("C", 20.0, 14970.0), ("C", 25.0, 12530.0))


def balloon(kind: str, radius: float) -> PhysicalSphere:
    """The Table 7.2 balloon of type ``kind`` inflated to ``radius`` cm, in water."""
    for k, r, pressure in BALLOONS:
        if k == kind and r == radius:
            return PhysicalSphere(rho=1.0, mu=0.01, radius=r, sigma=young_laplace_sigma(pressure, r))
    known = ", ".join(f"{k} {r:g}" for k, r, _ in BALLOONS)
    raise ParameterError(f"balloon = {kind} {radius:g} is invalid: must be one of {known}")


def fibre_forced(*, rho: float, mu: float, radius: float, sigma: float, omega: float) -> dict[str, float]:
    """Dimensionless {nu, kappa} of the 2D fibre: nu = mu/(rho R^2 omega) (4.5) and
    kappa = sigma/(rho R^2 omega^2) (4.6), sigma in g cm/s^2 (a force: the 2D stiffness)."""
    inputs = {"rho": rho, "mu": mu, "radius": radius, "sigma": sigma, "omega": omega}
    for name in ("rho", "radius", "sigma", "omega"):
        require_positive(name, inputs[name])
    require_nonnegative("mu", mu)
    return {"nu": _derived("nu", "mu / (rho R^2 omega)", mu, rho * radius * radius * omega, inputs,
                           zero_ok=True),
            "kappa": _derived("kappa", "sigma / (rho R^2 omega^2)", sigma,
                              rho * radius * radius * omega * omega, inputs)}


#: Table 4.1 (2D simulations, tau = 0.45): physical values; the printed (nu, kappa) are the check.
TABLE_4_1 = {1: {"rho": 1.0, "mu": 0.02, "radius": 0.2, "sigma": 5e3, "omega": 2500.0},
             2: {"rho": 1.0, "mu": 0.02, "radius": 0.2, "sigma": 2e4, "omega": 2500.0}}


# ---------------------------------------------------------------------------------------------
# Cochlea (thesis chapter 5)
# ---------------------------------------------------------------------------------------------

#: Units of the cgs quantities of the cochlea model. sigma is a stiffness per unit area
#: (g cm^-2 s^-2: force per unit area per unit displacement); omega is the angular frequency of
#: the pumping (rad/s), the omega of K = sigma e^{-lambda_c x}(1 + 2 tau sin(omega t)) (5.3).
COCHLEA_UNITS = {"rho": "g/cm^3", "mu": "g/(cm s)", "sigma": "g/(cm^2 s^2)", "length": "cm",
                 "lambda_c": "1/cm", "omega": "rad/s"}

#: Table 5.1 (values of LeVeque, Peskin & Lax, thesis ref. [74]; sigma is theirs, not a human
#: value): rho, mu, sigma, BM length L, stiffness decay rate lambda_c, and the frequency range.
#: The printed dimensionless ranges nu in [8.06e-6, 1.61e-4], kappa in [0.135, 53.9] belong to
#: omega in [100, 2000] rad/s (ERRATA; derivations/cochlea_linear.py Part 1), not to the printed
#: [400, 1600]; omega_range_dimensionless records that range. We use the formulas
#: (cochlea_forced) with omega in rad/s; Table 5.2 and Figs 5.8-5.14 use omega in [400, 1600].
TABLE_5_1 = {"rho": 1.0, "mu": 0.02, "sigma": 6e5, "length": 3.5, "lambda_c": 1.4,
             "omega_range": (400.0, 1600.0), "omega_range_dimensionless": (100.0, 2000.0)}

#: Thesis 5.6.2 / Fig 5.18: human stiffness range (refs [71], [93]) and audible range as printed
#: ("Hz"); gerbil stiffness decay, length and stiffness range (refs [90], [96]).
COCHLEA_HUMAN = {"sigma_range": (1e7, 2e9), "frequency_range": (50.0, 20000.0)}
COCHLEA_GERBIL = {"rho": 1.0, "mu": 0.02, "length": 1.3, "lambda_c": 3.7,
                  "sigma_range": (1.5e8, 2e9), "frequency_range": (100.0, 50000.0)}


def cochlea_forced(*, rho: float, mu: float, sigma: float, length: float, lambda_c: float,
                   omega: float) -> dict[str, float]:
    """Dimensionless {nu, kappa, alpha} of the cochlea (thesis 5.2): lengths in units L/pi,
    time in 1/omega, so nu = mu pi^2/(rho L^2 omega), kappa = sigma pi/(rho L omega^2),
    alpha = lambda_c L/pi (derived in derivations/cochlea_linear.py Part 1)."""
    inputs = {"rho": rho, "mu": mu, "sigma": sigma, "length": length, "lambda_c": lambda_c,
              "omega": omega}
    for name in ("rho", "sigma", "length", "omega"):
        require_positive(name, inputs[name])
    for name in ("mu", "lambda_c"):
        require_nonnegative(name, inputs[name])
    return {"nu": _derived("nu", "mu pi^2 / (rho L^2 omega)", mu * math.pi**2,
                           rho * length * length * omega, inputs, zero_ok=True),
            "kappa": _derived("kappa", "sigma pi / (rho L omega^2)", sigma * math.pi,
                              rho * length * omega * omega, inputs),
            "alpha": _derived("alpha", "lambda_c L / pi", lambda_c * length, math.pi, inputs,
                              zero_ok=True)}


def cochlea_time_scale(*, rho: float, sigma: float, length: float) -> float:
    """T = sqrt(rho L / (pi sigma)) in s: the time unit of the natural modes (gamma/sqrt(kappa)
    of (5.14)); zeta = mu / sqrt(rho sigma (L/pi)^3) is then their only fluid parameter."""
    inputs = {"rho": rho, "sigma": sigma, "length": length}
    for name, value in inputs.items():
        require_positive(name, value)
    return math.sqrt(_derived("T^2", "rho L / (pi sigma)", rho * length, math.pi * sigma, inputs))


#: Which physical quantity each dimensionless cochlea parameter replaces when both are given.
_COCHLEA_SOURCE = {"nu": "mu", "kappa": "sigma", "alpha": "lambda_c"}


def cochlea_params(values: dict) -> dict:
    """``values`` with cgs inputs (keys of COCHLEA_UNITS, missing ones from TABLE_5_1) converted to
    nu, kappa, alpha by :func:`cochlea_forced`; explicitly given nu, kappa or alpha win.

    Without ``omega`` nothing is converted (the values must then hold nu, kappa, alpha). A
    dimensionless value given together with the quantity it replaces (nu with mu, kappa with
    sigma, alpha with lambda_c) is contradictory and refused.
    """
    phys = physical_inputs({k: v for k, v in values.items() if k in COCHLEA_UNITS}, COCHLEA_UNITS)
    rest = {k: v for k, v in values.items() if k not in COCHLEA_UNITS}
    if not phys:
        return rest
    if "omega" not in phys:
        raise ParameterError(f"omega = None is invalid with {', '.join(sorted(phys))}: physical "
                             "input needs the forcing angular frequency omega (rad/s)")
    for name, source in _COCHLEA_SOURCE.items():
        if name in rest and source in phys:
            raise ParameterError(f"{name} = {rest[name]!r} is invalid together with {source} = "
                                 f"{phys[source]!r}: give one of them")
    base = {k: TABLE_5_1[k] for k in ("rho", "mu", "sigma", "length", "lambda_c")}
    converted = cochlea_forced(**{**base, **phys})
    return {**converted, **rest}


def cochlea_physical(values: dict) -> tuple[dict, dict | None]:
    """(cochlea parameters, the cgs inputs used -- given or Table 5.1 -- or None when none was
    given): the conversion of :func:`cochlea_params`, the cochlea's physical input."""
    if not any(k in COCHLEA_UNITS for k in values):
        return dict(values), None
    phys = physical_inputs({k: v for k, v in values.items() if k in COCHLEA_UNITS}, COCHLEA_UNITS)
    base = {k: TABLE_5_1[k] for k in ("rho", "mu", "sigma", "length", "lambda_c")}
    return cochlea_params(values), {**base, **phys}


#: cgs inputs of the cochlea's natural modes (no forcing frequency: rates come out in s^-1).
COCHLEA_MODE_INPUTS = {k: COCHLEA_UNITS[k] for k in ("rho", "mu", "sigma", "length", "lambda_c")}
#: cgs inputs of the sphere's natural modes.
SPHERE_MODE_INPUTS = {k: PHYSICAL_UNITS[k] for k in ("radius", "sigma", "rho", "mu")}


def sphere_mode_scale(params: dict, physical: dict) -> tuple[dict, float, dict]:
    """(parameters kappa = 1, nu = zeta, 1 / T in s^-1, the cgs values to record) of the
    sphere's natural modes from {rho, mu, radius, sigma} (all required): T = sqrt(rho R^3/sigma),
    zeta = nu / sqrt(kappa) (:class:`PhysicalSphere`)."""
    phys = PhysicalSphere(**physical_inputs(physical, SPHERE_INPUTS, SPHERE_INPUTS))
    return ({**params, "kappa": 1.0, "nu": phys.zeta}, 1.0 / phys.time_scale,
            {**physical, "units": "s^-1"})


def cochlea_mode_scale(params: dict, physical: dict) -> tuple[dict, float, dict]:
    """(parameters kappa = 1, nu = zeta, alpha, 1 / T in s^-1, the cgs values to record) of the
    cochlea's natural modes from any of rho, mu, sigma, length, lambda_c (Table 5.1 defaults):
    T = sqrt(rho L/(pi sigma)) (:func:`cochlea_time_scale`), zeta = nu / sqrt(kappa) and
    alpha = lambda_c L / pi of :func:`cochlea_forced` (at omega = 1: zeta does not depend on it).
    """
    phys = {**{k: TABLE_5_1[k] for k in COCHLEA_MODE_INPUTS},
            **physical_inputs(physical, tuple(COCHLEA_MODE_INPUTS))}
    dimless = cochlea_forced(**phys, omega=1.0)
    zeta = dimless["nu"] / math.sqrt(dimless["kappa"])
    if "alpha" in params:
        raise ParameterError("alpha = given with physical input is invalid: lambda_c sets it")
    scale = 1.0 / cochlea_time_scale(rho=phys["rho"], sigma=phys["sigma"], length=phys["length"])
    return ({**params, "alpha": dimless["alpha"], "kappa": 1.0, "nu": zeta}, scale,
            {**phys, "zeta": float(zeta), "units": "s^-1"})


def hz_to_rad_per_s(frequency: float) -> float:
    """Angular frequency omega = 2 pi f in rad/s of a frequency f in Hz (cycles per second)."""
    return 2.0 * math.pi * require_positive("frequency", frequency)


#: The cgs inputs a cochlea sweep may fix or sweep: those of COCHLEA_UNITS and, in place of
#: omega, the frequency f in Hz (omega = 2 pi f; the natural unit of an audible range).
COCHLEA_SWEEP_UNITS = {**COCHLEA_UNITS, "frequency": "Hz"}


def cochlea_sweep_params(values: dict) -> dict:
    """:func:`cochlea_params` of ``values`` after converting a ``frequency`` (Hz) to omega (rad/s)
    by :func:`hz_to_rad_per_s`; giving both is contradictory and refused."""
    values = dict(values)
    if "frequency" in values:
        if "omega" in values:
            raise ParameterError(f"frequency = {values['frequency']!r} is invalid together with "
                                 f"omega = {values['omega']!r}: give one of them (omega = 2 pi f)")
        values["omega"] = hz_to_rad_per_s(values.pop("frequency"))
    return cochlea_params(values)
