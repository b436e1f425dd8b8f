"""Natural modes (tau = 0) of a model: dispersion-relation roots, inviscid closed forms and
the cochlea's nonlinear eigenproblem."""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Mapping
from typing import Any

import mpmath
import numpy as np

from .._validate import require_int_in_range, require_nonnegative
from ..errors import ConvergenceError, ParameterError
from ..models.registry import modal_system
from ..models.fibre import lambda0_squared as fibre_lambda0_squared
from ..models.sphere import lambda0_squared
from ..params.physical import SPHERE_INPUTS, PhysicalSphere, physical_inputs
from ..params.registry import check_model, make_params
from ..results.modes import NaturalModesResult
from ..results.floquet import provenance
from ..solvers.modes import find_modes


def natural_modes(model: str, *, count: int | None = None, precision: int | None = None,
                  zeta: float | None = None, physical: Mapping[str, float] | None = None,
                  **params: Any) -> NaturalModesResult:
    """Least-damped natural modes gamma (tau = 0: X ~ exp(gamma t)) of a model, one per
    conjugate pair (Im gamma >= 0), least damped first, each with an error estimate.

    Parameters
    ----------
    count : number of modes (default: every mode the dispersion relation has; a larger count
        returns them all, with a warning).
    precision : digits (e.g. 30) of an mpmath polish of every root (reference values).
    zeta : shorthand for kappa = 1, nu = zeta (the modes depend on zeta = nu/sqrt(kappa) only).
    physical : cgs values {rho, mu, radius, sigma} instead of kappa, nu: the modes are then
        returned in s^-1 (gamma / T, T = sqrt(rho R^3/sigma); ``params['units']``).
    **params : the model's parameters (sphere: m, kappa, nu, component; fibre: m, kappa, nu).

    Notes
    -----
    Roots of det D(gamma) = 0 (thesis (7.14); fibre: derivations/fibre_modes.py), solved in
    beta = sqrt(gamma/nu) by Newton's method from asymptotic seeds
    (:mod:`spectralshell.models.sphere_modes`, :func:`spectralshell.models.fibre.modal_system`,
    :func:`solvers.modes.find_modes`). Both models have two modes with Im gamma >= 0 (sphere:
    poloidal; its toroidal component has one). nu = 0 has the closed form gamma = i lambda0
    ((7.4), Lamb/Rayleigh; fibre: lambda0^2 = kappa m (m^2-1)/2) and no other mode.
    """
    model = check_model(model)
    if model == "cochlea":
        return _cochlea_natural_modes(count=count, precision=precision, zeta=zeta,
                                      physical=physical, params=params)
    if model not in ("sphere", "fibre"):
        raise ParameterError(f"model = {model!r} is invalid for natural modes: must be 'sphere', "
                             "'fibre' or 'cochlea'")
    if model == "fibre" and physical is not None:
        raise ParameterError("physical = given for model 'fibre' is invalid: give kappa and nu "
                             "(params.physical.fibre_forced converts cgs values) or zeta")
    scale = 1.0
    if zeta is not None or physical is not None:
        if {"kappa", "nu"} & set(params) or (zeta is not None and physical is not None):
            raise ParameterError("zeta/physical = given with kappa or nu is invalid: give one of "
                                 "(kappa, nu), zeta, or physical (rho, mu, radius, sigma)")
        if physical is not None:
            phys = PhysicalSphere(**physical_inputs(physical, SPHERE_INPUTS, SPHERE_INPUTS))
            zeta, scale = phys.zeta, 1.0 / phys.time_scale
        params = {**params, "kappa": 1.0, "nu": require_nonnegative("zeta", zeta)}
    p = make_params(model, dict(params))
    options = {"count": count, "precision": precision}
    if p.nu == 0.0:
        result = _inviscid_modes(model, p, count, precision, options)
    else:
        roots = find_modes(modal_system(p), count=count, precision=precision)
        result = NaturalModesResult.build(model=model, params=_unforced(p), roots=roots,
                                          options=options)
    if physical is None:
        return result
    digits = None if result.gamma_digits is None else tuple(
        tuple(mpmath.nstr(mpmath.mpf(d) * scale, len(d)) for d in pair) for pair in result.gamma_digits)
    return dataclasses.replace(result, gamma=result.gamma * scale,
                               error_estimate=result.error_estimate * scale, gamma_digits=digits,
                               params={**result.params, **physical, "units": "s^-1"})


def _unforced(p) -> dict[str, Any]:
    """Parameters of an unforced (tau = 0) computation: without the fibre's ``forcing`` (which
    jumps are pumped), which has no effect on natural modes."""
    return {k: v for k, v in dataclasses.asdict(p).items() if k != "forcing"}


MODES_START = 1e-10  # continuation of the cochlea's modes starts at zeta = MODES_START * zeta


def _cochlea_natural_modes(*, count, precision, zeta, physical, params) -> NaturalModesResult:
    """Natural modes of the cochlea: eigenvalues of the nonlinear matrix function
    T(s) = diag(Z_k(s; zeta)) + C (D(gamma)/kappa, s = gamma/sqrt(kappa), thesis (5.14)).

    Method (model-agnostic solver :mod:`spectralshell.solvers.nonlinear_eigen`): the inviscid
    modes s = i w_j (w_j^2 the eigenvalues of diag(sqrt(k/2)) C diag(sqrt(k/2))) are continued in
    zeta from MODES_START * zeta to zeta with step control (Newton on det T in trace form; the
    branches advance together, so a branch is compared with its neighbours at the same zeta; a
    conjugate pair that meets on the real axis in (-zeta, 0) is followed on as its two real roots).
    Roots are reported with Im s >= 0 (conjugate pairs), least damped first; the sheet margin
    min_k Re sqrt(s/zeta + k^2) classifies them. Near the cut s < -zeta (large zeta) the least
    damped modes become nearly real decays just above the cut, thesis Fig 5.7 right: at
    zeta = 1e-2, alpha = 1.56, M = 20 the three slowest have Im s = 2.5e-8, 1.6e-7, 7.5e-7; from
    zeta ~ 0.013 they pass the branch point -zeta one by one and become real decays on (-zeta, 0)
    (their mirror images leave through the branch point onto the other sheet).
    Completeness: the winding number of det T around the upper half of the physical sheet (a box
    of half-width 2 max|s| + 1 whose bottom edge runs along the upper edge of the cut, see
    :func:`spectralshell.models.cochlea.upper_half_contour`) must equal the number of modes found
    in it; otherwise the result warns.
    ``precision`` (digits >= 16): every root is polished by Newton's method on det T in mpmath
    at precision + 10 digits (:func:`spectralshell.solvers.modes.polish_root`,
    :func:`spectralshell.models.cochlea.natural_mode_residual_mp`), error = max(last step,
    10^-precision |s|), for the parameters as given in double precision (physical input is
    converted in double precision).
    Units: with ``zeta`` 1/sqrt(kappa) (kappa = 1); with ``kappa``, ``nu`` the forcing period
    (gamma = sqrt(kappa) s); with ``physical`` (cgs: rho, mu, sigma, length, lambda_c, Table 5.1
    defaults for the missing ones) s^-1, gamma = s / T with T = sqrt(rho L/(pi sigma)).
    """
    from ..models.cochlea import natural_frequencies, natural_mode_family, sheet_margin
    from ..params.physical import TABLE_5_1, cochlea_forced, cochlea_time_scale
    from ..solvers.modes import PRECISION_MAX
    from ..solvers.nonlinear_eigen import SINGULAR_RTOL, continue_roots, newton, singular_ratio

    if precision is not None:
        precision = require_int_in_range("precision", precision, 16, PRECISION_MAX)
    params = dict(params)
    scale, extras = 1.0, {}
    if zeta is not None or physical is not None:
        if {"kappa", "nu"} & set(params) or (zeta is not None and physical is not None):
            raise ParameterError("zeta/physical = given with kappa or nu is invalid: give one of "
                                 "(kappa, nu), zeta, or physical (rho, mu, sigma, length, lambda_c)")
        if physical is not None:
            phys = {**{k: TABLE_5_1[k] for k in ("rho", "mu", "sigma", "length", "lambda_c")},
                    **physical_inputs(physical, ("rho", "mu", "sigma", "length", "lambda_c"))}
            dimless = cochlea_forced(**phys, omega=1.0)
            zeta = dimless["nu"] / np.sqrt(dimless["kappa"])
            scale = 1.0 / cochlea_time_scale(rho=phys["rho"], sigma=phys["sigma"], length=phys["length"])
            if "alpha" in params:
                raise ParameterError("alpha = given with physical input is invalid: lambda_c sets it")
            params["alpha"] = dimless["alpha"]
            extras = {**phys, "zeta": float(zeta), "units": "s^-1"}
        params = {**params, "kappa": 1.0, "nu": require_nonnegative("zeta", zeta)}
    p = make_params("cochlea", params)
    if p.n_spatial is None or p.spatial_mode is not None:
        raise ParameterError(f"n_spatial = {p.n_spatial!r} is invalid for natural modes: give the "
                             "number of cosine modes M (e.g. 20, as in thesis Fig 5.7)")
    M = p.n_spatial
    count = None if count is None else require_int_in_range("count", count, 1, M)
    zeta = p.nu / np.sqrt(p.kappa)
    unit, scale = scale, scale * np.sqrt(p.kappa)  # s^-1 per forcing-period unit; gamma = scale s
    start = 1j * natural_frequencies(1.0, p.alpha, np.arange(1, M + 1))
    warnings: list[str] = []
    if zeta == 0.0:
        roots, steps = start, 4 * np.finfo(float).eps * np.abs(start)
    else:
        family = natural_mode_family(alpha=p.alpha, n_spatial=M)
        roots, steps, ok = continue_roots(family, MODES_START * zeta, zeta, start,
                                          conjugate_symmetric=True)
        T, dT = family(zeta)
        lost = 0
        for i in np.flatnonzero(~ok):  # a lost branch (near-collision): deflated Newton at zeta
            known = np.concatenate([roots[ok], roots[ok].conj()])  # roots pair up: T(conj s) = conj T(s)
            out = newton(T, dT, roots[i], known=known)
            near = np.min(np.abs(known - out[0]), initial=np.inf) if out is not None else 0.0
            if out is None or near <= 1e-5 * abs(out[0]) or singular_ratio(T, out[0]) > SINGULAR_RTOL:
                lost += 1
                continue
            roots[i], steps[i] = out
            ok[i] = True
        if lost:
            warnings.append(f"{lost} of the {roots.size} mode branches could not be followed to "
                            f"zeta = {zeta:g} and no further root was found near their last position")
        roots, steps = roots[ok], steps[ok]
        roots = np.where(roots.imag < 0, roots.conj(), roots)
        keep = [i for i in range(roots.size)
                if not np.any(np.abs(roots[:i] - roots[i]) <= 1e-8 * abs(roots[i]))]
        if len(keep) < roots.size:
            warnings.append(f"{roots.size - len(keep)} branch(es) merged with a conjugate branch")
        roots, steps = roots[keep], steps[keep]
        warnings += _cochlea_completeness(T, dT, roots, steps, zeta, M)
    order = np.argsort(-roots.real)[:count]
    roots, steps = roots[order], np.maximum(steps[order], 64 * np.finfo(float).eps * np.abs(roots[order]))
    digits, double_error = None, None
    if precision is not None:
        roots, steps, digits, double_error = _cochlea_polish(roots, precision, p, M, unit)
    gamma, err = roots * scale, steps * scale
    margin = np.array([np.inf if zeta == 0.0 else sheet_margin(r, zeta, M) for r in roots])
    margin_err = steps / max(zeta, 1e-300) / np.maximum(margin, 1e-300)  # d(Re sqrt) ~ ds/(zeta sqrt)
    on_cut = margin <= margin_err
    if on_cut.any():
        warnings.append(f"{int(on_cut.sum())} mode(s) lie on the branch cut to within their error")
    options = {"count": count, "precision": precision, "method": "continuation in zeta, Newton on "
               "det T (trace form)", "zeta": float(zeta)}
    if double_error is not None:
        options["double_error"] = [float(e) for e in double_error]
    return NaturalModesResult(model="cochlea", params={**dataclasses.asdict(p), **extras},
                              gamma=gamma, error_estimate=err, principal_sheet=~on_cut,
                              on_cut=on_cut, precision=precision, provenance=provenance(options),
                              gamma_digits=digits, warnings=tuple(warnings))


def _cochlea_completeness(T, dT, roots: np.ndarray, steps: np.ndarray, zeta: float,
                          M: int) -> list[str]:
    """Warnings unless the winding number of det T around the upper half of the physical sheet
    (:func:`spectralshell.models.cochlea.upper_half_contour`, half-width 2 max|s| + 1, dip
    zeta/4 deep, capped by the half-width) equals the number of modes found inside it: each mode
    with Im s > 0, plus, in the dip under (-zeta, 0), the mirror image of each complex mode there
    (a real mode counts once)."""
    from ..models.cochlea import upper_half_contour
    from ..solvers.nonlinear_eigen import count_by_winding

    radius = 2.0 * float(np.abs(roots).max(initial=0.0)) + 1.0
    depth = min(zeta, radius) / 4.0
    real = np.abs(roots.imag) <= steps
    mirrored = (~real) & (roots.real > -zeta) & (roots.real < 0) & (roots.imag < depth)
    expected = int(roots.size + mirrored.sum())
    try:
        counted = count_by_winding(T, upper_half_contour(zeta=zeta, n_spatial=M, radius=radius,
                                                         depth=depth), dT=dT)
    except ConvergenceError as exc:
        return [f"completeness not checked: {exc}"]
    if counted == expected:
        return []
    return [f"the winding number of det T counts {counted} modes with Im s >= 0 and |s| < "
            f"{radius:.3g} on the physical sheet where {expected} were found: "
            + ("some were missed" if counted > expected else "some found roots are spurious")]


def _cochlea_polish(roots: np.ndarray, precision: int, p, M: int, unit: float):
    """(roots, errors, gamma digits, |double - polished| in gamma): every root s of det T
    polished to ``precision`` digits (:func:`spectralshell.solvers.modes.polish_root`); gamma =
    unit sqrt(kappa) s, with sqrt(kappa) and zeta = nu/sqrt(kappa) in mpmath."""
    from ..models.cochlea import natural_mode_residual_mp
    from ..solvers.modes import polish_root

    with mpmath.workdps(precision + 10):
        zeta = mpmath.mpf(p.nu) / mpmath.sqrt(mpmath.mpf(p.kappa))
        residual = functools.partial(natural_mode_residual_mp, zeta=zeta, alpha=p.alpha, n_spatial=M)
        polished = [polish_root(residual, complex(r), precision=precision) for r in roots]
        factor = mpmath.mpf(unit) * mpmath.sqrt(mpmath.mpf(p.kappa))
        digits = tuple((mpmath.nstr(s.real * factor, precision), mpmath.nstr(s.imag * factor, precision))
                       for s, _ in polished)
        double_error = np.array([float(abs(s - r) * factor) for (s, _), r in zip(polished, roots)])
        return (np.array([complex(s) for s, _ in polished]),
                np.array([float(e) for _, e in polished]), digits, double_error)


#: model -> (lambda0^2(m, kappa), its source): the inviscid natural frequency of each model.
_INVISCID = {"sphere": (lambda0_squared, "closed form (7.4)"),
             "fibre": (fibre_lambda0_squared, "closed form lambda0^2 = kappa m (m^2 - 1)/2 "
                       "(derivations/fibre_linear_result.md, 4a)")}


FEWER_INVISCID = ("count = {} asks for more modes than nu = 0 has: its one mode is returned (the "
                  "viscous branches vanish with the viscosity)")


def _inviscid_modes(model, p, count, precision, options) -> NaturalModesResult:
    """nu = 0: the exact modes gamma = +-i lambda0 (sphere (7.4), fibre kappa m (m^2-1)/2); the
    viscous branches (the sphere's toroidal mode, the fast Stokes-layer modes) are absent."""
    if getattr(p, "component", None) == "toroidal":
        raise ParameterError("nu = 0 is invalid for toroidal modes: without viscosity the "
                             "toroidal component carries no mode")
    warnings = ()
    if count is not None and require_int_in_range("count", count, 1) > 1:
        warnings = (FEWER_INVISCID.format(count),)
    squared, method = _INVISCID[model]
    lam = np.sqrt(squared(p.m, p.kappa))
    digits = None
    if precision is not None:
        with mpmath.workdps(require_int_in_range("precision", precision, 16, 1000)):
            exact = mpmath.sqrt(squared(p.m, mpmath.mpf(p.kappa)))
            digits = (("0", mpmath.nstr(exact, precision)),)
    return NaturalModesResult(model=model, params=_unforced(p), gamma=np.array([1j * lam]),
                              error_estimate=np.array([4 * np.finfo(float).eps * lam]),
                              principal_sheet=np.array([True]), on_cut=np.array([False]),
                              precision=precision, gamma_digits=digits, warnings=warnings,
                              provenance=provenance({**options, "method": method}))


