"""The contract between a physical model and the Floquet engine.

A model describes a linear system with periodically pumped stiffness,

    D(d/dt) u(t) + 2 tau sin(t) G u(t) = 0,                                   (1)

where ``u`` has ``block_size`` real components, ``D`` is a real linear time-invariant operator
(its transfer function satisfies D(conj s) = conj D(s)) and ``G`` is a real matrix. Inserting the
Floquet-Fourier form u = exp(gamma t) sum_n u_n exp(i n t) (thesis (2.5)) and
sin t = (e^{it} - e^{-it}) / (2i) gives, for every integer n,

    D(s_n) u_n = i tau G (u_{n-1} - u_{n+1}),     s_n = gamma + i n,           (2)

the general form of thesis (2.6). A model therefore supplies only ``D(s)`` (vectorised over s) and
``G``; it never sees a truncation, a packing or a solver.

For the damped Mathieu equation (2.9), D(s) = s^2 + nu s + kappa and G = kappa: dividing (2) by
i kappa gives exactly the printed (2.6) -i((s^2 + nu s)/kappa + 1) u_n = tau (u_{n-1} - u_{n+1}).
"""

from __future__ import annotations

import cmath
import contextlib
import functools
import math
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ParameterError


@contextlib.contextmanager
def boundary_layer(nu: float) -> Iterator[None]:
    """Name the user's ``nu`` when a Bessel-ratio kernel refuses its argument
    beta = sqrt(s / nu) (the kernels call it z, which the user never gave)."""
    try:
        yield
    except ParameterError as exc:
        raise ParameterError(f"nu = {nu!r} is out of reach at this exponent s: the boundary-layer "
                             f"argument beta = sqrt(s / nu) of the Bessel ratios is refused "
                             f"({exc})") from None


@dataclass(frozen=True, kw_only=True, eq=False)
class HillSystem:
    """Physics of one model in the form (2): unforced response D(s) and forcing matrix G.

    Attributes
    ----------
    name : model name, for provenance only.
    block_size : number b of real components of u.
    unforced : D, mapping complex ``s`` of shape (k,) to an array of shape (k, b, b).
    forcing : G, real (b, b).
    polynomial : coefficient matrices (D_0, D_1, ..., D_p) with D(s) = sum_j s^j D_j when D is a
        matrix polynomial with invertible leading coefficient (needed for Floquet exponents as a
        linear eigenproblem), otherwise None.
    n_resonant : the Fourier index below which truncation must not stop: the natural frequency
        (in units of the forcing frequency) of the modes that set tau_min. For a scalar model it
        is the largest index at which D(i n) can be (nearly) singular; for a block model whose
        blocks carry many spatial modes (cochlea) it is the lowest mode frequency, since the
        high spatial modes are far from resonance and converge in N regardless (their
        convergence is checked by the N-refinement like everything else).
    n_highest : the highest natural frequency of the modes (units of the forcing frequency),
        where the model knows it (cochlea: of its M spatial modes), else None: the truncation at
        which every mode's resonances lie inside, used to price a solve before it starts
        (:mod:`spectralshell.solvers.cost`).
    branch_point : b, where D(s) is analytic off the real half-line (-inf, b] (its branch cut,
        the fluid's continuous spectrum; b <= 0): 0 for sqrt(s/nu), -nu k^2 for
        sqrt(s/nu + k^2). Floquet exponents on the cut are not listed.
    cut_poles : x -> the poles of D(s) on its cut in [x, branch_point] (x < branch_point), or
        None. Given where poles of several components coincide (the coupled sphere: an interior
        fluid's decay rate shared by two degrees), so that det D has poles of higher order
        there: the Floquet exponents' winding count puts a vertex of its slit above and below
        each (:func:`spectralshell.solvers.hill_exponents.hill_exponents`), since the phase
        turn of 2 pi by a double pole within the slit's width aliases to 0 between samples.
    inertia : the symmetric positive definite inertia Mass of the inviscid limit, where the model
        has one: D(s) = G + s^2 Mass at nu = 0, so that its natural modes solve
        G v = w^2 Mass v (cochlea: the added mass diag(2/k)); else None. Needed to project the
        blocks onto natural modes (:mod:`spectralshell.discretise.natural_modes`).
    diagonal_response : s (shape (k,)) -> the diagonal of D(s) - G, shape (k, b), where
        D(s) - G is diagonal (cochlea: Z_k(s)); else None. Lets a projection onto m modes cost
        O(b m^2) per s instead of O(b^2 m).
    """

    name: str
    block_size: int
    unforced: Callable[[np.ndarray], np.ndarray]
    forcing: np.ndarray
    polynomial: tuple[np.ndarray, ...] | None = None
    n_resonant: float = 0.0
    n_highest: float | None = None
    branch_point: float = 0.0
    cut_poles: Callable[[float], np.ndarray] | None = None
    inertia: np.ndarray | None = None
    diagonal_response: Callable[[np.ndarray], np.ndarray] | None = None


def modal_system_in_beta(name: str, *, nu: float, n_modes: int, residual, residual_mp, seeds,
                         **fixed: Any) -> ModalSystem:
    """A :class:`ModalSystem` whose variable is beta = sqrt(gamma/nu) (gamma = nu beta^2; the
    physical sheet is Re beta > 0), from residual(beta, **fixed), residual_mp(beta, **fixed) and
    seeds(**fixed)."""
    return ModalSystem(
        name=name,
        residual=functools.partial(residual, **fixed),
        residual_mp=functools.partial(residual_mp, **fixed),
        seeds=functools.partial(seeds, **fixed),
        to_gamma=lambda beta: nu * beta * beta,
        sheet_margin=lambda beta: beta.real,
        n_modes=n_modes,
    )


def damped_newton(residual: Callable[[complex], tuple[complex, complex]], x: complex, *,
                  rtol: float, max_iter: int = 30,
                  failures: tuple[type[Exception], ...] = ()) -> complex | None:
    """Newton's method x <- x - f/f' for ``residual`` x -> (f, f'), each step capped at |x|/2,
    until |step| <= rtol |x|. Used to refine the seeds of a :class:`ModalSystem` (in beta, where
    the cap keeps an iterate from jumping across the origin onto another sheet).

    Returns None when it does not converge in ``max_iter`` steps, an iterate reaches 0, the
    residual is not finite or has zero derivative, or it raises one of ``failures``.
    """
    for _ in range(max_iter):
        if x == 0:
            return None
        try:
            f, fp = residual(x)
        except failures:
            return None
        if fp == 0 or not (cmath.isfinite(f) and cmath.isfinite(fp)):
            return None
        step = f / fp
        if abs(step) > 0.5 * abs(x):
            step *= 0.5 * abs(x) / abs(step)
        x -= step
        if abs(step) <= rtol * abs(x):
            return x
    return None


def continued_roots(residual_at: Callable[[float], Callable[[complex], tuple[complex, complex]]],
                    roots: Iterable[complex], start: float, stop: float, *,
                    failures: tuple[type[Exception], ...] = (ParameterError, OverflowError,
                                                             ZeroDivisionError)) -> Iterator[complex]:
    """Roots of residual_at(zeta) (x -> (f, f')) near ``roots`` at zeta = start, each continued
    to zeta = stop > start in geometric steps of ratio <= 10^(1/40): predictor the root scaled
    by sqrt(zeta_old/zeta_new) on the first step (x ~ zeta^(-1/2) for x = beta ~ sqrt(gamma/nu)),
    then linear extrapolation in the step index; corrector :func:`damped_newton` (relative
    tolerance 1e-10). A branch whose corrector fails, or jumps by more than 10 % of |x|, is
    dropped; the others are yielded at ``stop`` in turn (lazily)."""
    steps = max(2, math.ceil(40 * math.log10(stop / start)))
    path = [start * (stop / start) ** (k / steps) for k in range(steps + 1)]

    def polish(zeta: float, x: complex) -> complex | None:
        return damped_newton(residual_at(zeta), x, rtol=1e-10, failures=failures)

    for x0 in roots:
        x = polish(start, complex(x0))
        history = [] if x is None else [x]
        for k in range(1, steps + 1):
            if not history:
                break
            guess = history[-1] * math.sqrt(path[k - 1] / path[k])
            if len(history) >= 2:
                guess = 2 * history[-1] - history[-2]
            x = polish(path[k], guess)
            if x is None or abs(x - guess) > 0.1 * abs(guess):
                history = []
            else:
                history.append(x)
        if history:
            yield history[-1]


def _conjugate(x):
    return x.conjugate()


@dataclass(frozen=True, kw_only=True, eq=False)
class ModalSystem:
    """Natural modes of one model in the form f(x) = 0: a dispersion relation in a variable x.

    The unforced system (tau = 0 in (1)) has solutions u = u_0 exp(gamma t) exactly when
    det D(gamma) = 0 (thesis (7.14) for the sphere). A model states that relation in a variable x
    in which it is analytic near the roots (for the sphere x = beta = sqrt(gamma/nu), where the
    branch cut of D on the negative real gamma axis opens into the imaginary beta axis), and
    supplies good starting points. A root finder needs nothing else; it never sees the physics.

    Attributes
    ----------
    name : model name, for provenance only.
    residual : x -> (f, fp), complex in double precision. f(x) = 0 exactly at the modes, and
        f / fp is the Newton step of an analytic function with the same roots (``fp`` may be the
        derivative of a pole-free multiple g f divided by g; the step is then that of g f).
    residual_mp : the same pair in mpmath at the current ``mpmath.mp.dps``.
    seeds : () -> iterable of complex starting points, best first; it may be lazy, and a root
        finder stops drawing from it once it has found ``n_modes`` distinct modes.
    to_gamma : x -> gamma; must accept complex and mpmath numbers.
    sheet_margin : x -> real number, > 0 on the physical sheet (the mode decays and its fields
        are bounded), < 0 on an unphysical one, 0 on the branch cut between them.
    conjugate : x -> the x of the root with conjugate gamma (real problems: roots pair up).
    n_modes : number of distinct roots on the physical sheet with Im gamma >= 0 (the whole
        natural-mode spectrum, counting one of each conjugate pair); ignored when ``region`` is
        given (the count then sets it).
    region : None, or (re_lo, re_hi, im_max): a rectangle re_lo <= Re x <= re_hi,
        |Im x| <= im_max of the physical sheet, closed under ``conjugate`` (x -> conj x) and
        holding every mode the model offers, in which ``determinant`` is analytic. A root finder
        then counts the roots inside by the argument principle and finds that many, so the
        number of modes is the count's, not a fixed n_modes.
    determinant : with ``region``, x (complex array) -> f(x) (the residual's f, vectorised).
    residuals : None, or x (complex array) -> (f, fp) arrays: the residual at many points in one
        batch (with ``region``, the argument-principle count's f'/f at its nodes).
    noise : None, or x -> an absolute bound on the error of a root at x that the residual's
        own rounding causes (|error of f| / |f'|); the root's error estimate is at least this.
    branch : the x of the branch point (beta = 0): a root finder's Newton step is capped at
        |x - branch|/2, which keeps an iterate from jumping across it onto another sheet (0 for
        x = beta; -k for the shifted x = beta - k).
    """

    name: str
    residual: Callable[[complex], tuple[complex, complex]]
    residual_mp: Callable[[Any], tuple[Any, Any]]
    seeds: Callable[[], Iterable[complex]]
    to_gamma: Callable[[Any], Any]
    sheet_margin: Callable[[Any], Any]
    n_modes: int
    conjugate: Callable[[Any], Any] = _conjugate
    region: tuple[float, float, float] | None = None
    determinant: Callable[[np.ndarray], np.ndarray] | None = None
    residuals: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]] | None = None
    noise: Callable[[complex], float] | None = None
    branch: float = 0.0


@dataclass(frozen=True, kw_only=True, eq=False)
class ModeFamily:
    """Natural modes of one model as the eigenvalues s of a nonlinear matrix function
    T(s; zeta), continued in a viscosity-like parameter zeta from zeta -> 0, where they are known.

    Used where the modes are too many for seeds of a scalar relation (the cochlea's M coupled
    cosine modes, thesis (5.14)). A continuation solver
    (:mod:`spectralshell.solvers.continued_modes`) needs nothing else; it never sees the physics.

    Attributes
    ----------
    name : model name, for provenance only.
    zeta : the parameter value at which the modes are wanted (>= 0).
    at : zeta -> (T, T'), callables s -> complex (M, M) matrices (T' = dT/ds).
    start : the modes at zeta -> 0 (complex, shape (M,)), e.g. the inviscid s = i w_j.
    sheet_margin : (s, zeta) -> real, > 0 on the physical sheet, 0 on the branch cut.
    contour : (zeta, radius, depth) -> closed counter-clockwise polygon (list of complex) around
        the modes with Im s >= 0 and |s| <= radius on the physical sheet; ``depth`` is how far
        below the real axis it dips where T is analytic (for an argument-principle count).
    residual_mp : (s, zeta) -> (det T, d det T/ds) in mpmath at the current precision (zeta an
        mpmath number), for a high-precision polish.
    gamma_scale : gamma = gamma_scale * s (the time unit of s in units of the model's).
    zeta_mp, gamma_scale_mp : () -> zeta and gamma_scale in mpmath at the current precision,
        computed from the parameters as given (for the polish).
    """

    name: str
    zeta: float
    at: Callable[[float], tuple[Callable[[complex], np.ndarray], Callable[[complex], np.ndarray]]]
    start: np.ndarray
    sheet_margin: Callable[[complex, float], float]
    contour: Callable[[float, float, float], list[complex]]
    residual_mp: Callable[[Any, Any], tuple[Any, Any]]
    gamma_scale: float
    zeta_mp: Callable[[], Any]
    gamma_scale_mp: Callable[[], Any]


@dataclass(frozen=True, kw_only=True, eq=False)
class ResponseModel:
    """What a model supplies for response envelopes along its membrane (thesis 5.5).

    The displacement is h(x, t) = sum_k h_k(t) phi_k(x) over M spatial modes; the pure tone is
    the passive (tau = 0) response to a load oscillating at the forcing frequency; the
    parametric responses are the Floquet solutions at tau_min of a kind
    (:mod:`spectralshell.runner.response`).

    Attributes
    ----------
    domain : (x_start, x_end) of the membrane (dimensionless).
    basis : (x, M) -> (len(x), M) real matrix of the spatial modes phi_k(x).
    tone : M -> complex (M,) mode amplitudes of the pure-tone response.
    tone_start : the envelope's peak is searched for x >= tone_start in the tone (the load
        region itself is excluded).
    wkb_peak : response frequency -> the leading-order WKB peak position, or None where the
        approximation does not apply (its reason in ``wkb_note``).
    with_modes : M -> the parameter object with M spatial modes (for the parametric kinds).
    wkb_note : why ``wkb_peak`` is None, for the result's warnings.
    """

    domain: tuple[float, float]
    basis: Callable[[np.ndarray, int], np.ndarray]
    tone: Callable[[int], np.ndarray]
    tone_start: float
    wkb_peak: Callable[[float], float | None]
    with_modes: Callable[[int], Any]
    wkb_note: str = ""
