"""Natural modes (tau = 0) of a model, through the model's capability: a scalar dispersion
relation (roots from seeds), a nonlinear matrix eigenproblem (continued in the viscosity) or,
at nu = 0, a closed-form frequency."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

import mpmath
import numpy as np

from .._validate import require_int_in_range, require_nonnegative
from ..errors import ParameterError
from ..params.registry import Model, make_params, require_capability
from ..results.floquet import provenance
from ..results.modes import NaturalModesResult
from ..solvers.continued_modes import METHOD as CONTINUATION, continued_modes
from ..solvers.modes import find_modes


def natural_modes(model: str, *, count: int | None = None, precision: int | None = None,
                  zeta: float | None = None, physical: Mapping[str, float] | None = None,
                  **params: Any) -> NaturalModesResult:
    """Least-damped natural modes gamma (tau = 0: X ~ exp(gamma t)) of a model, one per
    conjugate pair (Im gamma >= 0), least damped first, each with an error estimate.

    Parameters
    ----------
    count : number of modes (default: every mode the model has; a larger count returns them
        all, with a warning, where the model has a fixed number).
    precision : digits (e.g. 30) of an mpmath polish of every root (reference values).
    zeta : shorthand for kappa = 1, nu = zeta (the modes depend on zeta = nu/sqrt(kappa) only).
    physical : cgs values instead of kappa, nu (the model's ``mode_inputs``: sphere rho, mu,
        radius, sigma, all required; cochlea any of rho, mu, sigma, length, lambda_c, Table 5.1
        defaults): the modes are then returned in s^-1 (``params['units']``).
    **params : the model's parameters (sphere: m, kappa, nu, component; fibre: m, kappa, nu;
        cochlea: kappa, nu, alpha, n_spatial).

    Notes
    -----
    Models with a dispersion relation (sphere (7.14), fibre derivations/fibre_modes.py): roots
    in beta = sqrt(gamma/nu) by Newton's method from asymptotic seeds
    (:func:`spectralshell.solvers.modes.find_modes`); both have two modes with Im gamma >= 0
    (the sphere's toroidal component one), and at nu = 0 the closed form gamma = i lambda0
    ((7.4), Lamb/Rayleigh; fibre lambda0^2 = kappa m (m^2-1)/2) and no other mode.
    Models with a mode family (the cochlea, T(s) of (5.14), s = gamma/sqrt(kappa)): the inviscid
    modes continued in zeta with a winding-number completeness check
    (:mod:`spectralshell.solvers.continued_modes`).
    """
    spec = require_capability(model, "natural modes", "modal_system", "mode_family")
    params, scale, extras = _scaled_inputs(spec, dict(params), zeta, physical)
    p = make_params(model, params)
    options: dict[str, Any] = {"count": count, "precision": precision}
    if spec.mode_family is not None:
        return _family_modes(spec, p, count, precision, scale, extras)
    if p.nu == 0.0 and spec.inviscid_modes is not None:
        result = _inviscid_modes(spec, p, count, precision, options)
    else:
        roots = find_modes(spec.modal_system(p), count=count, precision=precision)
        result = NaturalModesResult.build(model=model, params=_unforced(p), roots=roots,
                                          options=options)
    if physical is None:
        return result
    digits = None if result.gamma_digits is None else tuple(
        tuple(mpmath.nstr(mpmath.mpf(d) * scale, len(d)) for d in pair) for pair in result.gamma_digits)
    return dataclasses.replace(result, gamma=result.gamma * scale,
                               error_estimate=result.error_estimate * scale, gamma_digits=digits,
                               params={**result.params, **extras})


def _scaled_inputs(spec: Model, params: dict[str, Any], zeta: float | None,
                   physical: Mapping[str, float] | None) -> tuple[dict[str, Any], float, dict]:
    """(parameter values, 1 / time unit of the result, values to record) from the model's
    parameters, ``zeta`` (kappa = 1, nu = zeta) or the model's cgs ``mode_inputs``."""
    if zeta is None and physical is None:
        return params, 1.0, {}
    inputs = ", ".join(spec.mode_inputs)
    if {"kappa", "nu"} & set(params) or (zeta is not None and physical is not None):
        raise ParameterError("zeta/physical = given with kappa or nu is invalid: give one of "
                             f"(kappa, nu), zeta, or physical ({inputs or 'none for this model'})")
    if physical is None:
        return {**params, "kappa": 1.0, "nu": require_nonnegative("zeta", zeta)}, 1.0, {}
    if spec.mode_scale is None:
        raise ParameterError(f"physical = given for model {spec.name!r} is invalid: give kappa "
                             "and nu, or zeta")
    values, scale, extras = spec.mode_scale(params, dict(physical))
    return {**values, "nu": require_nonnegative("zeta", values["nu"])}, scale, extras


def _unforced(p) -> dict[str, Any]:
    """Parameters of an unforced (tau = 0) computation: without a ``forcing`` choice (which
    jumps are pumped, the fibre's), which has no effect on natural modes."""
    return {k: v for k, v in dataclasses.asdict(p).items() if k != "forcing"}


def _family_modes(spec: Model, p, count: int | None, precision: int | None, unit: float,
                  extras: dict[str, Any]) -> NaturalModesResult:
    """Natural modes of a model with a mode family (gamma in ``unit`` times the family's
    scale; :func:`spectralshell.solvers.continued_modes.continued_modes`).

    Units: with ``zeta`` 1/sqrt(kappa) (kappa = 1); with ``kappa``, ``nu`` the forcing period;
    with physical input s^-1 (the conversion in double precision)."""
    family = spec.mode_family(p)
    found = continued_modes(family, count=count, precision=precision, unit=unit)
    options: dict[str, Any] = {"count": count, "precision": precision, "method": CONTINUATION,
                               "zeta": float(family.zeta)}
    if found.double_error is not None:
        options["double_error"] = [float(e) for e in found.double_error]
    return NaturalModesResult(model=spec.name, params={**dataclasses.asdict(p), **extras},
                              gamma=found.gamma, error_estimate=found.error,
                              principal_sheet=~found.on_cut, on_cut=found.on_cut,
                              precision=precision, provenance=provenance(options),
                              gamma_digits=found.digits, warnings=found.warnings)


FEWER_INVISCID = ("count = {} asks for more modes than nu = 0 has: its one mode is returned (the "
                  "viscous branches vanish with the viscosity)")


def _inviscid_modes(spec: Model, p, count, precision, options) -> NaturalModesResult:
    """nu = 0: the exact modes gamma = +-i lambda0 of the model's closed form; the viscous
    branches (the sphere's toroidal mode, the fast Stokes-layer modes) are absent."""
    lam = np.sqrt(spec.inviscid_modes(p, p.kappa))
    warnings = ()
    if count is not None and require_int_in_range("count", count, 1) > 1:
        warnings = (FEWER_INVISCID.format(count),)
    digits = None
    if precision is not None:
        with mpmath.workdps(require_int_in_range("precision", precision, 16, 1000)):
            exact = mpmath.sqrt(spec.inviscid_modes(p, mpmath.mpf(p.kappa)))
            digits = (("0", mpmath.nstr(exact, precision)),)
    return NaturalModesResult(model=spec.name, params=_unforced(p), gamma=np.array([1j * lam]),
                              error_estimate=np.array([4 * np.finfo(float).eps * lam]),
                              principal_sheet=np.array([True]), on_cut=np.array([False]),
                              precision=precision, gamma_digits=digits, warnings=warnings,
                              provenance=provenance({**options, "method": spec.inviscid_method}))
