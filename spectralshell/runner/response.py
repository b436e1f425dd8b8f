"""Basilar-membrane response envelopes (thesis 5.5)."""

from __future__ import annotations

import dataclasses
import functools
from typing import Any

import numpy as np

from ..errors import ParameterError
from ..models.registry import hill_system
from ..params.physical import convert_physical
from ..params.registry import check_model, make_params
from ..results.floquet import provenance
from ..solvers.marginal import marginal_tau
from .floquet import priced_spatial, solver_options, spatial_system


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


def _response_at(p, n_spatial: int, kind: str, options: dict[str, Any]):
    """(envelope, profile, peak, tau, response frequency) of the cochlea with n_spatial modes."""
    from ..models.cochlea import TONE_WIDTH, tone_response
    from ..solvers.marginal_mode import marginal_mode

    x = np.linspace(0.0, np.pi, RESPONSE_POINTS)
    basis = np.cos(np.outer(x, np.arange(1, n_spatial + 1)))
    if kind == "tone":
        h = basis @ tone_response(kappa=p.kappa, nu=p.nu, alpha=p.alpha, n_spatial=n_spatial)
        env = np.abs(h)
        profile = (h * np.exp(-1j * np.angle(h[np.argmax(env)]))).real  # t_peak: phase of the peak
        tau, freq, start = None, 1.0, 4 * TONE_WIDTH
    else:
        q = make_params("cochlea", {**dataclasses.asdict(p), "n_spatial": n_spatial})
        system = hill_system(q)
        m = marginal_tau(system, kind, **options)
        if m.tau_min is None:
            raise ParameterError(f"kind = {kind!r} has no marginal tau here (tau_max = "
                                 f"{options.get('tau_max')}): no parametric response to show")
        mode = marginal_mode(system, kind, m.tau_min, m.n_temporal)
        period = 2 * np.pi if kind == "harmonic" else 4 * np.pi
        field = mode.evaluate(np.linspace(0.0, period, RESPONSE_TIMES, endpoint=False)) @ basis.T
        env = np.abs(field).max(axis=0)
        profile = field[np.argmax(np.abs(field).max(axis=1))]
        tau, freq, start = m.tau_min, GAMMA_OF_KIND[kind], 0.0
    scale = env.max()
    return x, env / scale, profile / scale, _peak(x, env, start), tau, freq


def response(model: str, *, kind: str = "tone", tol: float = 1e-10, n_temporal: int | None = None,
             tau_max: float | None = None, max_seconds: float | None = None,
             **params: Any) -> "ResponseResult":
    """Basilar-membrane displacement envelope for a pure tone (thesis 5.5, Figs 5.8-5.10).

    Parameters
    ----------
    model : 'cochlea'.
    kind : 'tone' (passive response, tau = 0, to a pressure load at the base oscillating at the
        forcing frequency: the externally forced tone of LeVeque, Peskin & Lax), or 'harmonic' /
        'subharmonic' (the Floquet solution at tau_min of that kind, as in thesis 5.5: response
        at the forcing frequency, or half of it).
    tol, n_temporal, tau_max : options of the marginal tau (parametric kinds).
    max_seconds : raises the limit on the estimated cost of the parametric kinds' solves (at M
        and M // 2; refused above it before anything runs, as for :func:`floquet`).
    **params : as for :func:`floquet` ('cochlea' parameters or cgs inputs with omega);
        n_spatial defaults to RESPONSE_MODES; the peak's error estimate compares with n_spatial // 2.

    Notes
    -----
    The envelope is the largest |h(x, t)| over a period (for the tone, |complex amplitude|); the
    thesis draws the Hilbert-transform envelope of one snapshot instead. The peak is searched for
    x >= 4 * TONE_WIDTH for the tone (the load region itself is excluded).
    """
    from ..results.response import ResponseResult

    model = check_model(model)
    if model != "cochlea":
        raise ParameterError(f"model = {model!r} is invalid for response: must be 'cochlea'")
    if kind not in ("tone", "harmonic", "subharmonic"):
        raise ParameterError(f"kind = {kind!r} is invalid: must be one of 'tone', 'harmonic', "
                             "'subharmonic'")
    options = solver_options(tol, n_temporal, tau_max)
    params, physical = convert_physical(model, dict(params))
    p = make_params(model, params)
    if p.spatial_mode is not None:
        raise ParameterError(f"spatial_mode = {p.spatial_mode} is invalid for response: the "
                             "envelope needs n_spatial cosine modes")
    M = p.n_spatial or RESPONSE_MODES
    if kind != "tone":  # the parametric kinds solve marginal_tau at M and M // 2: priced first
        priced_spatial(model, functools.partial(spatial_system, model, dataclasses.asdict(p)), (kind,),
                options, M, max_seconds)
    elif max_seconds is not None:
        raise ParameterError(f"max_seconds = {max_seconds!r} is invalid for kind = 'tone': it "
                             "solves no marginal tau")
    x, env, profile, peak, tau, freq = _response_at(p, M, kind, options)
    coarse = _response_at(p, max(M // 2, 1), kind, options)[3]
    from ..models.cochlea import wkb_peak

    wkb = wkb_peak(kappa=p.kappa, nu=p.nu, alpha=p.alpha, frequency=freq) if p.nu > 0 and p.alpha > 0 \
        else float("nan")
    warnings = [] if np.isfinite(wkb) else ["the WKB peak needs nu > 0 and alpha > 0: reported as NaN"]
    if np.isfinite(wkb) and not 0 < wkb < np.pi:
        warnings.append(f"the WKB peak x = {wkb:.3g} lies outside the membrane [0, pi]")
    return ResponseResult(model=model, params={**dataclasses.asdict(p), "n_spatial": M}, kind=kind,
                          response_frequency=freq, x=x, envelope=env, profile=profile,
                          peak_x=peak, peak_error=abs(peak - coarse) + (x[1] - x[0]) / 10,
                          wkb_peak_x=wkb if np.isfinite(wkb) else None, tau=tau,
                          length=None if physical is None else physical["length"],
                          physical=physical, provenance=provenance({"kind": kind, **options}),
                          warnings=tuple(warnings))


