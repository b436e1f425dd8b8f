"""Response envelopes along a membrane: the pure tone and the parametric responses at tau_min
(thesis 5.5), for models with the ``response`` capability."""

from __future__ import annotations

import dataclasses
import functools
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ConvergenceError, ParameterError
from ..models.registry import hill_system
from ..params.registry import Model, make_params, physical_values, require_capability
from ..results.floquet import provenance
from .floquet import CERTIFIED, priced_spatial, solver_options
from .solve import solve_kinds, spatial_system

if TYPE_CHECKING:  # imported where it is built (below)
    from ..results.response import ResponseResult


RESPONSE_MODES = 128    # default number of cosine modes of a response
RESPONSE_POINTS = 2001  # grid on [0, pi]
RESPONSE_TIMES = 256    # time samples per period of the parametric solution
GAMMA_OF_KIND = {"harmonic": 1.0, "subharmonic": 0.5}  # dominant response frequency


def _peak(x: np.ndarray, env: np.ndarray, start: float) -> float:
    """Location of the maximum of env over x >= start, refined by a parabola through 3 points."""
    i = int(np.flatnonzero(x >= start)[0] + np.argmax(env[x >= start]))
    if 0 < i < x.size - 1:
        a, b, c = env[i - 1], env[i], env[i + 1]
        denom = a - 2 * b + c
        if denom < 0:
            return float(x[i] + 0.5 * (a - c) / denom * (x[1] - x[0]))
    return float(x[i])


def _response_at(spec: Model, p, n_spatial: int, kind: str, options: dict[str, Any]):
    """(x, envelope, profile, peak, tau, tau's error estimate in N, response frequency) of the
    model's response with ``n_spatial`` spatial modes (its
    :class:`~spectralshell.models.base.ResponseModel`); tau and its error None for the tone."""
    from ..solvers.marginal_mode import marginal_mode

    shape = spec.response(p)
    x = np.linspace(*shape.domain, RESPONSE_POINTS)
    basis = shape.basis(x, n_spatial)
    if kind == "tone":
        h = basis @ shape.tone(n_spatial)
        env = np.abs(h)
        profile = (h * np.exp(-1j * np.angle(h[np.argmax(env)]))).real  # t_peak: phase of the peak
        tau, tau_error, freq, start = None, None, 1.0, shape.tone_start
    else:
        system = hill_system(shape.with_modes(n_spatial))
        m = solve_kinds(system, (kind,), {**options, **CERTIFIED})[kind]  # "none" is proved
        if m.tau_min is None:
            tau_max = options.get("tau_max")
            if tau_max is None or m.unproved_empty(tau_max):  # found none, proved none
                raise ConvergenceError(
                    f"kind = {kind!r}: no marginal tau found at N = {m.n_temporal} below "
                    f"tau_max = {tau_max}, and their absence is proved only up to tau = "
                    f"{m.complete_to:g}: leave n_temporal free or lower tau_max")
            raise ParameterError(f"kind = {kind!r} has no marginal tau here (tau_max = "
                                 f"{tau_max}, proved up to it): no parametric response to "
                                 "show")
        mode = marginal_mode(system, kind, m.tau_min, m.n_temporal)
        period = 2 * np.pi if kind == "harmonic" else 4 * np.pi
        field = mode.evaluate(np.linspace(0.0, period, RESPONSE_TIMES, endpoint=False)) @ basis.T
        env = np.abs(field).max(axis=0)
        profile = field[np.argmax(np.abs(field).max(axis=1))]
        tau, tau_error = m.tau_min, m.error_estimate
        freq, start = GAMMA_OF_KIND[kind], shape.domain[0]
    scale = env.max()
    return x, env / scale, profile / scale, _peak(x, env, start), tau, tau_error, freq


def response(model: str, *, kind: str = "tone", tol: float = 1e-10, n_temporal: int | None = None,
             tau_max: float | None = None, max_seconds: float | None = None,
             **params: Any) -> ResponseResult:
    """Displacement envelope along the membrane for a pure tone, or the parametric response at
    tau_min (thesis 5.5, Figs 5.8-5.10), of a model with the ``response`` capability (the
    cochlea).

    Parameters
    ----------
    model : a model with a response ('cochlea').
    kind : 'tone' (passive response, tau = 0, to a pressure load at the base oscillating at the
        forcing frequency: the externally forced tone of LeVeque, Peskin & Lax), or 'harmonic' /
        'subharmonic' (the Floquet solution at tau_min of that kind, as in thesis 5.5: response
        at the forcing frequency, or half of it).
    tol, n_temporal, tau_max : options of the marginal tau (parametric kinds).
    max_seconds : raises the limit on the estimated cost of the parametric kinds' solves (at M
        and M // 2; refused above it before anything runs, as for :func:`floquet`).
    **params : as for :func:`floquet` ('cochlea' parameters or cgs inputs with omega);
        n_spatial defaults to RESPONSE_MODES; the error estimates of the peak and of tau
        compare with n_spatial // 2 (tau's also includes its error in N)

    Notes
    -----
    The envelope is the largest ``|h(x, t)|`` over a period (for the tone, ``|complex amplitude|``); the
    thesis draws the Hilbert-transform envelope of one snapshot instead. The tone's peak is
    searched for x >= the model's ``tone_start`` (the cochlea: 4 TONE_WIDTH, past the load).
    """
    from ..results.response import ResponseResult

    spec = require_capability(model, "response", "response")
    if kind not in ("tone", "harmonic", "subharmonic"):
        raise ParameterError(f"kind = {kind!r} is invalid: must be one of 'tone', 'harmonic', "
                             "'subharmonic'")
    options = solver_options(tol, n_temporal, tau_max)
    params, physical = physical_values(model, dict(params))
    p = make_params(model, params)
    shape = spec.response(p)
    M = p.n_spatial or RESPONSE_MODES
    if kind != "tone":  # the parametric kinds solve marginal_tau at M and M // 2: priced first
        priced_spatial(model, functools.partial(spatial_system, model, dataclasses.asdict(p)),
                       (kind,), options, M, max_seconds)
    elif max_seconds is not None:
        raise ParameterError(f"max_seconds = {max_seconds!r} is invalid for kind = 'tone': it "
                             "solves no marginal tau")
    x, env, profile, peak, tau, tau_error, freq = _response_at(spec, p, M, kind, options)
    coarse = _response_at(spec, p, max(M // 2, 1), kind, options)
    if tau is not None:  # the truncation in M, and in N at M
        tau_error = max(abs(tau - coarse[4]), tau_error or 0.0)
    wkb = shape.wkb_peak(freq)
    warnings = [] if wkb is not None else [shape.wkb_note]
    low, high = shape.domain
    if wkb is not None and not low < wkb < high:
        warnings.append(f"the WKB peak x = {wkb:.3g} lies outside the membrane [{low:g}, "
                        f"{'pi' if high == np.pi else f'{high:g}'}]")
    return ResponseResult(model=model, params={**dataclasses.asdict(p), "n_spatial": M}, kind=kind,
                          response_frequency=freq, x=x, envelope=env, profile=profile,
                          peak_x=peak, peak_error=abs(peak - coarse[3]) + (x[1] - x[0]) / 10,
                          wkb_peak_x=wkb, tau=tau, tau_error=tau_error,
                          length=None if physical is None else physical.get("length"),
                          physical=physical, provenance=provenance({"kind": kind, **options}),
                          warnings=tuple(warnings))
