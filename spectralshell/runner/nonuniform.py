"""Floquet analysis of the sphere with non-uniform stiffness kappa(theta, phi) (issue 28, part 2).

The degrees 2..l_max of the membrane couple through the product of kappa with the shape
(:mod:`spectralshell.discretise.sphere_nonuniform`); the slots split into decoupled sectors,
each a Hill system. Per kind, tau_min is the smallest over the sectors: the sectors are solved in
turn (lowest degrees first), each with tau_max lowered to the smallest tau_min found so far, so a
sector only has to prove it has nothing below it (:func:`sector_minimum`).

What an answer proves (issue 23, section 2): a sector's empty answer is proved by the argument
principle's zero count at both truncations of its pair (``marginal_tau(certify_empty=...)``,
as for the uniform viscous models), the bound being tau_max or the smallest tau_min of the
sectors before it; where the count fails at another sector's tau_min (a real tau of this sector
at that bound: two sectors with the same tau_min) the sector is solved again 1 % higher
(:func:`sector_taus`). The kind's ``complete_to`` is what its sectors prove together, and an
empty kind at both l_max - 2 and l_max is proved as far as both are (:func:`both_proved`).
``floquet`` refuses an answer it cannot prove (ConvergenceError naming the sector); a fixed
n_temporal keeps it with complete_to 0 and a warning; sweeps keep it marked (``'mark'``).

Truncation in degree (``l_max = 'auto'``, the default): l_max = start, start + 2, ... (a step of
2 adds a degree of each parity) until every kind's tau_min changes by at most ``tol_spatial``
between l_max - 2 and l_max (as the cochlea's M, :mod:`spectralshell.solvers.spatial_refinement`,
whose change and error rules are used; the change from an unproved empty answer at l_max - 2
to a tau at l_max is unknown, :func:`degree_change`); start is the first degree whose natural frequency at
the mean stiffness lies above the harmonic resonance 1, plus one (at least 4). An integer l_max
is solved as given, with its change from l_max - 2 as the spatial error. Each truncation is
priced before it is solved (:class:`Price`, refused above the limit on estimated seconds).

Floquet exponents (:func:`exponents_nonuniform`): those of every sector, each continued from
the sector's natural modes (:func:`sector_modes`) by
:func:`~spectralshell.solvers.hill_exponents.hill_exponents` and counted complete there; each
truncation priced and refused as above.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import require_positive
from ..discretise.fourier import GAMMA, expand_kind
from ..discretise.sphere_nonuniform import (L_MAX_LIMIT, NonUniformSphere, Sector,
                                            nonuniform_sphere, perturbation_system)
from ..discretise.shtns_adapter import grid as dealiased_grid
from ..discretise.sphere_coupled import stiffness_field
from ..errors import ConvergenceError, ParameterError
from ..models.base import HillSystem
from ..models.sphere import lambda0_squared
from ..params.expression import parse_expression
from ..params.limits import SECONDS
from ..params.sphere import NonUniformSphereParams
from ..params.stiffness import threshold_warnings
from .floquet import CERTIFIED
from .progress import progress_bar
from ..results.floquet import certification_warnings, provenance, resolution_warnings
from ..results.nonuniform import NonUniformFloquetResult
from ..results.records import Exponents, MarginalTau
from ..solvers.exponents import distance
from ..solvers.hill_exponents import hill_exponents, pencil_family
from ..solvers.marginal import empty_not_certified, finer, marginal_tau
from ..solvers.marginal_mode import marginal_mode, marginal_sensitivity
from ..solvers.cost import duration, solve_seconds, temporal_schedule
from ..solvers.nonlinear_eigen import newton
from ..solvers.spatial_refinement import spatial_change, spatial_error

#: Default tolerance of tau_min in the degree truncation l_max (absolute).
TOL_DEGREES = 1e-6
SHARE_FLOOR = 1e-4     # smallest share of a mode listed in a result's content
DERIVATIVE_STEP = 1e-6  # relative step of D'(s) in the natural modes' Newton iteration


def sector_minimum(sphere: NonUniformSphere, kind: str, options: dict[str, Any],
                   bar=None) -> tuple[MarginalTau, int | None]:
    """(the MarginalTau of the kind: that of the sector with the smallest tau_min, with the
    kind's ``complete_to``; that sector's index, None: no sector has a tau <= tau_max).

    The sectors are solved in turn, each below the smallest tau_min so far (``options`` go to
    ``marginal_tau``; with ``certify_empty`` a sector's empty answer is proved by the zero count
    at both truncations of its pair, :func:`sector_taus`). ``complete_to`` of the kind (every
    real tau of the kind up to it is in its ``tau``, the critical sector's list) is the smallest
    of what each sector proves:

    * the critical sector: its own complete_to, at most the bound it was solved below;
    * a sector with no tau below its bound c: min(c, its complete_to) -- c where the count
      proves it empty, 0 where it cannot ('mark', or a fixed N);
    * a sector with a tau_min t no smaller than the kind's (one a later sector undercut, or an
      equal one): min(t, its complete_to) (its list is not the kind's).

    An empty kind is thus proved empty below complete_to, and a tau_min proved the smallest
    where complete_to >= tau_min. ``bar`` (a progress bar) moves by one per sector.

    Raises
    ------
    ConvergenceError : a sector's solve did not converge, or its empty answer could not be
        proved (certify_empty True, N not fixed); the message names the sector.
    """
    cap = options.get("tau_max") or math.inf
    best, where, own, proved = None, None, math.inf, math.inf
    for i in range(len(sphere.systems)):
        found, bound = sector_taus(sphere, i, kind, options, cap)
        if bar is not None:
            bar.update(1)
        if found.tau_min is None:
            proved = min(proved, bound, found.complete_to)
            best = found if best is None else best
        elif where is None or found.tau_min < best.tau_min:
            if where is not None:
                proved = min(proved, best.tau_min, own)
            best, where, own, cap = found, i, min(bound, found.complete_to), found.tau_min
        else:
            proved = min(proved, found.tau_min, found.complete_to)
    return dataclasses.replace(best, complete_to=min(proved, own)), where


#: A sector solved below another sector's tau_min whose empty answer the zero count cannot
#: prove is solved again below this much more (relative): the count fails where a real tau
#: lies at the bound, e.g. the same tau_min in two sectors that no symmetry identifies (the
#: asymmetric kappa 0.02 (1 + 0.2 sin(theta) cos(phi) + 0.1 cos(theta)) at l_max = 4: 0.3563731
#: in both of its sectors).
RAISE = 1e-2


def sector_taus(sphere: NonUniformSphere, i: int, kind: str, options: dict[str, Any],
                cap: float) -> tuple[MarginalTau, float]:
    """(marginal_tau of sector ``i`` below ``cap``, the bound it was solved below).

    With ``certify_empty`` in ``options`` an empty answer the zero count cannot prove
    (complete_to < the bound) is solved again below min(tau_max, cap (1 + RAISE)) where ``cap``
    lies below tau_max; if that does not prove it either, certify_empty True raises (N not
    fixed), else the answer is kept with what it proves (complete_to, 0: nothing).

    Raises
    ------
    ConvergenceError : naming the sector: its solve did not converge, or as above.
    """
    tau_max = options.get("tau_max") or math.inf
    certify = options.get("certify_empty", False)
    bounds = (cap,) if not certify or cap >= tau_max else (cap, min(tau_max, cap * (1 + RAISE)))
    for bound in bounds:
        try:
            found = marginal_tau(sphere.systems[i], kind, **{
                **options, "tau_max": bound, "certify_empty": "mark" if certify else False})
        except ConvergenceError as exc:
            raise ConvergenceError(f"{_sector_name(sphere, i, kind)}: {exc}") from None
        if found.tau_min is not None or found.complete_to >= bound:
            return found, bound
    if certify is True and options.get("n_temporal") is None:
        below = (f" ({bound:.6g} lies {RAISE:.0%} above {cap:.6g}, the smallest tau_min of "
                 "the sectors before it)" if cap < tau_max else "")
        raise ConvergenceError(f"{_sector_name(sphere, i, kind)}: " + str(empty_not_certified(
            kind, found.n_previous, found.n_temporal, bound)) + below)
    return found, bound


def _sector_name(sphere: NonUniformSphere, i: int, kind: str) -> str:
    """'harmonic, sector 2 of 12 at l_max = 6 (degrees 2, 4, 6)'."""
    sector = sphere.sectors[i]
    return (f"{kind}, sector {i + 1} of {len(sphere.sectors)} at l_max = {sphere.l_max} "
            f"(degrees {', '.join(map(str, sector.degrees))}"
            f"{', toroidal' if sector.toroidal else ''})")


def mode_content(sector: Sector, coefficients: np.ndarray) -> list[dict[str, Any]]:
    """Share of each mode (l, k, component) of a sector in the squared displacement norm
    |X^Y|^2 + l(l+1) (|X^Psi|^2 + |X^Phi|^2) of Fourier coefficients (n, slots), largest first."""
    power = np.sum(np.abs(coefficients) ** 2, axis=0)
    weight = np.array([1.0 if n == "Y" else l * (l + 1.0) for l, _, n in sector.slots])
    energy: dict[tuple, float] = {}
    for (l, k, n), e in zip(sector.slots, power * weight):
        key = (l, k, "poloidal" if n != "Phi" else "toroidal")
        energy[key] = energy.get(key, 0.0) + float(e)
    total = sum(energy.values())
    rows = [{"l": l, "k": k, "component": c, "share": e / total}
            for (l, k, c), e in energy.items() if e >= SHARE_FLOOR * total]
    return sorted(rows, key=lambda r: -r["share"])


def solve_truncation(sphere: NonUniformSphere, kinds: tuple[str, ...], options: dict[str, Any],
                     progress: bool = False) -> dict:
    """Per kind (MarginalTau, critical sector index) of the sectors of one truncation; with
    ``progress`` a bar over the sector solves, its label stating the estimate."""
    price = Price.of(sphere, len(kinds), options.get("n_temporal"))
    with progress_bar(len(sphere.systems) * len(kinds),
                      f"sphere, degrees <= {sphere.l_max} ({price.describe()})", "sector",
                      progress, leave=False) as bar:
        return {k: sector_minimum(sphere, k, options, bar) for k in kinds}


@dataclass(frozen=True)
class Price:
    """Estimated cost of the sector solves of one truncation (:mod:`spectralshell.solvers.cost`:
    each distinct sector priced as dense truncations of its block size up to the N its
    frequencies need): ``seconds``, the largest coupled block ``block`` (slots) and the largest
    truncation N ``n_temporal`` of the priced schedules.

    The price includes the zero count that proves a sector empty (``solve_seconds`` adds
    :func:`~spectralshell.solvers.cost.certify_seconds` at the last pair of each kind, as if
    every sector were empty). Measured (one BLAS thread, CPU time, 2 cores under a load of
    8-9): the asymmetric kappa 0.02 (1 + 0.2 sin(theta) cos(phi) + 0.1 cos(theta)) at
    l_max = 4 (blocks of 30 and 33 slots) priced its counts at 0.98 s and spent 0.83 s in them;
    for blocks of 1-8 slots (kappa = 0.02 (1 + 0.3 cos^2 theta)) a count walks ~17 nodes at
    ~1 ms each (Python's per-block LU calls, which the M^3 price does not see): at l_max = 8,
    2.7 s of 4.2 s profiled, the solve 0.4 s before the certificate and 1.8-2.0 s with it
    (``auto``, l_max = 6, 8: 0.9 s and 2.4-2.6 s), still far below any limit."""

    seconds: float
    block: int
    n_temporal: int

    @classmethod
    def of(cls, sphere: NonUniformSphere, kinds: int, n_temporal: int | None) -> Price:
        """The price of the truncation ``sphere`` for ``kinds`` kinds (``n_temporal``: a fixed
        N, or None)."""
        return cls(seconds=sum(solve_seconds(s, kinds, n_temporal) for s in sphere.systems),
                   block=max(s.block_size for s in sphere.systems),
                   n_temporal=max(temporal_schedule(s, n_temporal)[-1] for s in sphere.systems))

    def describe(self) -> str:
        """'blocks <= 120, N = 24: about 5 min', the sizes and the estimate in words."""
        return f"blocks <= {self.block}, N = {self.n_temporal}: about {duration(self.seconds)}"


def priced_sphere(kappa: Callable, nu: float, l_max: int, kinds: tuple[str, ...],
                  options: dict[str, Any], max_seconds: float | None) -> NonUniformSphere:
    """The truncation ``l_max`` of the sphere with stiffness ``kappa``, refused (ParameterError)
    when its sector solves are estimated above the limit on seconds
    (:data:`spectralshell.params.limits.SECONDS`; ``max_seconds`` raises it) before any is
    solved: a kappa without symmetry couples every mode (314 s measured at l_max = 10)."""
    sphere = nonuniform_sphere(kappa=kappa, nu=nu, l_max=l_max)
    price = Price.of(sphere, len(kinds), options.get("n_temporal"))
    SECONDS.check(f"the non-uniform sphere at l_max = {l_max} ({len(sphere.systems)} sectors, "
                  f"{price.describe()})", price.seconds, max_seconds,
                  "give a smaller l_max")
    return sphere


def start_degree(kappa_mean: float) -> int:
    """The first l_max of the refinement: one above the first degree whose natural frequency
    at the mean stiffness exceeds 1 (the harmonic resonance), at least 4."""
    lowest = next((l for l in range(2, L_MAX_LIMIT)
                   if lambda0_squared(l, kappa_mean) > 1.0), L_MAX_LIMIT - 3)
    return max(4, lowest + 1)


def _mean(kappa: Callable) -> float:
    """The average of kappa(theta, phi) over the sphere."""
    return stiffness_field(dealiased_grid(4), kappa).mean


def floquet_nonuniform(p: NonUniformSphereParams, *, kind: str = "both",
                       tol_spatial: float | None = None, options: dict[str, Any],
                       progress: bool = False, max_seconds: float | None = None
                       ) -> NonUniformFloquetResult:
    """Marginal tau of the sphere with stiffness kappa(theta, phi) (module docstring).

    Parameters
    ----------
    p : kappa (an expression), nu and l_max ('auto': refined to ``tol_spatial``, default
        :data:`TOL_DEGREES`; or an integer degree truncation).
    options : marginal_tau options (tol, n_temporal, tau_max).
    progress : a progress bar over the sector solves of each truncation on stderr, its label
        stating the estimate (a kappa without symmetry couples many modes: degrees <= 10 take
        minutes).
    max_seconds : raise the limit on the estimated seconds of a truncation's sector solves
        (default :data:`spectralshell.params.limits.SECONDS`, 600 s, or
        $SPECTRALSHELL_MAX_SECONDS): each truncation is priced (:class:`Price`) before it is
        solved, and refused above the limit.

    Each sector's empty answer is proved by the zero count (``certify_empty`` True unless
    ``options`` say otherwise: a sweep's 'mark'); each kind's ``complete_to`` states what the
    sectors of both degree truncations prove (:func:`sector_minimum`, :func:`both_proved`).

    Raises
    ------
    ParameterError : an argument out of range; a truncation estimated above the limit.
    ConvergenceError : tau_min did not settle in l_max by L_MAX_LIMIT, or in N; a sector's
        empty answer could not be proved (N not fixed; the message names the sector).
    """
    expr = parse_expression("kappa", p.kappa, positive=True)
    nu, l_max = p.nu, p.l_max
    kinds = expand_kind(kind)
    auto = l_max == "auto"
    if not auto and tol_spatial is not None:
        raise ParameterError(f"tol_spatial = {tol_spatial!r} is invalid with a fixed l_max: "
                             "it sets when the automatic refinement in l_max stops")
    tol_spatial = require_positive("tol_spatial", TOL_DEGREES if tol_spatial is None
                                   else tol_spatial)
    cap = options.get("tau_max") or math.inf
    solving = {**CERTIFIED, **options}     # a sweep's 'mark' overrides
    fine_l = l_max if not auto else start_degree(_mean(expr.function))
    priced = functools.partial(priced_sphere, expr.function, nu, kinds=kinds, options=options,
                               max_seconds=max_seconds)
    sphere = priced(fine_l)
    coarse = solve_truncation(priced(fine_l - 2), kinds, solving, progress)
    while True:
        fine = solve_truncation(sphere, kinds, solving, progress)
        change = {k: degree_change(fine[k][0], coarse[k][0], cap) for k in kinds}
        if not auto or all(c is not None and c <= tol_spatial for c in change.values()):
            break
        if fine_l + 2 > L_MAX_LIMIT:
            raise ConvergenceError(
                f"tau_min did not settle to tol_spatial={tol_spatial:g} in the degree truncation "
                f"by l_max={fine_l} (last changes {list(change.values())}); relax tol_spatial or "
                "give l_max")
        fine_l, coarse = fine_l + 2, fine
        sphere = priced(fine_l)
    res = {k: spatial_error(both_proved(fine[k][0], coarse[k][0]), change[k]) for k in kinds}
    content = {k: _content(sphere, k, *fine[k]) for k in kinds if fine[k][1] is not None}
    multiplicity = {k: sphere.sectors[fine[k][1]].copies for k in content}
    warnings = (list(sphere.field.warnings)
                + threshold_warnings({k: [m.tau_min] for k, m in res.items()})
                + certification_warnings(res, options.get("tau_max")))
    opts = {"kind": kind, **options, "tol_spatial": tol_spatial if auto else None}
    result = NonUniformFloquetResult(
        model="sphere", params=dataclasses.asdict(p),
        harmonic=res.get("harmonic"), subharmonic=res.get("subharmonic"),
        provenance=provenance(opts), warnings=tuple(warnings), l_max=fine_l,
        l_max_previous=fine_l - 2, l_change=change, content=content,
        multiplicity=multiplicity, sectors=len(sphere.sectors))
    notes = resolution_warnings(res, options["tol"], result.error_reason)
    return dataclasses.replace(result, warnings=result.warnings + tuple(notes))


def degree_change(fine: MarginalTau, coarse: MarginalTau, cap: float) -> float | None:
    """The kind's :func:`~spectralshell.solvers.spatial_refinement.spatial_change` from
    l_max - 2 (``coarse``) to l_max (``fine``), capped at ``cap``; unknown (None: not settled,
    the error estimate tau_min itself) where the coarse answer is an unproved empty one
    (complete_to below ``cap``: a sweep's 'mark', or a fixed n_temporal) and the fine one has a
    tau: a tau the coarse truncation missed could lie anywhere below it. Empty at both, the
    change is 0 and :func:`both_proved` marks the answer instead."""
    if fine.tau_min is not None and coarse.unproved_empty(cap):
        return None
    return spatial_change(fine, coarse, cap)


def both_proved(fine: MarginalTau, coarse: MarginalTau) -> MarginalTau:
    """The kind's answer at l_max (``fine``), whose empty answer also at l_max - 2 (``coarse``)
    is proved only as far as both are (the smaller complete_to): the pair in degree rests on
    both being empty."""
    if fine.tau_min is not None or coarse.tau_min is not None:
        return fine
    return dataclasses.replace(fine, complete_to=min(fine.complete_to, coarse.complete_to))


def tau_min_sensitivity(*, kappa: str, direction: str, nu: float, kind: str, l_max: int,
                        tol: float = 1e-10) -> tuple[float, float]:
    """(tau_min, d tau_min / d eps) of ``kind`` for the stiffness kappa + eps w at eps = 0, w the
    expression ``direction`` (any sign; e.g. kappa0 P_2(cos theta)), at the degree truncation
    l_max, from the eigenvector formula of
    :func:`spectralshell.solvers.marginal_mode.marginal_sensitivity` in the critical sector
    (every other sector proved to have nothing below its tau_min, :func:`sector_minimum`).

    Raises
    ------
    ParameterError : an argument out of range. ConvergenceError : no tau_min (or not simple);
        a sector not proved to have nothing below it.
    """
    l_max = NonUniformSphereParams(kappa=kappa, nu=nu, l_max=l_max).l_max
    expr = parse_expression("kappa", kappa, positive=True)
    w = parse_expression("direction", direction)
    sphere = nonuniform_sphere(kappa=expr.function, nu=nu, l_max=l_max)
    found, where = sector_minimum(sphere, kind, {"tol": tol, "n_temporal": None, **CERTIFIED})
    if where is None:
        raise ConvergenceError(f"no {kind} tau_min to differentiate")
    g = dealiased_grid(l_max)
    weight = g.synthesise(g.analyse(g.evaluate(w.function)))    # degrees <= l_max, as kappa
    derivative = perturbation_system(sphere.sectors[where], weight, l_max)
    slope = marginal_sensitivity(sphere.systems[where], derivative, kind, found.tau_min,
                                 found.n_temporal)
    return float(found.tau_min), slope


def _content(sphere: NonUniformSphere, kind: str, m: MarginalTau, where: int) -> list[dict]:
    mode = marginal_mode(sphere.systems[where], kind, m.tau_min, m.n_temporal)
    return mode_content(sphere.sectors[where], mode.coefficients)


#: P_2(cos theta) as an expression
P2 = "(1.5*cos(theta)**2 - 0.5)"


def p2_branches(*, kappa0: float, nu: float, eps: np.ndarray, l_max: int = 8,
                tau_max: float = 0.5, tol: float = 1e-8) -> list[dict[str, Any]]:
    """Marginal tau of every sector against eps for kappa = kappa0 (1 + eps P_2(cos theta)):
    rows {"eps", "kind", "l", "k", "tau_min"}, one per eps, kind and sector with a tau_min
    <= tau_max, the branch named by the dominant mode (l, |k|) of its critical solution (the
    orders of a degree split; eps = 0, where they are degenerate, belongs to no sector). A
    sector left out is proved to have no tau <= tau_max by the zero count (``certify_empty``).

    Raises
    ------
    ParameterError : eps = 0, or an argument out of range.
    ConvergenceError : a sector did not converge, or its empty answer could not be proved.
    """
    rows = []
    for e in np.asarray(eps, dtype=float):
        if e == 0.0:
            raise ParameterError("eps = 0 is invalid here: the orders of a degree are degenerate "
                                 "there, so no branch is defined (use eps != 0)")
        expr = parse_expression("kappa", f"{kappa0!r}*(1 + {float(e)!r}*{P2})", positive=True)
        sphere = nonuniform_sphere(kappa=expr.function, nu=nu, l_max=l_max)
        for sector, system in zip(sphere.sectors, sphere.systems):
            for kind in ("harmonic", "subharmonic"):
                m = marginal_tau(system, kind, tol=tol, tau_max=tau_max, **CERTIFIED)
                if m.tau_min is None:
                    continue
                mode = marginal_mode(system, kind, m.tau_min, m.n_temporal)
                lead = mode_content(sector, mode.coefficients)[0]
                rows.append({"eps": float(e), "kind": kind, "l": lead["l"], "k": abs(lead["k"]),
                             "tau_min": float(m.tau_min)})
    return rows


def critical_exponent(*, kappa: str, nu: float, kind: str, tau: float, l_max: int,
                      tol: float = 1e-10) -> tuple[complex, float]:
    """(gamma, error estimate): the Floquet exponent at amplitude ``tau`` that crosses
    Re gamma = 0 at the ``kind``'s tau_min, in the critical sector of kappa(theta, phi) at the
    degree truncation l_max: Newton's method on the truncated Hill determinant
    (:mod:`spectralshell.solvers.hill_exponents`) from g = 0, gamma = g + i GAMMA[kind]; the
    error estimate is its change from the truncation N to the next. For tau near tau_min (the
    exponent near the locking line; the time stepper's growth rate is Re gamma). The critical
    sector is that of :func:`sector_minimum` (the others proved to have nothing below it).

    Raises
    ------
    ConvergenceError : no tau_min, or Newton's method did not converge; a sector not proved to
        have nothing below the tau_min.
    """
    l_max = NonUniformSphereParams(kappa=kappa, nu=nu, l_max=l_max).l_max
    expr = parse_expression("kappa", kappa, positive=True)
    sphere = nonuniform_sphere(kappa=expr.function, nu=nu, l_max=l_max)
    found, where = sector_minimum(sphere, kind, {"tol": tol, "n_temporal": None, **CERTIFIED})
    if where is None:
        raise ConvergenceError(f"no {kind} tau_min: no exponent crosses Re gamma = 0")
    values = []
    for n in (found.n_temporal, finer(found.n_temporal)):
        T, dT = pencil_family(sphere.systems[where], kind, n)(float(tau))
        got = newton(T, dT, 0j, tol=1e-14)
        if got is None:
            raise ConvergenceError(f"Newton's method for the {kind} exponent at tau = {tau:g} "
                                   f"did not converge (n_temporal = {n})")
        values.append(got[0] + 1j * GAMMA[kind])
    return complex(values[1]), float(abs(values[1] - values[0]))


def sector_modes(sector: Sector, system: HillSystem, uniform: Callable[[int, str], np.ndarray],
                 tol: float = 1e-13) -> list[complex]:
    """Natural modes of a coupled sector (det D(s) = 0, one per conjugate pair): deflated
    Newton's method on det D from the natural modes ``uniform(l, component)`` of each of its
    modes at the mean stiffness (the exponents' count then proves the list complete in its
    region, :func:`~spectralshell.solvers.hill_exponents.hill_exponents`)."""
    def T(s: complex) -> np.ndarray:
        return system.unforced(np.array([s]))[0]

    def dT(s: complex) -> np.ndarray:    # central difference: Newton's rate, not its root
        h = DERIVATIVE_STEP * max(1.0, abs(s))
        return (T(s + h) - T(s - h)) / (2 * h)

    found: list[complex] = []
    for l, _, component in sector.modes:
        for seed in uniform(l, component):
            got = newton(T, dT, complex(seed), known=found + [g.conjugate() for g in found],
                         tol=tol)
            if got is not None:
                root = got[0] if got[0].imag >= 0 else got[0].conjugate()
                if all(abs(root - g) > 1e-9 * max(1.0, abs(g)) for g in found):
                    found.append(root)
    return found


def sector_exponents(sphere: NonUniformSphere, tau: float, options: dict[str, Any]
                     ) -> Exponents:
    """Floquet exponents of one degree truncation at amplitude ``tau``: those of every
    decoupled sector (a coupled Hill system: :func:`~spectralshell.solvers.hill_exponents.
    hill_exponents` from its natural modes, :func:`sector_modes`), merged; an exponent of a
    sector standing for several equal ones is listed that many times. ``complete_in`` is the
    Re gamma range every sector's count covers; the error estimate is the largest of the
    sectors' (the temporal truncation).

    Raises
    ------
    ConvergenceError : a sector's exponents did not converge or could not be counted.
    """
    from .modes import natural_modes

    @functools.cache
    def uniform(l: int, component: str) -> np.ndarray:
        return natural_modes("sphere", m=l, kappa=sphere.field.mean, nu=sphere.nu,
                             component=component).gamma

    gamma, errors, depths, lows, highs = [], [0.0], [0], [], []
    for sector, system in zip(sphere.sectors, sphere.systems):
        found = hill_exponents(system, tau, sector_modes(sector, system, uniform), **options)
        gamma += [g for g in found.gamma for _ in range(sector.copies)]
        errors.append(found.error_estimate)
        depths.append(found.n_temporal)
        lows.append(found.complete_in[0])
        highs.append(found.complete_in[1])
    gamma = np.array(gamma, dtype=complex)
    return Exponents(gamma=gamma[np.lexsort((gamma.imag, -gamma.real))],
                     n_temporal=max(depths), error_estimate=max(errors),
                     complete_in=(max(lows), min(highs)))


def exponents_nonuniform(p: NonUniformSphereParams, *, tau: float, options: dict[str, Any],
                         max_seconds: float | None = None) -> tuple[Exponents, int]:
    """(Floquet exponents, the degree truncation l_max used) of the sphere with stiffness
    kappa(theta, phi) at amplitude ``tau`` (:func:`sector_exponents`).

    ``p.l_max`` 'auto': l_max = start, start + 2, ... (:func:`start_degree`) until the least
    damped exponent (the first, largest Re gamma) moves by at most :data:`TOL_DEGREES` from
    l_max - 2; that move enters the error estimate. An integer l_max is solved as given (the
    error estimate is then that of the temporal truncation only). Each truncation is priced
    before it is solved, as :func:`floquet_nonuniform`'s (:func:`priced_sphere`, both kinds:
    the exponents are followed in both windows), and refused above the limit on estimated
    seconds (``max_seconds`` raises it).

    Raises
    ------
    ParameterError : an argument out of range; a truncation estimated above the limit.
    ConvergenceError : no convergence in N, or in l_max by L_MAX_LIMIT.
    """
    expr = parse_expression("kappa", p.kappa, positive=True)
    priced = functools.partial(priced_sphere, expr.function, p.nu, kinds=expand_kind("both"),
                               options=options, max_seconds=max_seconds)

    def solve(l_max: int) -> Exponents:
        return sector_exponents(priced(l_max), tau, options)

    if p.l_max != "auto":
        return solve(p.l_max), p.l_max
    l_max = start_degree(_mean(expr.function))
    priced(l_max)  # the finer truncation too, before the coarser one is solved
    coarse = solve(l_max - 2)
    while True:
        fine = solve(l_max)
        change = float(distance(fine.gamma[:1], coarse.gamma[:1]))
        if change <= TOL_DEGREES:
            return dataclasses.replace(fine, error_estimate=max(fine.error_estimate,
                                                                change)), l_max
        if l_max + 2 > L_MAX_LIMIT:
            raise ConvergenceError(
                f"the least damped Floquet exponent did not settle to {TOL_DEGREES:g} in the "
                f"degree truncation by l_max={l_max} (last change {change:.3g}); give l_max")
        l_max, coarse = l_max + 2, fine
